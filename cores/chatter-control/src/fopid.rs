//! Fractional-order PID (seed 000, Eq. 28): `u0 = Kp e + Ki D^(−λ) e + Kd D^μ e`.
//!
//! The two fractional operators are [`FractionalOperator`]s (Grünwald–Letnikov short memory or
//! Oustaloup, integer part exact), so the discrete law is
//!
//! ```text
//! C(z) = Kp + Ki·F_{−λ}(z) + Kd·F_{μ}(z)
//! ```
//!
//! with `F_α(z)` the operator's transfer ([`FractionalOperator::response`]).
//!
//! The derivative branch may take a different input than the proportional/integral branch:
//! the standalone FOPID feeds `e` to both; inside ADRC-FOPID the proportional/integral branch
//! gets `e1 = v1 − z1` and the derivative branch `e2 = v2 − z2` through `D^(μ−1)` (since
//! `D^μ e1 = D^(μ−1) ė1` and `e2` is the observer's estimate of `ė1`; Section 4.1).
//!
//! Anti-windup: the running sums of `D^(−λ)` hold while the previous command was saturated
//! and their input pushes further into saturation (see [`FractionalOperator::step`]).

use crate::fractional::{FractionalOperator, FractionalParams};
use num_complex::Complex64;
use serde::{Deserialize, Serialize};

/// FOPID gains. Standalone (`fopid.*`): `u` in N, so `kp` \[N/m\], `ki` \[N/(m·s^λ)\],
/// `kd` \[N·s^μ/m\]. Inside ADRC (`adrc.*`): `u0` in m/s², so `kp` \[1/s²\], `ki` \[s^(λ−2)\],
/// `kd` \[s^(μ−2)\].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FopidGains {
    /// Proportional gain.
    pub kp: f64,
    /// Fractional integral gain.
    pub ki: f64,
    /// Fractional derivative gain.
    pub kd: f64,
    /// Integral order λ.
    pub lambda: f64,
    /// Derivative order μ.
    pub mu: f64,
}

/// Discrete FOPID.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Fopid {
    g: FopidGains,
    int_op: FractionalOperator,
    der_op: FractionalOperator,
}

impl Fopid {
    /// New gains `kp`, `ki`, `kd` from the next sample on, the operators' memories kept (the
    /// derivative memory is filled only while `kd ≠ 0`: a `kd` changed from 0 starts from an
    /// empty one).
    pub(crate) fn set_gains(&mut self, kp: f64, ki: f64, kd: f64) {
        (self.g.kp, self.g.ki, self.g.kd) = (kp, ki, kd);
    }

    /// A restored FOPID: the gains and operators `fresh` has.
    pub(crate) fn check(&self, fresh: &Self) -> Result<(), String> {
        if self.g != fresh.g {
            return Err("FOPID gains do not match the parameters".into());
        }
        self.int_op.check(&fresh.int_op)?;
        self.der_op.check(&fresh.der_op)
    }

    /// FOPID whose derivative branch applies `D^derivative_order` (μ standalone, μ − 1 in ADRC).
    pub fn new(g: FopidGains, derivative_order: f64, ts: f64, fp: &FractionalParams) -> Self {
        Fopid {
            g,
            int_op: FractionalOperator::new(-g.lambda, ts, fp),
            der_op: FractionalOperator::new(derivative_order, ts, fp),
        }
    }

    /// One sample: `e_pi` feeds the proportional and integral branches, `e_d` the derivative one.
    #[inline]
    pub fn step(&mut self, e_pi: f64, e_d: f64, sat_dir: f64) -> f64 {
        // Ki ≥ 0: the integral branch pushes u in the direction of its input's sign.
        let i = self.int_op.step(e_pi, if self.g.ki > 0.0 { sat_dir } else { -sat_dir });
        let d = if self.g.kd == 0.0 { 0.0 } else { self.der_op.step(e_d, 0.0) };
        self.g.kp * e_pi + self.g.ki * i + self.g.kd * d
    }

    /// Transfer of the proportional + integral branch, `Kp + Ki F_{−λ}(z)`.
    pub fn response_pi(&self, z: Complex64) -> Complex64 {
        self.g.kp + self.g.ki * self.int_op.response(z)
    }

    /// Transfer of the derivative branch, `Kd F(z)`.
    pub fn response_d(&self, z: Complex64) -> Complex64 {
        self.g.kd * self.der_op.response(z)
    }
}
