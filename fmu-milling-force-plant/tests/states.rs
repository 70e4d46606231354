//! The plant FMU: the shared adapter checks, and through the instance state machine exact ramp
//! steps, bad inputs, restored states.

use fmi2_export::instance::{CallError, Instance, Snapshot};
use fmi2_export::table::checks::{initializing, ready, real, reseal, set_real, vr};
use fmu_milling_force_plant::MillingForcePlant;
use milling_force_plant::{ForcePlant, ForcePlantInputs, ForcePlantParams};
use model_description::{ScalarType, Value};

type M = MillingForcePlant;

const H: f64 = 0.05;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [{
        let mut p = ForcePlantParams { tau_s: 0.0, tau_c: 0.04, ..Default::default() };
        p.depth.segments = 8;
        p.depth.b[7] = 0.5;
        p
    }],
    work: Work::Fixed,
    step: H,
    states: { stepped: driven(30), fresh: ready::<M>, seed: 0x2f6b_1d3e_99aa_0c41, tries: 2000 },
}

/// 80 steps (4 s, across the first depth change) with a varying ramp.
fn drive(inst: &mut Instance<M>, from: usize, to: usize) {
    for j in from..to {
        set_real(inst, "f_c", 20.0 + 5.0 * (j as f64 * 0.3).sin());
        set_real(inst, "f_c_rate", 40.0 * (j as f64 * 0.7).cos());
        inst.do_step(j as f64 * H, H).unwrap();
    }
}

/// A fresh instance after `steps` steps of [`drive`].
fn driven(steps: usize) -> Instance<M> {
    let mut inst = ready::<M>();
    drive(&mut inst, 0, steps);
    inst
}

#[test]
fn the_fmu_steps_the_core_bitwise_and_follows_the_depth_profile() {
    let mut inst = ready::<M>();
    drive(&mut inst, 0, 80);
    let mut core = ForcePlant::new(&ForcePlantParams::default()).unwrap();
    for j in 0..80 {
        core.set_time(j as f64 * H);
        let i = ForcePlantInputs {
            feed_command: 20.0 + 5.0 * (j as f64 * 0.3).sin(),
            feed_command_rate: 40.0 * (j as f64 * 0.7).cos(),
        };
        core.step(H, &i).unwrap();
    }
    assert_eq!(real(&mut inst, "F_p").to_bits(), core.outputs().force.to_bits());
    assert_eq!(real(&mut inst, "b").to_bits(), 4.0f64.to_bits());
    assert!((real(&mut inst, "K_p") - 4.0 * 25.174825).abs() < 1e-4);
}

#[test]
fn state_survives_serialize_bitwise_and_corruptions_are_refused() {
    let mut a = ready::<M>();
    drive(&mut a, 0, 30);
    let bytes = a.snapshot().serialize().unwrap();
    drive(&mut a, 30, 80);
    let mut b = ready::<M>();
    b.restore(&Snapshot::<M>::deserialize(&bytes).unwrap());
    drive(&mut b, 30, 80);
    for n in ["F_p", "f_a"] {
        assert_eq!(real(&mut a, n).to_bits(), real(&mut b, n).to_bits(), "{n}");
    }
    // τ_c = 60/(715·4) appears in the parameters and the values store: a negative copy is refused
    let pat = (60.0f64 / (715.0 * 4.0)).to_le_bytes();
    let hits: Vec<usize> = bytes.windows(8).enumerate().filter(|(_, w)| *w == pat).map(|(i, _)| i).collect();
    assert!(hits.len() >= 2);
    for at in hits {
        let mut bad = bytes.clone();
        bad[at..at + 8].copy_from_slice(&(-1.0f64).to_le_bytes());
        reseal(&mut bad);
        assert!(matches!(Snapshot::<M>::deserialize(&bad), Err(CallError::Error(m)) if m.contains("invalid state")));
    }
}

#[test]
fn non_finite_or_out_of_range_commands_are_refused_with_a_message() {
    let mut inst = ready::<M>();
    for x in [f64::NAN, f64::NEG_INFINITY, 1e7] {
        let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("f_c")], &[Value::Real(x)]).unwrap_err();
        let (CallError::Error(m) | CallError::Discard(m)) = e;
        assert!(m.contains("f_c"), "{m}");
    }
    // decreasing segment times are refused at initialization
    let mut inst = initializing::<M>();
    set_real(&mut inst, "depth.t3", 1.0);
    let CallError::Error(m) = inst.exit_initialization().unwrap_err() else { panic!("expected fmi2Error") };
    assert!(m.contains("increase"), "{m}");
}
