//! The controller's shared adapter checks; restored FMU states of the controller are
//! validated: a corrupted sample period, buffer or gain is `fmi2Error` with a message, never a
//! hang or a panic on the next step.

use chatter_control::ControllerParams;
use fmi2_export::instance::{CallError, Instance, Snapshot};
use fmi2_export::table::checks::{ready_with, reseal, set_real};
use fmu_controller::ChatterController;
use model_description::Value;

type M = ChatterController;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [ControllerParams::paper_table2()],
    work: Work::Bound("Ts"),
    step: 1e-4,
    states: { stepped: stepped(), fresh: stepped, seed: 0x9e37_79b9_7f4a_7c15_u64, tries: 2000 },
}

/// An ADRC-FOPID (Grünwald–Letnikov) instance after 50 steps with a moving input.
fn stepped() -> Instance<M> {
    let mut inst = ready_with::<M>(&[("structure", Value::Integer(3))]);
    for k in 0..50 {
        set_real(&mut inst, "y", 1e-5 * (k as f64 * 0.3).sin());
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
