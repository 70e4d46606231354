//! The controller through the `Fmi2Model` trait (what the C ABI wraps): variable table,
//! timing, frequency response at the communication points, FMU state.

#![allow(clippy::needless_range_loop)]

use chatter_control::{Controller, ControllerParams, FractionalMethod, Structure};
use fmi2_export::model_kit::Choice;
use fmi2_export::table::checks::{Quiet, vr};
use fmi2_export::{Environment, Fmi2Model, Values};
use fmu_controller::ChatterController;
use num_complex::Complex64;
use std::f64::consts::PI;

type M = ChatterController;

fn values(structure: Structure, method: FractionalMethod) -> Values {
    let mut v = Values::from_description(ChatterController::description());
    v.set_integer(vr::<M>("structure"), structure.index());
    v.set_integer(vr::<M>("fractional.method"), if method == FractionalMethod::Oustaloup { 2 } else { 1 });
    v
}

/// Least-squares phasor of `y` at ω with an offset term, samples at `t0 + k·ts`.
fn phasor(y: &[f64], t0: f64, ts: f64, w: f64) -> Complex64 {
    let mut a = [[0.0f64; 3]; 3];
    let mut b = [0.0f64; 3];
    for (k, &yk) in y.iter().enumerate() {
        let t = t0 + ts * k as f64;
        let f = [(w * t).cos(), (w * t).sin(), 1.0];
        for i in 0..3 {
            b[i] += f[i] * yk;
            for j in 0..3 {
                a[i][j] += f[i] * f[j];
            }
        }
    }
    // Gaussian elimination (well conditioned: many periods)
    for i in 0..3 {
        for r in i + 1..3 {
            let f = a[r][i] / a[i][i];
            for c in i..3 {
                a[r][c] -= f * a[i][c];
            }
            b[r] -= f * b[i];
        }
    }
    let mut x = [0.0; 3];
    for i in (0..3).rev() {
        x[i] = (b[i] - (i + 1..3).map(|c| a[i][c] * x[c]).sum::<f64>()) / a[i][i];
    }
    Complex64::new(x[0], -x[1])
}

#[test]
fn variable_table_follows_the_contract() {
    let md = ChatterController::description();
    for name in [
        "y",
        "r",
        "u",
        "e",
        "z1",
        "z2",
        "z3",
        "saturated",
        "structure",
        "u_max",
        "Ts",
        "pid.kp",
        "pid.ki",
        "pid.kd",
        "fopid.kp",
        "fopid.ki",
        "fopid.kd",
        "fopid.lambda",
        "fopid.mu",
        "adrc.kp",
        "adrc.ki",
        "adrc.kd",
        "adrc.lambda",
        "adrc.mu",
        "adrc.omega_o",
        "adrc.b0",
        "adrc.td_r",
        "adrc.td_h",
        "fractional.method",
        "fractional.memory_length",
        "fractional.omega_b",
        "fractional.omega_h",
        "fractional.order",
    ] {
        assert!(md.variable(name).is_some(), "missing {name}");
    }
    let items: Vec<String> = md.enumeration_items("Structure").into_iter().map(|(n, _)| n).collect();
    assert_eq!(items, ["off", "pid", "fopid", "adrc_fopid"]);
    let items: Vec<String> = md.enumeration_items("FractionalMethod").into_iter().map(|(n, _)| n).collect();
    assert_eq!(items, ["grunwald_letnikov", "oustaloup"]);
    for (n, u) in
        [("y", "m"), ("r", "m"), ("u", "N"), ("e", "m"), ("z2", "m/s"), ("z3", "m/s2"), ("u_max", "N"), ("Ts", "s")]
    {
        assert_eq!(md.variable(n).unwrap().unit(), Some(u), "{n}");
    }
    // no direct feedthrough: every output declares an empty dependency list
    let xml = md.to_xml().unwrap();
    let outputs = xml.split("<Outputs>").nth(1).unwrap().split("</Outputs>").next().unwrap();
    assert_eq!(outputs.matches("<Unknown").count(), 6);
    assert_eq!(outputs.matches("dependencies=\"\"").count(), 6, "{outputs}");
    // start values come from the one default block
    let d = ControllerParams::default();
    let v = Values::from_description(md);
    assert!((v.real(vr::<M>("fopid.kp")) - d.fopid.kp).abs() < 1e-12);
    assert_eq!(v.integer(vr::<M>("fractional.memory_length")) as usize, d.fractional.memory_length);
}

