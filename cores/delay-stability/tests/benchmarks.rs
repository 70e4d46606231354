//! Benchmarks with known answers: the delayed oscillator's analytic D-curves, the damped
//! Mathieu tongues, the 1-DOF low-immersion milling model of Insperger & Stépán (flip lobes),
//! the power-law directional matrix against its closed form, and the O(1/m²) convergence.

use delay_stability::milling::{Cutter, ForceLaw, Milling, MillingModel, ModeShape, Structure};
use delay_stability::oscillator::{DelayedMathieu, d_curve};
use delay_stability::presets::{seed002, seed002_cutter};
use delay_stability::sd::Bifurcation;
use delay_stability::{BisectionOptions, critical_value, lobes};
use std::f64::consts::PI;

/// Smallest b > 0 (sign +1) or b < 0 (sign −1, returned as |b|) on the ε = 0 boundary at `delta`:
/// the D-curves of [`d_curve`] crossing `delta`, and the fold line b = δ.
fn analytic_b(kappa: f64, delta: f64, sign: f64) -> f64 {
    let mut best = if sign > 0.0 { delta } else { f64::INFINITY };
    let f = |w: f64| d_curve(kappa, w).0 - delta;
    let n = 200_000;
    let w_max = 20.0;
    for k in 1..n {
        let (a, b) = (w_max * k as f64 / n as f64, w_max * (k + 1) as f64 / n as f64);
        // skip the poles of b(ω) at sin 2πω = 0
        if (2.0 * a).floor() as i64 != (2.0 * b).floor() as i64 {
            continue;
        }
        if f(a).signum() != f(b).signum() {
            let (mut lo, mut hi) = (a, b);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if f(mid).signum() == f(lo).signum() { lo = mid } else { hi = mid }
            }
            let bw = d_curve(kappa, 0.5 * (lo + hi)).1 * sign;
            if bw > 0.0 {
                best = best.min(bw);
            }
        }
    }
    best
}

#[test]
fn delayed_oscillator_matches_the_analytic_d_curves() {
    let kappa = 0.1;
    let o = BisectionOptions { m: 150, start: 0.02, growth: 1.25, max: 50.0, rel_tol: 1e-6 };
    for (delta, sign) in [(0.5625, 1.0), (2.0, 1.0), (4.0, -1.0), (1.0, -1.0), (0.3, 1.0)] {
        let exact = analytic_b(kappa, delta, sign);
        let c = critical_value(|p| Ok(DelayedMathieu { kappa, delta, epsilon: 0.0, b: sign * p }), &o).unwrap();
        let sd = c.value.unwrap();
        println!("δ = {delta}, sign {sign}: SD b = {sd:.6}, analytic {exact:.6}, {:?}", c.kind());
        assert!((sd / exact - 1.0).abs() < 1e-3, "δ = {delta}: SD {sd} vs analytic {exact}");
    }
}

#[test]
fn damped_mathieu_tongues_are_flip_then_fold() {
    // b = 0: the principal tongue at δ = 1/4 is period doubling (μ = −1), the one at δ = 1 has μ = +1.
    let o = BisectionOptions { m: 60, start: 1e-3, growth: 1.05, max: 5.0, rel_tol: 1e-6 };
    let run =
        |delta: f64| critical_value(|e| Ok(DelayedMathieu { kappa: 0.1, delta, epsilon: e, b: 0.0 }), &o).unwrap();
    let first = run(0.25);
    let second = run(1.0);
    println!(
        "ε_crit at δ = 1/4: {:?} {:?}; at δ = 1: {:?} {:?}",
        first.value,
        first.kind(),
        second.value,
        second.kind()
    );
    assert_eq!(first.kind(), Some(Bifurcation::Flip));
    assert_eq!(second.kind(), Some(Bifurcation::Fold));
    // the first tongue opens first (its damped threshold ≈ κ·... is the lower one)
    assert!(first.value.unwrap() < second.value.unwrap());
    // with a delayed term the boundary is a Hopf one in between the tongues (δ = 0.6, ε = 0)
    let hopf = critical_value(|p| Ok(DelayedMathieu { kappa: 0.1, delta: 0.6, epsilon: 0.0, b: p }), &o).unwrap();
    assert_eq!(hopf.kind(), Some(Bifurcation::Hopf));
}

/// Insperger & Stépán's 1-DOF benchmark: f_n = 922 Hz, ζ = 0.011, m = 0.03993 kg, K_t = 6e8,
/// K_n = 2e8 N/m², z = 2, a/D = 0.05 down-milling, flexible along x (the feed).
fn one_dof(immersion: f64, milling: Milling) -> MillingModel {
    let m = 0.03993f64;
    let mode = ModeShape { omega: 2.0 * PI * 922.0, zeta: 0.011, tool: [1.0 / m.sqrt(), 0.0], actuator: [0.0, 0.0] };
    let s = Structure::from_modes(&[mode]).unwrap();
    let (e, x) = Cutter::immersion(immersion, milling);
    MillingModel::new(&s, Cutter::new(2, e, x, 6e8, 2e8, ForceLaw::Linear).unwrap(), None).unwrap()
}

