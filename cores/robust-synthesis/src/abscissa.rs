//! The spectral abscissa of `ẋ = A₀ x + B_d C_d x(t − τ)`: the largest real part of the roots of
//!
//! ```text
//! det Δ(λ) = 0,     Δ(λ) = λI − A₀ − A₁ e^{−λτ},     A₁ = B_d C_d,
//! ```
//!
//! (seed 002 Eq. 21, `Ψ(K)`). The seed uses DDE-BIFTOOL; here:
//!
//! # Discretisation (infinitesimal generator, Breda, Maset & Vermiglio, SIAM J. Sci. Comput. 27, 2005)
//!
//! The delayed term needs only the history of the `r` outputs `y = C_d x` on `[−τ, 0]`. That
//! history is represented by its values at the Chebyshev points `θ_j = (τ/2)(cos(jπ/N) − 1)`,
//! `j = 0…N` (`θ₀ = 0`, `θ_N = −τ`), with `y(θ₀) = C_d x`; the generator `d/dt y(θ) = ∂_θ y(θ)` is
//! collocated with the Chebyshev differentiation matrix, and `ẋ = A₀x + B_d y(θ_N)`. The
//! eigenvalues of the resulting `(n + rN)`-square matrix approximate the characteristic roots,
//! spectrally accurate for `|λ|τ ≪ N`.
//!
//! # Newton refinement
//!
//! The rightmost few approximations are refined by Newton on `(Δ(λ) v = 0, c*v = 1)`,
//! `Δ'(λ) = I + τ A₁ e^{−λτ}`, from the singular vector of `Δ(λ₀)`'s smallest singular value;
//! the residual `σ_min(Δ(λ))` of the result is reported.
//!
//! # Derivative
//!
//! For a simple root with right and left null vectors `v`, `u` of `Δ(λ)`, a parameter `p`
//! entering `A₀` and `A₁` moves it by
//!
//! ```text
//! dλ/dp = u* (∂A₀/∂p + e^{−λτ} ∂A₁/∂p) v / (u* (I + τ A₁ e^{−λτ}) v).
//! ```

use crate::SynthError;
use crate::mu::CMat;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use std::f64::consts::PI;

/// `ẋ = A₀ x + B_d C_d x(t − τ)`.
#[derive(Clone, Debug, PartialEq)]
pub struct DelaySystem {
    /// A₀ (n × n).
    pub a0: DMatrix<f64>,
    /// B_d (n × r).
    pub bd: DMatrix<f64>,
    /// C_d (r × n).
    pub cd: DMatrix<f64>,
    /// Delay τ > 0 \[s\].
    pub tau: f64,
}

/// A refined characteristic root.
#[derive(Clone, Debug, PartialEq)]
pub struct Root {
    /// The root λ.
    pub lambda: Complex64,
    /// Right null vector of Δ(λ).
    pub right: DVector<Complex64>,
    /// Left null vector of Δ(λ) (`u* Δ(λ) = 0`).
    pub left: DVector<Complex64>,
    /// `σ_min(Δ(λ))` at the result.
    pub residual: f64,
}

/// Chebyshev points `x_j = cos(jπ/N)` and the differentiation matrix on `[−1, 1]` (Trefethen,
/// *Spectral Methods in MATLAB*, `cheb`).
pub fn chebyshev(n: usize) -> (Vec<f64>, DMatrix<f64>) {
    let x: Vec<f64> = (0..=n).map(|j| (PI * j as f64 / n as f64).cos()).collect();
    let c = |j: usize| (if j == 0 || j == n { 2.0 } else { 1.0 }) * if j.is_multiple_of(2) { 1.0 } else { -1.0 };
    let mut d = DMatrix::zeros(n + 1, n + 1);
    for i in 0..=n {
        for j in 0..=n {
            if i != j {
                d[(i, j)] = c(i) / c(j) / (x[i] - x[j]);
            }
        }
    }
    for i in 0..=n {
        let s: f64 = (0..=n).filter(|&j| j != i).map(|j| d[(i, j)]).sum();
        d[(i, i)] = -s;
    }
    (x, d)
}

impl DelaySystem {
    /// Checks dimensions and finiteness.
    pub fn new(a0: DMatrix<f64>, bd: DMatrix<f64>, cd: DMatrix<f64>, tau: f64) -> Result<DelaySystem, SynthError> {
        let n = a0.nrows();
        let r = cd.nrows();
        if a0.ncols() != n || bd.shape() != (n, r) || cd.ncols() != n {
            return Err(SynthError::Invalid(format!(
                "A0 {:?}, B_d {:?}, C_d {:?} do not fit",
                a0.shape(),
                bd.shape(),
                cd.shape()
            )));
        }
        if !(tau.is_finite() && tau > 0.0) || a0.iter().chain(bd.iter()).chain(cd.iter()).any(|v| !v.is_finite()) {
            return Err(SynthError::Invalid(format!("need finite matrices and τ > 0 (τ = {tau})")));
        }
        Ok(DelaySystem { a0, bd, cd, tau })
    }

