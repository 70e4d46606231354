//! The exact stability boundary of the time-invariant case (D-subdivision).
//!
//! When the directional matrix is constant, `H(t) ≡ H̄` (full immersion, z ≥ 3, linear law), the
//! closed loop `Ẋ = S0 X + T0 X(t − τ) + a_p B_t H̄ C_t (X − X(t − τ))` is time-invariant. Its
//! characteristic function, by the matrix determinant lemma, is
//!
//! ```text
//! det(Q0(s)) · det(I − a_p (1 − e^{−sτ}) H̄ G(s)),   Q0 = sI − S0 − T0 e^{−sτ},   G = C_t Q0⁻¹ B_t,
//! ```
//!
//! so, with the structure and controller stable without cutting (`det Q0 ≠ 0` on the imaginary
//! axis), a root `s = iω` appears at the depth `a_p = 1/λ` for every eigenvalue `λ(ω)` of the
//! 2 × 2 matrix `M(ω) = (1 − e^{−iωτ}) H̄ G(iω)` that is real and positive. The stability
//! boundary at a speed is the smallest such `a_p` over `ω > 0` (D-subdivision: the region that
//! contains `a_p = 0` ends at the first crossing).
//!
//! [`TimeInvariant::critical_depth`] evaluates `λ₁,₂(ω)` (closed form) on a uniform grid up to
//! three times the fastest pole of `S0`, follows each branch by nearest-neighbour matching,
//! brackets every sign change of `Im λ` with `Re λ > 0`, refines it by 60 bisections in ω, and
//! returns the smallest depth. A root pair closer than one grid step can be missed; the grid
//! (default 40 000 points) is far finer than the resonance widths of the test cases.

use crate::StabilityError;
use nalgebra::{DMatrix, Matrix2};
use num_complex::Complex64;

/// The time-invariant closed loop (module docs).
#[derive(Clone, Debug)]
pub struct TimeInvariant {
    /// Undelayed matrix without cutting (structure + controller).
    pub s0: DMatrix<f64>,
    /// Delayed matrix without cutting (the controller's Pyragas term).
    pub t0: DMatrix<f64>,
    /// Cutting-force input (n × 2).
    pub bt: DMatrix<f64>,
    /// Tool displacement output (2 × n).
    pub ct: DMatrix<f64>,
    /// Mean directional matrix H̄.
    pub hbar: Matrix2<f64>,
    /// Number of teeth (τ = 60/(z n)).
    pub teeth: u32,
}

/// A point of the exact boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactPoint {
    /// Critical depth \[m\].
    pub depth: f64,
    /// Chatter frequency \[rad/s\].
    pub omega: f64,
}

impl TimeInvariant {
    /// `M(ω)` of the module docs at delay `tau`.
    pub fn m(&self, omega: f64, tau: f64) -> Result<[[Complex64; 2]; 2], StabilityError> {
        let n = self.s0.nrows();
        let e = Complex64::from_polar(1.0, -omega * tau);
        let q0 = DMatrix::from_fn(n, n, |i, j| {
            let d = if i == j { Complex64::new(0.0, omega) } else { Complex64::new(0.0, 0.0) };
            d - self.s0[(i, j)] - e * self.t0[(i, j)]
        });
        let bt = self.bt.map(Complex64::from);
        let x = q0.lu().solve(&bt).ok_or_else(|| {
            StabilityError::Invalid(format!("the loop without cutting has a pole on the imaginary axis at ω = {omega}"))
        })?;
        let g = self.ct.map(Complex64::from) * x;
        let f = Complex64::new(1.0, 0.0) - e;
        let h = |i: usize, j: usize| Complex64::from(self.hbar[(i, j)]);
        let mut out = [[Complex64::new(0.0, 0.0); 2]; 2];
        for (i, row) in out.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = f * (h(i, 0) * g[(0, j)] + h(i, 1) * g[(1, j)]);
            }
        }
        Ok(out)
    }

    fn eig(&self, omega: f64, tau: f64) -> Result<[Complex64; 2], StabilityError> {
        let m = self.m(omega, tau)?;
        let tr = m[0][0] + m[1][1];
        let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        let d = (tr * tr * 0.25 - det).sqrt();
        Ok([tr * 0.5 + d, tr * 0.5 - d])
    }

    /// The exact critical depth at `rpm` (module docs) with `points` grid points, or `None` if no
    /// eigenvalue becomes real and positive (unconditionally stable).
    pub fn critical_depth(&self, rpm: f64, points: usize) -> Result<Option<ExactPoint>, StabilityError> {
        if !(rpm.is_finite() && rpm > 0.0) || points < 10 {
            return Err(StabilityError::Invalid(format!("need speed > 0 and >= 10 points (got {rpm}, {points})")));
        }
        let tau = 60.0 / (self.teeth as f64 * rpm);
        let fastest = self.s0.complex_eigenvalues().iter().map(|e| e.norm()).fold(0.0, f64::max);
        let w_hi = 3.0 * fastest.max(2.0 * std::f64::consts::PI / tau);
        let dw = w_hi / points as f64;
        let mut prev = self.eig(dw, tau)?;
        let mut best: Option<ExactPoint> = None;
        for k in 2..=points {
            let w = k as f64 * dw;
            let mut cur = self.eig(w, tau)?;
            let straight = (cur[0] - prev[0]).norm() + (cur[1] - prev[1]).norm();
            let crossed = (cur[1] - prev[0]).norm() + (cur[0] - prev[1]).norm();
            if crossed < straight {
                cur.swap(0, 1);
            }
            for b in 0..2 {
                let (l0, l1) = (prev[b], cur[b]);
                if l0.im.signum() != l1.im.signum() && (l0.re > 0.0 || l1.re > 0.0) {
                    let (w_root, lam) = self.refine(w - dw, w, l0, l1, tau)?;
                    if lam.re > 0.0 && lam.norm() > 0.0 {
                        let depth = 1.0 / lam.re;
                        if best.is_none_or(|p| depth < p.depth) {
                            best = Some(ExactPoint { depth, omega: w_root });
                        }
                    }
                }
            }
            prev = cur;
        }
        Ok(best)
    }

    /// Bisection in ω on the sign of `Im λ` of the branch that starts at `l0`.
    fn refine(
        &self,
        mut a: f64,
        mut b: f64,
        mut la: Complex64,
        mut lb: Complex64,
        tau: f64,
    ) -> Result<(f64, Complex64), StabilityError> {
        for _ in 0..60 {
            let c = 0.5 * (a + b);
            let guess = (la + lb) * 0.5;
            let ev = self.eig(c, tau)?;
            let lc = if (ev[0] - guess).norm() <= (ev[1] - guess).norm() { ev[0] } else { ev[1] };
            if lc.im.signum() == la.im.signum() {
                a = c;
                la = lc;
            } else {
                b = c;
                lb = lc;
            }
        }
        // interpolate Im λ = 0 on the final bracket
        let gap = la.im - lb.im;
        let t = if gap.abs() > 0.0 { la.im / gap } else { 0.5 };
        Ok((a + t * (b - a), la + (lb - la) * t))
    }
}
