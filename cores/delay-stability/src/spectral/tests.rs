use super::*;
use crate::oscillator::{DelayedMathieu, d_curve};
use crate::presets::{SEED002_GAINS, seed002, seed002_gain};
use crate::sd::eigenvalues;
use crate::search::{LobeOptions, Method, critical};

fn spectral(nodes: usize) -> Spectral {
    Spectral::new(SpectralOptions::new(nodes)).unwrap()
}

fn depth(model: &crate::milling::MillingModel, rpm: f64, method: Method, start: f64) -> f64 {
    let o = LobeOptions { method, start, growth: 1.1, max: 0.02, rel_tol: 1e-8 };
    critical(|a| model.at(rpm, a), &o).unwrap().value.unwrap()
}

#[test]
fn the_operator_is_its_dense_matrix() {
    // controller (every element has a delayed term), power law (graded elements)
    let (k1, k2) = SEED002_GAINS;
    let model = seed002(0.744, Some(seed002_gain(k1, k2))).unwrap();
    let sys = model.at(36000.0, 1.5e-3).unwrap();
    let mut s = spectral(5);
    let op = s.operator(&sys).unwrap();
    let phi = op.dense();
    assert_eq!(phi.nrows(), op.dim());
    let z: Vec<f64> = (0..op.dim()).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
    let mut out = vec![0.0; op.dim()];
    op.apply(&z, &mut out, &mut Vec::new());
    let expect = &phi * nalgebra::DVector::from_column_slice(&z);
    let err = (nalgebra::DVector::from_column_slice(&out) - &expect).norm();
    assert!(err < 1e-12 * expect.norm(), "{err} vs {}", expect.norm());
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
    // the layout: graded layers at both sides of the singular instant t = 0 (= T)
    let mut s = spectral(6);
    let sys = model.at(36000.0, 1e-3).unwrap();
    s.operator(&sys).unwrap();
    let c = s.cache.as_ref().unwrap();
    let h = |i: usize| c.lengths[c.elements[i].kernel];
    let last = c.elements.len() - 1;
    // [0, σ^L R], [σ^L R, σ^{L−1} R]: the first is σ times the first two
    assert!((GRADING * (h(0) + h(1)) - h(0)).abs() < 1e-12 * h(1), "{} {}", h(0), h(1));
    let layers = SpectralOptions::new(6).layers();
    for k in 0..layers {
        assert!(h(k + 1) > h(k), "layer {k}");
        assert!((h(last - k) - h(k)).abs() < 1e-12 * h(k), "mirror {k}");
    }
}

#[test]
fn elements_end_at_the_breakpoints_and_tile_the_period() {
    let (e, x) = crate::milling::Cutter::immersion(0.1, crate::milling::Milling::Down);
    let s0 = crate::milling::Structure::from_modes(&[crate::milling::ModeShape {
        omega: 2.0 * std::f64::consts::PI * 922.0,
        zeta: 0.011,
        tool: [5.0, 0.0],
        actuator: [0.0, 0.0],
    }])
    .unwrap();
    let cutter = crate::milling::Cutter::new(2, e, x, 6e8, 2e8, crate::milling::ForceLaw::Linear).unwrap();
    let model = crate::milling::MillingModel::new(&s0, cutter, None).unwrap();
    let sys = model.at(5000.0, 1e-3).unwrap();
    let bp = sys.breakpoints();
    assert_eq!(bp.len(), 1, "{bp:?}");
    let mut s = spectral(6);
    let op = s.operator(&sys).unwrap();
    let c = s.cache.as_ref().unwrap();
    let starts: Vec<f64> = c.elements.iter().map(|e| e.t0).collect();
    assert!(starts.iter().any(|&t| (t - bp[0]).abs() < 1e-15 * sys.period()), "{starts:?} vs {bp:?}");
    let end = c.elements.last().map(|e| e.t0 + c.lengths[e.kernel]).unwrap();
    assert!((end / sys.period() - 1.0).abs() < 1e-13);
    // a/D = 0.1: only the cut (one piece, one oscillation at most per element) carries nodes
    let free = op.maps.iter().filter(|m| matches!(m, Map::Free(_))).count();
    assert!(free >= 1 && op.dim() == 2 + 6 * (c.elements.len() - free), "{free} free of {}", c.elements.len());
    // the multipliers of the operator are those of its dense matrix
    let ev = eigenvalues(&op.dense()).unwrap();
    assert!(ev[0].norm() < 1.0);
}
