//! First-order semi-discretisation: the monodromy matrix of `ẋ = A(t)x + B_d(t) C_d x(t − τ)`.
//!
//! # Discretisation
//!
//! The period `T = τ` is cut into `m` intervals `[t_i, t_{i+1})`, `Δt = τ/m`. On each, `A` and
//! `B_d` are replaced by their averages `A_i`, `B_i` ([`PeriodicDde::averaged`]), and the delayed
//! output `y(t − τ)`, `y = C_d x`, by the straight line through its values at the grid points
//! `t_{i−m}` and `t_{i−m+1}` (first order in the delayed term, Insperger & Stépán 2004):
//!
//! ```text
//! y(t_i + s − τ) ≈ (1 − s/Δt) y_{i−m} + (s/Δt) y_{i−m+1},        0 ≤ s ≤ Δt.
//! ```
//!
//! The ODE is then solved exactly over the interval:
//!
//! ```text
//! x_{i+1} = P_i x_i + (M0 − M1/Δt) B_i y_{i−m} + (M1/Δt) B_i y_{i−m+1},
//! P_i = e^{A_i Δt},  M0 = ∫₀^Δt e^{A_i(Δt−s)} ds,  M1 = ∫₀^Δt e^{A_i(Δt−s)} s ds,
//! ```
//!
//! all three from one exponential (Van Loan): `exp([[A_i, I, 0], [0, 0, I], [0, 0, 0]]·Δt)` has
//! `P_i, M0, M1` in its first block row.
//!
//! # Monodromy matrix
//!
//! With `z_i = (x_i, y_{i−1}, …, y_{i−m})` (dimension `N = n + r m`) the step is
//! `z_{i+1} = G_i z_i`, and over one period `Φ = G_{m−1} ⋯ G_1 G_0`. The periodic solution
//! (here: the zero of the perturbation) is asymptotically stable iff the spectral radius
//! `ρ(Φ) < 1`. [`monodromy`] builds Φ by applying each sparse `G_i` to a dense matrix
//! (`O(m N² (n + r))` work); [`monodromy_dense`] is the reference with the full delayed state
//! (`C_d = I`, `N = n(m + 1)`), whose nonzero eigenvalues are the same.
//!
//! The error of the first-order scheme in the critical parameter is `O(Δt²) = O(1/m²)`
//! (Insperger & Stépán 2004, checked in the tests).
//!
//! # Critical multiplier
//!
//! At the stability boundary the multiplier of largest modulus `μ` leaves the unit circle
//! ([`Bifurcation::of`]): a complex pair `e^{±iωT}` is a secondary **Hopf** (quasi-periodic
//! chatter, the classic lobes), a real `μ = −1` a **flip** (period doubling, the separate lobes
//! of low-immersion milling), a real `μ = +1` a **fold** (a static divergence).
//!
//! The eigenvalues come from nalgebra's dense real Schur decomposition; with the reduced state
//! the matrices stay small (a two-axis two-mass spindle with a static Pyragas controller at
//! m = 40 has N = 8 + 4·40 = 168).

use crate::{PeriodicDde, StabilityError};
use nalgebra::DMatrix;
use num_complex::Complex64;
use std::f64::consts::PI;

/// The kind of instability at the boundary, from the critical multiplier.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Bifurcation {
    /// A complex pair crosses the unit circle (secondary Hopf, quasi-periodic chatter).
    Hopf,
    /// A real multiplier crosses at −1 (period doubling).
    Flip,
    /// A real multiplier crosses at +1.
    Fold,
}

impl Bifurcation {
    /// Angle tolerance \[rad\]: a multiplier within it of the real axis counts as real.
    pub const ANGLE_TOL: f64 = 1e-3;

    /// The kind of a critical multiplier: within [`Self::ANGLE_TOL`] of the negative real axis
    /// → flip, of the positive real axis → fold, otherwise Hopf.
    pub fn of(mu: Complex64) -> Bifurcation {
        let arg = mu.arg().abs();
        if PI - arg < Self::ANGLE_TOL {
            Bifurcation::Flip
        } else if arg < Self::ANGLE_TOL {
            Bifurcation::Fold
        } else {
            Bifurcation::Hopf
        }
    }

