//! Continuous algebraic Riccati and Lyapunov equations.
//!
//! The CARE `AᵀX + XA − XGX + Q = 0` (`G`, `Q` symmetric) has the Hamiltonian
//! `H = [[A, −G], [−Q, −Aᵀ]]`; its stabilising solution (`A − GX` Hurwitz) spans the stable
//! invariant subspace `[I; X]` of `H`. Three independent solvers:
//!
//! * [`care`] (the one the designs use): the **matrix sign function** of `H` by the Newton
//!   iteration `Z ← (cZ + (cZ)⁻¹)/2` with determinant scaling `c = |det Z|^{−1/2n}` (Roberts
//!   1971, Byers 1987); the stable subspace is the null space of `sign(H) + I`, so `X` solves
//!   the overdetermined `[Z₁₂; Z₂₂ + I] X = −[Z₁₁ + I; Z₂₁]` (least squares). `G` may be
//!   indefinite (the H∞ Riccati equations).
//! * [`care_eigenvectors`]: the stable eigenvectors `[U₁; U₂]` of `H` (each from the null
//!   space of `H − λI` by a complex SVD), `X = Re(U₂ U₁⁻¹)` (Laub's method with
//!   eigenvectors instead of Schur vectors; needs distinct stable eigenvalues).
//! * [`care_newton_kleinman`]: Kleinman's iteration `(A − GXₖ)ᵀXₖ₊₁ + Xₖ₊₁(A − GXₖ) + Q + XₖGXₖ
//!   = 0` from a stabilising `X₀` (a Lyapunov equation per step), quadratically convergent for
//!   `G ⪰ 0`.
//!
//! [`lyapunov`] solves `AX + XAᵀ + Q = 0` by its Kronecker form (the orders here are ≤ 14).
//! [`lqr`] and [`kalman`] are the two CAREs of an LQG design.

use crate::DesignError;
use nalgebra::DMatrix;
use num_complex::Complex64;

type Mat = DMatrix<f64>;

fn symmetric(x: &Mat) -> Mat {
    (x + x.transpose()) * 0.5
}

/// The relative residual `‖AᵀX + XA − XGX + Q‖_F / (‖AᵀX‖_F + ‖XGX‖_F + ‖Q‖_F)`.
pub fn care_residual(a: &Mat, g: &Mat, q: &Mat, x: &Mat) -> f64 {
    let ax = a.transpose() * x;
    let xgx = x * g * x;
    let r = &ax + ax.transpose() - &xgx + q;
    r.norm() / (2.0 * ax.norm() + xgx.norm() + q.norm()).max(f64::MIN_POSITIVE)
}

/// The largest real part of the eigenvalues of `m`.
pub fn abscissa(m: &Mat) -> f64 {
    if m.nrows() == 0 {
        return f64::NEG_INFINITY;
    }
    m.complex_eigenvalues().iter().map(|l| l.re).fold(f64::NEG_INFINITY, f64::max)
}

fn hamiltonian(a: &Mat, g: &Mat, q: &Mat) -> Result<Mat, DesignError> {
    let n = a.nrows();
    if a.ncols() != n || g.shape() != (n, n) || q.shape() != (n, n) {
        return Err(DesignError::Invalid("CARE: A, G and Q must be square of one size".into()));
    }
    if ![a, g, q].iter().all(|m| m.iter().all(|x| x.is_finite())) {
        return Err(DesignError::Invalid("CARE: the matrices must be finite".into()));
    }
    let mut h = Mat::zeros(2 * n, 2 * n);
    h.view_mut((0, 0), (n, n)).copy_from(a);
    h.view_mut((0, n), (n, n)).copy_from(&(-g));
    h.view_mut((n, 0), (n, n)).copy_from(&(-q));
    h.view_mut((n, n), (n, n)).copy_from(&(-a.transpose()));
    Ok(h)
}

/// The largest relative residual a solution may have.
pub const RESIDUAL_TOL: f64 = 1e-8;

