//! The controller FMU: the shared adapter checks, and through the instance state machine: the
//! RLS estimate and every other part of the state survive get/set and serialize/deserialize FMU
//! state bitwise; bad inputs and corrupted states are refused with a message.

use fmi2_export::instance::{CallError, Instance, Snapshot};
use fmi2_export::table::checks::{initializing, ready_with, real, reseal, set_real, vr};
use fmu_froh_mrac_controller::FrohMracController;
use froh_mrac::MracParams;
use model_description::{ScalarType, Value};

type M = FrohMracController;

const H: f64 = 60.0 / 715.0 / 4.0;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [MracParams { beta: 0.4, adapt: false, lambda: 1.0, ..Default::default() }],
    work: Work::Bound("Ts"),
    step: H,
    states: { stepped: learned(30), fresh: fresh, seed: 0x51_7cc1_b727_220a_u64, tries: 2000 },
}

fn fresh() -> Instance<M> {
    ready_with::<M>(&[("beta", Value::Real(0.4))])
}

/// A toy first-order force response to the command, so that the RLS has something to learn.
fn run(inst: &mut Instance<M>, from: usize, to: usize, force: &mut f64) {
    for j in from..to {
        set_real(inst, "F_p", *force);
        inst.do_step(j as f64 * H, H).unwrap();
        let fc = real(inst, "f_c");
        *force += 0.6 * (50.0 * fc - *force);
    }
}

/// A fresh instance after `steps` steps of [`run`] from zero force.
fn learned(steps: usize) -> Instance<M> {
    let mut inst = fresh();
    run(&mut inst, 0, steps, &mut 0.0);
    inst
}

const WATCH: [&str; 8] = ["f_c", "f_c_rate", "f_hold", "u_k", "F_m", "a_hat", "b0_hat", "b1_hat"];

fn watched(inst: &mut Instance<M>) -> Vec<u64> {
    WATCH.iter().map(|n| real(inst, n).to_bits()).collect()
}

#[test]
fn rls_estimates_and_state_survive_get_set_and_serialize_bitwise() {
    let mut a = fresh();
    let mut force = 0.0;
    run(&mut a, 0, 37, &mut force);
    let theta = a.model().unwrap().controller().theta();
    let theta0 = fresh().model().unwrap().controller().theta();
    assert!(theta.iter().zip(theta0).all(|(a, b)| (a - b).abs() > 1e-6 * b.abs()), "the RLS did not move");
    let snap = a.snapshot();
    let bytes = snap.serialize().unwrap();
    // the estimate is in the bytes
    for x in theta {
        assert!(bytes.windows(8).any(|w| w == x.to_le_bytes()), "{x} not in the serialized state");
    }
    let (f0, mut fa) = (force, force);
    run(&mut a, 37, 80, &mut fa);
    let end_a = watched(&mut a);
    let rls_a = a.model().unwrap().controller().rls().clone();
    // get/set: restore into the same instance and rerun
    a.restore(&snap);
    let mut fb = f0;
    run(&mut a, 37, 80, &mut fb);
    assert_eq!(watched(&mut a), end_a);
    assert_eq!(a.model().unwrap().controller().rls(), &rls_a);
    // serialize/deserialize into a fresh instance
    let mut c = fresh();
    c.restore(&Snapshot::<M>::deserialize(&bytes).unwrap());
    let mut fc = f0;
    run(&mut c, 37, 80, &mut fc);
    assert_eq!(watched(&mut c), end_a);
    let rls_c = c.model().unwrap().controller().rls();
    assert!(rls_c.theta.iter().zip(&rls_a.theta).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert!(rls_c.p.iter().zip(&rls_a.p).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert_eq!(fa.to_bits(), fc.to_bits());
}

#[test]
fn out_of_range_inputs_are_refused_with_a_message() {
    let mut inst = fresh();
    for x in [f64::NAN, f64::INFINITY, 2e9] {
        let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("F_p")], &[Value::Real(x)]).unwrap_err();
        let (CallError::Error(m) | CallError::Discard(m)) = e;
        assert!(m.contains("F_p"), "{m}");
    }
    // a parameter outside its range is refused before initialization ends
    let mut inst = initializing::<M>();
    assert!(inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("beta")], &[Value::Real(1.5)]).is_err());
    // β = −0.9 puts the initial model's zero outside the unit circle: the design is refused
    inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("beta")], &[Value::Real(-0.9)]).unwrap();
    let CallError::Error(m) = inst.exit_initialization().unwrap_err() else { panic!("expected fmi2Error") };
    assert!(m.contains("not stable"), "{m}");
}

#[test]
fn a_restored_state_with_a_bad_forgetting_factor_is_refused() {
    let mut inst = fresh();
    let mut force = 0.0;
    run(&mut inst, 0, 20, &mut force);
    let bytes = inst.snapshot().serialize().unwrap();
    let pat = 0.98f64.to_le_bytes();
    let hits: Vec<usize> = bytes.windows(8).enumerate().filter(|(_, w)| *w == pat).map(|(i, _)| i).collect();
    assert!(hits.len() >= 2, "{}", hits.len());
    for at in hits {
        let mut bad = bytes.clone();
        bad[at..at + 8].copy_from_slice(&1.5f64.to_le_bytes());
        reseal(&mut bad);
        match Snapshot::<M>::deserialize(&bad) {
            Err(CallError::Error(m)) => assert!(m.contains("invalid state"), "{m}"),
            other => panic!("lambda = 1.5 at byte {at} accepted: {}", other.is_ok()),
        }
    }
}