    /// A₁ = B_d C_d.
    pub fn a1(&self) -> DMatrix<f64> {
        &self.bd * &self.cd
    }

    /// The discretised generator (module docs) with `nodes` = N Chebyshev intervals.
    pub fn generator(&self, nodes: usize) -> DMatrix<f64> {
        let (n, r) = (self.a0.nrows(), self.cd.nrows());
        let (_, dm) = chebyshev(nodes);
        // θ = (τ/2)(x − 1): d/dθ = (2/τ) d/dx
        let s = 2.0 / self.tau;
        let dim = n + r * nodes;
        let mut g = DMatrix::zeros(dim, dim);
        g.view_mut((0, 0), (n, n)).copy_from(&self.a0);
        g.view_mut((0, n + r * (nodes - 1)), (n, r)).copy_from(&self.bd);
        for i in 1..=nodes {
            let row = n + r * (i - 1);
            // y(θ₀) = C_d x
            g.view_mut((row, 0), (r, n)).copy_from(&(&self.cd * (s * dm[(i, 0)])));
            for j in 1..=nodes {
                for k in 0..r {
                    g[(row + k, n + r * (j - 1) + k)] = s * dm[(i, j)];
                }
            }
        }
        g
    }

    /// Δ(λ).
    pub fn characteristic(&self, lambda: Complex64) -> CMat {
        let n = self.a0.nrows();
        let e = (-lambda * self.tau).exp();
        let a1 = self.a1();
        CMat::from_fn(n, n, |i, j| {
            let d = if i == j { lambda } else { Complex64::from(0.0) };
            d - self.a0[(i, j)] - a1[(i, j)] * e
        })
    }

    /// Newton refinement of an approximate root (module docs).
    pub fn refine(&self, lambda0: Complex64) -> Result<Root, SynthError> {
        let n = self.a0.nrows();
        let a1 = self.a1().map(Complex64::from);
        let mut lambda = lambda0;
        let svd = self.characteristic(lambda).svd(false, true);
        let k = argmin(svd.singular_values.as_slice());
        let mut v: DVector<Complex64> = svd.v_t.expect("v_t").row(k).adjoint();
        let c = v.clone();
        for _ in 0..30 {
            let delta = self.characteristic(lambda);
            let dd = CMat::identity(n, n) + &a1 * ((-lambda * self.tau).exp() * self.tau);
            let mut jac = CMat::zeros(n + 1, n + 1);
            jac.view_mut((0, 0), (n, n)).copy_from(&delta);
            jac.view_mut((0, n), (n, 1)).copy_from(&(&dd * &v));
            jac.view_mut((n, 0), (1, n)).copy_from(&c.adjoint());
            let mut rhs = DVector::zeros(n + 1);
            rhs.rows_mut(0, n).copy_from(&(-(&delta * &v)));
            rhs[n] = Complex64::from(1.0) - c.dotc(&v);
            let Some(step) = jac.lu().solve(&rhs) else { break };
            v += step.rows(0, n);
            lambda += step[n];
            if step[n].norm() <= 1e-13 * lambda.norm().max(1.0) {
                break;
            }
        }
        let svd = self.characteristic(lambda).svd(true, true);
        let k = argmin(svd.singular_values.as_slice());
        let residual = svd.singular_values[k];
        let right: DVector<Complex64> = svd.v_t.expect("v_t").row(k).adjoint();
        let left = svd.u.expect("u").column(k).into_owned();
        if !lambda.re.is_finite() {
            return Err(SynthError::Eigen(format!("Newton diverged from {lambda0}")));
        }
        Ok(Root { lambda, right, left, residual })
    }

    /// The rightmost root: the `candidates` rightmost eigenvalues of the generator with
    /// `Im ≥ 0`, each refined, the largest real part kept.
    pub fn rightmost(&self, nodes: usize, candidates: usize) -> Result<Root, SynthError> {
        if nodes < 2 {
            return Err(SynthError::Invalid(format!("need at least 2 Chebyshev intervals (got {nodes})")));
        }
        let g = self.generator(nodes);
        let dim = g.nrows();
        let ev = g.try_schur(1e-14, 100 * dim).ok_or_else(|| SynthError::Eigen(format!("{dim}×{dim} generator")))?;
        let mut ev: Vec<Complex64> = ev.complex_eigenvalues().iter().copied().filter(|z| z.im >= -1e-9).collect();
        ev.sort_by(|a, b| b.re.total_cmp(&a.re));
        let mut best: Option<Root> = None;
        for &z in ev.iter().take(candidates.max(1)) {
            // a Newton run that jumped far away from its start is not this root
            let near = 0.2 * z.norm().max(1.0 / self.tau);
            let root = match self.refine(z) {
                Ok(r) if (r.lambda - z).norm() <= near => r,
                _ => self.refine_fixed(z),
            };
            if best.as_ref().is_none_or(|b| root.lambda.re > b.lambda.re) {
                best = Some(root);
            }
        }
        best.ok_or_else(|| SynthError::Eigen("no eigenvalue of the generator".into()))
    }