/// Accept `x` only if it is finite, solves the equation (relative residual below
/// [`RESIDUAL_TOL`]) and is stabilising (`A − GX` Hurwitz).
fn stabilising(a: &Mat, g: &Mat, q: &Mat, x: Mat, method: &str) -> Result<Mat, DesignError> {
    if !x.iter().all(|v| v.is_finite()) {
        return Err(DesignError::Riccati(format!("{method}: the solution is not finite")));
    }
    let res = care_residual(a, g, q, &x);
    if res.is_nan() || res > RESIDUAL_TOL {
        return Err(DesignError::Riccati(format!("{method}: relative residual {res:e} (no solution?)")));
    }
    let s = abscissa(&(a - g * &x));
    if s.is_nan() || s >= 0.0 {
        return Err(DesignError::Riccati(format!("{method}: A − GX is not stable (abscissa {s:e})")));
    }
    Ok(x)
}

/// The stabilising solution of `AᵀX + XA − XGX + Q = 0` by the matrix sign function (module
/// docs). Fails when `H` has eigenvalues on (or too near) the imaginary axis, or when the
/// stable subspace is not a graph `[I; X]`.
pub fn care(a: &Mat, g: &Mat, q: &Mat) -> Result<Mat, DesignError> {
    let n = a.nrows();
    let h = hamiltonian(a, g, q)?;
    if n == 0 {
        return Ok(Mat::zeros(0, 0));
    }
    let mut z = h;
    let mut scale = true;
    let mut converged = false;
    for _ in 0..100 {
        let lu = z.clone().lu();
        let det = lu.determinant();
        let inv = lu.try_inverse().ok_or_else(|| {
            DesignError::Riccati("sign function: singular iterate (an eigenvalue on the imaginary axis)".into())
        })?;
        let c = if scale && det.is_finite() && det != 0.0 { (-det.abs().ln() / (2 * n) as f64).exp() } else { 1.0 };
        let next = (&z * c + inv / c) * 0.5;
        let change = (&next - &z).norm();
        let size = next.norm();
        z = next;
        if !size.is_finite() {
            break;
        }
        if change < 1e-2 * size {
            scale = false;
        }
        if change <= 1e-13 * size {
            converged = true;
            break;
        }
    }
    let id2 = Mat::identity(2 * n, 2 * n);
    if !converged || (&z * &z - &id2).norm() > 1e-8 * z.norm_squared().max(1.0) {
        return Err(DesignError::Riccati(
            "sign function did not converge (eigenvalues of the Hamiltonian on the imaginary axis?)".into(),
        ));
    }
    let id = Mat::identity(n, n);
    let mut m = Mat::zeros(2 * n, n);
    m.view_mut((0, 0), (n, n)).copy_from(&z.view((0, n), (n, n)));
    m.view_mut((n, 0), (n, n)).copy_from(&(z.view((n, n), (n, n)) + &id));
    let mut rhs = Mat::zeros(2 * n, n);
    rhs.view_mut((0, 0), (n, n)).copy_from(&(-(z.view((0, 0), (n, n)) + &id)));
    rhs.view_mut((n, 0), (n, n)).copy_from(&(-z.view((n, 0), (n, n))));
    let mut x = symmetric(
        &m.svd(true, true)
            .solve(&rhs, 1e-14)
            .map_err(|e| DesignError::Riccati(format!("sign function: least-squares solve failed ({e})")))?,
    );
    // up to three Newton steps (Kleinman's form, valid for any symmetric G near the solution)
    // when the sign function's accuracy suffers from conditioning; a step is kept only if it
    // lowers the residual
    let mut res = care_residual(a, g, q, &x);
    for _ in 0..3 {
        if res.is_nan() || res <= 1e-13 {
            break;
        }
        let ak = a - g * &x;
        let Ok(next) = lyapunov(&ak.transpose(), &(q + &x * g * &x)) else { break };
        let r = care_residual(a, g, q, &next);
        if r.is_nan() || r >= res {
            break;
        }
        (x, res) = (next, r);
    }
    stabilising(a, g, q, x, "sign function")
}