    /// Lower-case name (`hopf`, `flip`, `fold`).
    pub fn name(&self) -> &'static str {
        match self {
            Bifurcation::Hopf => "hopf",
            Bifurcation::Flip => "flip",
            Bifurcation::Fold => "fold",
        }
    }
}

/// The critical (largest-modulus) multiplier of a monodromy matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Multiplier {
    /// The multiplier μ.
    pub mu: Complex64,
    /// Its modulus, the spectral radius ρ(Φ).
    pub rho: f64,
}

impl Multiplier {
    /// Its classification.
    pub fn kind(&self) -> Bifurcation {
        Bifurcation::of(self.mu)
    }
}

/// One step's matrices: `P = e^{AΔt}`, `R0 = (M0 − M1/Δt) B`, `R1 = (M1/Δt) B`.
#[derive(Clone, Debug)]
pub(crate) struct Step {
    p: DMatrix<f64>,
    r0: DMatrix<f64>,
    r1: DMatrix<f64>,
}

/// The matrices of one interval (module docs), from one `3n × 3n` exponential.
pub(crate) fn step(a: &DMatrix<f64>, b: &DMatrix<f64>, dt: f64) -> Step {
    let n = a.nrows();
    let mut e = DMatrix::<f64>::zeros(3 * n, 3 * n);
    e.view_mut((0, 0), (n, n)).copy_from(&(a * dt));
    for k in 0..n {
        e[(k, n + k)] = dt;
        e[(n + k, 2 * n + k)] = dt;
    }
    let x = e.exp();
    let p = x.view((0, 0), (n, n)).into_owned();
    let m0 = x.view((0, n), (n, n)).into_owned();
    let m1 = x.view((0, 2 * n), (n, n)).into_owned() / dt;
    Step { r0: (&m0 - &m1) * b, r1: m1 * b, p }
}

fn check(n: usize, r: usize, m: usize, period: f64) -> Result<(), StabilityError> {
    if m == 0 {
        return Err(StabilityError::Invalid("the discretisation m must be >= 1".into()));
    }
    if n == 0 || r == 0 {
        return Err(StabilityError::Invalid(format!("empty system (n = {n}, r = {r})")));
    }
    if !(period.is_finite() && period > 0.0) {
        return Err(StabilityError::Invalid(format!("the period must be finite and > 0 (got {period})")));
    }
    Ok(())
}

/// Φ for the state `(x_i, y_{i−1}, …, y_{i−m})` with `y = cd x` and the step matrices `steps(i)`.
fn monodromy_with(
    n: usize,
    m: usize,
    cd: &DMatrix<f64>,
    steps: impl Fn(usize) -> (DMatrix<f64>, DMatrix<f64>),
    dt: f64,
) -> DMatrix<f64> {
    let r = cd.nrows();
    let big = n + r * m;
    let mut z = DMatrix::<f64>::identity(big, big);
    let slot = |k: usize| n + (k - 1) * r; // first row of y_{i−k}, k ≥ 1
    for i in 0..m {
        let (a, b) = steps(i);
        let s = step(&a, &b, dt);
        let zx = z.rows(0, n).into_owned();
        let mut next = DMatrix::<f64>::zeros(big, big);
        // x_{i+1} = P x_i + R0 y_{i−m} + R1 y_{i−m+1}
        let mut xn = &s.p * &zx + &s.r0 * z.rows(slot(m), r);
        if m >= 2 {
            xn += &s.r1 * z.rows(slot(m - 1), r);
        } else {
            xn += &s.r1 * cd * &zx;
        }
        next.rows_mut(0, n).copy_from(&xn);
        next.rows_mut(slot(1), r).copy_from(&(cd * &zx));
        for k in 2..=m {
            let old = z.rows(slot(k - 1), r).into_owned();
            next.rows_mut(slot(k), r).copy_from(&old);
        }
        z = next;
    }
    z
}

