//! RLS, the model-following design and the closed loop with exact parameters.

use froh_mrac::mrac::{self, MracParams};
use froh_mrac::{Rls, simulate};
use milling_force_plant::plant::{DepthProfile, ForcePlant, ForcePlantInputs, ForcePlantParams};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Noise-free data of `y_k = a y_{k−1} + b₀u_{k−1} + b₁u_{k−2}` under a random input.
fn data(theta: [f64; 3], n: usize) -> Vec<([f64; 3], f64)> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut y1, mut u1, mut u2) = (0.0, 0.0, 0.0);
    let mut out = Vec::new();
    for _ in 0..n {
        let phi = [y1, u1, u2];
        let y = theta[0] * y1 + theta[1] * u1 + theta[2] * u2;
        out.push((phi, y));
        y1 = y;
        u2 = u1;
        u1 = rng.random_range(0.0..40.0);
    }
    out
}

#[test]
fn rls_recovers_the_froh_model_to_1e_8() {
    let p = MracParams { beta: 0.4, ..Default::default() };
    let plant = ForcePlantParams::default();
    let truth = p.theta_of(plant.gain(2.0), plant.tau_c).unwrap();
    let theta0 = p.theta_of(p.gain_estimate, p.tau_estimate).unwrap();
    for (lambda, p0, n) in [(1.0, 1e12, 400), (0.98, 100.0, 2000)] {
        let mut rls = Rls::new(theta0.to_vec(), p0, lambda, f64::INFINITY);
        for (phi, y) in data(truth, n) {
            rls.update(&phi, y);
        }
        for (e, t) in rls.theta.iter().zip(truth) {
            assert!((e - t).abs() <= 1e-8 * t.abs().max(1.0), "lambda {lambda}: {:?} vs {truth:?}", rls.theta);
        }
    }
}

#[test]
fn the_design_solves_the_model_following_equations() {
    let p = MracParams { beta: 0.4, ..Default::default() };
    let reference = p.reference_model().unwrap();
    let theta = p.theta_of(50.0, 0.02).unwrap();
    let c = mrac::design(&theta, &reference).unwrap();
    // A R + B S = B⁺ A_m
    let a = [1.0, -theta[0], 0.0];
    let b = [theta[1], theta[2]];
    let r = [1.0, c.r[0], c.r[1]];
    let lhs: Vec<f64> = {
        let mut l = milling_force_plant::poly::mul(&a, &r);
        let bs = milling_force_plant::poly::mul(&b, &c.s);
        let off = l.len() - bs.len();
        for (i, x) in bs.iter().enumerate() {
            l[off + i] += x;
        }
        l
    };
    let rhs = milling_force_plant::poly::mul(&[1.0, theta[2] / theta[1]], &reference.den);
    for (x, y) in lhs.iter().zip(&rhs) {
        assert!((x - y).abs() < 1e-12, "{lhs:?} vs {rhs:?}");
    }
    // a zero outside the unit circle is refused
    let p = MracParams { beta: -0.8, ..Default::default() };
    let theta = p.theta_of(50.0, 0.021).unwrap();
    assert!(mrac::design(&theta, &p.reference_model().unwrap()).is_err());
}

#[test]
fn with_the_true_parameters_the_loop_follows_the_reference_model_at_the_samples() {
    for beta in [-0.5, -0.2, 0.0, 0.4, 1.0] {
        for substeps in [1, 7] {
            let plant = ForcePlantParams { tau_s: 0.0, depth: DepthProfile::constant(2.0), ..Default::default() };
            let ctrl = MracParams {
                beta,
                adapt: false,
                gain_estimate: plant.gain(2.0),
                tau_estimate: plant.tau_c,
                ..Default::default()
            };
            let f_ref = 1200.0;
            let n = 60;
            let run = simulate(&plant, &ctrl, f_ref, substeps, n * substeps as usize).unwrap();
            let fm = ctrl.reference_model().unwrap().simulate(&vec![f_ref; n + 1]);
            for k in 0..=n {
                let s = &run[k * substeps as usize];
                assert!(
                    (s.force - fm[k]).abs() <= 1e-9 * f_ref,
                    "beta {beta}, M {substeps}, k {k}: {} vs {}",
                    s.force,
                    fm[k]
                );
                // the controller's continuous reference model agrees at the samples
                assert!((s.reference_force - fm[k]).abs() <= 1e-9 * f_ref, "F_m at k {k}");
            }
        }
    }
}

