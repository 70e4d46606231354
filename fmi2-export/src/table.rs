//! One row per variable: the declarative variable table of an FMU adapter.
//!
//! An FMU adapter crate translates between a core's plain types (a parameter struct `P`, an
//! input struct `I`, an output struct `O`) and FMI variables. It declares each variable once,
//! as one row of [`variables!`](crate::variables!):
//!
//! ```text
//! vr  name                  [field path]            unit   [min, max]   description
//! 100 "workpiece.mass"      [workpiece.first.mass]  "kg"   [1e-9, 1e9]  "first-mode modal mass";
//! 3   "cutting.model"       [enum cutting.model]    ""     []           "cutting-force model";
//! 104 "mode2.frequency"     [get |p| …, set |p, v| …] "Hz" [1e-3, 1e6]  "second mode";
//! ```
//!
//! From that row come:
//! * the value reference and the `modelDescription.xml` entry (name, type, causality,
//!   variability, unit and its definition, bounds, start value, description; the FMI type
//!   follows from the Rust type of the field through [`Scalar`], and enumerations from
//!   [`model_kit::Choice`], whose items become the XML type definition);
//! * reading parameters into the core's struct ([`Table::read_parameters`]) and inputs into
//!   the input struct ([`Table::read_inputs`]);
//! * writing outputs ([`Table::write_outputs`]);
//! * the parameter set → `(name, value)` pairs a master sets to reproduce it
//!   ([`Table::assignments`], for `--set` and SSP parameter bindings).
//!
//! Start values are read from `P::default()` and `I::default()`, so the core's defaults are the
//! FMU's start values. Every output is declared without direct feedthrough (its value at a
//! communication point is that of the state there; `ModelStructure` lists no dependencies).
//! A field of `P` without a row is caught by [`checks::parameter_coverage`] (feature `checks`),
//! a row without a field does not compile.

use crate::model::Values;
use model_description::{
    Causality, DescriptionError, ModelBuilder, ModelDescription, ScalarType, ScalarVariable, Value, ValueReference,
    Variability,
};
use model_kit::Choice;

#[cfg(feature = "checks")]
pub mod checks;

/// A Rust type stored in one FMI scalar variable.
pub trait Scalar: Sized {
    /// The FMI type.
    const TYPE: ScalarType;
    /// To an FMI value.
    fn to_value(&self) -> Value;
    /// From an FMI value of type [`Scalar::TYPE`]; the error says why the value does not fit.
    fn from_value(v: &Value) -> Result<Self, String>;
    /// The field selected by `read` and `write` as a [`RealField`] when `Self` is `f64` (the
    /// per-step inputs and outputs then bypass [`Value`]); `None` for the other types.
    fn real_field<S>(_read: fn(&S) -> &Self, _write: fn(&mut S) -> &mut Self) -> Option<RealField<S>> {
        None
    }
}

/// A Real field of `S` read and written directly (no [`Value`], no boxed closure): what
/// [`Table::read_inputs`] and [`Table::write_outputs`] use every step for `f64` rows.
pub struct RealField<S> {
    read: fn(&S) -> &f64,
    write: fn(&mut S) -> &mut f64,
}

impl<S> Clone for RealField<S> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<S> Copy for RealField<S> {}

fn mismatch(expected: &str, v: &Value) -> String {
    format!("expected {expected}, got {v:?}")
}

impl Scalar for f64 {
    const TYPE: ScalarType = ScalarType::Real;
    fn to_value(&self) -> Value {
        Value::Real(*self)
    }
    fn from_value(v: &Value) -> Result<Self, String> {
        match v {
            Value::Real(x) => Ok(*x),
            v => Err(mismatch("a Real", v)),
        }
    }
    fn real_field<S>(read: fn(&S) -> &f64, write: fn(&mut S) -> &mut f64) -> Option<RealField<S>> {
        Some(RealField { read, write })
    }
}

impl Scalar for bool {
    const TYPE: ScalarType = ScalarType::Boolean;
    fn to_value(&self) -> Value {
        Value::Boolean(*self)
    }
    fn from_value(v: &Value) -> Result<Self, String> {
        match v {
            Value::Boolean(b) => Ok(*b),
            v => Err(mismatch("a Boolean", v)),
        }
    }
}

impl Scalar for String {
    const TYPE: ScalarType = ScalarType::String;
    fn to_value(&self) -> Value {
        Value::String(self.clone())
    }
    fn from_value(v: &Value) -> Result<Self, String> {
        match v {
            Value::String(s) => Ok(s.clone()),
            v => Err(mismatch("a String", v)),
        }
    }
}

