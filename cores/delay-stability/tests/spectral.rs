//! The spectral collocation's boundaries against exact and extrapolated references (its
//! operator and layout are tested next to the code, `spectral::tests`).

use delay_stability::milling::MillingModel;
use delay_stability::oscillator::{DelayedMathieu, d_curve};
use delay_stability::presets::{SEED002_GAINS, seed002, seed002_gain};
use delay_stability::{LobeOptions, Method, SpectralOptions, critical};

fn depth(model: &MillingModel, rpm: f64, method: Method, start: f64) -> f64 {
    let o = LobeOptions { method, start, growth: 1.1, max: 0.02, rel_tol: 1e-8 };
    critical(|a| model.at(rpm, a), &o).unwrap().value.unwrap()
}

#[test]
fn the_time_invariant_boundary_is_exact() {
    // x_F = 1, full immersion, z = 4: H constant, the exact D-subdivision boundary is the
    // reference; the semi-discretisation at m = 40 is 4e-4 (open) and 1.6e-3 (closed) off
    let (k1, k2) = SEED002_GAINS;
    for (gain, rpm) in [(None, 38000.0), (Some(seed002_gain(k1, k2)), 37800.0)] {
        let model = seed002(1.0, gain).unwrap();
        let exact = model.time_invariant().critical_depth(rpm, 40_000).unwrap().unwrap().depth;
        let ours = depth(&model, rpm, Method::Spectral(SpectralOptions::new(12)), 1e-3);
        println!("{rpm} rpm: spectral N = 12 {:.8} mm, exact {:.8} mm", ours * 1e3, exact * 1e3);
        assert!((ours / exact - 1.0).abs() < 2e-7, "{ours} vs {exact}");
    }
}

#[test]
fn a_system_without_splitting_matches_the_analytic_d_curve() {
    // ẍ + 0.1ẋ + δx = b x(t − 2π) on the first b > 0 branch, ω ∈ (0.5, 1): the generic path
    // (A₀ = mean of A, G = C₀ = I, point values from `averaged`)
    let kappa = 0.1;
    for w in [0.62, 0.8] {
        let (delta, b) = d_curve(kappa, w);
        let o = LobeOptions {
            method: Method::Spectral(SpectralOptions::new(10)),
            start: 0.2 * b,
            growth: 1.1,
            max: 5.0 * b,
            rel_tol: 1e-10,
        };
        let c = critical(|p| Ok(DelayedMathieu { kappa, delta, epsilon: 0.0, b: p }), &o).unwrap();
        let ours = c.value.unwrap();
        println!("ω = {w}: δ = {delta:.6}, analytic b = {b:.10}, spectral {ours:.10} ({:?})", c.kind());
        assert!((ours / b - 1.0).abs() < 1e-8, "{ours} vs {b}");
    }
}

#[test]
fn smooth_periodic_coefficients_converge_exponentially() {
    // the damped Mathieu equation (cos t coefficient, no breakpoints): the flip tongue at δ = 1/4
    let run = |nodes: usize| {
        let o = LobeOptions {
            method: Method::Spectral(SpectralOptions::new(nodes)),
            start: 1e-3,
            growth: 1.05,
            max: 5.0,
            rel_tol: 1e-11,
        };
        critical(|e| Ok(DelayedMathieu { kappa: 0.1, delta: 0.25, epsilon: e, b: 0.0 }), &o).unwrap().value.unwrap()
    };
    // one element over the period: errors 1e-1, 1e-5, 1e-9 at N = 4, 8, 12 (SD m = 400: 2e-5)
    let (e4, e8, e12, e16) = (run(4), run(8), run(12), run(16));
    println!("ε_crit: N = 4 {e4:.12}, N = 8 {e8:.12}, N = 12 {e12:.12}, N = 16 {e16:.12}");
    assert!((e8 - e16).abs() < 1e-3 * (e4 - e16).abs(), "{e4} {e8} {e16}");
    assert!((e12 - e16).abs() < 1e-3 * (e8 - e16).abs(), "{e8} {e12} {e16}");
    assert!((e12 / e16 - 1.0).abs() < 1e-7);
}

#[test]
fn graded_elements_converge_at_the_power_law_singularity() {
    let model = seed002(0.744, None).unwrap();
    let a = |n| depth(&model, 36000.0, Method::Spectral(SpectralOptions::new(n)), 0.5e-3);
    let (a6, a12) = (a(6), a(12));
    // the semi-discretisation extrapolated in m (Richardson on m = 80, 160)
    let (s80, s160) =
        (depth(&model, 36000.0, Method::Sd { m: 80 }, 0.9e-3), depth(&model, 36000.0, Method::Sd { m: 160 }, 0.9e-3));
    let richardson = s160 + (s160 - s80) / 3.0;
    println!("N = 6 {:.8}, N = 12 {:.8}, SD Richardson {:.8} mm", a6 * 1e3, a12 * 1e3, richardson * 1e3);
    assert!((a6 / a12 - 1.0).abs() < 1e-4);
    assert!((a12 / richardson - 1.0).abs() < 3e-6, "{a12} vs {richardson}");
}
