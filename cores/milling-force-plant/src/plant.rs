//! # Milling force plant (seed 004, Eqs. 1–3)
//!
//! A feed-rate command `f_c` [mm/s] drives the CNC feed drive, a first-order lag
//! `τ_s ḟ_a = f_c − f_a`, and the actual feed `f_a` drives the cutting force through the chip
//! lag `τ_c Ḟ_p = K_p(t) f_a − F_p`:
//!
//! ```text
//! G(s) = F_p/f_c = K_p / ((τ_s s + 1)(τ_c s + 1)),   K_p = K_c b(t) S_t / (N n)  [N·s/mm],
//! ```
//!
//! with `K_c` [N/mm²] the specific cutting pressure, `b(t)` [mm] the axial depth of cut
//! (piecewise constant: up to [`MAX_SEGMENTS`] segments `(t_i, b_i)`, `b = b_i` for
//! `t_i ≤ t < t_{i+1}`, `b_0` before `t_0`), `S_t` the immersion function (constant for four
//! flutes at full immersion; 1 for tangential forces only), `N` teeth and `n` [rev/s]. The
//! chip-thickness form `F = K_c b S_t f/(N n)` is the feed per tooth `f/(N n)` times `K_c b`.
//!
//! ## Exact integration
//!
//! Over a step `[t, t+h)` the command is the ramp `f_c + ḟ_c (s − t − h/2)` (mean `f_c`, slope
//! `ḟ_c`; a zero slope is the usual held input). The step is split at the depth changes and
//! each piece is integrated exactly with [`RampPropagator`] (augmented matrix exponential of the
//! linear model), so the plant is exact for the FROH's piecewise-linear command. With
//! `τ_s = 0` the drive is ideal (`f_a = f_c`) and the model is the first-order lag alone.

use crate::ForceError;
use crate::froh::{RampPropagator, StateSpace};
use nalgebra::DVector;
use serde::{Deserialize, Serialize};

/// Most depth segments.
pub const MAX_SEGMENTS: usize = 8;

/// The axial depth-of-cut profile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DepthProfile {
    /// Number of segments used (1..=8).
    pub segments: u32,
    /// Segment start times [s], increasing.
    pub t: [f64; MAX_SEGMENTS],
    /// Depth of each segment [mm].
    pub b: [f64; MAX_SEGMENTS],
}

impl Default for DepthProfile {
    /// The reading of Figure 1: b = 2 / 4 / 1 / 3 mm on 0–3 / 3–6 / 6–9 / 9–12 s.
    fn default() -> Self {
        DepthProfile {
            segments: 4,
            t: [0.0, 3.0, 6.0, 9.0, 12.0, 15.0, 18.0, 21.0],
            b: [2.0, 4.0, 1.0, 3.0, 3.0, 3.0, 3.0, 3.0],
        }
    }
}

impl DepthProfile {
    /// A constant depth.
    pub fn constant(b: f64) -> Self {
        let mut p = DepthProfile { segments: 1, ..Default::default() };
        p.b[0] = b;
        p
    }

    /// Index of the segment in force at `t`.
    pub fn segment_at(&self, t: f64) -> usize {
        let n = self.segments as usize;
        (1..n).rev().find(|&i| t >= self.t[i]).unwrap_or(0)
    }

    /// Depth at `t` [mm].
    pub fn depth_at(&self, t: f64) -> f64 {
        self.b[self.segment_at(t)]
    }
}

/// Parameters of the force plant (the paper's values where it gives them).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ForcePlantParams {
    /// Specific cutting pressure K_c [N/mm²] (1200, aluminium).
    pub kc: f64,
    /// Number of teeth N (4).
    pub teeth: u32,
    /// Spindle speed [rpm] (715).
    pub spindle_speed_rpm: f64,
    /// Immersion function S_t (1: full immersion, tangential force).
    pub immersion: f64,
    /// CNC feed-drive time constant τ_s [s] (0.1 ms as printed).
    pub tau_s: f64,
    /// Chip time constant τ_c [s] (reading: one tooth period 1/(N n)).
    pub tau_c: f64,
    /// Depth-of-cut profile.
    pub depth: DepthProfile,
}

impl Default for ForcePlantParams {
    fn default() -> Self {
        let rpm = 715.0;
        let teeth = 4;
        ForcePlantParams {
            kc: 1200.0,
            teeth,
            spindle_speed_rpm: rpm,
            immersion: 1.0,
            tau_s: 1e-4,
            tau_c: 60.0 / (rpm * teeth as f64),
            depth: DepthProfile::default(),
        }
    }
}

impl ForcePlantParams {
    /// Spindle period 1/n [s] (the sample period of the paper).
    pub fn spindle_period(&self) -> f64 {
        60.0 / self.spindle_speed_rpm
    }

    /// Tooth period 1/(N n) [s].
    pub fn tooth_period(&self) -> f64 {
        self.spindle_period() / self.teeth as f64
    }

    /// Process gain K_p = K_c b S_t/(N n) [N·s/mm] at depth `b` [mm].
    pub fn gain(&self, b: f64) -> f64 {
        self.kc * b * self.immersion * self.tooth_period()
    }

    /// The continuous model at depth `b`.
    pub fn model(&self, b: f64) -> StateSpace {
        if self.tau_s > 0.0 {
            StateSpace::two_lags(self.gain(b), self.tau_s, self.tau_c)
        } else {
            StateSpace::first_order(self.gain(b), self.tau_c)
        }
    }

