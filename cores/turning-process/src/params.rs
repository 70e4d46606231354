//! Parameters of the turning process (Table 2 of seed 001 and the readings of what it omits).
//!
//! # Equations (seed 001, Eqs. 3–5)
//!
//! ```text
//! ẍ + 2ζω_n ẋ + ω_n² x = −(ω_n²/k) ΔF cos α
//! ΔF = P w [ s^Y − s₀^Y + (Y s₀^{Y−1}/N) C ẋ ] + ΔF_d(t)
//! s  = max(x(t) − x(t − T) + s₀, 0),   s₀ = f sin K,   T: one revolution (θ(t) − θ(t−T) = 2π)
//! ```
//!
//! Linearised at `s₀`: `ẍ + a₁ẋ + (ω_n² + a₂) x = a₂ x(t − T)` with
//! `a₂ = (ω_n²/k) P w Y s₀^{Y−1} cos α`.
//!
//! The paper gives neither `k`, `P`, `α` nor the units that tie them; only their product
//! enters. We lump them into `κ = a₂/(ω_n² w)` [1/mm] at the reference feed `f_ref`, so that
//! `(P cos α)/k = κ / (Y s_ref^{Y−1})` with `s_ref = f_ref sin K`. Readings (documented in the
//! README and the FMU documentation):
//!
//! * `Y = 0.75`, `K = 90°`, `α = 0`, `C = 0` (no process damping), `f_ref = f₀ = 0.1 mm/rev`
//!   (Table 2 prints "0.1 mm/sec"; a feed per revolution is what the chip needs);
//! * `κ = 0.01994 mm⁻¹`: at 450 rpm (an exact lobe minimum, `a₂,lim = 2ζ(1+ζ)ω_n²`) the
//!   limiting depth is then 4.0 mm, so Table 2's 2 mm is stable and 5 mm unstable, while 5 mm
//!   is stable at 520–524 rpm (the reference speed of the controller);
//! * the disturbance "1 % at 0.02 s" is a force pulse `ΔF_d` of 1 % of the static force
//!   `P w s₀^Y`, lasting 1 ms.

use crate::TurningError;
use serde::{Deserialize, Serialize};

/// Parameters of [`crate::TurningProcess`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TurningParams {
    /// Natural frequency f_n [Hz] (Table 2: 85).
    pub natural_frequency: f64,
    /// Damping ratio ζ (Table 2: 0.0384).
    pub damping_ratio: f64,
    /// Lumped cutting stiffness κ = a₂/(ω_n² w) at the reference feed [1/mm] (reading: 0.01994).
    pub kappa: f64,
    /// Feed at which κ is given [mm/rev] (reading: 0.1, the initial feed).
    pub reference_feed: f64,
    /// Force exponent Y (reading: 0.75).
    pub force_exponent: f64,
    /// Cutting edge angle K [deg] (reading: 90).
    pub edge_angle: f64,
    /// Process damping constant C [rpm·s] (reading: 0, as the paper's `a₁ ≈ 2ζω_n`).
    pub process_damping: f64,
    /// Depth of cut w [mm] (Table 2: 5 unstable, 2 stable).
    pub depth: f64,
    /// Start of the disturbance pulse [s] (Table 2: 0.02).
    pub pulse_time: f64,
    /// Duration of the disturbance pulse [s] (reading: 1 ms).
    pub pulse_duration: f64,
    /// Size of the pulse as a fraction of the static force P w s₀^Y (Table 2: 1 %).
    pub pulse_fraction: f64,
    /// Largest internal RK4 step [s].
    pub max_step: f64,
}

impl Default for TurningParams {
    fn default() -> Self {
        TurningParams {
            natural_frequency: 85.0,
            damping_ratio: 0.0384,
            kappa: 0.01994,
            reference_feed: 0.1,
            force_exponent: 0.75,
            edge_angle: 90.0,
            process_damping: 0.0,
            depth: 5.0,
            pulse_time: 0.02,
            pulse_duration: 1e-3,
            pulse_fraction: 0.01,
            max_step: 1e-4,
        }
    }
}