/// The monodromy matrix of `sys` with `m` intervals per period, on the reduced state
/// `(x, y_{−1}, …, y_{−m})`, dimension `n + r m` (module docs).
pub fn monodromy<S: PeriodicDde + ?Sized>(sys: &S, m: usize) -> Result<DMatrix<f64>, StabilityError> {
    let cd = sys.delayed_output();
    let n = sys.dim();
    check(n, cd.nrows(), m, sys.period())?;
    let dt = sys.period() / m as f64;
    Ok(monodromy_with(n, m, &cd, |i| sys.averaged(i as f64 * dt, (i + 1) as f64 * dt), dt))
}

/// The reference: the same discretisation on the full delayed state `(x_i, x_{i−1}, …, x_{i−m})`
/// (`B(t) = B_d(t) C_d`, dimension `n(m + 1)`). Slow; for tests.
pub fn monodromy_dense<S: PeriodicDde + ?Sized>(sys: &S, m: usize) -> Result<DMatrix<f64>, StabilityError> {
    let cd = sys.delayed_output();
    let n = sys.dim();
    check(n, cd.nrows(), m, sys.period())?;
    let dt = sys.period() / m as f64;
    let eye = DMatrix::<f64>::identity(n, n);
    Ok(monodromy_with(
        n,
        m,
        &eye,
        |i| {
            let (a, b) = sys.averaged(i as f64 * dt, (i + 1) as f64 * dt);
            (a, b * &cd)
        },
        dt,
    ))
}

/// The monodromy operator of the semi-discretisation in product form: the `m` step matrices,
/// applied to a vector one step at a time ([`SdOperator::apply`]) without forming Φ. The delayed
/// outputs sit in a ring buffer: a step writes `C_d x_i` over the slot of `y_{i−m}`, which it has
/// just used, and after `m` steps the ring is back in its original order, so `apply` equals
/// `Φ z` with Φ of [`monodromy`] (tested) at `O(m (n² + n r))` operations and no allocation.
#[derive(Clone, Debug)]
pub struct SdOperator {
    n: usize,
    r: usize,
    m: usize,
    cd: DMatrix<f64>,
    steps: Vec<Step>,
}

impl SdOperator {
    /// The operator of `sys` with `m` intervals (one Van Loan exponential per interval).
    pub fn new<S: PeriodicDde + ?Sized>(sys: &S, m: usize) -> Result<SdOperator, StabilityError> {
        let cd = sys.delayed_output();
        let n = sys.dim();
        let r = cd.nrows();
        check(n, r, m, sys.period())?;
        let dt = sys.period() / m as f64;
        let steps = (0..m)
            .map(|i| {
                let (a, b) = sys.averaged(i as f64 * dt, (i + 1) as f64 * dt);
                step(&a, &b, dt)
            })
            .collect::<Vec<_>>();
        if steps.iter().any(|s| s.p.iter().chain(s.r0.iter()).chain(s.r1.iter()).any(|v| !v.is_finite())) {
            return Err(StabilityError::Invalid("the monodromy matrix has non-finite entries".into()));
        }
        Ok(SdOperator { n, r, m, cd, steps })
    }

    /// Dimension `n + r m`.
    pub fn dim(&self) -> usize {
        self.n + self.r * self.m
    }

    /// `out = Φ z`; `work` holds the ring and two state vectors (resized once).
    pub fn apply(&self, z: &[f64], out: &mut [f64], work: &mut Vec<f64>) {
        let (n, r, m) = (self.n, self.r, self.m);
        work.resize(r * m + 2 * n + r, 0.0);
        let (ring, rest) = work.split_at_mut(r * m);
        let (x, rest) = rest.split_at_mut(n);
        let (xn, y0) = rest.split_at_mut(n);
        ring.copy_from_slice(&z[n..]);
        x.copy_from_slice(&z[..n]);
        // slot of y_{i−k} (k ≥ 1) when the ring starts at `head`
        let slot = |head: usize, k: usize| (head + k - 1) % m;
        let mut head = 0;
        for s in &self.steps {
            let ym = slot(head, m) * r;
            let ym1 = if m >= 2 {
                slot(head, m - 1) * r
            } else {
                // y_{i−m+1} = y_i = C_d x_i
                for (k, v) in y0.iter_mut().enumerate() {
                    *v = (0..n).map(|j| self.cd[(k, j)] * x[j]).sum();
                }
                usize::MAX
            };
            for (i, out) in xn.iter_mut().enumerate() {
                let mut acc = 0.0;
                for (j, xj) in x.iter().enumerate() {
                    acc += s.p[(i, j)] * xj;
                }
                for k in 0..r {
                    acc += s.r0[(i, k)] * ring[ym + k];
                    acc += s.r1[(i, k)] * if ym1 == usize::MAX { y0[k] } else { ring[ym1 + k] };
                }
                *out = acc;
            }
            // y_{i+1−1} = C_d x_i into the slot of y_{i−m}, now used
            head = (head + m - 1) % m;
            for k in 0..r {
                ring[head * r + k] = (0..n).map(|j| self.cd[(k, j)] * x[j]).sum();
            }
            x.copy_from_slice(xn);
        }
        out[..n].copy_from_slice(x);
        out[n..].copy_from_slice(ring);
    }
}