macro_rules! integer_scalar {
    ($($t:ty),*) => {$(
        impl Scalar for $t {
            const TYPE: ScalarType = ScalarType::Integer;
            /// # Panics
            /// If the value does not fit an `fmi2Integer` (a core default outside the table's
            /// declared range: a bug caught by the adapter's tests).
            fn to_value(&self) -> Value {
                Value::Integer(i32::try_from(*self).unwrap_or_else(|_| panic!("{} does not fit an fmi2Integer", self)))
            }
            fn from_value(v: &Value) -> Result<Self, String> {
                match v {
                    Value::Integer(i) => <$t>::try_from(*i).map_err(|_| format!("{i} is out of range for {}", stringify!($t))),
                    v => Err(mismatch("an Integer", v)),
                }
            }
        }
    )*};
}
integer_scalar!(i32, u32, u64, usize);

/// The FMI enumeration type of a [`Choice`] row.
#[derive(Clone, Debug, PartialEq)]
pub struct ChoiceType {
    /// Type name.
    pub name: &'static str,
    /// Type description.
    pub description: &'static str,
    /// Items `(name, description)`, valued `1..=n`.
    pub items: Vec<(&'static str, &'static str)>,
}

/// The attributes of a row other than its accessors (filled in by [`variables!`](crate::variables!)).
#[derive(Clone, Debug, PartialEq)]
pub struct Attrs {
    /// Value reference (unique per FMI API type).
    pub vr: ValueReference,
    /// Variable name.
    pub name: &'static str,
    /// Unit of a Real (a name of [`model_description::units::UNITS`]), `""` for none.
    pub unit: &'static str,
    /// `(min, max)`.
    pub bounds: Option<(f64, f64)>,
    /// Description.
    pub description: &'static str,
    /// A Real output that changes only at sample instants (`variability="discrete"`).
    pub discrete: bool,
}

type Getter<S> = Box<dyn Fn(&S) -> Value + Send + Sync>;
type Setter<S> = Box<dyn Fn(&mut S, &Value) -> Result<(), String> + Send + Sync>;

/// One variable: its attributes and how to read it from / write it into a struct `S`.
pub struct Row<S> {
    /// Attributes.
    pub attrs: Attrs,
    /// FMI type (`Enumeration` for [`Choice`] rows).
    pub ty: ScalarType,
    /// The enumeration type of a [`Choice`] row.
    pub choice: Option<ChoiceType>,
    get: Getter<S>,
    set: Setter<S>,
    /// The same field as `get`/`set` for `f64` fields of [`Row::field`] (the per-step path).
    real: Option<RealField<S>>,
}

impl<S> std::fmt::Debug for Row<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Row").field("attrs", &self.attrs).field("ty", &self.ty).finish()
    }
}

impl<S> Row<S> {
    /// The variable's value in `s`.
    pub fn get(&self, s: &S) -> Value {
        (self.get)(s)
    }

    /// Store `v` in `s`; the error names the variable.
    pub fn set(&self, s: &mut S, v: &Value) -> Result<(), String> {
        (self.set)(s, v).map_err(|e| format!("{}: {e}", self.attrs.name))
    }
}