impl TurningParams {
    /// ω_n [rad/s].
    pub fn omega_n(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.natural_frequency
    }

    /// sin K.
    pub fn sin_k(&self) -> f64 {
        self.edge_angle.to_radians().sin()
    }

    /// The lumped force factor c = (P cos α)/k = κ/(Y s_ref^{Y−1}) [mm^{1−Y}].
    pub fn force_factor(&self) -> f64 {
        let s_ref = self.reference_feed * self.sin_k();
        self.kappa / (self.force_exponent * s_ref.powf(self.force_exponent - 1.0))
    }

    /// a₂ of the linearised equation (5) at feed `f` [mm/rev] and depth `w` [mm], [1/s²].
    pub fn a2(&self, feed: f64, depth: f64) -> f64 {
        let s0 = feed * self.sin_k();
        let y = self.force_exponent;
        self.omega_n().powi(2) * self.force_factor() * depth * y * s0.powf(y - 1.0)
    }

    /// a₁ = 2ζω_n (+ the process-damping term at speed `rpm`, feed `f` and the parameter depth).
    pub fn a1(&self, feed: f64, rpm: f64) -> f64 {
        2.0 * self.damping_ratio * self.omega_n() + self.a2(feed, self.depth) * self.process_damping / rpm
    }

    /// Check ranges.
    pub fn validate(&self) -> Result<(), TurningError> {
        let bad = |name: &str, v: f64| TurningError::Params(format!("{name} = {v} is out of range"));
        let pos = |name: &str, v: f64, max: f64| {
            if v.is_finite() && v > 0.0 && v <= max { Ok(()) } else { Err(bad(name, v)) }
        };
        let nonneg = |name: &str, v: f64, max: f64| {
            if v.is_finite() && (0.0..=max).contains(&v) { Ok(()) } else { Err(bad(name, v)) }
        };
        pos("natural_frequency", self.natural_frequency, 1e5)?;
        nonneg("damping_ratio", self.damping_ratio, 10.0)?;
        nonneg("kappa", self.kappa, 1e3)?;
        pos("reference_feed", self.reference_feed, 100.0)?;
        if !(self.force_exponent.is_finite() && self.force_exponent > 0.0 && self.force_exponent <= 2.0) {
            return Err(bad("force_exponent", self.force_exponent));
        }
        if !(self.edge_angle.is_finite() && self.edge_angle > 0.0 && self.edge_angle <= 90.0) {
            return Err(bad("edge_angle", self.edge_angle));
        }
        nonneg("process_damping", self.process_damping, 1e6)?;
        nonneg("depth", self.depth, 1e3)?;
        if !self.pulse_time.is_finite() || self.pulse_time.abs() > 1e9 {
            return Err(bad("pulse_time", self.pulse_time));
        }
        nonneg("pulse_duration", self.pulse_duration, 1e3)?;
        if !self.pulse_fraction.is_finite() || self.pulse_fraction.abs() > 1e3 {
            return Err(bad("pulse_fraction", self.pulse_fraction));
        }
        if !(self.max_step.is_finite() && self.max_step >= 1e-7 && self.max_step <= 1e-2) {
            return Err(bad("max_step", self.max_step));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kappa_is_a2_per_depth_at_the_reference_feed() {
        let p = TurningParams::default();
        let a2 = p.a2(0.1, 5.0);
        assert!((a2 / (p.omega_n().powi(2) * 5.0) - 0.01994).abs() < 1e-15);
        // a₂ ∝ s₀^{Y−1}: doubling the feed scales it by 2^{−0.25}
        assert!((p.a2(0.2, 5.0) / a2 - 2f64.powf(-0.25)).abs() < 1e-14);
        assert!(p.validate().is_ok());
        assert!(TurningParams { depth: f64::NAN, ..p.clone() }.validate().is_err());
        assert!(TurningParams { max_step: 0.0, ..p }.validate().is_err());
    }
}