#[test]
fn low_immersion_down_milling_has_separate_flip_lobes() {
    let model = one_dof(0.05, Milling::Down);
    let o = BisectionOptions { m: 40, start: 1e-4, growth: 1.1, max: 0.05, rel_tol: 1e-4 };
    let speeds: Vec<f64> = (0..=24).map(|k| 12000.0 + 500.0 * k as f64).collect();
    let l = lobes(&speeds, |r, a| model.at(r, a), &o, &|_, _| {}).unwrap();
    for p in &l {
        println!("{:6.0} rpm {:7.4} mm {:?}", p.rpm, p.critical.value.unwrap() * 1e3, p.critical.kind());
    }
    let kind = |rpm: f64| l.iter().find(|p| (p.rpm - rpm).abs() < 1e-9).unwrap().critical.kind().unwrap();
    // period doubling where twice the natural frequency is an odd multiple of the tooth-passing
    // frequency: 120 f_n/(3 z) = 18440 rpm; the flip lobe spans ≈ 13700–18300 rpm (Insperger,
    // Stépán, Bayly, Mann, J. Sound Vib. 262, 2003: separate flip lobes at low immersion)
    for rpm in [14000.0, 16000.0, 18000.0] {
        assert_eq!(kind(rpm), Bifurcation::Flip, "{rpm} rpm");
    }
    for rpm in [12000.0, 19000.0, 22000.0, 24000.0] {
        assert_eq!(kind(rpm), Bifurcation::Hopf, "{rpm} rpm");
    }
    // the boundary jumps where the flip and Hopf lobes meet (a separate lobe, not one curve)
    let depth = |rpm: f64| l.iter().find(|p| (p.rpm - rpm).abs() < 1e-9).unwrap().critical.value.unwrap();
    assert!(depth(19000.0) > 2.0 * depth(18000.0));
    // full-immersion up-milling of the same tool has no flip at these speeds (Hopf only)
    let full = one_dof(1.0, Milling::Up);
    let c = critical_value(|a| full.at(16000.0, a), &o).unwrap();
    assert_eq!(c.kind(), Some(Bifurcation::Hopf));
}

#[test]
fn power_law_mean_directional_matrix_has_its_closed_form() {
    // full immersion, one tooth: (z/2π) x_F f^{x_F−1} ∫₀^π sin^{x_F−1}φ S[K_t;K_r][sin, cos] dφ,
    // with I(p) = ∫₀^π sin^p = √π Γ((p+1)/2)/Γ(p/2+1): [[−K_r I₊, −K_t (I₋ − I₊)], [K_t I₊, −K_r (I₋ − I₊)]]
    let (i_minus, i_plus) = (3.8785370238868606, 1.6546052441352206); // I(x_F − 1), I(x_F + 1)
    let c = seed002_cutter(0.744).unwrap();
    let scale = 4.0 / (2.0 * PI) * 0.744 * (0.2e-3f64).powf(0.744 - 1.0);
    let expect = [[-c.kr * i_plus, -c.kt * (i_minus - i_plus)], [c.kt * i_plus, -c.kr * (i_minus - i_plus)]];
    let h = c.mean();
    for i in 0..2 {
        for j in 0..2 {
            let e = expect[i][j] * scale;
            assert!((h[(i, j)] - e).abs() < 3e-9 * c.kt * scale, "H̄[{i},{j}] = {} vs {e}", h[(i, j)]);
        }
    }
    // the sub-interval averages add up: 40 of them average to the mean
    let p = c.pitch();
    let sum: nalgebra::Matrix2<f64> = (0..40).map(|k| c.averaged(p * k as f64 / 40.0, p * (k + 1) as f64 / 40.0)).sum();
    assert!((sum / 40.0 - h).norm() < 1e-9 * h.norm());
}

#[test]
fn semi_discretisation_converges_as_one_over_m_squared() {
    let model = seed002(0.744, None).unwrap();
    let depth = |m: usize| {
        let o = BisectionOptions { m, start: 0.3e-3, growth: 1.1, max: 0.01, rel_tol: 1e-8 };
        critical_value(|a| model.at(36000.0, a), &o).unwrap().value.unwrap()
    };
    let (a15, a30, a60) = (depth(15), depth(30), depth(60));
    let ratio = (a15 - a30) / (a30 - a60);
    let richardson = a60 + (a60 - a30) / 3.0;
    println!(
        "x_F = 0.744, 36000 rpm: m=15 {:.5} mm, m=30 {:.5} mm, m=60 {:.5} mm, ratio {ratio:.3}, extrapolated {:.5} mm (paper 1.067)",
        a15 * 1e3,
        a30 * 1e3,
        a60 * 1e3,
        richardson * 1e3
    );
    assert!(ratio > 3.5 && ratio < 4.5, "ratio of successive differences {ratio} (4 for O(1/m²))");
}

#[test]
fn power_law_monodromy_is_finite_where_a_sub_interval_ends_on_a_zero_of_sin() {
    // 36000 rpm, m = 40: the last sub-interval of tooth 1 ends within rounding of φ = π, which
    // once produced a piece [π, π + ulp] evaluated at sin < 0 (NaN)
    let model = seed002(0.744, None).unwrap();
    for m in [15, 30, 40, 60] {
        let phi = delay_stability::monodromy(&model.at(36000.0, 1e-3).unwrap(), m).unwrap();
        assert!(phi.iter().all(|v| v.is_finite()), "m = {m}");
    }
}
