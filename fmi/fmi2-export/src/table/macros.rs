//! [`variables!`](crate::variables!): the rows of an FMU's variable table, and the per-step
//! functions generated from the same rows.

/// Declare an FMU's variables, one row each, and get a [`Variables`](crate::table::Variables) value.
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
/// A row is `[discrete|tunable] VR "name" [ACCESS] "unit" [BOUNDS] "description";` (`discrete`: a
/// Real output that changes at sample instants only; `tunable`: a parameter the master may
/// change between steps, which the model applies in [`Fmi2Model::retune`](crate::Fmi2Model::retune)) where ACCESS is a
/// field path of the group's struct (`a.b`, `a.m[0][1]`), `enum PATH` for a [`model_kit::Choice`](crate::model_kit::Choice) field, or
/// `get CLOSURE, set CLOSURE` for a computed variable; BOUNDS is empty or `min, max`; the unit is
/// a name of [`model_description::units::UNITS`](crate::model_description::units::UNITS) or `""`.
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
            direct: $crate::table::Direct {
                read_inputs: |v: &$crate::Values, s: &mut $I| {
                    let _ = (&v, &s);
                    $crate::__direct!(load v, s; $($irow)*);
                },
                write_outputs: |s: &$O, v: &mut $crate::Values| {
                    let _ = (&v, &s);
                    $crate::__direct!(store v, s; $($orow)*);
                },
            },
        }
    };
}

/// The statements of a [`Direct`](crate::table::Direct) function: one per field row (`f64` and `bool` fields move, the others
/// compile to nothing), enumeration and computed rows none.
#[doc(hidden)]
#[macro_export]
macro_rules! __direct {
    ($op:ident $v:ident, $s:ident; $( $($kw:ident)? $vr:literal $name:literal [$($acc:tt)+] $unit:literal [$($b:tt)*] $desc:literal ; )* ) => {
        $( $crate::__direct_row!($op $v, $s, $vr; $($acc)+); )*
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __direct_row {
    ($op:ident $v:ident, $s:ident, $vr:literal; enum $($f:ident).+) => {};
    ($op:ident $v:ident, $s:ident, $vr:literal; get $get:expr, set $set:expr) => {};
    (load $v:ident, $s:ident, $vr:literal; $($path:tt)+) => {
        $crate::table::Scalar::load_direct(&mut $s.$($path)+, $v, $vr)
    };
    (store $v:ident, $s:ident, $vr:literal; $($path:tt)+) => {
        $crate::table::Scalar::store_direct(&$s.$($path)+, $v, $vr)
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
                tunable: $crate::__tunable!($($kw)?),
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
    (tunable) => {
        false
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __tunable {
    () => {
        false
    };
    (discrete) => {
        false
    };
    (tunable) => {
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

/// The shape every FMU adapter repeats around its [`Table`](crate::Table): its
/// [`TableModel`](crate::table::TableModel) impl, the public `parameter_assignments` of its
/// parameter struct, and the mapping of its core's step errors to FMI statuses.
///
/// ```text
/// fmi2_export::adapter! {
///     model: MillingPlant,
///     table: TABLE as Table<PlantParams, PlantInputs, PlantOutputs>,
///     parameters: |m| m.plant.params(),
///     input_errors: PlantError::Input,
/// }
/// ```
/// gives
/// * `impl TableModel for MillingPlant` with the three types, `table()` = `&TABLE` and
///   `parameters()` = the closure's body with `m` = `self`;
/// * `pub fn parameter_assignments(p: &PlantParams) -> Vec<(String, Value)>`: what a master
///   sets (`--set NAME=VALUE`, SSP parameter bindings) to run the FMU with `p`;
/// * with `input_errors` (a tuple variant of the core's error enum):
///   `MillingPlant::step_error(e: PlantError) -> StepError`, `StepError::Discard` for that
///   variant (the step was not taken, the master may retry with other inputs) and
///   `StepError::Error` for every other, each with the error's message.
///
/// The adapter's `Fmi2Model::description` is `TABLE.description()`.
#[macro_export]
macro_rules! adapter {
    (
        model: $M:ty,
        table: $table:ident as Table<$P:ty, $I:ty, $O:ty>,
        parameters: |$m:ident| $params:expr
        $(, input_errors: $E:ident :: $input:ident)?
        $(,)?
    ) => {
        impl $crate::table::TableModel for $M {
            type Params = $P;
            type Inputs = $I;
            type Outputs = $O;
            fn table() -> &'static $crate::Table<$P, $I, $O> {
                &$table
            }
            fn parameters(&self) -> &$P {
                let $m = self;
                $params
            }
        }

        /// The FMU's parameters holding `p`, as (variable name, value) pairs: what a master sets
        /// (`--set NAME=VALUE`, SSP parameter bindings) to run the FMU with `p`. Generated from
        /// the same table as `modelDescription.xml`.
        pub fn parameter_assignments(p: &$P) -> ::std::vec::Vec<(::std::string::String, $crate::model_description::Value)> {
            $table.assignments(p)
        }

        $(
            impl $M {
                /// A step error of the core as the step's FMI status: `fmi2Discard` for an input
                /// error (the step was not taken; the master may retry with other inputs),
                /// `fmi2Error` for any other; the message is the error's.
                fn step_error(e: $E) -> $crate::StepError {
                    match e {
                        e @ $E::$input(..) => $crate::StepError::Discard(e.to_string()),
                        e => $crate::StepError::Error(e.to_string()),
                    }
                }
            }
        )?
    };
}