impl<S: 'static> Row<S> {
    /// A row stored in a field of `S` (`read` and `write` select the same field).
    pub fn field<T: Scalar + 'static>(attrs: Attrs, read: fn(&S) -> &T, write: fn(&mut S) -> &mut T) -> Self {
        Row {
            attrs,
            ty: T::TYPE,
            choice: None,
            get: Box::new(move |s| read(s).to_value()),
            set: Box::new(move |s, v| {
                *write(s) = T::from_value(v)?;
                Ok(())
            }),
            real: T::real_field(read, write),
        }
    }

    /// A row stored in a [`Choice`] field of `S`: an FMI enumeration valued by [`Choice::index`].
    pub fn choice<T: Choice>(attrs: Attrs, read: fn(&S) -> &T, write: fn(&mut S) -> &mut T) -> Self {
        Row {
            attrs,
            ty: ScalarType::Enumeration,
            choice: Some(ChoiceType {
                name: T::TYPE_NAME,
                description: T::DESCRIPTION,
                items: T::ITEMS.iter().map(|(_, n, d)| (*n, *d)).collect(),
            }),
            get: Box::new(move |s| Value::Integer(read(s).index())),
            set: Box::new(move |s, v| match v {
                Value::Integer(i) => {
                    *write(s) = T::from_index(*i).ok_or_else(|| format!("{i} is not an item of {}", T::TYPE_NAME))?;
                    Ok(())
                }
                v => Err(mismatch("an enumeration value", v)),
            }),
            real: None,
        }
    }

    /// A row computed from `S` by `get` and stored by `set` (a parametrisation that differs from
    /// the core's fields, e.g. a mode given by frequency and peak receptance).
    pub fn computed<T: Scalar + 'static>(attrs: Attrs, get: fn(&S) -> T, set: fn(&mut S, T)) -> Self {
        Row {
            attrs,
            ty: T::TYPE,
            choice: None,
            get: Box::new(move |s| get(s).to_value()),
            set: Box::new(move |s, v| {
                set(s, T::from_value(v)?);
                Ok(())
            }),
            real: None,
        }
    }

    /// The scalar variable of this row with causality `c` and start value `start`.
    fn scalar_variable(&self, c: Causality, start: Option<Value>) -> ScalarVariable {
        let a = &self.attrs;
        let variability = match (c, self.ty) {
            (Causality::Parameter, _) => Variability::Fixed,
            (_, ScalarType::Real) if !a.discrete => Variability::Continuous,
            _ => Variability::Discrete,
        };
        let mut v = match (self.ty, &self.choice) {
            (ScalarType::Real, _) => ScalarVariable::real(a.name, a.vr, c, variability),
            (ScalarType::Integer, _) => ScalarVariable::integer(a.name, a.vr, c, variability),
            (ScalarType::Boolean, _) => ScalarVariable::boolean(a.name, a.vr, c, variability),
            (ScalarType::String, _) => ScalarVariable::string(a.name, a.vr, c, variability),
            (ScalarType::Enumeration, Some(t)) => ScalarVariable::enumeration(a.name, a.vr, c, variability, t.name),
            (ScalarType::Enumeration, None) => unreachable!("enumeration rows carry their type"),
        };
        if let Some(s) = start {
            v = v.start(s);
        }
        if !a.unit.is_empty() {
            v = v.unit_of(a.unit);
        }
        if let Some((lo, hi)) = a.bounds {
            v = v.bounds(lo, hi);
        }
        if !a.description.is_empty() {
            v = v.describe(a.description);
        }
        if c == Causality::Output {
            v = v.depends_on(&[]);
        }
        v
    }
}

/// The rows of an FMU, by causality (built by [`variables!`](crate::variables!)).
pub struct Variables<P, I, O> {
    /// Inputs, read from the store into `I` before every step.
    pub inputs: Vec<Row<I>>,
    /// Outputs, written from `O` into the store after every step.
    pub outputs: Vec<Row<O>>,
    /// Parameters, read into `P` when the model is built.
    pub parameters: Vec<Row<P>>,
}

/// What a `modelDescription.xml` says besides the variables.
#[derive(Clone, Debug, PartialEq)]
pub struct Header {
    /// `modelName`.
    pub model_name: &'static str,
    /// `modelIdentifier` (the cdylib's library name).
    pub identifier: &'static str,
    /// One-line description.
    pub description: &'static str,
    /// Default experiment `(start, stop, step)` \[s\].
    pub default_experiment: (f64, f64, f64),
}

/// An FMU's variable table: [`Header`] plus [`Variables`].
pub struct Table<P, I, O> {
    /// Header.
    pub header: Header,
    /// Rows (read through [`vars`](Self::vars): the per-step lists below are derived from them).
    vars: Variables<P, I, O>,
    /// The declared work bound: (internal-step parameter, extra internal steps per call).
    work_bound: Option<(&'static str, f64)>,
    /// The per-step path: the `f64` input and output rows as (value reference, field), in row
    /// order and contiguous (a step touches one or two cache lines instead of every row), and the
    /// indices of the other rows, which go through [`Value`]s.
    real_inputs: Vec<(ValueReference, RealField<I>)>,
    other_inputs: Vec<usize>,
    real_outputs: Vec<(ValueReference, RealField<O>)>,
    other_outputs: Vec<usize>,
}

/// The `f64` rows of `rows` as (value reference, field), and the indices of the others.
fn split_real<S>(rows: &[Row<S>]) -> (Vec<(ValueReference, RealField<S>)>, Vec<usize>) {
    let real = rows.iter().filter_map(|r| r.real.map(|f| (r.attrs.vr, f))).collect();
    let other = rows.iter().enumerate().filter(|(_, r)| r.real.is_none()).map(|(i, _)| i).collect();
    (real, other)
}

impl<P: Default + 'static, I: Default + 'static, O: 'static> Table<P, I, O> {
    /// A table.
    pub fn new(header: Header, vars: Variables<P, I, O>) -> Self {
        let (real_inputs, other_inputs) = split_real(&vars.inputs);
        let (real_outputs, other_outputs) = split_real(&vars.outputs);
        Table { header, vars, work_bound: None, real_inputs, other_inputs, real_outputs, other_outputs }
    }

