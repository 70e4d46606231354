//! Regression tests of the plant FMU against hostile calls: a bounded amount of work per
//! `fmi2DoStep`, and bounded memory for every input in its declared range.

use fmi2_export::instance::{CallError, Instance, LogLevel, LogSink};
use fmi2_export::{Environment, Fmi2Model, MAX_INTERNAL_STEPS_PER_CALL};
use fmu_plant::MillingPlant;
use model_description::{ScalarType, Value};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// Collects the messages an instance sends to its host.
#[derive(Clone, Default)]
struct Log(Arc<Mutex<Vec<String>>>);
impl LogSink for Log {
    fn emit(&mut self, _level: LogLevel, _category: &str, message: &str) {
        self.0.lock().unwrap().push(message.to_string());
    }
}

fn vr(name: &str) -> u32 {
    MillingPlant::description().variable(name).unwrap_or_else(|| panic!("no variable {name}")).value_reference
}

/// An initialized plant instance (no stop time) with `reals` set before initialization.
fn ready(reals: &[(&str, f64)]) -> (Instance<MillingPlant>, Log) {
    let log = Log::default();
    let mut inst = Instance::<MillingPlant>::new(Environment::default(), false, Box::new(log.clone()));
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization().unwrap();
    for (name, x) in reals {
        inst.set("fmi2SetReal", ScalarType::Real, &[vr(name)], &[Value::Real(*x)]).unwrap();
    }
    inst.exit_initialization().unwrap();
    (inst, log)
}

#[test]
fn a_huge_step_without_stop_time_is_refused_at_once_not_run() {
    let (mut inst, _) = ready(&[]);
    let t = Instant::now();
    let err = inst.do_step(0.0, 1e6).unwrap_err();
    assert!(t.elapsed().as_secs_f64() < 1.0, "refused after {:?}", t.elapsed());
    let CallError::Error(m) = err else { panic!("expected fmi2Error, got {err:?}") };
    assert!(m.contains("internal steps") && m.contains("limit"), "{m}");
    // an ordinary step is still accepted
    let (mut inst, _) = ready(&[]);
    assert!(inst.do_step(0.0, 0.1).is_ok());
}

#[test]
fn the_bound_follows_the_internal_step_parameter() {
    // at a 0.1 ms grid a 100 s step is 1e6 internal steps: allowed; 1e4 s is 1e8: refused
    let (inst, _) = ready(&[("internal_step", 1e-4)]);
    let m = inst.model().unwrap();
    assert!(m.internal_steps(100.0) <= MAX_INTERNAL_STEPS_PER_CALL);
    assert!(m.internal_steps(1e4) > MAX_INTERNAL_STEPS_PER_CALL);
}
