//! The time-domain turning process: RK4 on a fixed internal grid, the chip from the surface one
//! revolution back (found by angle), loss of contact, the disturbance pulse.
//!
//! # Equations
//!
//! With `u = ẋ`, the tool angle `θ(t) = ∫ 2πN/60 dt` and `c = (P cos α)/k`
//! ([`TurningParams::force_factor`]):
//!
//! ```text
//! ẋ = u
//! u̇ = −2ζω_n u − ω_n² x − ω_n² q(t),   q = c w [s^Y − s₀^Y + (Y s₀^{Y−1}/N) C u + d(t) s₀^Y]
//! s = max(x(t) − x(t*) + s₀, 0),  θ(t*) = θ(t) − 2π,  s₀ = f sin K
//! ```
//!
//! `q = ΔF cos α / k` is the cutting force expressed as the static deflection it causes [mm]
//! (the output `force`); `d(t)` is the pulse fraction inside `[t_d, t_d + τ_d)`, else 0.
//! `x(t*)` comes from the angle-indexed history of `milling-process` (cubic Hermite through
//! the stored `x, ẋ`, third order like the integrator); before the cut has gone once around,
//! the surface is the fresh, round one (`x = 0`).
//!
//! # Timing
//!
//! A step `[t, t + h]` holds the speed and the feed, and takes `n = ⌈h/max_step⌉` RK4 steps of
//! `h/n`. Outputs are those at `t + h`.
//!
//! # A stopped spindle
//!
//! Below [`min_speed`] (one revolution would not fit the history at the internal step), and at
//! 0 rpm, the spindle counts as stopped: the workpiece does not turn and the tool does not cut
//! (no chip, no cutting force: `q = −c w s₀^Y`, the static force released, so `x` stays the
//! displacement from the static equilibrium of the cut at this feed). A master that starts the
//! speed connection at 0 (FMPy's `simulate_ssp`) used to get fmi2Discard at the first step.

use crate::{TurningError, TurningParams};
use milling_process::history::{History, MAX_SAMPLES, Sample};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Inputs held over a step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TurningInputs {
    /// Spindle speed N [rpm] (> 0).
    pub spindle_speed: f64,
    /// Feed f [mm/rev] (≥ 0).
    pub feed: f64,
}

impl Default for TurningInputs {
    /// Table 2: 450 rpm, 0.1 mm/rev.
    fn default() -> Self {
        TurningInputs { spindle_speed: 450.0, feed: 0.1 }
    }
}

/// Outputs at the current time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TurningOutputs {
    /// Tool displacement x [mm] (from the static equilibrium).
    pub x: f64,
    /// Tool velocity ẋ [mm/s].
    pub v: f64,
    /// Dynamic cutting force as the static deflection it causes, ΔF cos α/k [mm].
    pub force: f64,
    /// Chip thickness s [mm].
    pub chip: f64,
    /// Regenerative delay: time since the surface now cut was left [s] (0 in the first revolution).
    pub delay: f64,
    /// Workpiece angle θ mod 2π [rad].
    pub angle: f64,
}

/// The turning process.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TurningProcess {
    params: TurningParams,
    t: f64,
    theta: f64,
    x: f64,
    v: f64,
    history: History<Sample>,
    last: TurningInputs,
    out: TurningOutputs,
}

/// Below this speed one revolution would not fit in the history at the internal step.
pub fn min_speed(params: &TurningParams) -> f64 {
    60.0 / (0.5 * MAX_SAMPLES as f64 * params.max_step)
}

impl TurningProcess {
    /// A process at rest (`x = ẋ = 0`) on a fresh workpiece at `t = 0`.
    pub fn new(params: &TurningParams) -> Result<Self, TurningError> {
        params.validate()?;
        let mut history = History::default();
        history.push(Sample { t: 0.0, theta: 0.0, x: 0.0, v: 0.0 });
        let mut p = TurningProcess {
            params: params.clone(),
            t: 0.0,
            theta: 0.0,
            x: 0.0,
            v: 0.0,
            history,
            last: TurningInputs::default(),
            out: TurningOutputs::default(),
        };
        p.out = p.evaluate(&TurningInputs::default());
        Ok(p)
    }

