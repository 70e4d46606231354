//! The upper bound of the structured singular value with full-block D scalings.
//!
//! # Bound
//!
//! For `Δ = diag(δ₁ I_{k₁}, …, Δ_F, …)` (repeated complex scalars and full complex blocks) every
//! invertible `D` that commutes with every `Δ` gives `μ_Δ(N) ≤ σ̄(D N D⁻¹)`: for a repeated
//! scalar `δ I_k` the block of `D` is any invertible `k × k` matrix (full block), for a full
//! block `Δ_F` it is `d I` with `d > 0`. The bound is `inf_D σ̄(D N D⁻¹)` (convex in `X = D*D`,
//! Doyle 1982; Packard & Doyle 1993). Each block of `D` is parameterised by a complex
//! lower-triangular factor with positive diagonal `exp(θ)` (a Cholesky factor of `X`); the
//! infimum is sought by [`crate::optim::bfgs`] on `log σ̄` (nonsmooth where `σ̄` is multiple; any
//! `D` found is a valid bound, so an inexact minimum only costs conservatism).
//!
//! Always `ρ(N) ≤ μ(N) ≤ bound ≤ σ̄(N)`; for one full block the bound is `σ̄(N)`, for one repeated
//! scalar it tends to `ρ(N)` (= μ there), and for at most three blocks of the `2S + F ≤ 3` kind
//! it equals μ (tests).
//!
//! # Gradient
//!
//! With `M = D N D⁻¹ = σ u v* + …` (top singular triplet, simple),
//!
//! ```text
//! dσ̄ = Re(u* dM v),   dM = D dN D⁻¹ + dD D⁻¹ M − M dD D⁻¹,
//! ```
//!
//! so `∂σ̄/∂D` gives `σ Re tr(dD D⁻¹ (u u* − v v*))` and `∂σ̄/∂N = D* u v* D⁻*` (used by the
//! K-step through [`crate::plant`]).

use crate::optim::{Options, bfgs};
use nalgebra::DMatrix;
use num_complex::Complex64;

/// Complex matrix.
pub type CMat = DMatrix<Complex64>;

/// One block of the uncertainty structure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Block {
    /// Repeated complex scalar `δ I_k` (full `k × k` scaling).
    Scalar(usize),
    /// Full complex `k × k` block (scaling `d I_k`).
    Full(usize),
}

impl Block {
    fn size(&self) -> usize {
        match *self {
            Block::Scalar(k) | Block::Full(k) => k,
        }
    }
    fn params(&self) -> usize {
        match *self {
            Block::Scalar(k) => k * k,
            Block::Full(_) => 1,
        }
    }
}

/// A block structure (blocks along the diagonal, in order).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Structure(pub Vec<Block>);

impl Structure {
    /// Dimension of `N`.
    pub fn dim(&self) -> usize {
        self.0.iter().map(Block::size).sum()
    }
    /// Number of real scaling parameters.
    pub fn params(&self) -> usize {
        self.0.iter().map(Block::params).sum()
    }

    /// `D(θ)` (module docs); θ = 0 is the identity.
    pub fn scaling(&self, theta: &[f64]) -> CMat {
        let n = self.dim();
        let mut d = CMat::zeros(n, n);
        let (mut o, mut p) = (0, 0);
        for b in &self.0 {
            match *b {
                Block::Scalar(k) => {
                    for i in 0..k {
                        d[(o + i, o + i)] = Complex64::from(theta[p].exp());
                        p += 1;
                    }
                    for i in 0..k {
                        for j in 0..i {
                            d[(o + i, o + j)] = Complex64::new(theta[p], theta[p + 1]);
                            p += 2;
                        }
                    }
                }
                Block::Full(k) => {
                    for i in 0..k {
                        d[(o + i, o + i)] = Complex64::from(theta[p].exp());
                    }
                    p += 1;
                }
            }
            o += b.size();
        }
        d
    }

    /// `∂σ̄/∂θ` from `W = D⁻¹(u u* − v v*)` (module docs): `σ Re Σ_ij ∂D_ij/∂θ · W_ji`.
    fn gradient(&self, theta: &[f64], d: &CMat, w: &CMat, sigma: f64) -> Vec<f64> {
        let mut g = vec![0.0; theta.len()];
        let (mut o, mut p) = (0, 0);
        for b in &self.0 {
            match *b {
                Block::Scalar(k) => {
                    for i in 0..k {
                        g[p] = sigma * (d[(o + i, o + i)] * w[(o + i, o + i)]).re;
                        p += 1;
                    }
                    for i in 0..k {
                        for j in 0..i {
                            let wji = w[(o + j, o + i)];
                            g[p] = sigma * wji.re;
                            g[p + 1] = -sigma * wji.im;
                            p += 2;
                        }
                    }
                }
                Block::Full(k) => {
                    g[p] = sigma * (0..k).map(|i| (d[(o + i, o + i)] * w[(o + i, o + i)]).re).sum::<f64>();
                    p += 1;
                }
            }
            o += b.size();
        }
        g
    }
}

/// The top singular triplet `(σ̄, u, v)` of a complex matrix.
pub fn top_singular(m: &CMat) -> (f64, nalgebra::DVector<Complex64>, nalgebra::DVector<Complex64>) {
    let svd = m.clone().svd(true, true);
    let (k, &s) = svd.singular_values.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).expect("nonempty");
    let u = svd.u.as_ref().expect("u").column(k).into_owned();
    let v = svd.v_t.as_ref().expect("v_t").row(k).adjoint();
    (s, u, v)
}

