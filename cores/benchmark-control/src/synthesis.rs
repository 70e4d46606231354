//! Full-order H∞ synthesis by two Riccati equations and γ-iteration (Doyle, Glover, Khargonekar
//! & Francis 1989; the formulas of Zhou, Doyle & Glover, *Robust and Optimal Control*, 1996,
//! Ch. 14–17, for `D₁₁ = 0`, `D₂₂ = 0` with the cross terms `D₁₂ᵀC₁` and `B₁D₂₁ᵀ` kept).
//!
//! For the generalised plant of [`Generalized`] with `D₁₂` of full column rank and `D₂₁` of full
//! row rank, first normalise `u = R₁₂^{-1/2}ũ`, `ỹ = R₂₁^{-1/2}y` (`R₁₂ = D₁₂ᵀD₁₂`,
//! `R₂₁ = D₂₁D₂₁ᵀ`), so that `D₁₂ᵀD₁₂ = I`, `D₂₁D₂₁ᵀ = I`. With
//! `Aₓ = A − B₂D₁₂ᵀC₁`, `Ĉ₁ = (I − D₁₂D₁₂ᵀ)C₁`, `A_y = A − B₁D₂₁ᵀC₂`, `B̂₁ = B₁(I − D₂₁ᵀD₂₁)`:
//!
//! ```text
//! X∞: Aₓᵀ X + X Aₓ − X (B₂B₂ᵀ − γ⁻²B₁B₁ᵀ) X + Ĉ₁ᵀĈ₁ = 0,
//! Y∞: A_y Y + Y A_yᵀ − Y (C₂ᵀC₂ − γ⁻²C₁ᵀC₁) Y + B̂₁B̂₁ᵀ = 0,
//! ```
//!
//! and a controller with `‖T_zw‖∞ < γ` exists iff both have stabilising solutions `X∞ ⪰ 0`,
//! `Y∞ ⪰ 0` and `ρ(X∞Y∞) < γ²`. The central controller is
//!
//! ```text
//! F = −(B₂ᵀX∞ + D₁₂ᵀC₁),  L = −(Y∞C₂ᵀ + B₁D₂₁ᵀ),  Z = (I − γ⁻²Y∞X∞)⁻¹,
//! x̂' = (A + γ⁻²B₁B₁ᵀX∞ + B₂F + ZL(C₂ + γ⁻²D₂₁B₁ᵀX∞)) x̂ − ZL y,   u = F x̂.
//! ```
//!
//! [`hinfsyn`] bisects γ (on log γ) between a level that fails and one that passes to the
//! relative width `tol`, then returns the central controller at `(1 + backoff)·γ_opt`: near
//! the optimum `I − γ⁻²Y∞X∞` is nearly singular and the controller has very fast poles. The
//! caller checks the achieved closed-loop norm independently ([`crate::norm`]).

use crate::DesignError;
use crate::riccati::care;
use crate::ss::{Generalized, StateSpace};
use nalgebra::DMatrix;

type Mat = DMatrix<f64>;

/// The outcome of a synthesis.
#[derive(Clone, Debug, PartialEq)]
pub struct Synthesis {
    /// The central controller `u = K y` at [`Synthesis::gamma`].
    pub controller: StateSpace,
    /// The level of the controller.
    pub gamma: f64,
    /// The optimal level found by bisection (the controller exists for all γ above it).
    pub gamma_opt: f64,
}

/// Symmetric inverse square root of a positive definite matrix.
fn inv_sqrt(m: &Mat) -> Result<Mat, DesignError> {
    let e = m.clone().symmetric_eigen();
    if e.eigenvalues.iter().any(|&l| l.is_nan() || l <= 0.0) {
        return Err(DesignError::Invalid(
            "D₁₂ must have full column rank and D₂₁ full row rank (regular H∞ problem)".into(),
        ));
    }
    let d = Mat::from_diagonal(&e.eigenvalues.map(|l| 1.0 / l.sqrt()));
    Ok(&e.eigenvectors * d * e.eigenvectors.transpose())
}

/// The normalised problem and the scalings that undo it.
struct Normalised {
    p: Generalized,
    su: Mat,
    sy: Mat,
}