    /// The rows.
    pub fn vars(&self) -> &Variables<P, I, O> {
        &self.vars
    }

    /// Declare in `modelDescription.xml` what a step costs (a
    /// [`WorkBound`](model_description::WorkBound) vendor annotation): `h / p + extra` internal
    /// steps, `p` being the Real parameter `parameter`, at most
    /// [`MAX_INTERNAL_STEPS_PER_CALL`](crate::MAX_INTERNAL_STEPS_PER_CALL) per call. It must be
    /// the model's own [`Fmi2Model::internal_steps`](crate::Fmi2Model::internal_steps) (checked
    /// by [`checks::work_bound_matches_internal_steps`], feature `checks`), so that a master
    /// can refuse a too large step before instantiating, exactly as the layer would refuse it.
    pub fn work_bound(mut self, parameter: &'static str, extra: f64) -> Self {
        self.work_bound = Some((parameter, extra));
        self
    }

    /// The model description with the start values of `params` (and `I::default()` for inputs).
    /// Variables are listed inputs, outputs, parameters, each in row order; units and
    /// enumeration types in order of first use.
    pub fn model_description(&self, params: &P) -> Result<ModelDescription, DescriptionError> {
        let h = &self.header;
        let inputs = I::default();
        let mut vars = Vec::new();
        let mut units: Vec<&str> = Vec::new();
        let mut choices: Vec<&ChoiceType> = Vec::new();
        for r in &self.vars.inputs {
            vars.push(r.scalar_variable(Causality::Input, Some(r.get(&inputs))));
            collect(&r.attrs, &r.choice, &mut units, &mut choices);
        }
        for r in &self.vars.outputs {
            vars.push(r.scalar_variable(Causality::Output, None));
            collect(&r.attrs, &r.choice, &mut units, &mut choices);
        }
        for r in &self.vars.parameters {
            vars.push(r.scalar_variable(Causality::Parameter, Some(r.get(params))));
            collect(&r.attrs, &r.choice, &mut units, &mut choices);
        }
        let (start, stop, step) = h.default_experiment;
        let mut b = ModelBuilder::new(h.model_name, h.identifier)
            .description(h.description)
            .author_version("chatter-fmu", env!("CARGO_PKG_VERSION"));
        for u in units {
            b = b.known_unit(u)?;
        }
        for t in choices {
            b = b.enumeration(t.name, t.description, &t.items);
        }
        b = b.default_experiment(start, stop, step);
        if let Some((parameter, extra)) = self.work_bound {
            b = b.work_bound(model_description::WorkBound {
                max_internal_steps_per_call: crate::MAX_INTERNAL_STEPS_PER_CALL,
                internal_step_parameter: parameter.into(),
                extra_internal_steps_per_call: extra,
            });
        }
        for v in vars {
            b = b.var(v);
        }
        crate::with_log_categories(b).build()
    }

    /// The parameter struct held by the store: `P::default()` with every parameter row applied.
    pub fn read_parameters(&self, v: &Values) -> Result<P, String> {
        let mut p = P::default();
        for r in &self.vars.parameters {
            r.set(&mut p, &v.get(r.ty.api_type(), r.attrs.vr))?;
        }
        Ok(p)
    }

    /// The input struct held by the store (the `f64` field rows first, then the others: input
    /// rows write distinct fields, so the order does not matter).
    pub fn read_inputs(&self, v: &Values) -> Result<I, String> {
        let mut i = I::default();
        for &(vr, f) in &self.real_inputs {
            *(f.write)(&mut i) = v.real(vr);
        }
        for &k in &self.other_inputs {
            let r = &self.vars.inputs[k];
            r.set(&mut i, &v.get(r.ty.api_type(), r.attrs.vr))?;
        }
        Ok(i)
    }

    /// Write every output of `o` into the store.
    pub fn write_outputs(&self, o: &O, v: &mut Values) {
        for &(vr, f) in &self.real_outputs {
            v.set_real(vr, *(f.read)(o));
        }
        for &k in &self.other_outputs {
            let r = &self.vars.outputs[k];
            v.set(r.attrs.vr, &r.get(o));
        }
    }

    /// The parameters as `(name, value)` pairs: what a master sets (`--set`, SSP parameter
    /// bindings) to run the FMU with `p`.
    pub fn assignments(&self, p: &P) -> Vec<(String, Value)> {
        self.vars.parameters.iter().map(|r| (r.attrs.name.to_string(), r.get(p))).collect()
    }

