//! The safe side of the export layer: what a model implements.
//!
//! A model is a plain Rust type holding its physics state. The export layer
//! owns the variable store ([`Values`]), initialised from the start values of
//! the model's [`ModelDescription`], and does every get/set, type, range and
//! settability check itself; the model only sees consistent values:
//!
//! * [`Fmi2Model::initialize`] builds the model from parameters and inputs,
//!   when the master leaves initialization mode (and, to answer `fmi2Get*` of
//!   calculated outputs, during initialization mode);
//! * [`Fmi2Model::do_step`] advances the model from `t` to `t + h`, reading
//!   inputs and tunable parameters from the store and writing outputs back.
//!
//! No FFI type appears here.

use model_description::{ModelDescription, ScalarType, Value, ValueReference};
use serde::{Deserialize, Serialize, de::DeserializeOwned};

/// Where and as what the model was instantiated.
#[derive(Clone, Debug, Default)]
pub struct Environment {
    /// The instance name given by the master (may be empty).
    pub instance_name: String,
    /// The FMU's `resources/` directory, decoded from the resource location URI, if any.
    pub resources: Option<std::path::PathBuf>,
}

/// Severity of a model message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    /// Informational (category `logEvents`).
    Info,
    /// Warning (category `logStatusWarning`).
    Warning,
}

/// A message sink the model may use during a step; messages go to the host's
/// logger when the category is enabled.
pub trait ModelLog {
    /// Emit a message.
    fn log(&mut self, severity: Severity, message: &str);
}

/// A step that could not be completed.
#[derive(Clone, Debug, PartialEq)]
pub enum StepError {
    /// The step was not performed but the instance stays usable (`fmi2Discard`),
    /// e.g. the master asked for an operating point outside the model's range.
    Discard(String),
    /// The instance is in error (`fmi2Error`); only get, reset and free are allowed afterwards.
    Error(String),
}

/// What a model implements to be exported as an FMI 2.0 Co-Simulation FMU.
pub trait Fmi2Model: Sized + Send + Clone + Serialize + DeserializeOwned + 'static {
    /// The model's one variable table (built once, e.g. in a `OnceLock`).
    fn description() -> &'static ModelDescription;

    /// Build the model from the current parameter and input values.
    /// An `Err` is reported as `fmi2Error` with the message.
    fn initialize(values: &Values, env: &Environment) -> Result<Self, String>;

    /// Write outputs (and calculated parameters) for the current state into `values`.
    fn update_outputs(&self, values: &mut Values);

    /// Advance from `t` to `t + h`, reading inputs and tunable parameters from
    /// `values` and writing the outputs at `t + h` back.
    fn do_step(&mut self, values: &mut Values, t: f64, h: f64, log: &mut dyn ModelLog) -> Result<(), StepError>;

    /// How many internal steps (the model's unit of work: integrator steps, controller samples)
    /// a communication step of size `h` costs. The layer refuses, with `fmi2Error` before
    /// calling [`Fmi2Model::do_step`], a step that would cost more than
    /// [`MAX_INTERNAL_STEPS_PER_CALL`], so that no single call can run unboundedly long.
    /// The default, one, suits models whose step does a fixed amount of work.
    fn internal_steps(&self, h: f64) -> f64 {
        let _ = h;
        1.0
    }

    /// Apply the tunable parameters in `values` (set by the master since the last step) to the
    /// running model, keeping its state; called before the next [`Fmi2Model::do_step`]. An `Err`
    /// is `fmi2Error` with the message. The default does nothing: right for models that read no
    /// tunable parameter, or read them from `values` in every step.
    fn retune(&mut self, values: &Values) -> Result<(), String> {
        let _ = values;
        Ok(())
    }

    /// Check a model restored from a serialized FMU state (`fmi2DeSerializeFMUstate`) before it
    /// is accepted: the same validation as its parameters get at initialization, plus the
    /// invariants of its state (finite values, buffer shapes, derived fields), so that a
    /// corrupted state is `fmi2Error` with this message, never a hang or a panic later. The
    /// default accepts everything; models with state invariants override it.
    fn validate_state(&self) -> Result<(), String> {
        Ok(())
    }
}

/// 64-bit FNV-1a hash of `bytes` (the checksum of serialized FMU states, and the seed of the
/// magic numbers of component and state handles).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

/// The most internal steps ([`Fmi2Model::internal_steps`]) one `fmi2DoStep` may cost:
/// 10⁷, i.e. 100 s of simulated time for a model on a 10 µs grid, a few seconds of
/// computation. A master with a larger step splits it into several calls.
pub const MAX_INTERNAL_STEPS_PER_CALL: f64 = 1e7;

