//! Restored FMU states of the controller are validated: a corrupted sample period, buffer or
//! gain is `fmi2Error` with a message, never a hang or a panic on the next step.

use fmi2_export::instance::{CallError, Instance, LogLevel, LogSink, Snapshot};
use fmi2_export::table::checks::{self, reseal};
use fmi2_export::{Environment, Fmi2Model};
use fmu_controller::ChatterController;
use model_description::{ScalarType, Value};

struct NoLog;
impl LogSink for NoLog {
    fn emit(&mut self, _level: LogLevel, _category: &str, _message: &str) {}
}

fn vr(name: &str) -> u32 {
    ChatterController::description().variable(name).unwrap().value_reference
}

/// An ADRC-FOPID (Grünwald–Letnikov) instance after 50 steps with a moving input.
fn stepped() -> Instance<ChatterController> {
    let mut inst = Instance::<ChatterController>::new(Environment::default(), false, Box::new(NoLog));
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization().unwrap();
    inst.set("fmi2SetInteger", ScalarType::Integer, &[vr("structure")], &[Value::Integer(3)]).unwrap();
    inst.exit_initialization().unwrap();
    for k in 0..50 {
        let y = 1e-5 * (k as f64 * 0.3).sin();
        inst.set("fmi2SetReal", ScalarType::Real, &[vr("y")], &[Value::Real(y)]).unwrap();
        inst.do_step(k as f64 * 1e-4, 1e-4).unwrap();
    }
    inst
}

#[test]
fn a_valid_state_loads_and_a_zero_sample_period_is_refused() {
    let bytes = stepped().snapshot().serialize().unwrap();
    assert!(Snapshot::<ChatterController>::deserialize(&bytes).is_ok());
    // before: ts = 0 in the adapter's clock made the next fmi2DoStep loop forever
    let pat = 1e-5f64.to_le_bytes();
    let hits: Vec<usize> = bytes.windows(8).enumerate().filter(|(_, w)| *w == pat).map(|(i, _)| i).collect();
    assert!(hits.len() >= 3, "{}", hits.len());
    for at in hits {
        let mut bad = bytes.clone();
        bad[at..at + 8].copy_from_slice(&0.0f64.to_le_bytes());
        reseal(&mut bad);
        match Snapshot::<ChatterController>::deserialize(&bad) {
            Err(CallError::Error(m)) => assert!(m.contains("invalid state"), "{m}"),
            other => panic!("ts = 0 at byte {at} accepted: {}", other.is_ok()),
        }
    }
}

#[test]
fn randomly_corrupted_resealed_states_never_panic_or_hang() {
    let (refused, loaded) = checks::corrupted_states_never_panic_or_hang::<ChatterController>(
        &stepped().snapshot().serialize().unwrap(),
        0x9e37_79b9_7f4a_7c15_u64,
        2000,
        stepped,
        1e-4,
    );
    println!("random corruptions: {refused} refused, {loaded} loaded and stepped without panic");
}
