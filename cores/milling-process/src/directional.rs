//! Averaged (zero-order) directional matrix of the linearised process, and the averaged cubic
//! law of seed 003 (Eq. 6).
//!
//! # Directional matrix
//!
//! Linearising the tooth force about the nominal chip `h₀ = f_z sin φ` gives the dynamic force
//! on the tool `F = A₀ (r(t) − r(t − τ))` with
//!
//! `A₀ = Z/(2π) ∫_{φ_st}^{φ_ex} H(φ) dφ`,
//! `H(φ) = −[F_t'(h₀) (cos φ, −sin φ)ᵀ + F_r'(h₀) (sin φ, cos φ)ᵀ] (sin φ, cos φ)`
//!
//! (seed 002, Eq. 9, averaged over a revolution; `F'` the slope of the law). For the power law
//! with `x_F < 1`, `F' ∝ (sin φ)^{x_F−1}` is singular where the window touches `φ = 0` or `π`; the
//! singularity is integrable. [`directional_matrix`] averages `H` over `m` equal sub-intervals
//! (4-point Gauss–Legendre on each: no node sits on the singular end), which converges like
//! `m^{−x_F}`; [`directional_matrix_reference`] removes the singularity by the substitution
//! `φ = φ_st + (φ_ex − φ_st) g(g(g(s)))`, `g(s) = (1 − cos πs)/2` (each `g` squares the
//! behaviour at both ends, so the integrand becomes `O(s^{8 x_F − 1})`) and integrates with
//! many Gauss–Legendre panels: the slow, accurate path the fast one is tested against.
//!
//! # Seed 003, Eq. 6
//!
//! Eq. 5 is the average over the window of the same tooth force, with the polynomial law in the
//! dynamic chip `h = Δx sin φ + Δy cos φ` (no feed term, no loss of contact): the force on the
//! workpiece `(Z/2π) ∫ [F_t (cos φ, −sin φ) + F_r (sin φ, cos φ)] dφ`. Expanding `h^p` gives the
//! coefficient of `Δx^a Δy^b` as `C(a+b, a) ∫ sin^a φ cos^b φ (ξ cos φ + δ sin φ) dφ` for `F_x`
//! and the analogous one for `F_y`; [`cubic_average`] evaluates these integrals (exact
//! trigonometric polynomials, Gauss–Legendre to rounding) in the paper's layout.

use crate::params::ProcessParams;
use std::f64::consts::PI;

/// 4-point Gauss–Legendre nodes and weights on [−1, 1].
const GL4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];

/// `H(φ)` (module docs) at nominal feed `feed` [m], row-major.
pub fn h_matrix(p: &ProcessParams, feed: f64, phi: f64) -> [[f64; 2]; 2] {
    let (s, c) = phi.sin_cos();
    if p.coefficients.law == crate::params::ForceLaw::Power && feed * s <= 0.0 {
        return [[0.0; 2]; 2]; // the power law's slope at a zero chip: a measure-zero set of angles
    }
    let (dt, dr) = p.tooth_force_slope(feed * s);
    let f = [-(dt * c + dr * s), -(-dt * s + dr * c)];
    [[f[0] * s, f[0] * c], [f[1] * s, f[1] * c]]
}

fn add(a: &mut [[f64; 2]; 2], b: [[f64; 2]; 2], w: f64) {
    for i in 0..2 {
        for j in 0..2 {
            a[i][j] += w * b[i][j];
        }
    }
}

/// `A₀` [N/m] by averaging `H` over `m` equal sub-intervals of the engagement window.
pub fn directional_matrix(p: &ProcessParams, feed: f64, m: usize) -> [[f64; 2]; 2] {
    let (st, ex) = p.engagement();
    let w = (ex - st) / m as f64;
    let mut a = [[0.0; 2]; 2];
    for i in 0..m {
        let mid = st + (i as f64 + 0.5) * w;
        for (x, wt) in GL4 {
            add(&mut a, h_matrix(p, feed, mid + 0.5 * w * x), 0.5 * w * wt);
        }
    }
    let z = p.teeth as f64 / (2.0 * PI);
    a.map(|r| r.map(|v| v * z))
}

