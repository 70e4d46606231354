//! The MillingProcess adapter: the shared adapter checks, and refusals of bad displacements.

use fmi2_export::instance::{CallError, Instance};
use fmi2_export::table::checks::{ready, vr};
use fmu_milling_process::MillingProcess;
use milling_process::ProcessParams;
use model_description::{ScalarType, Value};

type M = MillingProcess;

fmi2_export::adapter_tests! {
    model: M,
    // the window must stay in [0, pi] with entry < exit
    valid: [("entry_angle", Value::Real(0.3)), ("exit_angle", Value::Real(2.0))],
    params: [{
        let mut p = ProcessParams::default();
        p.coefficients.law = milling_process::ForceLaw::Power;
        p.coefficients.exponent = 0.744;
        p.variable_pitch = true;
        p.tooth_angles[1] = 1.4;
        p
    }],
    work: Work::Fixed,
    step: 1e-5,
    states: { stepped: stepped_10_ms(), fresh: ready::<M>, seed: 0x9e37_79b9_7f4a_7c15, tries: 1000 },
}

/// An instance after 1000 steps of 10 µs with the start inputs.
fn stepped_10_ms() -> Instance<M> {
    let mut inst = ready::<M>();
    for k in 0..1000 {
        inst.do_step(k as f64 * 1e-5, 1e-5).unwrap();
    }
    inst
}

#[test]
fn a_nan_or_an_out_of_range_displacement_is_discarded_with_a_message() {
    let mut inst = ready::<M>();
    // NaN: the export layer discards the value itself, naming the variable (fmi2SetReal -> fmi2Discard)
    let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("tool_x")], &[Value::Real(f64::NAN)]).unwrap_err();
    let CallError::Discard(m) = e else { panic!("expected fmi2Discard, got {e:?}") };
    assert!(m.contains("tool_x") && m.contains("not finite"), "{m}");
    // the instance is still usable: a step runs
    inst.do_step(0.0, 1e-5).unwrap();
    // a finite but unphysical displacement reaches the model: fmi2Discard with a logged message, no step
    inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("workpiece_y")], &[Value::Real(5.0)]).unwrap();
    let e = inst.do_step(1e-5, 1e-5).unwrap_err();
    let CallError::Discard(m) = e else { panic!("expected fmi2Discard, got {e:?}") };
    assert!(m.contains("workpiece_y"), "{m}");
    // (the C boundary, fmi2-export's ffi, logs every refusal's message under logStatusDiscard /
    // logStatusError before returning the status; the messages are these)
    assert!((inst.model().unwrap().process().time() - 1e-5).abs() < 1e-20, "the refused step was taken");
}
