//! Seed 000's inertial actuator as its own model.
//!
//! `ż = A z + B u_sat`, `F = C z + D u_sat`, the command clipped to `±f_max` and held over a
//! step; the force acts along `(cos β_a, sin β_a)`. Defaults (seed 000, Section 3.3):
//! `F/u = s²/(s² + 15.834 s + 2785.6)`, a high-pass of unit gain above the 8.4 Hz corner,
//! saturated at ±27 N. Integrated by classical RK4 on sub-steps of at most `internal_step` (the
//! monolithic plant's grid), so that at the plant's step it is the same arithmetic.

use serde::{Deserialize, Serialize};

/// Why the actuator refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ActuatorError {
    /// A parameter is out of range.
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// An input is out of range (the step was not taken).
    #[error("invalid input: {0}")]
    Input(String),
}

/// Actuator parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ActuatorParams {
    /// State matrix, row-major [1/s, 1/s²; 1, 0].
    pub a: [[f64; 2]; 2],
    /// Input vector.
    pub b: [f64; 2],
    /// Output row.
    pub c: [f64; 2],
    /// Feedthrough.
    pub d: f64,
    /// Saturation of the command [N].
    pub f_max: f64,
    /// Direction β_a of the force from +x towards +y [rad].
    pub direction_angle: f64,
    /// Largest RK4 sub-step [s].
    pub internal_step: f64,
}

impl Default for ActuatorParams {
    fn default() -> Self {
        ActuatorParams {
            a: [[-15.834, -2785.6], [1.0, 0.0]],
            b: [1.0, 0.0],
            c: [-15.834, -2785.6],
            d: 1.0,
            f_max: 27.0,
            direction_angle: 0.0,
            internal_step: 1e-5,
        }
    }
}

impl ActuatorParams {
    /// Check ranges.
    pub fn validate(&self) -> Result<(), String> {
        let all = self.a.iter().flatten().chain(&self.b).chain(&self.c).chain([&self.d, &self.direction_angle]);
        if !all.clone().all(|x| x.is_finite()) {
            return Err("actuator matrices and direction must be finite".into());
        }
        if self.f_max.is_nan() || self.f_max < 0.0 {
            return Err("f_max must be >= 0".into());
        }
        if !(self.internal_step.is_finite() && self.internal_step > 0.0) {
            return Err("internal_step must be finite and > 0".into());
        }
        Ok(())
    }
}

/// Outputs at the current time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ActuatorOutputs {
    /// Force along the actuator's direction [N].
    pub force: f64,
    /// Its components (x, y) [N].
    pub force_xy: [f64; 2],
    /// Was the command clipped over the last step?
    pub saturated: bool,
}

/// The actuator.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct InertialActuator {
    p: ActuatorParams,
    z: [f64; 2],
    out: ActuatorOutputs,
}

impl InertialActuator {
    /// An actuator at rest.
    pub fn new(p: &ActuatorParams) -> Result<InertialActuator, ActuatorError> {
        p.validate().map_err(ActuatorError::Parameter)?;
        let mut a = InertialActuator { p: p.clone(), z: [0.0; 2], out: ActuatorOutputs::default() };
        a.refresh(0.0);
        Ok(a)
    }

    /// The parameters.
    pub fn params(&self) -> &ActuatorParams {
        &self.p
    }

    /// Outputs at the current time.
    pub fn outputs(&self) -> ActuatorOutputs {
        self.out
    }

    /// Sub-steps a step of `h` takes.
    pub fn internal_steps(&self, h: f64) -> f64 {
        (h / self.p.internal_step).ceil() + 1.0
    }

    fn sat(&self, u: f64) -> (f64, bool) {
        (u.clamp(-self.p.f_max, self.p.f_max), u.abs() > self.p.f_max)
    }

    /// Recompute the outputs for the command `u` now (feedthrough `D u`).
    pub fn set_command(&mut self, u: f64) -> Result<(), ActuatorError> {
        if !u.is_finite() {
            return Err(ActuatorError::Input(format!("u = {u} is not finite")));
        }
        self.refresh(u);
        Ok(())
    }