/// All eigenvalues of a square matrix (dense real Schur), largest modulus first.
///
/// nalgebra's Schur iteration deflates with a purely relative test, which never succeeds on the
/// clusters of (structurally) zero eigenvalues a monodromy matrix has when teeth are out of cut
/// (`B_i = 0` makes the step singular). The eigenvalues are therefore computed of `Φ + σI`
/// (shifts [`SHIFTS`], the next one tried if the iteration fails) and shifted back; the shift
/// moves the zero cluster away from the origin and changes nothing else.
pub fn eigenvalues(phi: &DMatrix<f64>) -> Result<Vec<Complex64>, StabilityError> {
    eigenvalues_with(phi, SHIFTS)
}

/// The shifts of [`eigenvalues_unshifted_first`].
pub const ZERO_FIRST: &[f64] = &[0.0, 0.3141, -0.2718, 0.1618];

/// [`eigenvalues`] trying the unshifted matrix first: for the spectral collocation's matrices
/// (and the Krylov iteration's projections), whose zero eigenvalues the unshifted iteration
/// deflates at once while a shift can stall on them.
pub fn eigenvalues_unshifted_first(phi: &DMatrix<f64>) -> Result<Vec<Complex64>, StabilityError> {
    eigenvalues_with(phi, ZERO_FIRST)
}

/// [`eigenvalues`] with the shifts tried in the order given.
pub fn eigenvalues_with(phi: &DMatrix<f64>, shifts: &[f64]) -> Result<Vec<Complex64>, StabilityError> {
    let dim = phi.nrows();
    if phi.iter().any(|v| !v.is_finite()) {
        return Err(StabilityError::Invalid("the monodromy matrix has non-finite entries".into()));
    }
    for &sigma in shifts {
        let mut shifted = phi.clone();
        for k in 0..dim {
            shifted[(k, k)] += sigma;
        }
        if let Some(schur) = nalgebra::Schur::try_new(shifted, SCHUR_EPS, 200 * dim.max(10)) {
            let mut ev: Vec<Complex64> = schur.complex_eigenvalues().iter().map(|z| z - sigma).collect();
            ev.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
            return Ok(ev);
        }
    }
    Err(StabilityError::Eigen { dim })
}

/// The shifts tried by [`eigenvalues`] (none of them a likely multiplier).
pub const SHIFTS: &[f64] = &[0.3141, -0.2718, 0.1618, 0.0];

/// Relative deflation tolerance of the Schur iteration.
pub const SCHUR_EPS: f64 = 1e-13;

