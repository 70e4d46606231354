//! # Fractional-order hold (FROH) and its exact discretisation
//!
//! The FROH of gain β turns the samples `u_k` into the piecewise-linear signal
//!
//! ```text
//! u(t) = u_k + β (u_k − u_{k−1}) (t − kT)/T,   kT ≤ t < (k+1)T,
//! ```
//!
//! so β = 0 is the zero-order hold and β = 1 the (predictive) first-order hold. Its transfer
//! function is `G_h(s) = (1 − βe^{−sT})(1 − e^{−sT})/s + β(1 − e^{−sT})²/(Ts²)`.
//!
//! ## Exact integration of a ramp input
//!
//! For `ẋ = Ax + Bw` with `w(s) = w₀ + v s` on `[0, h]`, the augmented system
//! `d/ds [x; w; v] = M [x; w; v]`, `M = [[A, B, 0], [0, 0, 1], [0, 0, 0]]` gives
//!
//! ```text
//! e^{Mh} = [[Φ, Γ₀, Γ₁'], [0, 1, h], [0, 0, 1]],
//! Φ = e^{Ah},  Γ₀ = ∫₀ʰ e^{Aσ} dσ B,  Γ₁' = ∫₀ʰ e^{A(h−s)} B s ds,
//! ```
//!
//! so `x(h) = Φ x(0) + Γ₀ w₀ + Γ₁' v` exactly ([`RampPropagator`]; the matrix exponential is
//! nalgebra's scaling-and-squaring Padé approximant).
//!
//! ## Discrete model under the FROH
//!
//! Over one sample period (`h = T`, `v = β(u_k − u_{k−1})/T`, `Γ₁ = Γ₁'/T`):
//! `x_{k+1} = Φ x_k + (Γ₀ + βΓ₁) u_k − βΓ₁ u_{k−1}`. With the state `[x_k; u_{k−1}]` this is the
//! state-space model
//!
//! ```text
//! Φ_d = [[Φ, −βΓ₁], [0, 0]],  Γ_d = [Γ₀ + βΓ₁; 1],  C_d = [C, 0],
//! ```
//!
//! of order n + 1: the FROH adds a pole at the origin (for β = 0 it is cancelled by a zero at
//! the origin, and the model is the ZOH model). [`DiscreteTf`] holds its pulse transfer function
//! `H(z) = N(z)/D(z)`: `D` is the characteristic polynomial of `Φ_d` (Faddeev–LeVerrier) and `N`
//! follows from the Markov parameters `h_i = C_d Φ_d^{i−1} Γ_d` by `N_j = Σ_{i≤j} D_{j−i} h_i`
//! (no difference of two characteristic polynomials, so small numerators keep their digits).
//!
//! Known zeros (Bárcena, De la Sen, Sagastabeitia, IEE Proc. CTA 147, 2000): `1/s` has the zero
//! `β/(2+β)`; `1/s²` has the zero −1 at β = 0 (Åström–Hagander–Sternby 1984) and leaves the
//! unit circle for β > 0. For the first-order lag `K/(τs + 1)`, `a = e^{−T/τ}`,
//! `Γ₀ = K(1 − a)`, `Γ₁ = K(1 − (τ/T)(1 − a))`, the zero `βΓ₁/(Γ₀ + βΓ₁)` reaches −1 at
//! `β = −Γ₀/(2Γ₁)` ([`first_order_nmp_boundary`]).

use crate::ForceError;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use serde::{Deserialize, Serialize};

/// A single-input single-output continuous model `ẋ = Ax + Bu`, `y = Cx` (no feedthrough).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StateSpace {
    /// State matrix, row-major `n × n`.
    pub a: Vec<Vec<f64>>,
    /// Input column.
    pub b: Vec<f64>,
    /// Output row.
    pub c: Vec<f64>,
}

impl StateSpace {
    /// The first-order lag `k/(τ s + 1)`.
    pub fn first_order(k: f64, tau: f64) -> Self {
        StateSpace { a: vec![vec![-1.0 / tau]], b: vec![k / tau], c: vec![1.0] }
    }

    /// Two lags in series `k/((τ₁ s + 1)(τ₂ s + 1))`, state `[w; y]` with `τ₁ ẇ = u − w`,
    /// `τ₂ ẏ = k w − y` (the milling force plant: CNC lag τ₁ = τ_s, chip lag τ₂ = τ_c).
    pub fn two_lags(k: f64, tau1: f64, tau2: f64) -> Self {
        StateSpace {
            a: vec![vec![-1.0 / tau1, 0.0], vec![k / tau2, -1.0 / tau2]],
            b: vec![1.0 / tau1, 0.0],
            c: vec![0.0, 1.0],
        }
    }

