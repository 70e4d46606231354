//! Instances for an adapter's tests, through the same instance API the C boundary calls:
//! value references by name, a log sink that drops messages, instances in initialization mode
//! or initialized with some variables set, Real values by name.

use crate::Fmi2Model;
use crate::instance::{CallResult, Instance, LogLevel, LogSink};
use crate::model::{Environment, ModelLog, Severity};
use model_description::{ScalarType, Value, ValueReference};

/// The value reference of `M`'s variable `name`.
///
/// # Panics
/// If `M` has no variable `name`.
pub fn vr<M: Fmi2Model>(name: &str) -> ValueReference {
    M::description().variable(name).unwrap_or_else(|| panic!("no variable {name}")).value_reference
}

/// A log sink that drops every message: for an [`Instance`] ([`LogSink`]) and for a model's
/// `do_step` called directly ([`ModelLog`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Quiet;

impl LogSink for Quiet {
    fn emit(&mut self, _level: LogLevel, _category: &str, _message: &str) {}
}

impl ModelLog for Quiet {
    fn log(&mut self, _severity: Severity, _message: &str) {}
}

/// A fresh instance of `M` (logging off, messages dropped), set up at t = 0 without a stop
/// time, in initialization mode: set what the test needs, then `exit_initialization`.
///
/// # Panics
/// If the fresh instance refuses setup or initialization mode.
pub fn initializing<M: Fmi2Model>() -> Instance<M> {
    let mut inst = Instance::<M>::new(Environment::default(), false, Box::new(Quiet));
    inst.setup_experiment(0.0, None).expect("setup of a fresh instance");
    inst.enter_initialization().expect("initialization mode of a fresh instance");
    inst
}

/// An initialized instance of `M` with `sets` (variable name, value) set in initialization mode.
///
/// # Panics
/// If a value is refused or the initialization fails (the message says which).
pub fn ready_with<M: Fmi2Model>(sets: &[(&str, Value)]) -> Instance<M> {
    let mut inst = initializing::<M>();
    for (name, value) in sets {
        set(&mut inst, name, value.clone()).unwrap_or_else(|e| panic!("{name} = {value:?}: {e:?}"));
    }
    inst.exit_initialization().expect("initialization with the start values");
    inst
}

/// An initialized instance of `M` with its start values (no stop time, messages dropped).
pub fn ready<M: Fmi2Model>() -> Instance<M> {
    ready_with::<M>(&[])
}

/// Set `M`'s variable `name` to `value` through `fmi2Set<Type>` of its type.
///
/// # Panics
/// If `M` has no variable `name`.
pub fn set<M: Fmi2Model>(inst: &mut Instance<M>, name: &str, value: Value) -> CallResult<()> {
    let v = M::description().variable(name).unwrap_or_else(|| panic!("no variable {name}"));
    let ty = v.scalar_type().api_type();
    let call = match ty {
        ScalarType::Real => "fmi2SetReal",
        ScalarType::Boolean => "fmi2SetBoolean",
        ScalarType::String => "fmi2SetString",
        ScalarType::Integer | ScalarType::Enumeration => "fmi2SetInteger",
    };
    inst.set(call, ty, &[v.value_reference], &[value])
}

/// Set the Real `name` to `x` (`fmi2SetReal`).
///
/// # Panics
/// If the value is refused.
pub fn set_real<M: Fmi2Model>(inst: &mut Instance<M>, name: &str, x: f64) {
    inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>(name)], &[Value::Real(x)])
        .unwrap_or_else(|e| panic!("{name} = {x}: {e:?}"));
}

/// The Real `name` (`fmi2GetReal`).
///
/// # Panics
/// If it cannot be read or is not a Real.
pub fn real<M: Fmi2Model>(inst: &mut Instance<M>, name: &str) -> f64 {
    let mut out = Vec::new();
    inst.get("fmi2GetReal", ScalarType::Real, &[vr::<M>(name)], &mut out).unwrap_or_else(|e| panic!("{name}: {e:?}"));
    match out[0] {
        Value::Real(x) => x,
        ref v => panic!("{v:?}"),
    }
}

/// An initialized instance of `M` after `steps` steps of `h` with every Real input at `input`
/// (a state that holds history, not only start values).
///
/// # Panics
/// If an input refuses `input` or a step fails.
pub fn stepped<M: Fmi2Model>(input: f64, steps: usize, h: f64) -> Instance<M> {
    let mut inst = ready::<M>();
    for (name, vr) in super::real_inputs::<M>() {
        inst.set("fmi2SetReal", ScalarType::Real, &[vr], &[Value::Real(input)])
            .unwrap_or_else(|e| panic!("{name} = {input}: {e:?}"));
    }
    for k in 0..steps {
        inst.do_step(k as f64 * h, h).expect("a step with the inputs held");
    }
    inst
}