/// The variable store of an instance: one slot per declared variable, indexed
/// by (API type, value reference).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Values {
    reals: Vec<f64>,
    integers: Vec<i32>,
    booleans: Vec<bool>,
    strings: Vec<String>,
}

/// Value references above this are refused by [`Values::from_description`]:
/// the store is dense.
pub const MAX_VALUE_REFERENCE: ValueReference = 65_535;

impl Values {
    /// A store holding the start values of `md`.
    ///
    /// # Panics
    /// If a value reference exceeds [`MAX_VALUE_REFERENCE`] (a bug in the model's table).
    pub fn from_description(md: &ModelDescription) -> Self {
        let mut v = Values { reals: Vec::new(), integers: Vec::new(), booleans: Vec::new(), strings: Vec::new() };
        for var in md.variables() {
            let vr = var.value_reference;
            assert!(vr <= MAX_VALUE_REFERENCE, "value reference {vr} of {} too large", var.name);
            let i = vr as usize;
            match (var.scalar_type().api_type(), var.initial_value()) {
                (ScalarType::Real, Value::Real(x)) => put(&mut v.reals, i, x, 0.0),
                (ScalarType::Integer, Value::Integer(x)) => put(&mut v.integers, i, x, 0),
                (ScalarType::Boolean, Value::Boolean(x)) => put(&mut v.booleans, i, x, false),
                (ScalarType::String, Value::String(x)) => put(&mut v.strings, i, x, String::new()),
                (t, x) => panic!("variable {}: value {x:?} does not fit type {t:?}", var.name),
            }
        }
        v
    }

    /// Real value.
    #[inline]
    pub fn real(&self, vr: ValueReference) -> f64 {
        self.reals[vr as usize]
    }
    /// Integer (or enumeration) value.
    #[inline]
    pub fn integer(&self, vr: ValueReference) -> i32 {
        self.integers[vr as usize]
    }
    /// Boolean value.
    #[inline]
    pub fn boolean(&self, vr: ValueReference) -> bool {
        self.booleans[vr as usize]
    }
    /// String value.
    #[inline]
    pub fn string(&self, vr: ValueReference) -> &str {
        &self.strings[vr as usize]
    }
    /// Set a Real.
    #[inline]
    pub fn set_real(&mut self, vr: ValueReference, x: f64) {
        self.reals[vr as usize] = x;
    }
    /// Set an Integer (or enumeration).
    #[inline]
    pub fn set_integer(&mut self, vr: ValueReference, x: i32) {
        self.integers[vr as usize] = x;
    }
    /// Set a Boolean.
    #[inline]
    pub fn set_boolean(&mut self, vr: ValueReference, x: bool) {
        self.booleans[vr as usize] = x;
    }
    /// Set a String.
    #[inline]
    pub fn set_string(&mut self, vr: ValueReference, x: &str) {
        x.clone_into(&mut self.strings[vr as usize]);
    }
}

impl Values {
    /// The value of `vr` of the API type `ty` (`Enumeration` reads the Integer slot).
    pub fn get(&self, ty: ScalarType, vr: ValueReference) -> Value {
        match ty.api_type() {
            ScalarType::Real => Value::Real(self.real(vr)),
            ScalarType::Integer | ScalarType::Enumeration => Value::Integer(self.integer(vr)),
            ScalarType::Boolean => Value::Boolean(self.boolean(vr)),
            ScalarType::String => Value::String(self.string(vr).to_string()),
        }
    }

    /// Store `x` at `vr` in the slot of its type.
    pub fn set(&mut self, vr: ValueReference, x: &Value) {
        match x {
            Value::Real(r) => self.set_real(vr, *r),
            Value::Integer(i) => self.set_integer(vr, *i),
            Value::Boolean(b) => self.set_boolean(vr, *b),
            Value::String(s) => self.set_string(vr, s),
        }
    }

    /// Does this store have one slot per variable of `md`?
    pub fn same_shape(&self, md: &ModelDescription) -> bool {
        let fresh = Values::from_description(md);
        (self.reals.len(), self.integers.len(), self.booleans.len(), self.strings.len())
            == (fresh.reals.len(), fresh.integers.len(), fresh.booleans.len(), fresh.strings.len())
    }
}

fn put<T: Clone>(vec: &mut Vec<T>, i: usize, x: T, fill: T) {
    if vec.len() <= i {
        vec.resize(i + 1, fill);
    }
    vec[i] = x;
}