    /// `ω²/(s² + 2ζωs + ω²)` in controllable form, state `[y; ẏ]`.
    pub fn second_order(zeta: f64, omega: f64) -> Self {
        StateSpace {
            a: vec![vec![0.0, 1.0], vec![-omega * omega, -2.0 * zeta * omega]],
            b: vec![0.0, omega * omega],
            c: vec![1.0, 0.0],
        }
    }

    /// `1/s^m` as a chain of integrators.
    pub fn integrators(m: usize) -> Self {
        let mut a = vec![vec![0.0; m]; m];
        for (i, row) in a.iter_mut().enumerate().take(m - 1) {
            row[i + 1] = 1.0;
        }
        let mut b = vec![0.0; m];
        b[m - 1] = 1.0;
        let mut c = vec![0.0; m];
        c[0] = 1.0;
        StateSpace { a, b, c }
    }

    /// Number of states.
    pub fn order(&self) -> usize {
        self.b.len()
    }

    fn check(&self) -> Result<(), ForceError> {
        let n = self.b.len();
        let ok = n > 0
            && self.c.len() == n
            && self.a.len() == n
            && self.a.iter().all(|r| r.len() == n && r.iter().all(|x| x.is_finite()))
            && self.b.iter().chain(&self.c).all(|x| x.is_finite());
        if ok { Ok(()) } else { Err(ForceError::Model("state-space model of inconsistent size or not finite".into())) }
    }
}

/// The exact propagator of `ẋ = Ax + Bw` over a step `h` with a ramp input `w₀ + v s`.
#[derive(Clone, Debug, PartialEq)]
pub struct RampPropagator {
    /// `e^{Ah}`.
    pub phi: DMatrix<f64>,
    /// `∫₀ʰ e^{Aσ}dσ B`.
    pub gamma0: DVector<f64>,
    /// `∫₀ʰ e^{A(h−s)} B s ds`.
    pub gamma1: DVector<f64>,
    /// The step.
    pub h: f64,
}

impl RampPropagator {
    /// The propagator of `sys` over `h > 0` (one augmented matrix exponential).
    pub fn new(sys: &StateSpace, h: f64) -> Result<Self, ForceError> {
        sys.check()?;
        if !(h.is_finite() && h > 0.0) {
            return Err(ForceError::Model(format!("step {h} is not positive and finite")));
        }
        let n = sys.order();
        let mut m = DMatrix::<f64>::zeros(n + 2, n + 2);
        for i in 0..n {
            for j in 0..n {
                m[(i, j)] = sys.a[i][j] * h;
            }
            m[(i, n)] = sys.b[i] * h;
        }
        // the ramp state carries v·h so that the whole matrix is scaled by h
        m[(n, n + 1)] = 1.0;
        let e = m.exp();
        // the third block column multiplies v·h: Γ₁' = h · e[0..n, n+1]
        Ok(RampPropagator {
            phi: e.view((0, 0), (n, n)).into_owned(),
            gamma0: e.view((0, n), (n, 1)).column(0).into_owned(),
            gamma1: e.view((0, n + 1), (n, 1)).column(0).into_owned() * h,
            h,
        })
    }

    /// `x(h)` from `x(0) = x` with the input `w₀ + v s`.
    pub fn propagate(&self, x: &DVector<f64>, w0: f64, v: f64) -> DVector<f64> {
        &self.phi * x + &self.gamma0 * w0 + &self.gamma1 * v
    }
}

/// A pulse transfer function `N(z)/D(z)`, coefficients in descending powers of z, `D` monic.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DiscreteTf {
    /// Numerator, same length as `den` (leading coefficient 0: strictly proper).
    pub num: Vec<f64>,
    /// Denominator, monic.
    pub den: Vec<f64>,
}

impl DiscreteTf {
    /// The exact model of `sys` behind a FROH of gain `beta` and period `t`.
    pub fn froh(sys: &StateSpace, t: f64, beta: f64) -> Result<Self, ForceError> {
        let p = RampPropagator::new(sys, t)?;
        Ok(Self::from_propagator(sys, &p, beta))
    }

    /// The exact model of `sys` behind a zero-order hold (the textbook `[[A, B], [0, 0]]`
    /// exponential; independent of the FROH path, for the β = 0 check).
    pub fn zoh(sys: &StateSpace, t: f64) -> Result<Self, ForceError> {
        sys.check()?;
        let n = sys.order();
        let mut m = DMatrix::<f64>::zeros(n + 1, n + 1);
        for i in 0..n {
            for j in 0..n {
                m[(i, j)] = sys.a[i][j] * t;
            }
            m[(i, n)] = sys.b[i] * t;
        }
        let e = m.exp();
        let phi = e.view((0, 0), (n, n)).into_owned();
        let g = e.view((0, n), (n, 1)).column(0).into_owned();
        let c = DVector::from_column_slice(&sys.c);
        Ok(Self::from_state_space(&phi, &g, &c))
    }

