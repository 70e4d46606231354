//! The reference delay model of the controller and its Lyapunov–Krasovskii data `Q₀`, `Q(σ)`
//! and `P` (seed 001, Eqs. 6, 8–9, 14, 17).
//!
//! # Maths
//!
//! The reference model is the linearised turning equation at a stable speed:
//! `ẏ = A y + B y(t − T)` with
//!
//! ```text
//! A = [[0, 1], [−ω_n² − a₂, −a₁]],   B = [[0, 0], [a₂, 0]]
//! ```
//!
//! (Eq. 17 prints "A =" twice; the second matrix is `B`.) Eq. 14 asks for `Q(σ) = e^{Sσ}Q₀`,
//! `S = A + Q₀`, with `Q(T) = B`, i.e. `e^{ST}Q₀ = B`. Because `B = a₂ e₂e₁ᵀ`,
//! `Q₀ = e^{−ST}B` has only a first column `q = (q₁, q₂)`; the two equations
//! `e^{ST}q = (0, a₂)` are solved by Newton (central-difference Jacobian), started from the
//! `S` whose eigenvalues are the dominant characteristic pair of the delay equation.
//!
//! **Why the eigenvalues of S solve the delay equation.** If `wᵀS = λwᵀ` then
//! `wᵀe^{−ST} = e^{−λT}wᵀ`, so `wᵀ(S − A) = wᵀQ₀ = wᵀe^{−ST}B = e^{−λT}wᵀB`, i.e.
//! `wᵀ(λI − A − Be^{−λT}) = 0`: every eigenvalue of `S` is a root of
//! `Δ(λ) = det(λI − A − Be^{−λT}) = λ² + a₁λ + ω_n² + a₂(1 − e^{−λT})` (test: to 1e-9).
//!
//! **P** solves the Lyapunov equation `PS + SᵀP + R = 0` (Eq. 8) with `R = I` (the paper
//! leaves `R` free); it exists and is positive definite because `S` is Hurwitz when the
//! reference delay model is stable.
//!
//! **Why Q∗ε.** With `(Q∗ε)(t) = ∫₀^T Q(σ) ε(t − σ) dσ`, Leibniz gives
//! `d/dt (Q∗ε) = Q₀ε(t) − Bε(t−T) + S(Q∗ε)`, so for `ε̇ = Aε + Bε(t−T) + φZ` the combination
//! `z = ε + Q∗ε` obeys the delay-free `ż = Sz + φZ`: `V = zᵀPz + …` then has
//! `V̇ = −zᵀRz + 2zᵀPφZ + …`, which the adaptation laws cancel ([`crate::controller`]).

use crate::AfracError;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};
use num_complex::Complex64;
use serde::{Deserialize, Serialize};

/// The reference delay model `ẏ = Ay + By(t − T)` with its `Q₀`, `S = A + Q₀` and `P`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DelayModel {
    /// ω_n [rad/s].
    pub omega_n: f64,
    /// a₁ [1/s].
    pub a1: f64,
    /// a₂ [1/s²].
    pub a2: f64,
    /// Reference delay T [s].
    pub delay: f64,
    /// First column of Q₀ (the second is zero).
    pub q0: [f64; 2],
    /// Lyapunov matrix P (symmetric): [P₁₁, P₁₂, P₂₂].
    pub p: [f64; 3],
}

/// Δ(λ) = λ² + a₁λ + ω_n² + a₂(1 − e^{−λT}).
pub fn characteristic(lambda: Complex64, omega_n: f64, a1: f64, a2: f64, delay: f64) -> Complex64 {
    lambda * lambda + a1 * lambda + omega_n * omega_n + a2 * (1.0 - (-lambda * delay).exp())
}

/// The root of Δ nearest the structural mode (Newton from `−a₁/2 + i√(ω_n² + a₂)`).
pub fn dominant_root(omega_n: f64, a1: f64, a2: f64, delay: f64) -> Result<Complex64, AfracError> {
    let mut l = Complex64::new(-0.5 * a1, (omega_n * omega_n + a2).sqrt());
    for _ in 0..100 {
        let f = characteristic(l, omega_n, a1, a2, delay);
        let df = 2.0 * l + a1 + a2 * delay * (-l * delay).exp();
        let step = f / df;
        l -= step;
        if step.norm() <= 1e-15 * l.norm() {
            return Ok(l);
        }
    }
    Err(AfracError::Design("no characteristic root found near the structural mode".into()))
}

impl DelayModel {
    /// `A`.
    pub fn a(&self) -> Matrix2<f64> {
        Matrix2::new(0.0, 1.0, -self.omega_n * self.omega_n - self.a2, -self.a1)
    }

    /// `B`.
    pub fn b(&self) -> Matrix2<f64> {
        Matrix2::new(0.0, 0.0, self.a2, 0.0)
    }

    /// `Q₀`.
    pub fn q0(&self) -> Matrix2<f64> {
        Matrix2::new(self.q0[0], 0.0, self.q0[1], 0.0)
    }

    /// `S = A + Q₀`.
    pub fn s(&self) -> Matrix2<f64> {
        self.a() + self.q0()
    }

    /// `P`.
    pub fn p(&self) -> Matrix2<f64> {
        Matrix2::new(self.p[0], self.p[1], self.p[1], self.p[2])
    }

    /// `Q(σ) = e^{Sσ}Q₀`, first column.
    pub fn q_column(&self, sigma: f64) -> Vector2<f64> {
        (self.s() * sigma).exp() * Vector2::new(self.q0[0], self.q0[1])
    }