fn normalise(p: &Generalized) -> Result<Normalised, DesignError> {
    if p.d11.iter().any(|&x| x != 0.0) {
        return Err(DesignError::Invalid("this synthesis needs D₁₁ = 0".into()));
    }
    let su = inv_sqrt(&(p.d12.transpose() * &p.d12))?;
    let sy = inv_sqrt(&(&p.d21 * p.d21.transpose()))?;
    let mut q = p.clone();
    q.b2 = &p.b2 * &su;
    q.d12 = &p.d12 * &su;
    q.c2 = &sy * &p.c2;
    q.d21 = &sy * &p.d21;
    Ok(Normalised { p: q, su, sy })
}

fn min_eig(m: &Mat) -> f64 {
    m.clone().symmetric_eigen().eigenvalues.iter().copied().fold(f64::INFINITY, f64::min)
}

/// The central controller at level `gamma` of a normalised problem, or why there is none.
fn central(p: &Generalized, gamma: f64) -> Result<StateSpace, DesignError> {
    let g2 = gamma.powi(-2);
    let (a, b1, b2, c1, c2, d12, d21) = (&p.a, &p.b1, &p.b2, &p.c1, &p.c2, &p.d12, &p.d21);
    let nz = c1.nrows();
    let nw = b1.ncols();
    let ax = a - b2 * d12.transpose() * c1;
    let c1h = (Mat::identity(nz, nz) - d12 * d12.transpose()) * c1;
    let x = care(&ax, &(b2 * b2.transpose() - b1 * b1.transpose() * g2), &(c1h.transpose() * &c1h))?;
    let ay = a - b1 * d21.transpose() * c2;
    let b1h = b1 * (Mat::identity(nw, nw) - d21.transpose() * d21);
    let y = care(&ay.transpose(), &(c2.transpose() * c2 - c1.transpose() * c1 * g2), &(&b1h * b1h.transpose()))?;
    let scale = |m: &Mat| m.norm().max(1.0);
    if min_eig(&x) < -1e-9 * scale(&x) || min_eig(&y) < -1e-9 * scale(&y) {
        return Err(DesignError::Synthesis(format!("γ = {gamma:e}: X∞ or Y∞ is not positive semidefinite")));
    }
    let rho = (&y * &x).complex_eigenvalues().iter().map(|l| l.norm()).fold(0.0, f64::max);
    if rho.is_nan() || rho >= gamma * gamma {
        return Err(DesignError::Synthesis(format!("γ = {gamma:e}: ρ(X∞Y∞) = {rho:e} ≥ γ²")));
    }
    let n = a.nrows();
    let f = -(b2.transpose() * &x + d12.transpose() * c1);
    let l = -(&y * c2.transpose() + b1 * d21.transpose());
    let z = (Mat::identity(n, n) - &y * &x * g2)
        .try_inverse()
        .ok_or_else(|| DesignError::Synthesis(format!("γ = {gamma:e}: I − γ⁻²Y∞X∞ is singular")))?;
    let zl = &z * &l;
    let c2x = c2 + d21 * b1.transpose() * &x * g2;
    let ak = a + b1 * b1.transpose() * &x * g2 + b2 * &f + &zl * c2x;
    StateSpace::new(ak, -zl, f, Mat::zeros(b2.ncols(), c2.nrows()))
}

/// Does a controller with `‖T_zw‖∞ < γ` exist (module docs)?
pub fn feasible(p: &Generalized, gamma: f64) -> Result<bool, DesignError> {
    let q = normalise(p)?;
    Ok(central(&q.p, gamma).is_ok())
}

/// The central controller at level `gamma` (module docs), in the original (unnormalised) signals.
pub fn central_controller(p: &Generalized, gamma: f64) -> Result<StateSpace, DesignError> {
    let q = normalise(p)?;
    let k = central(&q.p, gamma)?;
    // ũ = K ỹ with u = S_u ũ, ỹ = S_y y
    Ok(StateSpace { a: k.a.clone(), b: &k.b * &q.sy, c: &q.su * &k.c, d: &q.su * &k.d * &q.sy })
}

