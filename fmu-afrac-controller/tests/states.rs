//! The controller FMU: the shared adapter checks, and through the instance state machine:
//! bitwise equal to the core, the convolution memory and the fractional integrators survive
//! get/set and serialize/deserialize FMU state bitwise, bad inputs and corrupted states are
//! refused with a message.

use afrac_control::{Afrac, AfracParams, Schedule};
use fmi2_export::instance::{CallError, Instance, Snapshot};
use fmi2_export::table::checks::{self, initializing, ready_with, real, set_real, vr};
use fmu_afrac_controller::AfracController;
use model_description::{ScalarType, Value};
use std::f64::consts::PI;

type M = AfracController;

const TAU: f64 = 1e-4;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [AfracParams { schedule: Schedule::fixed(1.5), bumpless: true, depth: 4.5, ..Default::default() }],
    work: Work::Bound("Ts"),
    step: TAU,
    states: { stepped: driven(700), fresh: fresh, seed: 0xafac_0001_5eed_u64, tries: 400 },
}

/// An initialized instance; `bumpless` set through the API (the switches of Table 5 at 0.6935 s
/// and later are inside the runs below when `t1` is moved to 0.05 s).
fn fresh() -> Instance<M> {
    ready_with::<M>(&[("t1", Value::Real(0.05)), ("bumpless", Value::Boolean(true))])
}

/// A fresh instance after `steps` steps of [`drive`].
fn driven(steps: usize) -> Instance<M> {
    let mut inst = fresh();
    drive(&mut inst, 0, steps);
    inst
}

fn params() -> AfracParams {
    let mut p = AfracParams { bumpless: true, ..Default::default() };
    p.schedule.times[0] = 0.05;
    p
}

/// A chatter-like measurement: 88 Hz, growing.
fn measurement(k: usize) -> (f64, f64) {
    let t = k as f64 * TAU;
    let (w, g) = (2.0 * PI * 88.0, 3.0);
    let a = 1e-4 * (g * t).exp();
    (a * (w * t).sin(), a * (g * (w * t).sin() + w * (w * t).cos()))
}

fn drive(inst: &mut Instance<M>, from: usize, to: usize) {
    for k in from..to {
        let (x, v) = measurement(k);
        set_real(inst, "x", x);
        set_real(inst, "v", v);
        inst.do_step(k as f64 * TAU, TAU).unwrap();
    }
}

const WATCH: [&str; 8] = ["spindle_speed", "feed", "beta", "eps1", "eps2", "h", "delta_feed", "G"];

fn watched(inst: &mut Instance<M>) -> Vec<u64> {
    WATCH.iter().map(|n| real(inst, n).to_bits()).collect()
}

#[test]
fn the_fmu_samples_the_core_bitwise() {
    let mut inst = fresh();
    let mut core = Afrac::new(&params()).unwrap();
    for k in 0..1500 {
        drive(&mut inst, k, k + 1);
        let (x, v) = measurement(k);
        let o = core.sample(x, v).unwrap();
        let c = [o.spindle_speed, o.feed, o.beta, o.eps1, o.eps2, o.h, o.delta_feed, o.g];
        assert_eq!(watched(&mut inst), c.map(f64::to_bits).to_vec(), "sample {k}");
    }
    // the adaptation moved the speed and the schedule switched
    let (n, b) = (real(&mut inst, "spindle_speed"), real(&mut inst, "beta"));
    assert!((n - 450.0).abs() > 1.0, "{n}");
    assert_eq!(b.to_bits(), 1.75f64.to_bits());
}

#[test]
fn memory_and_fractional_integrators_survive_get_set_and_serialize_bitwise() {
    let mut a = fresh();
    drive(&mut a, 0, 600); // across the switch at 0.05 s: two integrator banks hold state
    let snap = a.snapshot();
    let bytes = snap.serialize().unwrap();
    drive(&mut a, 600, 1500);
    let end = watched(&mut a);
    // get/set into the same instance
    a.restore(&snap);
    drive(&mut a, 600, 1500);
    assert_eq!(watched(&mut a), end);
    // serialize/deserialize into a fresh instance
    let mut b = fresh();
    b.restore(&Snapshot::<M>::deserialize(&bytes).unwrap());
    drive(&mut b, 600, 1500);
    assert_eq!(watched(&mut b), end);
    // a fresh instance that did not get the state goes elsewhere: the state carries the memory
    let mut c = fresh();
    for (j, k) in (600..1500).enumerate() {
        let (x, v) = measurement(k);
        set_real(&mut c, "x", x);
        set_real(&mut c, "v", v);
        c.do_step(j as f64 * TAU, TAU).unwrap();
    }
    assert_ne!(watched(&mut c), end);
}

#[test]
fn several_samples_per_step_and_steps_without_a_sample() {
    // h = 10 τ: ten samples per step with the inputs of the step start, as the core fed the same
    let mut inst = fresh();
    let mut core = Afrac::new(&params()).unwrap();
    for j in 0..50 {
        let (x, v) = measurement(10 * j);
        set_real(&mut inst, "x", x);
        set_real(&mut inst, "v", v);
        inst.do_step(j as f64 * 10.0 * TAU, 10.0 * TAU).unwrap();
        for _ in 0..10 {
            core.sample(x, v).unwrap();
        }
    }
    assert_eq!(real(&mut inst, "h").to_bits(), core.outputs().h.to_bits());
    // h = τ/2: the sample at t_k is taken in the first half step, the second holds
    let mut inst = fresh();
    drive(&mut inst, 0, 300);
    let held = watched(&mut inst);
    let n = inst.model().unwrap().controller().next_sample_time();
    set_real(&mut inst, "x", 1e-3);
    inst.do_step(300.0 * TAU, 0.5 * TAU).unwrap();
    let first = watched(&mut inst);
    assert_ne!(first, held);
    inst.do_step(300.5 * TAU, 0.5 * TAU).unwrap();
    assert_eq!(watched(&mut inst), first);
    assert!(inst.model().unwrap().controller().next_sample_time() > n);
}

#[test]
fn bad_inputs_are_refused_and_corrupted_states_never_panic() {
    let mut inst = fresh();
    for x in [f64::NAN, f64::INFINITY, 2e5] {
        let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("x")], &[Value::Real(x)]).unwrap_err();
        let (CallError::Error(m) | CallError::Discard(m)) = e;
        assert!(m.contains('x'), "{m}");
    }
    // a reference speed at which the reference model is unstable: refused at initialization
    let mut bad = initializing::<M>();
    set_real(&mut bad, "reference_speed", 450.0);
    let CallError::Error(m) = bad.exit_initialization().unwrap_err() else { panic!("expected fmi2Error") };
    assert!(m.contains("design"), "{m}");
    // (the state after 700 steps of `drive`: the shared checks; here after constant inputs)
    let (refused, loaded) = checks::corrupted_states_after_steps::<M>(1e-5, 300, TAU, 7, 200);
    println!("after constant inputs: {refused} refused, {loaded} loaded");
}