    /// The parameters.
    pub fn params(&self) -> &TurningParams {
        &self.params
    }

    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Set the clock (a master's communication point; the history keeps its own times).
    pub fn set_time(&mut self, t: f64) {
        self.t = t;
    }

    /// The outputs at the current time.
    pub fn outputs(&self) -> TurningOutputs {
        self.out
    }

    fn check(&self, h: f64, i: &TurningInputs) -> Result<(), TurningError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(TurningError::Input(format!("step {h} s is not positive and finite")));
        }
        if !(i.spindle_speed.is_finite() && (0.0..=1e6).contains(&i.spindle_speed)) {
            return Err(TurningError::Input(format!(
                "spindle_speed = {} rpm is outside [0, 1e6] rpm",
                i.spindle_speed
            )));
        }
        if !(i.feed.is_finite() && (0.0..=100.0).contains(&i.feed)) {
            return Err(TurningError::Input(format!("feed = {} mm/rev is outside [0, 100]", i.feed)));
        }
        Ok(())
    }

    /// Pulse fraction d(t).
    fn pulse(&self, t: f64) -> f64 {
        let p = &self.params;
        if t >= p.pulse_time && t < p.pulse_time + p.pulse_duration { p.pulse_fraction } else { 0.0 }
    }

    /// Surface displacement one revolution back from angle `theta`.
    fn delayed(&self, theta: f64) -> f64 {
        self.history.at_angle(theta - 2.0 * PI).map_or(0.0, |(_, x)| x)
    }

    /// Does the spindle turn (and the tool cut) at the inputs `i`? (See the module doc.)
    pub fn turning(&self, i: &TurningInputs) -> bool {
        i.spindle_speed >= min_speed(&self.params)
    }

    /// (q, s): force as deflection and chip at (t, θ, x, u).
    fn force(&self, t: f64, theta: f64, x: f64, u: f64, i: &TurningInputs) -> (f64, f64) {
        let p = &self.params;
        let y = p.force_exponent;
        let s0 = i.feed * p.sin_k();
        if !self.turning(i) {
            return (-p.force_factor() * p.depth * s0.powf(y), 0.0);
        }
        let s = (x - self.delayed(theta) + s0).max(0.0);
        let s0y = s0.powf(y);
        let damping = if p.process_damping > 0.0 && s0 > 0.0 {
            y * s0.powf(y - 1.0) * p.process_damping * u / i.spindle_speed
        } else {
            0.0
        };
        let q = p.force_factor() * p.depth * (s.powf(y) - s0y + damping + self.pulse(t) * s0y);
        (q, s)
    }

    fn evaluate(&self, i: &TurningInputs) -> TurningOutputs {
        let (force, chip) = self.force(self.t, self.theta, self.x, self.v, i);
        let delay = self.history.at_angle(self.theta - 2.0 * PI).map_or(0.0, |(ts, _)| self.t - ts);
        TurningOutputs { x: self.x, v: self.v, force, chip, delay, angle: self.theta.rem_euclid(2.0 * PI) }
    }

    /// Advance by `h` with the inputs held. On an error the state is unchanged.
    pub fn step(&mut self, h: f64, i: &TurningInputs) -> Result<(), TurningError> {
        self.check(h, i)?;
        let n = (h / self.params.max_step - 1e-9).ceil().max(1.0) as usize;
        let dt = h / n as f64;
        let omega = if self.turning(i) { 2.0 * PI * i.spindle_speed / 60.0 } else { 0.0 };
        let w2 = self.params.omega_n().powi(2);
        let zw = 2.0 * self.params.damping_ratio * self.params.omega_n();
        let saved = (self.t, self.theta, self.x, self.v);
        let t0 = self.t;
        for k in 0..n {
            let (t, th, x, v) = (t0 + k as f64 * dt, self.theta, self.x, self.v);
            let acc = |tc: f64, thc: f64, xc: f64, uc: f64| -zw * uc - w2 * xc - w2 * self.force(tc, thc, xc, uc, i).0;
            let (k1x, k1v) = (v, acc(t, th, x, v));
            let (x2, v2) = (x + 0.5 * dt * k1x, v + 0.5 * dt * k1v);
            let (k2x, k2v) = (v2, acc(t + 0.5 * dt, th + 0.5 * dt * omega, x2, v2));
            let (x3, v3) = (x + 0.5 * dt * k2x, v + 0.5 * dt * k2v);
            let (k3x, k3v) = (v3, acc(t + 0.5 * dt, th + 0.5 * dt * omega, x3, v3));
            let (x4, v4) = (x + dt * k3x, v + dt * k3v);
            let (k4x, k4v) = (v4, acc(t + dt, th + dt * omega, x4, v4));
            self.x = x + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            self.v = v + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            self.theta = th + dt * omega;
            self.t = t0 + (k + 1) as f64 * dt;
            if !(self.x.is_finite() && self.v.is_finite() && self.x.abs() < 1e6) {
                let t_fail = self.t;
                (self.t, self.theta, self.x, self.v) = saved;
                return Err(TurningError::Diverged { t: t_fail });
            }
            self.history.push(Sample { t: self.t, theta: self.theta, x: self.x, v: self.v });
        }
        // keep a little more than one revolution (the lookups need θ − 2π and later)
        self.history.prune(self.theta - 2.0 * PI - omega * 4.0 * dt);
        self.last = *i;
        self.out = self.evaluate(i);
        Ok(())
    }

    /// Is a restored state usable? (finite values, an ordered history)
    pub fn validate_state(&self) -> Result<(), String> {
        self.params.validate().map_err(|e| e.to_string())?;
        if ![self.t, self.theta, self.x, self.v].iter().all(|v| v.is_finite()) {
            return Err("the process state is not finite".into());
        }
        self.history.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_delay_is_one_revolution_and_follows_a_speed_change() {
        let mut p = TurningProcess::new(&TurningParams::default()).unwrap();
        for _ in 0..2000 {
            p.step(1e-4, &TurningInputs::default()).unwrap();
        }
        assert!((p.outputs().delay - 60.0 / 450.0).abs() < 1e-9);
        // after a jump to 600 rpm the delay moves from the old to the new revolution time
        let fast = TurningInputs { spindle_speed: 600.0, feed: 0.1 };
        for _ in 0..500 {
            p.step(1e-4, &fast).unwrap();
        }
        // 0.05 s at 600 rpm = 0.5 rev: the remaining 0.5 rev came at 450 rpm → 0.05 + 0.0667
        assert!((p.outputs().delay - (0.05 + 0.5 * 60.0 / 450.0)).abs() < 1e-9, "{}", p.outputs().delay);
    }

    #[test]
    fn bad_inputs_are_refused_and_leave_the_state() {
        let mut p = TurningProcess::new(&TurningParams::default()).unwrap();
        p.step(1e-3, &TurningInputs::default()).unwrap();
        let before = format!("{:?}", p.outputs());
        for i in [
            TurningInputs { spindle_speed: f64::NAN, feed: 0.1 },
            TurningInputs { spindle_speed: -1.0, feed: 0.1 },
            TurningInputs { spindle_speed: 450.0, feed: -1.0 },
            TurningInputs { spindle_speed: 450.0, feed: f64::INFINITY },
        ] {
            assert!(matches!(p.step(1e-3, &i), Err(TurningError::Input(_))));
        }
        assert!(p.step(f64::NAN, &TurningInputs::default()).is_err());
        assert_eq!(before, format!("{:?}", p.outputs()));
    }

    /// FMPy's `simulate_ssp` starts every connection at 0: `Afrac.ssp` failed at once with
    /// "spindle_speed = 0 rpm is outside [4.578, 1e6] rpm" (fmi2Discard). A stopped spindle is a
    /// physical state: no cut, the static force released, the workpiece still.
    #[test]
    fn a_stopped_spindle_does_not_cut() {
        let p0 = TurningParams { pulse_fraction: 0.0, ..Default::default() };
        let n_min = min_speed(&p0);
        for speed in [0.0, 0.5 * n_min] {
            let mut p = TurningProcess::new(&p0).unwrap();
            let stopped = TurningInputs { spindle_speed: speed, feed: 0.1 };
            for _ in 0..200 {
                p.step(1e-4, &stopped).unwrap();
            }
            let o = p.outputs();
            assert_eq!((o.chip, o.angle), (0.0, 0.0), "{speed} rpm");
            let released = -p0.force_factor() * p0.depth * (0.1 * p0.sin_k()).powf(p0.force_exponent);
            assert_eq!(o.force, released);
            assert!(o.x != 0.0, "the tool springs back from the static deflection");
            // with no feed either (FMPy's first step) nothing moves
            let mut p = TurningProcess::new(&p0).unwrap();
            p.step(1e-4, &TurningInputs { spindle_speed: speed, feed: 0.0 }).unwrap();
            assert_eq!((p.outputs().x, p.outputs().force), (0.0, 0.0));
            // and the spindle starts again: it cuts
            p.step(1e-4, &TurningInputs::default()).unwrap();
            assert!(p.outputs().chip > 0.0);
        }
    }

    #[test]
    fn no_disturbance_no_motion_and_the_pulse_pushes_the_tool() {
        let quiet = TurningParams { pulse_fraction: 0.0, ..Default::default() };
        let mut p = TurningProcess::new(&quiet).unwrap();
        for _ in 0..1000 {
            p.step(1e-4, &TurningInputs::default()).unwrap();
        }
        assert_eq!(p.outputs().x.to_bits(), 0f64.to_bits());
        let mut p = TurningProcess::new(&TurningParams::default()).unwrap();
        for _ in 0..220 {
            p.step(1e-4, &TurningInputs::default()).unwrap();
        }
        assert!(p.outputs().x < 0.0, "a positive force pushes the tool to negative x");
    }
}
