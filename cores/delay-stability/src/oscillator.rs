//! The damped delayed Mathieu equation (Insperger & Stépán, Proc. R. Soc. A 458, 2002):
//!
//! ```text
//! ẍ + κ ẋ + (δ + ε cos t) x = b x(t − 2π),
//! ```
//!
//! period and delay 2π. With `ε = 0` (the delayed oscillator) its stability boundaries are known
//! in closed form ([`d_curve`]): substituting `x = e^{iωt}`,
//! `δ − ω² = b cos 2πω` and `κω = −b sin 2πω`, so along `ω > 0`
//!
//! ```text
//! b(ω) = −κω / sin 2πω,    δ(ω) = ω² + b(ω) cos 2πω,
//! ```
//!
//! plus the line `δ = b` of the root `s = 0` (ω = 0).

use crate::PeriodicDde;
use nalgebra::DMatrix;
use std::f64::consts::PI;

/// The delayed Mathieu equation as a [`PeriodicDde`] (state `(x, ẋ)`, delayed output `x`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DelayedMathieu {
    /// Damping κ.
    pub kappa: f64,
    /// Stiffness δ.
    pub delta: f64,
    /// Parametric excitation ε.
    pub epsilon: f64,
    /// Delayed gain b.
    pub b: f64,
}

impl PeriodicDde for DelayedMathieu {
    fn dim(&self) -> usize {
        2
    }
    fn period(&self) -> f64 {
        2.0 * PI
    }
    fn delayed_output(&self) -> DMatrix<f64> {
        DMatrix::from_row_slice(1, 2, &[1.0, 0.0])
    }
    fn averaged(&self, t0: f64, t1: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        let mean_cos = if t1 > t0 { (t1.sin() - t0.sin()) / (t1 - t0) } else { t0.cos() };
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -(self.delta + self.epsilon * mean_cos), -self.kappa]);
        (a, DMatrix::from_row_slice(2, 1, &[0.0, self.b]))
    }
}

/// The point `(δ, b)` of the `ε = 0` boundary at frequency `ω > 0` (module docs).
pub fn d_curve(kappa: f64, omega: f64) -> (f64, f64) {
    let b = -kappa * omega / (2.0 * PI * omega).sin();
    (omega * omega + b * (2.0 * PI * omega).cos(), b)
}
