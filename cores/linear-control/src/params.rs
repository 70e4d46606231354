//! The controller's parameters: the matrices in fixed 8-state storage (entries beyond `n_c`
//! are ignored), β, the delay source, the form and the saturation.

use serde::{Deserialize, Serialize};

/// The largest controller order n_c.
pub const MAX_ORDER: usize = 8;

/// Parameters of [`crate::LinearController`] (module docs of the crate). SI units: `v` in m,
/// `F` in N, so `D_c` is in N/m; `A_c` in 1/s (continuous) or dimensionless (discrete).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinearControlParams {
    /// Order n_c ∈ 0..=8.
    pub n_c: u32,
    /// A_c (row, column), first n_c × n_c used.
    pub ac: [[f64; MAX_ORDER]; MAX_ORDER],
    /// B_c, first n_c rows used.
    pub bc: [[f64; 2]; MAX_ORDER],
    /// C_c, first n_c columns used.
    pub cc: [[f64; MAX_ORDER]; 2],
    /// D_c.
    pub dc: [[f64; 2]; 2],
    /// β of `w = v − β v(t − τ)`.
    pub beta: f64,
    /// τ = 60/(z n) from the spindle-speed input (else the `delay` parameter).
    pub delay_from_speed: bool,
    /// Number of teeth z.
    pub teeth: u32,
    /// τ \[s\] when not from the speed.
    pub delay: f64,
    /// The longest delay the buffer keeps \[s\].
    pub max_delay: f64,
    /// Discrete form (`ξ_{j+1} = A_c ξ_j + B_c w_j` every `sample_period`).
    pub discrete: bool,
    /// Sample period T_s of the discrete form \[s\] (and the unit of the work bound).
    pub sample_period: f64,
    /// Saturation `|F_i| ≤ saturation[i]` \[N\].
    pub saturation: [f64; 2],
}

impl Default for LinearControlParams {
    /// Order 0, zero gain, Pyragas β = 1, τ from the speed with 4 teeth, continuous, 1 MN
    /// saturation (effectively none).
    fn default() -> Self {
        LinearControlParams {
            n_c: 0,
            ac: [[0.0; MAX_ORDER]; MAX_ORDER],
            bc: [[0.0; 2]; MAX_ORDER],
            cc: [[0.0; MAX_ORDER]; 2],
            dc: [[0.0; 2]; 2],
            beta: 1.0,
            delay_from_speed: true,
            teeth: 4,
            delay: 4e-4,
            max_delay: 0.01,
            discrete: false,
            sample_period: 1e-6,
            saturation: [1e6; 2],
        }
    }
}

impl LinearControlParams {
    /// n_c as an index.
    pub fn order(&self) -> usize {
        (self.n_c as usize).min(MAX_ORDER)
    }

    /// Ranges and finiteness.
    pub fn validate(&self) -> Result<(), String> {
        if self.n_c as usize > MAX_ORDER {
            return Err(format!("n_c must be in 0..={MAX_ORDER} (got {})", self.n_c));
        }
        let all = self.ac.iter().flatten().chain(self.bc.iter().flatten()).chain(self.cc.iter().flatten());
        if !all.chain(self.dc.iter().flatten()).all(|x| x.is_finite()) {
            return Err("the matrices A_c, B_c, C_c, D_c must be finite".into());
        }
        if !self.beta.is_finite() {
            return Err(format!("beta must be finite (got {})", self.beta));
        }
        if self.teeth == 0 {
            return Err("teeth must be >= 1".into());
        }
        if !(self.max_delay.is_finite() && self.max_delay > 0.0 && self.max_delay <= 1.0) {
            return Err(format!("max_delay must be in (0, 1] s (got {})", self.max_delay));
        }
        if !(self.delay.is_finite() && self.delay >= 0.0 && self.delay <= self.max_delay) {
            return Err(format!("delay must be in [0, max_delay] (got {})", self.delay));
        }
        if !(self.sample_period.is_finite() && self.sample_period >= 1e-9 && self.sample_period <= 1.0) {
            return Err(format!("sample_period must be in [1e-9, 1] s (got {})", self.sample_period));
        }
        if !self.saturation.iter().all(|s| s.is_finite() && *s >= 0.0) {
            return Err(format!("saturation limits must be finite and >= 0 (got {:?})", self.saturation));
        }
        Ok(())
    }
}