/// The stabilising CARE solution from the stable eigenvectors of the Hamiltonian (module docs).
pub fn care_eigenvectors(a: &Mat, g: &Mat, q: &Mat) -> Result<Mat, DesignError> {
    let n = a.nrows();
    let h = hamiltonian(a, g, q)?;
    let hc = h.map(Complex64::from);
    let stable: Vec<Complex64> = h.complex_eigenvalues().iter().copied().filter(|l| l.re < 0.0).collect();
    if stable.len() != n {
        return Err(DesignError::Riccati(format!("the Hamiltonian has {} stable eigenvalues, not {n}", stable.len())));
    }
    let mut u = DMatrix::<Complex64>::zeros(2 * n, n);
    for (k, &l) in stable.iter().enumerate() {
        let shifted = &hc - DMatrix::<Complex64>::identity(2 * n, 2 * n) * l;
        let svd = shifted.svd(false, true);
        let v_t = svd.v_t.ok_or_else(|| DesignError::Riccati("SVD without vectors".into()))?;
        let (i, _) = svd.singular_values.iter().enumerate().min_by(|x, y| x.1.total_cmp(y.1)).expect("nonempty");
        u.set_column(k, &v_t.row(i).adjoint());
    }
    let u1 = u.view((0, 0), (n, n)).into_owned();
    let u2 = u.view((n, 0), (n, n)).into_owned();
    let u1_inv =
        u1.try_inverse().ok_or_else(|| DesignError::Riccati("the stable subspace is not a graph [I; X]".into()))?;
    let x = (u2 * u1_inv).map(|z| z.re);
    stabilising(a, g, q, symmetric(&x), "Hamiltonian eigenvectors")
}

/// `AX + XAᵀ + Q = 0` by the Kronecker form `(I ⊗ A + A ⊗ I) vec X = −vec Q`.
pub fn lyapunov(a: &Mat, q: &Mat) -> Result<Mat, DesignError> {
    let n = a.nrows();
    let mut k = Mat::zeros(n * n, n * n);
    for i in 0..n {
        for j in 0..n {
            // vec index of X[(i, j)] (column-major): i + n j
            for l in 0..n {
                k[(i + n * j, l + n * j)] += a[(i, l)]; // (A X)_{ij} = Σ_l A_il X_lj
                k[(i + n * j, i + n * l)] += a[(j, l)]; // (X Aᵀ)_{ij} = Σ_l X_il A_jl
            }
        }
    }
    let rhs = Mat::from_iterator(n * n, 1, q.iter().map(|v| -v));
    let x = k.lu().solve(&rhs).ok_or_else(|| DesignError::Riccati("singular Lyapunov equation".into()))?;
    Ok(symmetric(&Mat::from_iterator(n, n, x.iter().copied())))
}

/// Kleinman's Newton iteration from a stabilising `x0` (module docs), to a relative change of
/// `tol`, at most `max_iter` steps.
pub fn care_newton_kleinman(
    a: &Mat,
    g: &Mat,
    q: &Mat,
    x0: &Mat,
    tol: f64,
    max_iter: usize,
) -> Result<Mat, DesignError> {
    hamiltonian(a, g, q)?;
    let mut x = x0.clone();
    let s = abscissa(&(a - g * &x));
    if s.is_nan() || s >= 0.0 {
        return Err(DesignError::Riccati(format!("Newton–Kleinman: X₀ is not stabilising (abscissa {s:e})")));
    }
    for _ in 0..max_iter {
        let ak = a - g * &x;
        let next = lyapunov(&ak.transpose(), &(q + &x * g * &x))?;
        let change = (&next - &x).norm();
        x = next;
        if change <= tol * x.norm().max(f64::MIN_POSITIVE) {
            return stabilising(a, g, q, x, "Newton–Kleinman");
        }
    }
    Err(DesignError::Riccati(format!("Newton–Kleinman did not converge in {max_iter} steps")))
}

/// The LQR of `ẋ = Ax + Bu`, cost `∫ xᵀQx + uᵀRu`: the gain `K = R⁻¹BᵀX` (`u = −Kx`) and `X`.
pub fn lqr(a: &Mat, b: &Mat, q: &Mat, r: &Mat) -> Result<(Mat, Mat), DesignError> {
    let ri = r.clone().try_inverse().ok_or_else(|| DesignError::Invalid("LQR: R is singular".into()))?;
    let x = care(a, &(b * &ri * b.transpose()), q)?;
    Ok((ri * b.transpose() * &x, x))
}