/// `A₀` by the singularity-removing substitution (module docs), `panels` Gauss–Legendre panels.
pub fn directional_matrix_reference(p: &ProcessParams, feed: f64, panels: usize) -> [[f64; 2]; 2] {
    let (st, ex) = p.engagement();
    // g and its derivative, composed three times
    let g = |s: f64| ((1.0 - (PI * s).cos()) / 2.0, PI / 2.0 * (PI * s).sin());
    let mut a = [[0.0; 2]; 2];
    let w = 1.0 / panels as f64;
    for i in 0..panels {
        let mid = (i as f64 + 0.5) * w;
        for (x, wt) in GL4 {
            let s = mid + 0.5 * w * x;
            let (g1, d1) = g(s);
            let (g2, d2) = g(g1);
            let (g3, d3) = g(g2);
            let phi = st + (ex - st) * g3;
            add(&mut a, h_matrix(p, feed, phi), 0.5 * w * wt * (ex - st) * d1 * d2 * d3);
        }
    }
    let z = p.teeth as f64 / (2.0 * PI);
    a.map(|r| r.map(|v| v * z))
}

/// Seed 003 Eq. 5's coefficients in the paper's layout (without the `±Z/2π` factor):
/// `[ζ₁, η₁, ζ₂, η₂, ζ₃, η₃, γ₁, γ₂, γ₃, γ₄]` for `F_x`, and the starred ones for `F_y`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubicAverage {
    /// Unstarred coefficients (F_x).
    pub x: [f64; 10],
    /// Starred coefficients (F_y, which Eq. 5 writes with a leading minus).
    pub y: [f64; 10],
}

/// `∫_a^b sin^i φ cos^j φ dφ` by 32 panels of 4-point Gauss–Legendre (a polynomial of degree ≤ 5
/// in sin and cos: converged to rounding).
fn trig_integral(i: i32, j: i32, a: f64, b: f64) -> f64 {
    let n = 32;
    let w = (b - a) / n as f64;
    let mut acc = 0.0;
    for k in 0..n {
        let mid = a + (k as f64 + 0.5) * w;
        for (x, wt) in GL4 {
            let (s, c) = (mid + 0.5 * w * x).sin_cos();
            acc += 0.5 * w * wt * s.powi(i) * c.powi(j);
        }
    }
    acc
}