    /// The unrefined root with its singular vectors.
    fn refine_fixed(&self, lambda: Complex64) -> Root {
        let svd = self.characteristic(lambda).svd(true, true);
        let k = argmin(svd.singular_values.as_slice());
        Root {
            lambda,
            residual: svd.singular_values[k],
            right: svd.v_t.expect("v_t").row(k).adjoint(),
            left: svd.u.expect("u").column(k).into_owned(),
        }
    }

    /// The denominator `u* (I + τ A₁ e^{−λτ}) v` of the root's derivative (module docs).
    pub fn sensitivity_denominator(&self, root: &Root) -> Complex64 {
        let n = self.a0.nrows();
        let dd = CMat::identity(n, n) + self.a1().map(Complex64::from) * ((-root.lambda * self.tau).exp() * self.tau);
        root.left.dotc(&(dd * &root.right))
    }
}

fn argmin(v: &[f64]) -> usize {
    v.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)).map_or(0, |(k, _)| k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scalar_delay_equation_has_the_lambert_w_root() {
        // ẋ = −x(t − 1): λ = W₀(−1) = −0.318131505204764 + 1.337235701430690i
        let sys =
            DelaySystem::new(DMatrix::zeros(1, 1), DMatrix::from_element(1, 1, -1.0), DMatrix::identity(1, 1), 1.0)
                .unwrap();
        let r = sys.rightmost(20, 4).unwrap();
        assert!((r.lambda.re + 0.318131505204764).abs() < 1e-12, "{}", r.lambda);
        assert!((r.lambda.im - 1.33723570143069).abs() < 1e-12, "{}", r.lambda);
        assert!(r.residual < 1e-12);
    }

    #[test]
    fn delayed_oscillator_roots_satisfy_the_characteristic_equation_and_match_the_semi_discretisation() {
        // ẍ + 2ζω ẋ + ω² x = −k x(t − τ) (state (x, ẋ), delayed output x)
        let (w, zeta, k, tau) = (2.0 * PI * 100.0, 0.02, 2.0e5, 3e-3);
        let a0 = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -w * w, -2.0 * zeta * w]);
        let bd = DMatrix::from_row_slice(2, 1, &[0.0, -k]);
        let cd = DMatrix::from_row_slice(1, 2, &[1.0, 0.0]);
        let sys = DelaySystem::new(a0.clone(), bd.clone(), cd.clone(), tau).unwrap();
        let r = sys.rightmost(30, 6).unwrap();
        // characteristic equation λ² + 2ζωλ + ω² + k e^{−λτ} = 0
        let l = r.lambda;
        let res = l * l + 2.0 * zeta * w * l + w * w + k * (-l * tau).exp();
        assert!(res.norm() < 1e-8 * w * w, "residual {res}");
        // spectral discretisation with more nodes: same root
        let r2 = sys.rightmost(50, 6).unwrap();
        assert!((r2.lambda - l).norm() < 1e-9 * l.norm(), "{} vs {l}", r2.lambda);
        // ln ρ(Φ)/τ of the semi-discretisation (delay_stability, an independent method)
        struct Lti(DMatrix<f64>, DMatrix<f64>, DMatrix<f64>, f64);
        impl delay_stability::PeriodicDde for Lti {
            fn dim(&self) -> usize {
                2
            }
            fn period(&self) -> f64 {
                self.3
            }
            fn delayed_output(&self) -> DMatrix<f64> {
                self.2.clone()
            }
            fn averaged(&self, _: f64, _: f64) -> (DMatrix<f64>, DMatrix<f64>) {
                (self.0.clone(), self.1.clone())
            }
        }
        let mult = delay_stability::sd::critical_multiplier(&Lti(a0, bd, cd, tau), 200).unwrap();
        let sd = mult.rho.ln() / tau;
        assert!((sd - l.re).abs() < 1e-3 * l.norm(), "SD {sd} vs {}", l.re);
    }

    #[test]
    fn root_derivative_matches_finite_differences() {
        let (w, zeta, tau) = (2.0 * PI * 100.0, 0.02, 3e-3);
        let sys = |k: f64| {
            DelaySystem::new(
                DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -w * w, -2.0 * zeta * w]),
                DMatrix::from_row_slice(2, 1, &[0.0, -k]),
                DMatrix::from_row_slice(1, 2, &[1.0, 0.0]),
                tau,
            )
            .unwrap()
        };
        let k = 2.0e5;
        let s = sys(k);
        let r = s.rightmost(30, 6).unwrap();
        // ∂A₁/∂k = [[0, 0], [−1, 0]]
        let da1 = CMat::from_row_slice(2, 2, &[0.0.into(), 0.0.into(), (-1.0).into(), 0.0.into()]);
        let num = r.left.dotc(&(da1 * (-r.lambda * tau).exp() * &r.right));
        let d = num / s.sensitivity_denominator(&r);
        let h = 1.0;
        let fd =
            (sys(k + h).refine(r.lambda).unwrap().lambda - sys(k - h).refine(r.lambda).unwrap().lambda) / (2.0 * h);
        assert!((fd - d).norm() < 1e-5 * fd.norm(), "{fd} vs {d}");
    }
}
