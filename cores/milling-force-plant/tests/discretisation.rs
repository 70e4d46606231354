//! The FROH discretisation against the ZOH, a fine continuous simulation and the known zeros.

use milling_force_plant::froh::{self, DiscreteTf, StateSpace};
use milling_force_plant::plant::ForcePlantParams;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

fn plant_model(tau_s: f64) -> (StateSpace, f64) {
    let p = ForcePlantParams { tau_s, ..Default::default() };
    (p.model(2.0), p.spindle_period())
}

#[test]
fn beta_zero_is_the_zero_order_hold_to_1e_14() {
    for tau_s in [1e-4, 5e-3] {
        let (sys, t) = plant_model(tau_s);
        let f = DiscreteTf::froh(&sys, t, 0.0).unwrap();
        let z = DiscreteTf::zoh(&sys, t).unwrap();
        // the FROH model at β = 0 is the ZOH model times z/z
        let mut zn = z.num.clone();
        zn.push(0.0);
        let mut zd = z.den.clone();
        zd.push(0.0);
        let scale = max_abs(&zn);
        for (a, b) in f.num.iter().zip(&zn) {
            assert!((a - b).abs() <= 1e-14 * scale, "num {:?} vs {:?}", f.num, zn);
        }
        for (a, b) in f.den.iter().zip(&zd) {
            assert!((a - b).abs() <= 1e-14, "den {:?} vs {:?}", f.den, zd);
        }
        // and the ZOH pulse response is the analytic step response sampled and differenced
        let p = ForcePlantParams { tau_s, ..Default::default() };
        let (k, tc) = (p.gain(2.0), p.tau_c);
        let step = |x: f64| k * (1.0 - (tc * (-x / tc).exp() - tau_s * (-x / tau_s).exp()) / (tc - tau_s));
        let mut u = vec![0.0; 12];
        u[0] = 1.0;
        let y = f.simulate(&u);
        for (i, yi) in y.iter().enumerate() {
            let exact = if i == 0 { 0.0 } else { step(i as f64 * t) - step((i - 1) as f64 * t) };
            assert!((yi - exact).abs() <= 1e-14 * k, "pulse {i}: {yi} vs {exact}");
        }
    }
    // the first-order lag in closed form: b₀ = K(1 − a), b₁ = 0, pole a
    let (k, tau, t) = (50.0, 0.021, 0.084);
    let f = DiscreteTf::froh(&StateSpace::first_order(k, tau), t, 0.0).unwrap();
    let a = (-t / tau).exp();
    assert!((f.num[1] - k * (1.0 - a)).abs() <= 1e-14 * k && f.num[2] == 0.0);
    assert!((f.den[1] + a).abs() <= 1e-15);
}

/// RK4 with `sub` steps per period of `ẋ = Ax + Bu(t)`, u the FROH signal of `uk`.
fn rk4_hold(sys: &StateSpace, t: f64, beta: f64, uk: &[f64], sub: usize) -> Vec<f64> {
    let n = sys.order();
    let f = |x: &[f64], u: f64| -> Vec<f64> {
        (0..n).map(|i| (0..n).map(|j| sys.a[i][j] * x[j]).sum::<f64>() + sys.b[i] * u).collect()
    };
    let mut x = vec![0.0; n];
    let mut y = Vec::with_capacity(uk.len());
    let h = t / sub as f64;
    for k in 0..uk.len() {
        y.push((0..n).map(|i| sys.c[i] * x[i]).sum());
        let prev = if k > 0 { uk[k - 1] } else { 0.0 };
        let hold = |s: f64| uk[k] + beta * (uk[k] - prev) * s / t;
        for j in 0..sub {
            let s = j as f64 * h;
            let add = |x: &[f64], d: &[f64], c: f64| -> Vec<f64> { x.iter().zip(d).map(|(a, b)| a + c * b).collect() };
            let k1 = f(&x, hold(s));
            let k2 = f(&add(&x, &k1, h / 2.0), hold(s + h / 2.0));
            let k3 = f(&add(&x, &k2, h / 2.0), hold(s + h / 2.0));
            let k4 = f(&add(&x, &k3, h), hold(s + h));
            for i in 0..n {
                x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
    }
    y
}

#[test]
fn the_discrete_model_equals_a_fine_continuous_simulation_driven_by_the_hold() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let uk: Vec<f64> = (0..40).map(|_| rng.random_range(-30.0..30.0)).collect();
    let (sys, t) = plant_model(2e-3);
    let reference = StateSpace::second_order(0.75, 7.448);
    for beta in [-0.6, -0.2, 0.0, 0.4, 1.0] {
        for s in [&sys, &reference] {
            let y = DiscreteTf::froh(s, t, beta).unwrap().simulate(&uk);
            let yc = rk4_hold(s, t, beta, &uk, 4000);
            let scale = max_abs(&yc);
            let err = y.iter().zip(&yc).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(err <= 1e-9 * scale, "beta {beta}: error {err:e} of {scale:e}");
        }
    }
}

#[test]
fn integrator_zero_is_beta_over_two_plus_beta_and_double_integrator_zero_is_minus_one() {
    for beta in [-0.9, -0.5, -0.2, 0.1, 0.4, 0.7, 1.0] {
        let z = DiscreteTf::froh(&StateSpace::integrators(1), 0.3, beta).unwrap().zeros();
        let nonzero: Vec<_> = z.iter().filter(|z| z.norm() > 1e-12).collect();
        assert_eq!(nonzero.len(), 1, "{beta}: {z:?}");
        assert!((nonzero[0].re - beta / (2.0 + beta)).abs() < 1e-13 && nonzero[0].im == 0.0, "{beta}: {z:?}");
    }
    let z = DiscreteTf::froh(&StateSpace::integrators(2), 1.0, 0.0).unwrap().dominant_zero().unwrap();
    assert!((z.re + 1.0).abs() < 1e-12 && z.im.abs() < 1e-12, "{z}");
    // non-minimum phase for β > 0 (−1.197 at 0.4)
    for beta in [0.1, 0.4, 1.0] {
        let z = DiscreteTf::froh(&StateSpace::integrators(2), 1.0, beta).unwrap().dominant_zero().unwrap();
        assert!(z.norm() > 1.0, "{beta}: {z}");
        if (beta - 0.4f64).abs() < 1e-12 {
            assert!((z.re + 1.197).abs() < 5e-4, "{z}");
        }
    }
}

#[test]
fn the_plant_zero_leaves_the_unit_circle_near_minus_0_65() {
    let (sys, t) = plant_model(1e-4);
    let b = froh::nmp_boundary(&sys, t, -1.0, 0.0).unwrap().unwrap();
    let tau_c = ForcePlantParams::default().tau_c;
    let analytic = froh::first_order_nmp_boundary(tau_c, t);
    println!("NMP boundary: two lags {b:.5}, chip lag alone {analytic:.5}");
    assert!((b + 0.65).abs() <= 0.05, "{b}");
    assert!((b - analytic).abs() < 0.01, "{b} vs {analytic}");
    let m = |beta: f64| froh::dominant_zero_modulus(&StateSpace::first_order(1.0, tau_c), t, beta).unwrap();
    assert!((m(-0.6) - 0.856).abs() < 2e-3 && (m(-0.7) - 1.164).abs() < 2e-3, "{} {}", m(-0.6), m(-0.7));
    // the first-order boundary is exactly where the zero is −1
    let z = DiscreteTf::froh(&StateSpace::first_order(1.0, tau_c), t, analytic).unwrap().dominant_zero().unwrap();
    assert!((z.re + 1.0).abs() < 1e-12, "{z}");
}