    /// Eigenvalues of `S`.
    pub fn eigenvalues(&self) -> [Complex64; 2] {
        let s = self.s();
        let (tr, det) = (s.trace(), s.determinant());
        let disc = Complex64::new(0.25 * tr * tr - det, 0.0).sqrt();
        [0.5 * tr + disc, 0.5 * tr - disc]
    }

    /// Solve for `Q₀` and `P`.
    pub fn new(omega_n: f64, a1: f64, a2: f64, delay: f64) -> Result<Self, AfracError> {
        if ![omega_n, a1, a2, delay].iter().all(|v| v.is_finite()) || omega_n <= 0.0 || delay <= 0.0 || a2 <= 0.0 {
            return Err(AfracError::Params(format!(
                "reference model needs ω_n > 0, a₂ > 0, T > 0 (got {omega_n}, {a2}, {delay})"
            )));
        }
        let a = Matrix2::new(0.0, 1.0, -omega_n * omega_n - a2, -a1);
        let target = Vector2::new(0.0, a2);
        let residual = |q: Vector2<f64>| ((a + Matrix2::new(q[0], 0.0, q[1], 0.0)) * delay).exp() * q - target;
        // start: the S of the same structure whose eigenvalues are the dominant pair
        let l = dominant_root(omega_n, a1, a2, delay)?;
        let q1 = 2.0 * l.re + a1;
        let s21 = -q1 * a1 - l.norm_sqr();
        let mut q = Vector2::new(q1, s21 + omega_n * omega_n + a2);
        let scale = a2;
        let mut converged = false;
        for _ in 0..100 {
            let r = residual(q);
            if r.norm() <= 1e-13 * scale {
                converged = true;
                break;
            }
            let mut jac = Matrix2::zeros();
            for j in 0..2 {
                let hj = 1e-6 * (q[j].abs() + 1.0);
                let mut qp = q;
                let mut qm = q;
                qp[j] += hj;
                qm[j] -= hj;
                jac.set_column(j, &((residual(qp) - residual(qm)) / (2.0 * hj)));
            }
            let step = jac.lu().solve(&r).ok_or_else(|| AfracError::Design("singular Newton step for Q₀".into()))?;
            q -= step;
        }
        if !converged {
            return Err(AfracError::Design("Newton for Q₀ did not converge".into()));
        }
        let s = a + Matrix2::new(q[0], 0.0, q[1], 0.0);
        let p = lyapunov(&s)?;
        Ok(DelayModel { omega_n, a1, a2, delay, q0: [q[0], q[1]], p })
    }
}

/// `P` with `PS + SᵀP + I = 0`, as [P₁₁, P₁₂, P₂₂]; refused unless positive definite.
pub fn lyapunov(s: &Matrix2<f64>) -> Result<[f64; 3], AfracError> {
    let (s11, s12, s21, s22) = (s[(0, 0)], s[(0, 1)], s[(1, 0)], s[(1, 1)]);
    let m = Matrix3::new(2.0 * s11, 2.0 * s21, 0.0, s12, s11 + s22, s21, 0.0, 2.0 * s12, 2.0 * s22);
    let p = m
        .lu()
        .solve(&Vector3::new(-1.0, 0.0, -1.0))
        .ok_or_else(|| AfracError::Design("the Lyapunov equation is singular".into()))?;
    if !(p[0] > 0.0 && p[0] * p[2] - p[1] * p[1] > 0.0) {
        return Err(AfracError::Design("P is not positive definite: the reference model is not stable".into()));
    }
    Ok([p[0], p[1], p[2]])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper() -> DelayModel {
        let wn = 2.0 * std::f64::consts::PI * 85.0;
        let a2 = 0.01994 * 5.0 * wn * wn;
        DelayModel::new(wn, 2.0 * 0.0384 * wn, a2, 60.0 / 524.0).unwrap()
    }

    #[test]
    fn eigenvalues_of_a_plus_q0_solve_the_delay_characteristic_equation() {
        let m = paper();
        let scale = m.omega_n * m.omega_n;
        for l in m.eigenvalues() {
            let r = characteristic(l, m.omega_n, m.a1, m.a2, m.delay);
            assert!(r.norm() / scale < 1e-9, "λ = {l}: |Δ|/ω_n² = {:e}", r.norm() / scale);
            assert!(l.re < 0.0);
        }
        // and they are the dominant pair
        let d = dominant_root(m.omega_n, m.a1, m.a2, m.delay).unwrap();
        let nearest = m.eigenvalues().iter().map(|l| (l - d).norm().min((l - d.conj()).norm())).fold(0.0, f64::max);
        assert!(nearest < 1e-6 * d.norm(), "{nearest}");
        // Q(T) = B
        let qt = m.q_column(m.delay);
        assert!(qt[0].abs() < 1e-10 * m.a2 && (qt[1] - m.a2).abs() < 1e-10 * m.a2, "{qt}");
        println!("S eigenvalues {:?}, Q0 = {:?}, P = {:?}", m.eigenvalues(), m.q0, m.p);
    }

    #[test]
    fn p_solves_the_lyapunov_equation() {
        let m = paper();
        let r = m.p() * m.s() + m.s().transpose() * m.p() + Matrix2::identity();
        assert!(r.norm() < 1e-9, "{r}");
    }

    #[test]
    fn an_unstable_reference_is_refused() {
        let wn = 2.0 * std::f64::consts::PI * 85.0;
        // 5 mm at 450 rpm is beyond the limit: S is not Hurwitz or Newton fails
        let r = DelayModel::new(wn, 2.0 * 0.0384 * wn, 0.01994 * 5.0 * wn * wn, 60.0 / 450.0);
        assert!(r.is_err());
        assert!(DelayModel::new(f64::NAN, 1.0, 1.0, 1.0).is_err());
    }
}