#[test]
fn the_plant_integrates_the_ramp_exactly_across_a_depth_change() {
    let mut p = ForcePlantParams { tau_s: 2e-3, ..Default::default() };
    p.depth.t[1] = 0.0137;
    let mut plant = ForcePlant::new(&p).unwrap();
    let h = 0.01;
    let inputs = [(20.0, 300.0), (25.0, -150.0), (5.0, 0.0)];
    // RK4 reference on a fine grid
    let sub = 20_000;
    let (mut fa, mut fp) = (0.0f64, 0.0f64);
    for (j, &(mean, rate)) in inputs.iter().enumerate() {
        plant.step(h, &ForcePlantInputs { feed_command: mean, feed_command_rate: rate }).unwrap();
        let dt = h / sub as f64;
        let t0 = j as f64 * h;
        let rhs = |s: f64, fa: f64, fp: f64| {
            let u = mean + rate * (s - t0 - h / 2.0);
            let k = p.gain(p.depth.depth_at(s));
            ((u - fa) / p.tau_s, (k * fa - fp) / p.tau_c)
        };
        for i in 0..sub {
            let s = t0 + i as f64 * dt;
            // the depth changes inside one of these cells: split it there
            let cut = p.depth.t[1];
            let pieces: Vec<(f64, f64)> =
                if s < cut && cut < s + dt { vec![(s, cut - s), (cut, s + dt - cut)] } else { vec![(s, dt)] };
            for (s, d) in pieces {
                let sm = s + d / 2.0;
                let k1 = rhs(s + 1e-15, fa, fp);
                let k2 = rhs(sm, fa + d / 2.0 * k1.0, fp + d / 2.0 * k1.1);
                let k3 = rhs(sm, fa + d / 2.0 * k2.0, fp + d / 2.0 * k2.1);
                let k4 = rhs(s + d - 1e-15, fa + d * k3.0, fp + d * k3.1);
                fa += d / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                fp += d / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            }
        }
        let o = plant.outputs();
        assert!((o.force - fp).abs() <= 1e-9 * fp.abs().max(1.0), "step {j}: {} vs {fp}", o.force);
        assert!((o.feed - fa).abs() <= 1e-9 * fa.abs().max(1.0), "step {j}: {} vs {fa}", o.feed);
    }
}

#[test]
fn the_adaptive_loop_is_independent_of_the_communication_step_at_the_samples() {
    let plant = ForcePlantParams::default();
    let ctrl = MracParams { beta: 0.4, ..Default::default() };
    let n = 80;
    let a = simulate(&plant, &ctrl, 1200.0, 1, n).unwrap();
    let b = simulate(&plant, &ctrl, 1200.0, 10, 10 * n).unwrap();
    for k in 0..=n {
        assert!((a[k].force - b[10 * k].force).abs() <= 1e-9 * 1200.0, "k {k}: {} vs {}", a[k].force, b[10 * k].force);
    }
}

/// At β = 0 the model is the ZOH's first-order `y_k = a y_{k−1} + b₀u_{k−1}`: RLS estimates the
/// two parameters `(a, b₀)` (three with `estimate_b1_at_zoh`, and for every other β), reports
/// `b̂₁ = 0`, and with the plant's data approaches `(a, b₀)` of the chip lag behind the ZOH (to 1e-3
/// in 200 samples: λ = 0.98, P₀ = 100 I).
#[test]
fn the_zoh_estimator_has_two_parameters() {
    let plant = ForcePlantParams { tau_s: 0.0, depth: DepthProfile::constant(2.0), ..Default::default() };
    for (beta, b1, n) in [(0.0, false, 2), (0.0, true, 3), (0.4, false, 3), (-0.2, false, 3)] {
        let p = MracParams { beta, estimate_b1_at_zoh: b1, ..Default::default() };
        assert_eq!(p.estimated_parameters(), n, "beta {beta}");
        let run = simulate(&plant, &p, 1200.0, 1, 200).unwrap();
        let last = run.last().unwrap().controller;
        if n == 2 {
            assert_eq!(last.b1_hat.to_bits(), 0.0f64.to_bits());
            let truth = p.theta_of(plant.gain(2.0), plant.tau_c).unwrap();
            assert!((last.a_hat - truth[0]).abs() < 1e-3 && (last.b0_hat / truth[1] - 1.0).abs() < 1e-3, "{last:?}");
        } else {
            assert!(last.b1_hat.abs() > 0.0, "beta {beta}: b1 is estimated");
        }
    }
}