    /// Advance by `h` with the command `u` held.
    pub fn step(&mut self, h: f64, u: f64) -> Result<(), ActuatorError> {
        if !u.is_finite() {
            return Err(ActuatorError::Input(format!("u = {u} is not finite")));
        }
        if !(h.is_finite() && h >= 0.0) {
            return Err(ActuatorError::Input(format!("step size {h} must be finite and >= 0")));
        }
        let n = (h / self.p.internal_step * (1.0 - 1e-9)).ceil().max(1.0) as u64;
        let dt = h / n as f64;
        let (us, _) = self.sat(u);
        let a = &self.p;
        let f = |z: [f64; 2]| {
            [a.a[0][0] * z[0] + a.a[0][1] * z[1] + a.b[0] * us, a.a[1][0] * z[0] + a.a[1][1] * z[1] + a.b[1] * us]
        };
        for _ in 0..n {
            let z = self.z;
            let k1 = f(z);
            let k2 = f([z[0] + 0.5 * dt * k1[0], z[1] + 0.5 * dt * k1[1]]);
            let k3 = f([z[0] + 0.5 * dt * k2[0], z[1] + 0.5 * dt * k2[1]]);
            let k4 = f([z[0] + dt * k3[0], z[1] + dt * k3[1]]);
            for j in 0..2 {
                self.z[j] = z[j] + dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
            }
        }
        self.refresh(u);
        Ok(())
    }

    fn refresh(&mut self, u: f64) {
        let (us, saturated) = self.sat(u);
        let force = self.p.c[0] * self.z[0] + self.p.c[1] * self.z[1] + self.p.d * us;
        let (s, c) = self.p.direction_angle.sin_cos();
        self.out = ActuatorOutputs { force, force_xy: [force * c, force * s], saturated };
    }

    /// Is this a state the actuator can continue from?
    pub fn validate_state(&self) -> Result<(), String> {
        self.p.validate()?;
        let o = &self.out;
        if !(self.z.iter().chain(&o.force_xy).chain([&o.force]).all(|x| x.is_finite())) {
            return Err("the actuator state is not finite".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sinusoidal_command_at_143_hz_passes_with_the_transfer_functions_gain() {
        // F/u = s²/(s² + 15.834 s + 2785.6) at 143 Hz: |G| ≈ 1.0013
        let mut a = InertialActuator::new(&ActuatorParams::default()).unwrap();
        let (f, h) = (143.0, 1e-5);
        let w = 2.0 * std::f64::consts::PI * f;
        let mut peak: f64 = 0.0;
        for k in 0..200_000 {
            let t = k as f64 * h;
            a.step(h, 10.0 * (w * (t + h)).sin()).unwrap();
            if t > 1.5 {
                peak = peak.max(a.outputs().force.abs());
            }
        }
        let s = num(w);
        assert!((peak / 10.0 - s).abs() < 2e-3, "{peak} vs gain {s}");
    }

    fn num(w: f64) -> f64 {
        let (re, im) = (2785.6 - w * w, 15.834 * w);
        w * w / (re * re + im * im).sqrt()
    }

    #[test]
    fn the_command_saturates_and_non_finite_commands_are_refused() {
        let mut a = InertialActuator::new(&ActuatorParams::default()).unwrap();
        a.step(1e-5, 100.0).unwrap();
        assert!(a.outputs().saturated && (a.outputs().force - 27.0).abs() < 0.1);
        assert!(a.step(1e-5, f64::NAN).is_err());
        let p = ActuatorParams { direction_angle: std::f64::consts::FRAC_PI_2, ..Default::default() };
        let mut a = InertialActuator::new(&p).unwrap();
        a.step(1e-5, 1.0).unwrap();
        assert!(a.outputs().force_xy[0].abs() < 1e-15 && a.outputs().force_xy[1] > 0.9);
    }
}
