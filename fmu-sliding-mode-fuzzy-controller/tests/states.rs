//! The controller FMU: the shared adapter checks, and through the instance state machine: the
//! learned fuzzy weights and every other part of the state survive get/set and
//! serialize/deserialize FMU state bitwise; bad inputs and corrupted states are refused with a
//! message.

use fmi2_export::instance::{CallError, Instance, Snapshot};
use fmi2_export::table::checks::{initializing, ready_with, real, set_real, vr};
use fmu_sliding_mode_fuzzy_controller::SlidingModeFuzzyController;
use model_description::{ScalarType, Value};
use sliding_fuzzy_control::controller::Compensator;
use sliding_fuzzy_control::{ControlMode, SlidingFuzzyParams, ToolInputs, ToolParams, ToolPlant};

type M = SlidingModeFuzzyController;

const H: f64 = 1e-4;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [SlidingFuzzyParams {
        mode: ControlMode::Dpid,
        karnik_mendel: true,
        pid_error_scale: 1.0,
        ..Default::default()
    }],
    work: Work::Bound("Ts"),
    step: H,
    states: { stepped: closed_loop(50), fresh: fresh, seed: 0x5eed_0003_u64, tries: 2000 },
}

/// A fresh instance in mode `mode` (enumeration index) with Karnik–Mendel and the computation
/// delay on or off.
fn fresh_with(mode: i32, km: bool, delay: bool) -> Instance<M> {
    ready_with::<M>(&[
        ("mode", Value::Integer(mode)),
        ("karnik_mendel", Value::Boolean(km)),
        ("computation_delay", Value::Boolean(delay)),
    ])
}

fn fresh() -> Instance<M> {
    fresh_with(5, false, false) // dsmc_t2
}

/// A fresh instance after `steps` steps of [`run`] with the seed's tool.
fn closed_loop(steps: usize) -> Instance<M> {
    let mut inst = fresh();
    run(&mut inst, &mut plant(), 0, steps);
    inst
}

/// The seed's tool (forced, cutting) closes the loop around the FMU.
fn run(inst: &mut Instance<M>, plant: &mut ToolPlant, from: usize, to: usize) {
    let xs = plant.static_deflection();
    for j in from..to {
        let o = plant.outputs();
        let vals = [o.x - xs[0], o.y - xs[1], o.vx, o.vy].map(Value::Real);
        inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("x"), vr::<M>("y"), vr::<M>("vx"), vr::<M>("vy")], &vals)
            .unwrap();
        inst.do_step(j as f64 * H, H).unwrap();
        let u = ToolInputs { ux: real(inst, "u_x"), uy: real(inst, "u_y") };
        plant.step(H, &u).unwrap();
    }
}

fn plant() -> ToolPlant {
    ToolPlant::new(&ToolParams { forcing_amplitude: [2.6, 25.0], ..Default::default() }).unwrap()
}

const WATCH: [&str; 10] = ["u_x", "u_y", "s_x", "s_y", "j_hat_x", "j_hat_y", "h_hat_x", "h_hat_y", "e_m_x", "e_m_y"];

fn watched(inst: &mut Instance<M>) -> Vec<u64> {
    WATCH.iter().map(|n| real(inst, n).to_bits()).collect()
}

fn weights(inst: &Instance<M>) -> Vec<f64> {
    let c = inst.model().unwrap().controller();
    let mut w = Vec::new();
    for a in 0..2 {
        match c.channel(a).compensator() {
            Compensator::T2(j, h) => w.extend(j.wl.iter().chain(&j.wr).chain(&h.wl).chain(&h.wr)),
            Compensator::T1(j, h) => w.extend(j.w.iter().chain(&h.w)),
            Compensator::None => {}
        }
    }
    w
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn fuzzy_weights_and_state_survive_get_set_and_serialize_bitwise() {
    // with the computation delay the command on its way is part of the state too
    for (mode, km, delay) in [(5, false, false), (5, true, false), (4, false, false), (5, false, true)] {
        let mut a = fresh_with(mode, km, delay);
        let mut pa = plant();
        run(&mut a, &mut pa, 0, 370);
        let w = weights(&a);
        assert!(!w.is_empty() && w.iter().any(|x| *x != 0.0), "the weights did not learn");
        let snap = a.snapshot();
        let bytes = snap.serialize().unwrap();
        for x in w.iter().filter(|x| **x != 0.0).take(8) {
            assert!(bytes.windows(8).any(|b| b == x.to_le_bytes()), "{x} not in the serialized state");
        }
        let pb0 = pa.clone();
        run(&mut a, &mut pa, 370, 800);
        let (end, w_end) = (watched(&mut a), bits(&weights(&a)));
        assert_ne!(bits(&w), w_end, "learning continued");
        // get/set FMU state into the same instance
        a.restore(&snap);
        let mut pb = pb0.clone();
        run(&mut a, &mut pb, 370, 800);
        assert_eq!(watched(&mut a), end);
        assert_eq!(bits(&weights(&a)), w_end);
        // serialize / deserialize into a fresh instance
        let mut c = fresh_with(mode, km, delay);
        c.restore(&Snapshot::<M>::deserialize(&bytes).unwrap());
        let mut pc = pb0.clone();
        run(&mut c, &mut pc, 370, 800);
        assert_eq!(watched(&mut c), end);
        assert_eq!(bits(&weights(&c)), w_end);
        assert_eq!(pc.outputs().x.to_bits(), pa.outputs().x.to_bits());
    }
}

#[test]
fn out_of_range_inputs_are_refused_with_a_message() {
    let mut inst = fresh();
    for x in [f64::NAN, f64::INFINITY, 2.0] {
        let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("x")], &[Value::Real(x)]).unwrap_err();
        let (CallError::Error(m) | CallError::Discard(m)) = e;
        assert!(m.contains('x'), "{m}");
    }
    // an unstable sliding surface is refused at the end of initialization
    let mut inst = initializing::<M>();
    set_real(&mut inst, "k2", -0.9);
    set_real(&mut inst, "k1", 1.5);
    let CallError::Error(m) = inst.exit_initialization().unwrap_err() else { panic!("expected fmi2Error") };
    assert!(m.contains("unit circle"), "{m}");
}