/// The steady-state Kalman filter of `ẋ = Ax + w`, `y = Cx + v`, `E[w wᵀ] = W δ`,
/// `E[v vᵀ] = V δ`: the gain `L = PCᵀV⁻¹` (`x̂' = Ax̂ + L(y − Cx̂) + …`) and the error
/// covariance `P` (the dual CARE).
pub fn kalman(a: &Mat, c: &Mat, w: &Mat, v: &Mat) -> Result<(Mat, Mat), DesignError> {
    let vi = v.clone().try_inverse().ok_or_else(|| DesignError::Invalid("Kalman: V is singular".into()))?;
    let p = care(&a.transpose(), &(c.transpose() * &vi * c), w)?;
    Ok((&p * c.transpose() * vi, p))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(rows: usize, cols: usize, v: &[f64]) -> Mat {
        Mat::from_row_slice(rows, cols, v)
    }

    /// Scalar CARE `2ax − (b²/r)x² + q = 0`: `x = r(a + √(a² + b²q/r))/b²`, for a stable and an
    /// unstable `a`.
    #[test]
    fn scalar_care_matches_the_closed_form() {
        for (a, b, q, r) in [(-3.0f64, 2.0f64, 5.0f64, 0.5f64), (4.0, 0.3, 10.0, 2.0), (0.0, 1.0, 1.0, 1.0)] {
            let want = r * (a + (a * a + b * b * q / r).sqrt()) / (b * b);
            let (k, x) = lqr(&m(1, 1, &[a]), &m(1, 1, &[b]), &m(1, 1, &[q]), &m(1, 1, &[r])).unwrap();
            assert!((x[(0, 0)] / want - 1.0).abs() < 1e-12, "a = {a}: {} vs {want}", x[(0, 0)]);
            assert!((k[(0, 0)] - b * want / r).abs() < 1e-12 * k[(0, 0)].abs());
        }
    }

    /// The double integrator `ẍ = u`, `Q = diag(q₁, q₂)`, `R = r`: `X = [[√(q₁)·√(q₂ + 2√(q₁r)),
    /// √(q₁ r)], [√(q₁ r), √(r(q₂ + 2√(q₁ r)))]]`, `K = [√(q₁/r), √((q₂ + 2√(q₁r))/r)]`.
    #[test]
    fn double_integrator_lqr_matches_the_closed_form() {
        let a = m(2, 2, &[0.0, 1.0, 0.0, 0.0]);
        let b = m(2, 1, &[0.0, 1.0]);
        for (q1, q2, r) in [(1.0f64, 1.0f64, 1.0f64), (100.0, 0.1, 0.01), (1e-3, 5.0, 3.0)] {
            let s = (q2 + 2.0 * (q1 * r).sqrt()).sqrt();
            let want = m(2, 2, &[q1.sqrt() * s, (q1 * r).sqrt(), (q1 * r).sqrt(), r.sqrt() * s]);
            let (k, x) = lqr(&a, &b, &m(2, 2, &[q1, 0.0, 0.0, q2]), &m(1, 1, &[r])).unwrap();
            assert!((&x - &want).norm() < 1e-10 * want.norm(), "{x} vs {want}");
            assert!((k[(0, 0)] - (q1 / r).sqrt()).abs() < 1e-10 * k[(0, 0)]);
            assert!((k[(0, 1)] - s / r.sqrt()).abs() < 1e-10 * k[(0, 1)]);
        }
    }

    /// A 4-state lightly damped mode + actuator problem (the shape of the LQR design, scaled):
    /// the sign function, the Hamiltonian eigenvectors and Newton–Kleinman agree to 1e-10
    /// relative, and the residual is at rounding level.
    #[test]
    fn three_methods_agree_on_a_lightly_damped_four_state_problem() {
        let (z, wa, za) = (0.0088, 0.0591, 0.15);
        let a = m(
            4,
            4,
            &[
                0.0,
                1.0,
                0.0,
                0.0, //
                -1.0,
                -2.0 * z,
                -2.0 * za * wa,
                -wa * wa, //
                0.0,
                0.0,
                -2.0 * za * wa,
                -wa * wa, //
                0.0,
                0.0,
                1.0,
                0.0,
            ],
        );
        let b = m(4, 1, &[0.0, 1.0, 1.0, 0.0]);
        for (q1, q2, r) in [(0.0, 3.0, 1.0), (10.0, 0.5, 0.2), (1e-2, 1e2, 1e-1)] {
            let q = Mat::from_diagonal(&nalgebra::DVector::from_vec(vec![q1, q2, 0.0, 0.0]));
            let g = &b * b.transpose() / r;
            let xs = care(&a, &g, &q).unwrap();
            let xe = care_eigenvectors(&a, &g, &q).unwrap();
            let xn = care_newton_kleinman(&a, &g, &q, &Mat::zeros(4, 4), 1e-14, 50).unwrap();
            let scale = xs.norm();
            assert!((&xs - &xe).norm() < 1e-10 * scale, "sign vs eigenvectors: {}", (&xs - &xe).norm() / scale);
            assert!((&xs - &xn).norm() < 1e-10 * scale, "sign vs Newton: {}", (&xs - &xn).norm() / scale);
            assert!(care_residual(&a, &g, &q, &xs) < 1e-13, "residual {}", care_residual(&a, &g, &q, &xs));
        }
    }

    /// An indefinite `G` (the H∞ state-feedback Riccati equation of `ẋ = −x + w + u`,
    /// `z = [x; u]`): `x² (1 − γ⁻²) + 2x − 1 = 0` has the stabilising root `(−1 + √(2 − γ⁻²))
    /// /(1 − γ⁻²)`.
    #[test]
    fn indefinite_care_matches_the_closed_form() {
        for gamma in [0.8f64, 1.5, 10.0] {
            let c = 1.0 - gamma.powi(-2);
            let want = if c.abs() < 1e-12 { 0.5 } else { (-1.0 + (1.0 + c).sqrt()) / c };
            let x = care(&m(1, 1, &[-1.0]), &m(1, 1, &[c]), &m(1, 1, &[1.0])).unwrap();
            assert!((x[(0, 0)] - want).abs() < 1e-12, "γ = {gamma}: {} vs {want}", x[(0, 0)]);
        }
    }

    #[test]
    fn lyapunov_matches_the_closed_form_and_imaginary_axis_eigenvalues_are_refused() {
        // ẋ = −a x: a X + X a = q → X = q/(2a)
        let x = lyapunov(&m(1, 1, &[-2.0]), &m(1, 1, &[3.0])).unwrap();
        assert!((x[(0, 0)] - 0.75).abs() < 1e-15);
        let a = m(2, 2, &[0.0, 1.0, -4.0, -0.3]);
        let q = m(2, 2, &[1.0, 0.0, 0.0, 2.0]);
        let x = lyapunov(&a, &q).unwrap();
        assert!((&a * &x + &x * a.transpose() + &q).norm() < 1e-13);
        // an undamped oscillator with Q = 0 and G = 0: H has eigenvalues ±2i
        let osc = m(2, 2, &[0.0, 1.0, -4.0, 0.0]);
        assert!(care(&osc, &Mat::zeros(2, 2), &Mat::zeros(2, 2)).is_err());
        assert!(care_eigenvectors(&osc, &Mat::zeros(2, 2), &Mat::zeros(2, 2)).is_err());
    }

    /// Kalman = the dual LQR: `L` of `(A, C, W, V)` is `Kᵀ` of `(Aᵀ, Cᵀ, W, V)`.
    #[test]
    fn kalman_is_the_dual_lqr() {
        let a = m(2, 2, &[0.0, 1.0, -1.0, -0.02]);
        let c = m(1, 2, &[1.0, 0.0]);
        let w = m(2, 2, &[0.0, 0.0, 0.0, 4.0]);
        let v = m(1, 1, &[1e-2]);
        let (l, p) = kalman(&a, &c, &w, &v).unwrap();
        let (k, x) = lqr(&a.transpose(), &c.transpose(), &w, &v).unwrap();
        assert!((&l - k.transpose()).norm() < 1e-12 * l.norm());
        assert!((&p - &x).norm() < 1e-12 * p.norm());
        assert!(abscissa(&(&a - &l * &c)) < 0.0);
    }
}
