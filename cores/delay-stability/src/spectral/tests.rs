use super::*;
use crate::presets::{SEED002_GAINS, seed002, seed002_gain};
use crate::sd::eigenvalues;

fn spectral(nodes: usize) -> Spectral {
    Spectral::new(SpectralOptions::new(nodes)).unwrap()
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
fn elements_are_graded_towards_the_power_law_singularity() {
    let model = seed002(0.744, None).unwrap();
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