    /// The FROH model from a propagator over one period.
    pub fn from_propagator(sys: &StateSpace, p: &RampPropagator, beta: f64) -> Self {
        let n = sys.order();
        let g1 = &p.gamma1 / p.h;
        let mut phi = DMatrix::<f64>::zeros(n + 1, n + 1);
        phi.view_mut((0, 0), (n, n)).copy_from(&p.phi);
        for i in 0..n {
            phi[(i, n)] = -beta * g1[i];
        }
        let mut g = DVector::<f64>::zeros(n + 1);
        for i in 0..n {
            g[i] = p.gamma0[i] + beta * g1[i];
        }
        g[n] = 1.0;
        let mut c = DVector::<f64>::zeros(n + 1);
        for i in 0..n {
            c[i] = sys.c[i];
        }
        Self::from_state_space(&phi, &g, &c)
    }

    /// `C(zI − Φ)⁻¹Γ` by Faddeev–LeVerrier and the Markov parameters.
    pub fn from_state_space(phi: &DMatrix<f64>, g: &DVector<f64>, c: &DVector<f64>) -> Self {
        let den = charpoly(phi);
        let m = phi.nrows();
        let mut markov = Vec::with_capacity(m);
        let mut v = g.clone();
        for _ in 0..m {
            markov.push(c.dot(&v));
            v = phi * v;
        }
        let mut num = vec![0.0; m + 1];
        for j in 1..=m {
            num[j] = (1..=j).map(|i| den[j - i] * markov[i - 1]).sum();
        }
        DiscreteTf { num, den }
    }

    /// Response to the input sequence `u` from rest: `y_k = Σ_j num_j u_{k−j} − Σ_{j≥1} den_j y_{k−j}`.
    pub fn simulate(&self, u: &[f64]) -> Vec<f64> {
        let n = self.den.len();
        let mut y = vec![0.0; u.len()];
        for k in 0..u.len() {
            let mut acc = 0.0;
            for j in 1..n {
                if k >= j {
                    acc += self.num[j] * u[k - j] - self.den[j] * y[k - j];
                }
            }
            y[k] = acc;
        }
        y
    }

    /// The zeros (roots of the numerator without its leading zero coefficients).
    pub fn zeros(&self) -> Vec<Complex64> {
        let scale = self.num.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let first = self.num.iter().position(|x| x.abs() > 1e-14 * scale);
        match first {
            Some(i) => crate::poly::roots(&self.num[i..]),
            None => Vec::new(),
        }
    }

    /// The zero of largest modulus (the one that decides minimum phase), if any.
    pub fn dominant_zero(&self) -> Option<Complex64> {
        self.zeros().into_iter().max_by(|a, b| a.norm().total_cmp(&b.norm()))
    }
}

/// Characteristic polynomial `det(zI − M)` (monic, descending powers) by Faddeev–LeVerrier.
pub fn charpoly(m: &DMatrix<f64>) -> Vec<f64> {
    let n = m.nrows();
    let mut c = vec![0.0; n + 1];
    c[0] = 1.0;
    let id = DMatrix::<f64>::identity(n, n);
    let mut mk = DMatrix::<f64>::zeros(n, n);
    for k in 1..=n {
        mk = m * (&mk + &id * c[k - 1]);
        c[k] = -mk.trace() / k as f64;
    }
    c
}

/// The β at which the FROH zero of `K/(τs+1)` sampled at `t` reaches −1: `−Γ₀/(2Γ₁)`.
pub fn first_order_nmp_boundary(tau: f64, t: f64) -> f64 {
    let a = (-t / tau).exp();
    let g0 = 1.0 - a;
    let g1 = 1.0 - tau / t * (1.0 - a);
    -g0 / (2.0 * g1)
}

/// Largest zero modulus of the FROH model of `sys` at `beta`.
pub fn dominant_zero_modulus(sys: &StateSpace, t: f64, beta: f64) -> Result<f64, ForceError> {
    let tf = DiscreteTf::froh(sys, t, beta)?;
    Ok(tf.dominant_zero().map_or(0.0, |z| z.norm()))
}

/// The non-minimum-phase boundary in β on `[lo, hi]`: the β where the largest zero modulus
/// crosses 1, by bisection to `1e-12` (`None` if it does not cross on the interval).
pub fn nmp_boundary(sys: &StateSpace, t: f64, lo: f64, hi: f64) -> Result<Option<f64>, ForceError> {
    let f = |b: f64| dominant_zero_modulus(sys, t, b).map(|m| m - 1.0);
    let (mut a, mut b) = (lo, hi);
    let (fa, fb) = (f(a)?, f(b)?);
    if fa.signum() == fb.signum() {
        return Ok(None);
    }
    for _ in 0..200 {
        let mid = 0.5 * (a + b);
        if (b - a).abs() < 1e-12 {
            break;
        }
        if f(mid)?.signum() == fa.signum() {
            a = mid;
        } else {
            b = mid;
        }
    }
    Ok(Some(0.5 * (a + b)))
}
