//! Unit tests of the controller core.

use super::*;
use std::f64::consts::PI;

/// A second-order MIMO controller: a lightly damped resonance on input 1 → both outputs, a
/// direct gain 2 × 2.
fn second_order() -> LinearControlParams {
    let mut p = LinearControlParams { n_c: 2, delay_from_speed: false, delay: 3e-4, ..Default::default() };
    let (w0, z) = (2.0 * PI * 800.0, 0.1);
    p.ac[0] = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    p.ac[1] = [-w0 * w0, -2.0 * z * w0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    p.bc[1] = [w0 * w0, 0.3 * w0 * w0];
    p.cc[0][0] = 1000.0;
    p.cc[1][0] = -400.0;
    p.cc[1][1] = 0.2;
    p.dc = [[50.0, -20.0], [10.0, 30.0]];
    p
}

/// Drive input `j` with a sine and fit the steady output `i` over whole periods.
fn measured(p: &LinearControlParams, freq: f64, h: f64, j: usize) -> [Complex64; 2] {
    let mut c = LinearController::new(p).unwrap();
    let w = 2.0 * PI * freq;
    let per = 1.0 / freq;
    let settle = (0.03 / per).ceil() * per;
    let n_fit = (20.0 * per / h).round() as usize;
    let n_set = (settle / h).round() as usize;
    let mut acc = [(0.0, 0.0); 2];
    let (mut ss, mut cc) = (0.0, 0.0);
    for k in 0..n_set + n_fit {
        let t = k as f64 * h;
        let mut u = ControlInputs { v: [0.0; 2], spindle_speed: 0.0 };
        u.v[j] = (w * t).sin();
        c.step(t, h, &u).unwrap();
        if k >= n_set {
            // the output of the step is F(t_k) (module docs)
            let (s, co) = (w * t).sin_cos();
            for (i, a) in acc.iter_mut().enumerate() {
                a.0 += c.outputs().force[i] * s;
                a.1 += c.outputs().force[i] * co;
            }
            ss += s * s;
            cc += co * co;
        }
    }
    acc.map(|(s, co)| Complex64::new(s / ss, co / cc))
}

#[test]
fn a_sine_through_step_reproduces_the_frequency_response() {
    let p = second_order();
    let c = LinearController::new(&p).unwrap();
    for freq in [200.0, 800.0, 2500.0] {
        for j in 0..2 {
            let want = c.frequency_response(2.0 * PI * freq, p.delay);
            let got = measured(&p, freq, 1e-6, j);
            for i in 0..2 {
                let err = (got[i] - want[i][j]).norm() / want[i][j].norm().max(1.0);
                // the zero-order hold of w delays by h/2: error ~ ω h / 2
                assert!(err < 2e-2, "{freq} Hz, F{i}/v{j}: {} vs {}", got[i], want[i][j]);
            }
        }
    }
    // at a coarse step the outputs at the communication points are K_d(e^{iωh}) exactly
    let c = LinearController::new(&p).unwrap();
    for freq in [200.0, 800.0] {
        let h = 2e-5;
        let kd = c.discrete_gain(2.0 * PI * freq, h).unwrap();
        #[allow(clippy::needless_range_loop)] // j indexes the input and kd's column alike
        for j in 0..2 {
            let got = measured(&p, freq, h, j);
            for i in 0..2 {
                let want = kd[i][j] * (1.0 - p.beta * Complex64::from_polar(1.0, -2.0 * PI * freq * p.delay));
                assert!((got[i] - want).norm() < 1e-6 * want.norm().max(1.0), "{freq} Hz: {} vs {want}", got[i]);
            }
        }
        // and the sampled response adds the delay and the hold
        let w = 2.0 * PI * freq;
        let s = c.sampled_response(w, h, p.delay).unwrap();
        let f = c.frequency_response(w, p.delay);
        assert!((s[0][0] - f[0][0]).norm() < 2.0 * w * h * f[0][0].norm());
    }
    // the discrete form: its own response (z = e^{iωT_s}) is reproduced exactly up to the fit
    let mut d = second_order();
    d.discrete = true;
    d.sample_period = 2e-5;
    let (phi, gamma) = LinearController::new(&second_order()).unwrap().discretise(d.sample_period).unwrap();
    for i in 0..2 {
        for j in 0..2 {
            d.ac[i][j] = phi[(i, j)];
        }
        d.bc[i] = [gamma[(i, 0)], gamma[(i, 1)]];
    }
    let cd = LinearController::new(&d).unwrap();
    let want = cd.frequency_response(2.0 * PI * 500.0, d.delay);
    let got = measured(&d, 500.0, 2e-5, 0);
    for i in 0..2 {
        let err = (got[i] - want[i][0]).norm() / want[i][0].norm();
        assert!(err < 3e-2, "discrete F{i}: {} vs {}", got[i], want[i][0]);
    }
}

#[test]
fn exact_discretisation_matches_a_fine_euler_reference() {
    let p = second_order();
    let c = LinearController::new(&p).unwrap();
    let h = 1e-5;
    let (phi, gamma) = c.discretise(h).unwrap();
    // x' = A x + B w with w = (1, −0.5) held, from x = (0.3, −2): many tiny explicit steps
    let n = 200_000;
    let dt = h / n as f64;
    let mut x = [0.3, -2.0];
    let w = [1.0, -0.5];
    for _ in 0..n {
        let dx0 = p.ac[0][0] * x[0] + p.ac[0][1] * x[1] + p.bc[0][0] * w[0] + p.bc[0][1] * w[1];
        let dx1 = p.ac[1][0] * x[0] + p.ac[1][1] * x[1] + p.bc[1][0] * w[0] + p.bc[1][1] * w[1];
        x = [x[0] + dt * dx0, x[1] + dt * dx1];
    }
    let ex = [
        phi[(0, 0)] * 0.3 - phi[(0, 1)] * 2.0 + gamma[(0, 0)] - 0.5 * gamma[(0, 1)],
        phi[(1, 0)] * 0.3 - phi[(1, 1)] * 2.0 + gamma[(1, 0)] - 0.5 * gamma[(1, 1)],
    ];
    for k in 0..2 {
        assert!((ex[k] - x[k]).abs() < 1e-4 * x[k].abs().max(1.0), "{ex:?} vs {x:?}");
    }
}

#[test]
fn pyragas_cancels_a_periodic_input_and_the_delay_follows_the_speed() {
    let p = LinearControlParams { dc: [[1000.0, 0.0], [0.0, 1000.0]], ..Default::default() };
    let mut c = LinearController::new(&p).unwrap();
    let rpm = 37_500.0;
    let tau = 60.0 / (4.0 * rpm);
    let h = tau / 50.0;
    for k in 0..2000 {
        let t = k as f64 * h;
        let v = [(2.0 * PI * t / tau).sin() * 1e-5, (4.0 * PI * t / tau).cos() * 2e-5];
        c.step(t, h, &ControlInputs { v, spindle_speed: rpm }).unwrap();
        if k > 60 {
            // samples fall on the grid: the periodic part cancels to rounding
            assert!(c.outputs().force.iter().all(|f| f.abs() < 1e-12), "{:?}", c.outputs());
        }
    }
    assert!((c.outputs().delay - tau).abs() < 1e-18);
    // a zero speed is refused (the delay would be infinite), the state is untouched
    let before = c.outputs();
    assert!(matches!(c.step(1.0, h, &ControlInputs { v: [0.0; 2], spindle_speed: 0.0 }), Err(ControlError::Input(_))));
    assert!(c.outputs().force.iter().zip(before.force).all(|(a, b)| a.to_bits() == b.to_bits()));
}

#[test]
fn delayed_values_are_interpolated_and_the_output_saturates() {
    let mut p = LinearControlParams { delay_from_speed: false, delay: 2.5e-6, ..Default::default() };
    p.dc = [[1e6, 0.0], [0.0, -1e6]];
    p.saturation = [5.0, 0.5];
    let mut c = LinearController::new(&p).unwrap();
    // v = t (ramp): w = v(t) − v(t − τ) = τ exactly (linear interpolation is exact on a ramp)
    for k in 0..10 {
        let t = k as f64 * 1e-6;
        c.step(t, 1e-6, &ControlInputs { v: [t, t], spindle_speed: 0.0 }).unwrap();
    }
    let o = c.outputs();
    assert!((o.w[0] - 2.5e-6).abs() < 1e-18, "{o:?}");
    assert!((o.force[0] - 2.5).abs() < 1e-9 && (o.force[1] + 0.5).abs() < 1e-15, "{o:?}");
}

#[test]
fn the_state_round_trips_bitwise() {
    let p = second_order();
    let mut c = LinearController::new(&p).unwrap();
    let drive = |c: &mut LinearController, k0: usize, k1: usize| {
        for k in k0..k1 {
            let t = k as f64 * 1e-6;
            c.step(t, 1e-6, &ControlInputs { v: [(t * 7e3).sin(), (t * 3e3).cos()], spindle_speed: 0.0 }).unwrap();
        }
    };
    drive(&mut c, 0, 700);
    let text = serde_json::to_string(&c).unwrap();
    let mut d: LinearController = serde_json::from_str(&text).unwrap();
    d.validate_state().unwrap();
    drive(&mut c, 700, 1500);
    drive(&mut d, 700, 1500);
    assert!(c.state().iter().zip(d.state()).all(|(a, b)| a.to_bits() == b.to_bits()));
    assert!(c.outputs().force.iter().zip(d.outputs().force).all(|(a, b)| a.to_bits() == b.to_bits()));
}

#[test]
fn bad_parameters_are_refused() {
    let p = LinearControlParams { n_c: 9, ..Default::default() };
    assert!(LinearController::new(&p).is_err());
    let mut p = LinearControlParams::default();
    p.dc[0][1] = f64::NAN;
    assert!(LinearController::new(&p).is_err());
    let p = LinearControlParams { delay_from_speed: false, delay: 2.0, ..Default::default() };
    assert!(LinearController::new(&p).is_err());
}