/// Eq. 6 for the window `[st, ex]` from the tangential `ξ₁..ξ₄` and radial `δ₁..δ₄`
/// coefficients of `h³, h², h, 1`.
pub fn cubic_average(xi: &[f64; 4], delta: &[f64; 4], st: f64, ex: f64) -> CubicAverage {
    let binom = |n: i32, k: i32| -> f64 { (1..=k).fold(1.0, |acc, i| acc * f64::from(n - k + i) / f64::from(i)) };
    let int = |a: i32, b: i32| trig_integral(a, b, st, ex);
    // coefficient of Δx^a Δy^b in ∫ (F_t cos + F_r sin) and in ∫ (F_t sin − F_r cos)
    let coef = |a: i32, b: i32| -> (f64, f64) {
        let i = (3 - (a + b)) as usize; // ξ index of the power a + b
        let c = binom(a + b, a);
        let fx = c * (xi[i] * int(a, b + 1) + delta[i] * int(a + 1, b));
        let fy = c * (xi[i] * int(a + 1, b) - delta[i] * int(a, b + 1));
        (fx, fy)
    };
    // (a, b, divisor): ζ₁, η₁, ζ₂, η₂, ζ₃, η₃, 3γ₁, 3γ₂, 2γ₃, γ₄
    let layout = [
        (3, 0, 1.0),
        (0, 3, 1.0),
        (2, 0, 1.0),
        (0, 2, 1.0),
        (1, 0, 1.0),
        (0, 1, 1.0),
        (2, 1, 3.0),
        (1, 2, 3.0),
        (1, 1, 2.0),
        (0, 0, 1.0),
    ];
    let mut out = CubicAverage { x: [0.0; 10], y: [0.0; 10] };
    for (k, (a, b, d)) in layout.into_iter().enumerate() {
        let (fx, fy) = coef(a, b);
        out.x[k] = fx / d;
        out.y[k] = fy / d;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::ForceLaw;

    fn rel(a: [[f64; 2]; 2], b: [[f64; 2]; 2]) -> f64 {
        let n = b.iter().flatten().map(|x| x.abs()).fold(0.0, f64::max);
        a.iter().flatten().zip(b.iter().flatten()).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / n
    }

    #[test]
    fn linear_full_immersion_four_teeth_is_the_instantaneous_sum() {
        // x_F = 1, full immersion, Z = 4: Σ_j H(φ_j) = −K_r I + K_t J at every angle (seed 002 §3.1),
        // so the average is that constant: A₀ = a_p (−K_r I + K_t J)
        let p = ProcessParams { radial_engagement: 16e-3, ..Default::default() };
        let (kt, kr, ap) = (p.coefficients.kt, p.coefficients.kr, p.axial_depth);
        let exact = [[-ap * kr, -ap * kt], [ap * kt, -ap * kr]];
        assert!(rel(directional_matrix(&p, 5e-5, 16), exact) < 1e-12);
        assert!(rel(directional_matrix_reference(&p, 5e-5, 64), exact) < 1e-12);
        let theta: f64 = 0.3;
        let mut sum = [[0.0; 2]; 2];
        for j in 0..4 {
            let phi = theta + j as f64 * PI / 2.0;
            if phi.rem_euclid(2.0 * PI) <= PI {
                add(&mut sum, h_matrix(&p, 5e-5, phi.rem_euclid(2.0 * PI)), 1.0);
            }
        }
        assert!(rel(sum, exact) < 1e-12);
    }

    #[test]
    fn power_law_sub_interval_averages_converge_to_the_reference() {
        // seed 002: x_F = 0.744, full immersion (singular at both ends)
        let mut p = ProcessParams { radial_engagement: 16e-3, ..Default::default() };
        p.coefficients.law = ForceLaw::Power;
        p.coefficients.exponent = 0.744;
        p.coefficients.kt = 462.0 * 1e3f64.powf(1.744); // 462 N/mm^(1+x_F) in N/m^(1+x_F)
        p.coefficients.kr = 38.6 * 1e3f64.powf(1.744);
        let feed = 0.2e-3;
        let r1 = directional_matrix_reference(&p, feed, 2000);
        let r2 = directional_matrix_reference(&p, feed, 4000);
        assert!(rel(r1, r2) < 1e-10, "reference not converged: {}", rel(r1, r2));
        let errs: Vec<f64> =
            [8, 32, 128, 512, 2048].iter().map(|&m| rel(directional_matrix(&p, feed, m), r2)).collect();
        println!("A0 = {r2:?} N/m; relative error at m = 8, 32, 128, 512, 2048 sub-intervals: {errs:?}");
        for w in errs.windows(2) {
            let order = (w[0] / w[1]).ln() / 4f64.ln();
            assert!(order > 0.6 && order < 1.0, "observed order {order} (errors {errs:?})");
        }
        assert!(errs[4] < 1e-3, "{errs:?}");
    }

    #[test]
    fn cubic_average_is_seed_003_eq_6() {
        let (xi, d) = ([6700e9, -4900e6, 3000e3, 1700.0], [13000e9, -7200e6, 13.0, 25.0]);
        let q = PI / 4.0;
        let eq6_x = [
            (xi[0] + 3.0 * q * d[0]) / 4.0,
            (d[0] + 3.0 * q * xi[0]) / 4.0,
            (xi[1] + 2.0 * d[1]) / 3.0,
            (d[1] + 2.0 * xi[1]) / 3.0,
            (xi[2] + 2.0 * q * d[2]) / 2.0,
            (d[2] + 2.0 * q * xi[2]) / 2.0,
            (d[0] + q * xi[0]) / 4.0,
            (xi[0] + q * d[0]) / 4.0,
            (d[1] + xi[1]) / 3.0,
            xi[3] + d[3],
        ];
        let eq6_y = [
            (-d[0] + 3.0 * q * xi[0]) / 4.0,
            (xi[0] - 3.0 * q * d[0]) / 4.0,
            (-d[1] + 2.0 * xi[1]) / 3.0,
            (xi[1] - 2.0 * d[1]) / 3.0,
            (-d[2] + 2.0 * q * xi[2]) / 2.0,
            (xi[2] - 2.0 * q * d[2]) / 2.0,
            (xi[0] - q * d[0]) / 4.0,
            (-d[0] + q * xi[0]) / 4.0,
            (xi[1] - d[1]) / 3.0,
            -d[3] + xi[3],
        ];
        let ours = cubic_average(&xi, &d, 0.0, PI / 2.0);
        for k in 0..10 {
            for (a, b, w) in [(ours.x[k], eq6_x[k], "x"), (ours.y[k], eq6_y[k], "y")] {
                assert!((a - b).abs() <= 1e-12 * b.abs(), "{w}[{k}]: {a} vs Eq. 6 {b}");
            }
        }
    }
}