    /// The inputs as `(name, value)` pairs (their start values for a run with `i`).
    pub fn input_assignments(&self, i: &I) -> Vec<(String, Value)> {
        self.vars.inputs.iter().map(|r| (r.attrs.name.to_string(), r.get(i))).collect()
    }

    /// The parameter row called `name`.
    pub fn parameter(&self, name: &str) -> Option<&Row<P>> {
        self.vars.parameters.iter().find(|r| r.attrs.name == name)
    }
}

fn collect<'a>(
    a: &Attrs,
    choice: &'a Option<ChoiceType>,
    units: &mut Vec<&'static str>,
    choices: &mut Vec<&'a ChoiceType>,
) {
    if !a.unit.is_empty() && !units.contains(&a.unit) {
        units.push(a.unit);
    }
    if let Some(t) = choice
        && !choices.iter().any(|c| c.name == t.name)
    {
        choices.push(t);
    }
}

/// Declare an FMU's variables, one row each, and get a [`Variables`] value.
///
/// ```text
/// fmi2_export::variables! {
///     inputs MyInputs {
///         0 "u" [u] "N" [] "actuator command";
///     }
///     outputs MyOutputs {
///         10 "x" [x] "m" [] "displacement";
///         discrete 11 "u_applied" [u] "N" [] "sampled command";
///     }
///     parameters MyParams {
///         100 "mass" [mass] "kg" [1e-9, 1e9] "modal mass";
///         1 "model" [enum model] "" [] "force model";
///         101 "frequency" [get |p| p.frequency(), set |p, f| p.set_frequency(f)] "Hz" [] "…";
///     }
/// }
/// ```
/// A row is `[discrete] VR "name" [ACCESS] "unit" [BOUNDS] "description";` where ACCESS is a
/// field path of the group's struct (`a.b`, `a.m[0][1]`), `enum PATH` for a [`model_kit::Choice`] field, or
/// `get CLOSURE, set CLOSURE` for a computed variable; BOUNDS is empty or `min, max`; the unit is
/// a name of [`model_description::units::UNITS`] or `""`.
#[macro_export]
macro_rules! variables {
    (
        inputs $I:ty { $($irow:tt)* }
        outputs $O:ty { $($orow:tt)* }
        parameters $P:ty { $($prow:tt)* }
    ) => {
        $crate::table::Variables::<$P, $I, $O> {
            inputs: $crate::__rows!($I; $($irow)*),
            outputs: $crate::__rows!($O; $($orow)*),
            parameters: $crate::__rows!($P; $($prow)*),
        }
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __rows {
    ($S:ty; $( $($kw:ident)? $vr:literal $name:literal [$($acc:tt)+] $unit:literal [$($b:tt)*] $desc:literal ; )* ) => {
        vec![ $(
            $crate::__access!($S; $crate::table::Attrs {
                vr: $vr,
                name: $name,
                unit: $unit,
                bounds: $crate::__bounds!($($b)*),
                description: $desc,
                discrete: $crate::__discrete!($($kw)?),
            }; $($acc)+)
        ),* ]
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __bounds {
    () => {
        None
    };
    ($lo:expr, $hi:expr) => {
        Some(($lo as f64, $hi as f64))
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __discrete {
    () => {
        false
    };
    (discrete) => {
        true
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __access {
    ($S:ty; $attrs:expr; enum $($f:ident).+) => {
        $crate::table::Row::<$S>::choice($attrs, |s: &$S| &s.$($f).+, |s: &mut $S| &mut s.$($f).+)
    };
    ($S:ty; $attrs:expr; get $get:expr, set $set:expr) => {
        $crate::table::Row::<$S>::computed($attrs, $get, $set)
    };
    ($S:ty; $attrs:expr; $($path:tt)+) => {
        $crate::table::Row::<$S>::field($attrs, |s: &$S| &s.$($path)+, |s: &mut $S| &mut s.$($path)+)
    };
}

/// A model whose variables are a [`Table`]: what the generic checks of an adapter need.
pub trait TableModel: crate::Fmi2Model {
    /// The core's parameter struct.
    type Params: Default + Clone + std::fmt::Debug + 'static;
    /// The inputs held over a step.
    type Inputs: Default + 'static;
    /// The outputs at a communication point.
    type Outputs: 'static;
    /// The one variable table.
    fn table() -> &'static Table<Self::Params, Self::Inputs, Self::Outputs>;
    /// The parameters the running model was built with.
    fn parameters(&self) -> &Self::Params;
}

#[cfg(test)]
mod tests;