/// The critical multiplier of `sys` at discretisation `m` (the spectral radius and its kind).
pub fn critical_multiplier<S: PeriodicDde + ?Sized>(sys: &S, m: usize) -> Result<Multiplier, StabilityError> {
    let ev = eigenvalues(&monodromy(sys, m)?)?;
    let mu = ev[0];
    Ok(Multiplier { mu, rho: mu.norm() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Scalar `ẋ = a x + b x(t − τ)` with constant coefficients.
    struct Scalar {
        a: f64,
        b: f64,
        tau: f64,
    }
    impl PeriodicDde for Scalar {
        fn dim(&self) -> usize {
            1
        }
        fn period(&self) -> f64 {
            self.tau
        }
        fn delayed_output(&self) -> DMatrix<f64> {
            DMatrix::from_element(1, 1, 1.0)
        }
        fn averaged(&self, _: f64, _: f64) -> (DMatrix<f64>, DMatrix<f64>) {
            (DMatrix::from_element(1, 1, self.a), DMatrix::from_element(1, 1, self.b))
        }
    }

    #[test]
    fn step_matrices_are_the_integrals() {
        // scalar a: P = e^{aΔt}, M0 = (e^{aΔt} − 1)/a, M1 = ∫ e^{a(Δt−s)} s ds = (e^{aΔt} − 1 − aΔt)/a²
        let (a, dt) = (-3.0, 0.2);
        let s = step(&DMatrix::from_element(1, 1, a), &DMatrix::from_element(1, 1, 1.0), dt);
        let e = (a * dt).exp();
        let m0 = (e - 1.0) / a;
        let m1 = (e - 1.0 - a * dt) / (a * a);
        assert_relative_eq!(s.p[(0, 0)], e, max_relative = 1e-13);
        assert_relative_eq!(s.r1[(0, 0)], m1 / dt, max_relative = 1e-12);
        assert_relative_eq!(s.r0[(0, 0)], m0 - m1 / dt, max_relative = 1e-12);
    }

    #[test]
    fn pure_delay_boundary_is_hayes() {
        // ẋ = −b x(t−1): stable iff 0 < b < π/2 (the Hayes boundary, Hopf at ω = π/2).
        let rho = |b: f64| critical_multiplier(&Scalar { a: 0.0, b: -b, tau: 1.0 }, 60).unwrap();
        let below = rho(std::f64::consts::FRAC_PI_2 * 0.99);
        let above = rho(std::f64::consts::FRAC_PI_2 * 1.01);
        assert!(below.rho < 1.0 && above.rho > 1.0, "{below:?} {above:?}");
        assert_eq!(above.kind(), Bifurcation::Hopf);
        // a + b = 0 with a < 0: the real root s = 0 (fold)
        let fold = critical_multiplier(&Scalar { a: -1.0, b: 1.02, tau: 1.0 }, 40).unwrap();
        assert!(fold.rho > 1.0);
        assert_eq!(fold.kind(), Bifurcation::Fold);
    }

    #[test]
    fn classification_by_angle() {
        assert_eq!(Bifurcation::of(Complex64::new(-1.0, 1e-5)), Bifurcation::Flip);
        assert_eq!(Bifurcation::of(Complex64::new(1.0, -1e-5)), Bifurcation::Fold);
        assert_eq!(Bifurcation::of(Complex64::from_polar(1.0, 2.0)), Bifurcation::Hopf);
    }

    #[test]
    fn the_product_form_is_the_monodromy_matrix() {
        // two states, one delayed output; m = 1 (y_{i−m+1} = y_i) and m > 1
        let sys = crate::oscillator::DelayedMathieu { kappa: 0.2, delta: 1.3, epsilon: 0.7, b: -0.4 };
        for m in [1, 2, 7, 30] {
            let phi = monodromy(&sys, m).unwrap();
            let op = SdOperator::new(&sys, m).unwrap();
            assert_eq!(op.dim(), phi.nrows());
            let z: Vec<f64> = (0..op.dim()).map(|i| ((i * 17) % 7) as f64 - 3.0).collect();
            let mut out = vec![0.0; op.dim()];
            op.apply(&z, &mut out, &mut Vec::new());
            let expect = &phi * nalgebra::DVector::from_column_slice(&z);
            for (a, b) in out.iter().zip(expect.iter()) {
                assert!((a - b).abs() < 1e-12 * expect.norm(), "m = {m}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn bad_arguments_are_refused() {
        let s = Scalar { a: 0.0, b: -1.0, tau: 1.0 };
        assert!(monodromy(&s, 0).is_err());
        assert!(monodromy(&Scalar { a: 0.0, b: -1.0, tau: f64::NAN }, 4).is_err());
    }
}