/// γ-iteration (module docs): bisection on log γ to the relative width `tol`, the central
/// controller at `(1 + backoff)·γ_opt`.
pub fn hinfsyn(p: &Generalized, tol: f64, backoff: f64) -> Result<Synthesis, DesignError> {
    let q = normalise(p)?;
    let ok = |g: f64| central(&q.p, g).is_ok();
    let mut hi = 1.0;
    let mut tries = 0;
    while !ok(hi) {
        hi *= 4.0;
        tries += 1;
        if tries > 40 {
            return Err(DesignError::Synthesis("no γ up to 4⁴⁰ is achievable".into()));
        }
    }
    let mut lo = hi;
    loop {
        lo /= 4.0;
        if !ok(lo) {
            break;
        }
        if lo < 1e-12 {
            return Err(DesignError::Synthesis("every γ down to 1e-12 is achievable (no performance channel?)".into()));
        }
    }
    while hi / lo - 1.0 > tol {
        let mid = (lo * hi).sqrt();
        if ok(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let gamma = (1.0 + backoff) * hi;
    let controller = central_controller(p, gamma)?;
    Ok(Synthesis { controller, gamma, gamma_opt: hi })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::norm::hinf_norm;

    fn m(r: usize, c: usize, v: &[f64]) -> Mat {
        Mat::from_row_slice(r, c, v)
    }

    /// A plant with every cross term present (`D₁₂ᵀC₁ ≠ 0`, `B₁D₂₁ᵀ ≠ 0`, non-unit `D₁₂`,
    /// `D₂₁`): for several levels above the optimum the central controller stabilises and its
    /// closed loop's norm, computed independently by the Hamiltonian bisection, is below γ; the
    /// optimum is a real boundary (just below it, no controller).
    #[test]
    fn central_controllers_achieve_their_level() {
        let p = Generalized {
            a: m(3, 3, &[0.0, 1.0, 0.0, -4.0, -0.1, 1.0, 0.0, 0.0, -2.0]),
            b1: m(3, 2, &[0.0, 0.0, 1.0, 0.0, 0.5, 0.0]),
            b2: m(3, 1, &[0.0, 1.0, 1.0]),
            c1: m(2, 3, &[1.0, 0.0, 0.0, 0.3, 0.0, 0.2]),
            c2: m(1, 3, &[1.0, 0.0, 0.0]),
            d11: Mat::zeros(2, 2),
            d12: m(2, 1, &[0.0, 0.7]),
            d21: m(1, 2, &[0.2, 0.05]),
        };
        let s = hinfsyn(&p, 1e-6, 0.05).unwrap();
        assert!(!feasible(&p, s.gamma_opt * (1.0 - 1e-4)).unwrap());
        for factor in [1.001, 1.05, 1.5, 4.0] {
            let gamma = s.gamma_opt * factor;
            let k = central_controller(&p, gamma).unwrap();
            let cl = p.close(&k);
            assert!(cl.spectral_abscissa() < 0.0, "γ factor {factor}: closed loop unstable");
            let nrm = hinf_norm(&cl, 1e-10).unwrap().value;
            assert!(nrm < gamma * (1.0 + 1e-8), "γ factor {factor}: ‖T_zw‖ = {nrm} ≥ γ = {gamma}");
            // and it is not trivially small: the central controller is near γ_opt near the optimum
            assert!(nrm >= s.gamma_opt * (1.0 - 1e-3), "‖T_zw‖ = {nrm} below γ_opt {}", s.gamma_opt);
        }
    }

    /// The scalar full-information problem `ẋ = −x + w + u`, `z = [x; u]`, `y = x + εn`: for
    /// ε → 0 the optimum tends to the state-feedback optimum, where `X∞` exists for all
    /// `γ > 1/√2` (the Riccati equation `x²(1 − γ⁻²) + 2x − 1 = 0` has a nonnegative stabilising
    /// root down to `1 − γ⁻² = −1`).
    #[test]
    fn scalar_problem_approaches_the_state_feedback_optimum() {
        let eps = 1e-4;
        let p = Generalized {
            a: m(1, 1, &[-1.0]),
            b1: m(1, 2, &[1.0, 0.0]),
            b2: m(1, 1, &[1.0]),
            c1: m(2, 1, &[1.0, 0.0]),
            c2: m(1, 1, &[1.0]),
            d11: Mat::zeros(2, 2),
            d12: m(2, 1, &[0.0, 1.0]),
            d21: m(1, 2, &[0.0, eps]),
        };
        let s = hinfsyn(&p, 1e-8, 0.0).unwrap();
        assert!((s.gamma_opt - 0.5f64.sqrt()).abs() < 1e-3, "γ_opt = {}", s.gamma_opt);
    }
}
