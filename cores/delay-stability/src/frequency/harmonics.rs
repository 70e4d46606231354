//! Fourier harmonics of the directional matrix over the tooth period.

use crate::milling::{Cutter, ForceLaw};
use crate::quadrature::{GaussLegendre, exponent_for};
use nalgebra::Matrix2;
use num_complex::Complex64;
use std::f64::consts::PI;

/// `H_r`, r = 0..=`r_max`, of `H(t) = Σ_r H_r e^{i r ω_T t}` (tooth 0 at φ = Ω t; `H_{−r} = conj H_r`):
///
/// ```text
/// H_r = (z/2π) ∫_0^{2π/z} H(φ) e^{−i r z φ} dφ,    H(φ) = Cutter::directional(φ),
/// ```
///
/// `H_0 = ` [`Cutter::mean`] exactly. The pitch is split at every entry, exit and zero of `sin` of
/// every tooth, so each piece is smooth (up to the integrable `sin^{x_F−1}` of the power law at
/// its ends); each piece is cut into `⌈r/2⌉ + 1` parts integrated by 24-point Gauss–Legendre with
/// the singularity-removing substitution of [`crate::quadrature`] (error < 1e-12 against a
/// closed form and a fine trapezoid rule, tested).
pub fn directional_harmonics(cutter: &Cutter, r_max: usize) -> Vec<Matrix2<Complex64>> {
    let pitch = cutter.pitch();
    let mut cuts = vec![0.0, pitch];
    for j in 0..cutter.teeth {
        for e in [0.0, PI, cutter.entry, cutter.exit] {
            let x = (e - j as f64 * pitch).rem_euclid(2.0 * PI);
            if x > 0.0 && x < pitch {
                cuts.push(x);
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let k = match cutter.law {
        ForceLaw::Linear => 1,
        ForceLaw::Power { x_f, .. } => exponent_for(x_f - 1.0),
    };
    let rule = GaussLegendre::new(24);
    let z = cutter.teeth as f64;
    let mut out = vec![cutter.mean().map(Complex64::from)];
    for r in 1..=r_max {
        let parts = r.div_ceil(2) + 1;
        let rz = r as f64 * z;
        let (mut re, mut im) = (Matrix2::<f64>::zeros(), Matrix2::<f64>::zeros());
        for w in cuts.windows(2) {
            let h = (w[1] - w[0]) / parts as f64;
            for q in 0..parts {
                let (a, b) = (w[0] + q as f64 * h, w[0] + (q + 1) as f64 * h);
                re += rule.singular(a, b, k, |p| cutter.directional(p) * (rz * p).cos());
                im -= rule.singular(a, b, k, |p| cutter.directional(p) * (rz * p).sin());
            }
        }
        let s = z / (2.0 * PI);
        out.push(Matrix2::from_fn(|i, j| Complex64::new(re[(i, j)] * s, im[(i, j)] * s)));
    }
    out
}
