//! Discrete PID with anti-windup (seed 000, Section 4.3, `u = Kp e + Ki ∫e + Kd ė`).
//!
//! ```text
//! I_k = I_{k−1} + T e_k                        (backward rectangle: T z/(z − 1))
//! D_k = (Tf D_{k−1} + Kd (e_k − e_{k−1})) / (Tf + T)
//!                                              (backward Euler of Kd s/(Tf s + 1); Tf = 0: Kd Δ)
//! u_k = Kp e_k + Ki I_k + D_k
//! C(z) = Kp + Ki T z/(z − 1) + Kd (1 − z⁻¹)/(Tf + T − Tf z⁻¹)
//! ```
//!
//! Anti-windup by conditional integration: when the previous command was saturated in
//! direction `s = ±1` and `e_k` would push further in that direction (`Ki e_k s > 0`), the
//! integrator holds. Unsaturated, the law is exactly the linear `C(z)` used by the
//! frequency response.

use num_complex::Complex64;
use serde::{Deserialize, Serialize};

/// PID gains (FMU group `pid.*`; `u` in N, `e` in m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PidGains {
    /// Proportional gain \[N/m\].
    pub kp: f64,
    /// Integral gain \[N/(m·s)\].
    pub ki: f64,
    /// Derivative gain \[N·s/m\].
    pub kd: f64,
    /// Derivative filter time constant \[s\] (0: pure backward difference).
    pub tf: f64,
}

/// Discrete PID state.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Pid {
    g: PidGains,
    ts: f64,
    integ: f64,
    d: f64,
    e_prev: f64,
}

impl Pid {
    /// New gains `kp`, `ki`, `kd` from the next sample on, the state kept (the integrator holds
    /// `∫e`, so a new `ki` weighs the accumulated integral at once).
    pub(crate) fn set_gains(&mut self, kp: f64, ki: f64, kd: f64) {
        (self.g.kp, self.g.ki, self.g.kd) = (kp, ki, kd);
    }

    /// A restored PID: the gains and period `fresh` has, a finite state.
    pub(crate) fn check(&self, fresh: &Self) -> Result<(), String> {
        if self.g != fresh.g || self.ts.to_bits() != fresh.ts.to_bits() {
            return Err("PID gains do not match the parameters".into());
        }
        crate::restored::finite("PID state", &[self.integ, self.d, self.e_prev])
    }

    /// PID at sample period `ts`.
    pub fn new(g: PidGains, ts: f64) -> Self {
        Pid { g, ts, integ: 0.0, d: 0.0, e_prev: 0.0 }
    }

    /// One sample; `sat_dir` is the saturation direction of the previous command (0 if none).
    #[inline]
    pub fn step(&mut self, e: f64, sat_dir: f64) -> f64 {
        let g = &self.g;
        if !(sat_dir != 0.0 && g.ki * e * sat_dir > 0.0) {
            self.integ += self.ts * e;
        }
        self.d = (g.tf * self.d + g.kd * (e - self.e_prev)) / (g.tf + self.ts);
        self.e_prev = e;
        g.kp * e + g.ki * self.integ + self.d
    }

    /// `C(z)` from `e` to `u` (same coefficients as [`step`](Self::step)).
    pub fn response(&self, z: Complex64) -> Complex64 {
        let g = &self.g;
        let zi = z.inv();
        let one = Complex64::new(1.0, 0.0);
        g.kp + g.ki * self.ts / (one - zi) + g.kd * (one - zi) / (g.tf + self.ts - g.tf * zi)
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    #[test]
    fn integrator_holds_while_saturated_in_the_same_direction() {
        let g = PidGains { kp: 0.0, ki: 1.0, kd: 0.0, tf: 0.0 };
        let mut p = Pid::new(g, 0.5);
        assert!((p.step(1.0, 0.0) - 0.5).abs() < 1e-15);
        assert!((p.step(1.0, 1.0) - 0.5).abs() < 1e-15);
        assert!((p.step(-1.0, 1.0) - 0.0).abs() < 1e-15);
        assert!((p.step(1.0, -1.0) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn step_matches_response_on_impulse() {
        // Ki = 0: the integrator's impulse response does not decay (its recurrence is tested above)
        let g = PidGains { kp: 2.0, ki: 0.0, kd: 0.01, tf: 1e-4 };
        let ts = 1e-5;
        let mut p = Pid::new(g, ts);
        let w = 2.0 * std::f64::consts::PI * 500.0;
        let mut acc = Complex64::new(0.0, 0.0);
        let n = 200_000;
        let mut prev = 0.0;
        // step response differenced = impulse response (the integrator makes the impulse response non-decaying)
        for k in 0..n {
            let u = p.step(1.0, 0.0);
            let h = u - prev;
            prev = u;
            acc += h * Complex64::from_polar(1.0, -w * ts * k as f64);
        }
        let want = p.response(Complex64::from_polar(1.0, w * ts));
        assert!((acc - want).norm() / want.norm() < 1e-6, "{acc} vs {want}");
    }
}