/// Sine input through `do_step(h = Ts)` at 5 frequencies in 100..200 Hz: the response from
/// `y(t_k)` to `u(t_{k+1})` equals `sampled_response` (1e-5) and `frequency_response`
/// within 1 % and 1° (the remaining difference is the hold, half a sample).
#[test]
fn frequency_response_through_the_fmi_calls() {
    for s in [Structure::Pid, Structure::Fopid, Structure::AdrcFopid] {
        for m in [FractionalMethod::GrunwaldLetnikov, FractionalMethod::Oustaloup] {
            let mut v = values(s, m);
            let mut model = ChatterController::initialize(&v, &Environment::default()).unwrap();
            let p = *model.params();
            let c = Controller::new(&p).unwrap();
            for f in [100.0, 125.0, 143.0, 170.0, 200.0] {
                let w = 2.0 * PI * f;
                let mut model = model.clone();
                let (n, keep) = (60_000usize, 10_000usize);
                let (mut ys, mut us) = (Vec::new(), Vec::new());
                let amp = 1e-7;
                for k in 0..n {
                    let t = k as f64 * p.ts;
                    let y = amp * (w * t).sin();
                    v.set_real(vr::<M>("y"), y);
                    model.do_step(&mut v, t, p.ts, &mut Quiet).unwrap();
                    assert!(!v.boolean(vr::<M>("saturated")));
                    if k >= n - keep {
                        ys.push(y);
                        us.push(v.real(vr::<M>("u"))); // value at t + Ts
                    }
                }
                // First differences of both signals (same transfer function): a slowly decaying
                // start-up transient of the integrators becomes a constant the fit absorbs.
                let diff = |x: &[f64]| x.windows(2).map(|p| p[1] - p[0]).collect::<Vec<_>>();
                let t0 = (n - keep + 1) as f64 * p.ts;
                let got = phasor(&diff(&us), t0 + p.ts, p.ts, w) / phasor(&diff(&ys), t0, p.ts, w);
                let exact = c.sampled_response(w);
                assert!((got - exact).norm() / exact.norm() < 1e-5, "{s:?}/{m:?} {f} Hz: {got} vs {exact}");
                let h = p.frequency_response(w);
                let mag = (got.norm() / h.norm() - 1.0).abs();
                let ph = (got / h).arg().to_degrees().abs();
                eprintln!("{s:?}/{m:?} {f} Hz: FMU vs frequency_response: {mag:.2e} rel, {ph:.3} deg");
                assert!(mag < 0.01 && ph < 1.0, "{s:?}/{m:?} {f} Hz: {mag} rel, {ph} deg");
            }
            model.do_step(&mut v, 0.0, p.ts, &mut Quiet).unwrap();
        }
    }
}

/// A step of 10·Ts runs 10 samples with the input held: same outputs as 10 steps of Ts.
/// A step that is not a multiple runs the samples inside it.
#[test]
fn long_steps_hold_the_input() {
    let mut v1 = values(Structure::AdrcFopid, FractionalMethod::GrunwaldLetnikov);
    let mut v2 = v1.clone();
    let mut a = ChatterController::initialize(&v1, &Environment::default()).unwrap();
    let mut b = a.clone();
    let ts = a.params().ts;
    let h = 10.0 * ts;
    for j in 0..50 {
        let y = 1e-7 * (j as f64 * 0.7).sin();
        v1.set_real(vr::<M>("y"), y);
        v2.set_real(vr::<M>("y"), y);
        a.do_step(&mut v1, j as f64 * h, h, &mut Quiet).unwrap();
        for i in 0..10 {
            b.do_step(&mut v2, j as f64 * h + i as f64 * ts, ts, &mut Quiet).unwrap();
        }
        assert!((v1.real(vr::<M>("u")) - v2.real(vr::<M>("u"))).abs() <= 1e-12 * v2.real(vr::<M>("u")).abs().max(1e-9));
    }
    // 2.5 Ts steps: samples at 0, Ts, 2Ts in the first, 3Ts, 4Ts in the second
    let mut v = values(Structure::Pid, FractionalMethod::GrunwaldLetnikov);
    let mut m = ChatterController::initialize(&v, &Environment::default()).unwrap();
    let mut c = Controller::new(m.params()).unwrap();
    v.set_real(vr::<M>("y"), 1e-6);
    m.do_step(&mut v, 0.0, 2.5 * ts, &mut Quiet).unwrap();
    let mut u = 0.0;
    for _ in 0..3 {
        u = c.sample(1e-6, 0.0).u;
    }
    assert!((v.real(vr::<M>("u")) - u).abs() < 1e-12);
}

/// A clock that jumps ahead of the sample index (a restored or restarted instance) continues
/// from the first sample at or after the new time and does not catch up on the skipped ones:
/// steps at 0 and 5 Ts take two samples, as steps at 0 and Ts do; a step just after the jump
/// target (rounding) still starts there.
#[test]
fn a_jump_in_time_is_not_caught_up() {
    let run = |t1: f64| {
        let mut v = values(Structure::Pid, FractionalMethod::GrunwaldLetnikov);
        let mut m = ChatterController::initialize(&v, &Environment::default()).unwrap();
        let ts = m.params().ts;
        v.set_real(vr::<M>("y"), 1e-6);
        m.do_step(&mut v, 0.0, ts, &mut Quiet).unwrap();
        m.do_step(&mut v, t1 * ts, ts, &mut Quiet).unwrap();
        v.real(vr::<M>("u"))
    };
    let v = values(Structure::Pid, FractionalMethod::GrunwaldLetnikov);
    let mut c = Controller::new(ChatterController::initialize(&v, &Environment::default()).unwrap().params()).unwrap();
    let two = (0..2).map(|_| c.sample(1e-6, 0.0).u).last().unwrap();
    let five = (0..3).map(|_| c.sample(1e-6, 0.0).u).last().unwrap();
    assert_ne!(two.to_bits(), five.to_bits(), "the PID command must tell two samples from five");
    for t1 in [1.0, 5.0, 5.0 + 1e-9, 37.0] {
        assert_eq!(run(t1).to_bits(), two.to_bits(), "jump to {t1} Ts");
    }
}