    /// Checks every field.
    pub fn validate(&self) -> Result<(), ForceError> {
        let bad = |m: String| Err(ForceError::Params(m));
        if !(self.kc.is_finite() && self.kc > 0.0) {
            return bad(format!("kc = {} must be positive", self.kc));
        }
        if self.teeth == 0 || self.teeth > 1000 {
            return bad(format!("teeth = {} must be in 1..=1000", self.teeth));
        }
        if !(self.spindle_speed_rpm.is_finite() && self.spindle_speed_rpm > 0.0) {
            return bad(format!("spindle speed {} rpm must be positive", self.spindle_speed_rpm));
        }
        if !(self.immersion.is_finite() && self.immersion >= 0.0) {
            return bad(format!("immersion {} must be >= 0", self.immersion));
        }
        if !(self.tau_s.is_finite() && self.tau_s >= 0.0) {
            return bad(format!("tau_s = {} must be >= 0", self.tau_s));
        }
        if !(self.tau_c.is_finite() && self.tau_c > 0.0) {
            return bad(format!("tau_c = {} must be positive", self.tau_c));
        }
        let d = &self.depth;
        let n = d.segments as usize;
        if n == 0 || n > MAX_SEGMENTS {
            return bad(format!("{n} depth segments (1..={MAX_SEGMENTS})"));
        }
        if d.t[..n].iter().chain(&d.b[..n]).any(|x| !x.is_finite()) || d.b[..n].iter().any(|&b| b < 0.0) {
            return bad("depth segments must be finite with b >= 0".into());
        }
        if d.t[..n].windows(2).any(|w| w[1] <= w[0]) {
            return bad("depth segment times must increase".into());
        }
        Ok(())
    }
}

/// The plant's outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ForcePlantOutputs {
    /// Cutting force F_p [N].
    pub force: f64,
    /// Actual feed rate f_a [mm/s].
    pub feed: f64,
    /// Axial depth of cut in force [mm].
    pub depth: f64,
    /// Process gain K_p in force [N·s/mm].
    pub gain: f64,
}

/// The plant's inputs over a step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ForcePlantInputs {
    /// Feed-rate command, mean over the step [mm/s].
    pub feed_command: f64,
    /// Slope of the feed-rate command within the step [mm/s²].
    pub feed_command_rate: f64,
}

/// The force plant: state `(f_a, F_p)` at time `t`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ForcePlant {
    params: ForcePlantParams,
    t: f64,
    feed: f64,
    force: f64,
    #[serde(skip)]
    cache: Option<(u64, u64, RampPropagator)>,
}

impl ForcePlant {
    /// A plant at rest at t = 0.
    pub fn new(params: &ForcePlantParams) -> Result<Self, ForceError> {
        params.validate()?;
        Ok(ForcePlant { params: params.clone(), t: 0.0, feed: 0.0, force: 0.0, cache: None })
    }

    /// The parameters.
    pub fn params(&self) -> &ForcePlantParams {
        &self.params
    }

    /// Time of the state [s].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Sets the clock (the FMU's start time).
    pub fn set_time(&mut self, t: f64) {
        self.t = t;
    }

    /// Outputs at the present state.
    pub fn outputs(&self) -> ForcePlantOutputs {
        let b = self.params.depth.depth_at(self.t);
        ForcePlantOutputs { force: self.force, feed: self.feed, depth: b, gain: self.params.gain(b) }
    }

    fn propagator(&mut self, h: f64, b: f64) -> Result<&RampPropagator, ForceError> {
        let key = (h.to_bits(), b.to_bits());
        if self.cache.as_ref().is_none_or(|c| (c.0, c.1) != key) {
            let p = RampPropagator::new(&self.params.model(b), h)?;
            self.cache = Some((key.0, key.1, p));
        }
        Ok(&self.cache.as_ref().expect("just set").2)
    }

    /// Advances by `h > 0` with the command ramp of `inputs` (exact).
    pub fn step(&mut self, h: f64, inputs: &ForcePlantInputs) -> Result<(), ForceError> {
        let (fc, rate) = (inputs.feed_command, inputs.feed_command_rate);
        if !(fc.is_finite() && rate.is_finite()) {
            return Err(ForceError::Input(format!("feed command {fc} mm/s, rate {rate} mm/s2")));
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(ForceError::Input(format!("step {h} s")));
        }
        let t0 = self.t;
        let end = t0 + h;
        let mut s = t0;
        while s < end {
            let seg = self.params.depth.segment_at(s);
            let n = self.params.depth.segments as usize;
            let next = if seg + 1 < n && self.params.depth.t[seg + 1] > s { self.params.depth.t[seg + 1] } else { end };
            let s1 = if next < end && next - s > 1e-12 * h { next } else { end };
            // a change within rounding of the step end is taken at the next step
            let s1 = if end - s1 <= 1e-12 * h { end } else { s1 };
            let b = self.params.depth.b[seg];
            let w0 = fc + rate * (s - t0 - 0.5 * h);
            let tau_s = self.params.tau_s;
            let (feed, force) = (self.feed, self.force);
            let p = self.propagator(s1 - s, b)?;
            if tau_s > 0.0 {
                let x = p.propagate(&DVector::from_column_slice(&[feed, force]), w0, rate);
                self.feed = x[0];
                self.force = x[1];
            } else {
                let x = p.propagate(&DVector::from_column_slice(&[force]), w0, rate);
                self.force = x[0];
                self.feed = fc + rate * (s1 - t0 - 0.5 * h);
            }
            s = s1;
        }
        self.t = end;
        if !(self.force.is_finite() && self.feed.is_finite()) {
            return Err(ForceError::Input("the state left the finite range".into()));
        }
        Ok(())
    }

    /// Parameters valid and state finite (for restored FMU states).
    pub fn validate_state(&self) -> Result<(), String> {
        self.params.validate().map_err(|e| e.to_string())?;
        if ![self.t, self.feed, self.force].iter().all(|x| x.is_finite()) {
            return Err("the plant state is not finite".into());
        }
        Ok(())
    }
}