/// Inverse of a block-lower-triangular scaling (dense LU; the blocks are small).
pub fn inverse(d: &CMat) -> CMat {
    d.clone().try_inverse().expect("a scaling with positive diagonal is invertible")
}

/// `σ̄(D N D⁻¹)` and its gradient in θ.
pub fn scaled_norm(n: &CMat, s: &Structure, theta: &[f64]) -> (f64, Vec<f64>) {
    let d = s.scaling(theta);
    let di = inverse(&d);
    let m = &d * n * &di;
    let (sigma, u, v) = top_singular(&m);
    let w = &di * (&u * u.adjoint() - &v * v.adjoint());
    (sigma, s.gradient(theta, &d, &w, sigma))
}

/// A μ upper bound and the scaling that gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct Bound {
    /// `σ̄(D N D⁻¹)` at the scaling found.
    pub value: f64,
    /// The scaling parameters θ.
    pub theta: Vec<f64>,
}

/// `inf_θ σ̄(D(θ) N D(θ)⁻¹)` by BFGS on `log σ̄`, from `warm` (or θ = 0).
pub fn upper_bound(n: &CMat, s: &Structure, warm: Option<&[f64]>, max_iter: usize) -> Bound {
    assert_eq!(n.nrows(), s.dim(), "N does not match the structure");
    let x0 = warm.map_or_else(|| vec![0.0; s.params()], <[f64]>::to_vec);
    let f = |t: &[f64]| {
        let (v, g) = scaled_norm(n, s, t);
        if v > 0.0 { (v.ln(), g.iter().map(|x| x / v).collect()) } else { (f64::NEG_INFINITY, g) }
    };
    let (v0, _) = scaled_norm(n, s, &x0);
    if v0 <= 0.0 || s.params() == 0 {
        return Bound { value: v0, theta: x0 };
    }
    let o = Options { max_iter, tol: 1e-9, gs_iter: 0, line_search: 40, ..Options::default() };
    let out = bfgs(&f, &x0, &o);
    let value = scaled_norm(n, s, &out.x).0;
    if value <= v0 { Bound { value, theta: out.x } } else { Bound { value: v0, theta: x0 } }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn random(n: usize, seed: u64) -> CMat {
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        CMat::from_fn(n, n, |_, _| Complex64::new(r.random::<f64>() - 0.5, r.random::<f64>() - 0.5))
    }

    fn rho(n: &CMat) -> f64 {
        n.clone().schur().eigenvalues().expect("eig").iter().map(|z| z.norm()).fold(0.0, f64::max)
    }

    #[test]
    fn one_full_block_gives_the_largest_singular_value() {
        let n = random(5, 3);
        let b = upper_bound(&n, &Structure(vec![Block::Full(5)]), None, 100);
        let sv = top_singular(&n).0;
        assert!((b.value - sv).abs() < 1e-12 * sv, "{} vs {sv}", b.value);
    }

    #[test]
    fn one_repeated_scalar_gives_the_spectral_radius() {
        // μ of δI is ρ(N); the full-block scaling reaches it (distinct eigenvalues)
        for seed in 0..4 {
            let n = random(4, 10 + seed);
            let b = upper_bound(&n, &Structure(vec![Block::Scalar(4)]), None, 500);
            let r = rho(&n);
            assert!(b.value >= r * (1.0 - 1e-9), "{} < ρ {r}", b.value);
            assert!((b.value / r - 1.0).abs() < 1e-3, "seed {seed}: {} vs ρ {r}", b.value);
        }
    }

    #[test]
    fn two_scalar_blocks_give_the_known_value() {
        // N = [[0, b], [c, 0]], Δ = diag(δ₁, δ₂): det(I − NΔ) = 1 − bc δ₁δ₂, so μ = √|bc|
        let (b, c) = (Complex64::new(3.0, 1.0), Complex64::new(0.2, -0.5));
        let n = CMat::from_row_slice(2, 2, &[Complex64::from(0.0), b, c, Complex64::from(0.0)]);
        let bound = upper_bound(&n, &Structure(vec![Block::Scalar(1), Block::Full(1)]), None, 200);
        let mu = (b * c).norm().sqrt();
        assert!((bound.value / mu - 1.0).abs() < 1e-6, "{} vs {mu}", bound.value);
    }

    #[test]
    fn the_bound_is_between_the_spectral_radius_and_the_norm() {
        // the seed's structure: δτ on 4, δa on 2, performance 2×2
        let s = Structure(vec![Block::Scalar(4), Block::Scalar(2), Block::Full(2)]);
        for seed in 0..6 {
            let n = random(8, 100 + seed);
            let b = upper_bound(&n, &s, None, 200);
            let (r, sv) = (rho(&n), top_singular(&n).0);
            assert!(b.value >= r * (1.0 - 1e-9) && b.value <= sv * (1.0 + 1e-12), "{r} {} {sv}", b.value);
        }
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let s = Structure(vec![Block::Scalar(3), Block::Full(2)]);
        let n = random(5, 7);
        let theta: Vec<f64> = (0..s.params()).map(|k| 0.1 * ((k * 7 % 5) as f64 - 2.0)).collect();
        let (_, g) = scaled_norm(&n, &s, &theta);
        for k in 0..theta.len() {
            let h = 1e-6;
            let mut tp = theta.clone();
            tp[k] += h;
            let mut tm = theta.clone();
            tm[k] -= h;
            let fd = (scaled_norm(&n, &s, &tp).0 - scaled_norm(&n, &s, &tm).0) / (2.0 * h);
            assert!((fd - g[k]).abs() < 1e-6 * (1.0 + fd.abs()), "θ{k}: {fd} vs {}", g[k]);
        }
    }
}