/// The whole state round-trips through serde (FMU state) and continues identically.
#[test]
fn fmu_state_round_trip() {
    for m in [FractionalMethod::GrunwaldLetnikov, FractionalMethod::Oustaloup] {
        let mut v = values(Structure::AdrcFopid, m);
        let mut a = ChatterController::initialize(&v, &Environment::default()).unwrap();
        let ts = a.params().ts;
        for k in 0..500 {
            v.set_real(vr::<M>("y"), 1e-7 * (k as f64 * 0.01).sin());
            a.do_step(&mut v, k as f64 * ts, ts, &mut Quiet).unwrap();
        }
        let bytes = postcard::to_allocvec(&a).unwrap();
        let mut b: ChatterController = postcard::from_bytes(&bytes).unwrap();
        let mut v2 = v.clone();
        for k in 500..1500 {
            let y = 1e-7 * (k as f64 * 0.01).sin();
            v.set_real(vr::<M>("y"), y);
            v2.set_real(vr::<M>("y"), y);
            a.do_step(&mut v, k as f64 * ts, ts, &mut Quiet).unwrap();
            b.do_step(&mut v2, k as f64 * ts, ts, &mut Quiet).unwrap();
            assert_eq!(v.real(vr::<M>("u")).to_bits(), v2.real(vr::<M>("u")).to_bits());
        }
    }
}

#[test]
fn invalid_parameters_are_refused_with_a_message() {
    let mut v = values(Structure::Fopid, FractionalMethod::Oustaloup);
    v.set_real(vr::<M>("fractional.omega_h"), 1.0);
    let err = ChatterController::initialize(&v, &Environment::default()).err().unwrap();
    assert!(err.contains("fractional.omega_h"), "{err}");
}

#[test]
fn off_gives_zero_command() {
    let mut v = values(Structure::Off, FractionalMethod::GrunwaldLetnikov);
    let mut m = ChatterController::initialize(&v, &Environment::default()).unwrap();
    v.set_real(vr::<M>("y"), 1e-3);
    m.do_step(&mut v, 0.0, 1e-3, &mut Quiet).unwrap();
    assert!(v.real(vr::<M>("u")).abs() < f64::MIN_POSITIVE && !v.boolean(vr::<M>("saturated")));
    assert!((v.real(vr::<M>("e")) + 1e-3).abs() < 1e-15);
}

/// `parameter_assignments` names the FMU's own variables and, applied to the default start
/// values, reproduces the Table 2 preset exactly (what packaging writes into
/// `ClosedLoopTable2.ssp`); the defaults are the tuned gains, not Table 2.
#[test]
fn parameter_assignments_reproduce_a_preset_through_the_variable_table() {
    use fmi2_export::model_description::Value;
    use fmu_controller::parameter_assignments;
    let md = ChatterController::description();
    let table2 = ControllerParams::paper_table2();
    assert_ne!(ControllerParams::default(), table2, "the shipped defaults are the PSO-tuned gains");
    assert_eq!(ControllerParams::default(), ControllerParams::tuned());
    let mut v = Values::from_description(md);
    let pairs = parameter_assignments(&table2);
    assert!(pairs.len() >= 25, "{pairs:?}");
    for (name, value) in &pairs {
        let var = md.variable(name).unwrap_or_else(|| panic!("{name} is not a variable of the FMU"));
        match value {
            Value::Real(x) => v.set_real(var.value_reference, *x),
            Value::Integer(i) => v.set_integer(var.value_reference, *i),
            Value::Boolean(b) => v.set_boolean(var.value_reference, *b),
            Value::String(s) => v.set_string(var.value_reference, s),
        }
    }
    let m = ChatterController::initialize(&v, &Environment::default()).unwrap();
    assert_eq!(*m.params(), table2);
}

#[test]
fn a_huge_step_costs_more_than_the_layers_work_bound() {
    let v = values(Structure::Pid, FractionalMethod::GrunwaldLetnikov);
    let c = ChatterController::initialize(&v, &Environment::default()).unwrap();
    assert!(c.internal_steps(1e6) > fmi2_export::MAX_INTERNAL_STEPS_PER_CALL);
    // a sample counts SAMPLE_COST = 100 internal steps: at Ts = 10 us a call takes at most
    // 1e5 samples, 0.99 s (1 s was accepted before issue 31)
    assert!(c.internal_steps(0.99) <= fmi2_export::MAX_INTERNAL_STEPS_PER_CALL);
    assert!(c.internal_steps(1.0) > fmi2_export::MAX_INTERNAL_STEPS_PER_CALL);
}
