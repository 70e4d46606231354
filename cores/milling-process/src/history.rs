//! Displacement history indexed by tool angle, for the regenerative delay (shared by the
//! monolithic plant `milling-plant`, which stores the beam tip with its velocity, and by
//! [`crate::Process`], which stores the tool-minus-workpiece displacement in x and y).
//!
//! The delay is the time since the previous tooth passed the current tooth's angle: with the
//! tool angle `θ(t) = ∫Ω dt`, the surface a tooth meets at `t` was left at `t*` where
//! `θ(t*) = θ(t) − 2π/Z`. The history stores `(t, θ, x, ẋ)` at the end of every internal step;
//! a lookup finds the bracketing samples (a short scan from the oldest sample, where lookups
//! land after pruning, then bisection on θ), converts the angle fraction into a
//! time fraction (Ω is constant within a step, so θ is linear there) and interpolates `x` with
//! the cubic Hermite polynomial through both samples' displacement and velocity (third order,
//! as accurate as the RK4 integrator uses it). A sample type says how it interpolates
//! ([`HistorySample`]): [`Sample`] (scalar, Hermite) for the plant, [`XySample`] (two axes,
//! linear in angle, because the process only sees displacements at communication points) for the
//! process. At constant speed `t − t* = 60/(Z N)` exactly.
//! Before the first sample the surface is taken as flat (`x = 0`): the cut starts on a fresh,
//! non-wavy surface.
//!
//! Memory is bounded for every input: a sample at the same angle as the two before it replaces
//! the newest of them (no lookup can need the middle one of three equal angles, so at 0 rpm the
//! history stays at a few samples, and lookups are bitwise unchanged), and the buffer never holds
//! more than [`MAX_SAMPLES`] (the plant refuses to cut at speeds whose tooth period would not
//! fit, see `Plant::min_cutting_speed_rpm`).

use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// What the history needs of a stored instant: its time and angle, a finiteness check and how
/// to interpolate between two samples.
pub trait HistorySample: Copy {
    /// The interpolated quantity (displacement).
    type Value: Copy;
    /// Time [s].
    fn t(&self) -> f64;
    /// Tool angle [rad].
    fn theta(&self) -> f64;
    /// Are all fields finite?
    fn is_finite(&self) -> bool;
    /// The value at the sample.
    fn value(&self) -> Self::Value;
    /// The value at fraction `s` ∈ [0, 1) of the way from `a` to `b` (`dt = b.t − a.t`).
    fn interpolate(a: &Self, b: &Self, s: f64, dt: f64) -> Self::Value;
}

/// One stored instant of a scalar displacement with its velocity (the plant's beam tip).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Sample {
    /// Time [s].
    pub t: f64,
    /// Tool angle [rad], non-decreasing.
    pub theta: f64,
    /// Tip displacement [m].
    pub x: f64,
    /// Tip velocity [m/s].
    pub v: f64,
}

impl HistorySample for Sample {
    type Value = f64;
    fn t(&self) -> f64 {
        self.t
    }
    fn theta(&self) -> f64 {
        self.theta
    }
    fn is_finite(&self) -> bool {
        self.t.is_finite() && self.theta.is_finite() && self.x.is_finite() && self.v.is_finite()
    }
    fn value(&self) -> f64 {
        self.x
    }
    /// Cubic Hermite through both displacements and velocities.
    fn interpolate(a: &Self, b: &Self, s: f64, dt: f64) -> f64 {
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * a.x
            + (s3 - 2.0 * s2 + s) * dt * a.v
            + (-2.0 * s3 + 3.0 * s2) * b.x
            + (s3 - s2) * dt * b.v
    }
}

/// One stored instant of a two-axis displacement (the process's tool-minus-workpiece vector).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct XySample {
    /// Time [s].
    pub t: f64,
    /// Tool angle [rad], non-decreasing.
    pub theta: f64,
    /// Displacement (x, y) [m].
    pub r: [f64; 2],
}

impl HistorySample for XySample {
    type Value = [f64; 2];
    fn t(&self) -> f64 {
        self.t
    }
    fn theta(&self) -> f64 {
        self.theta
    }
    fn is_finite(&self) -> bool {
        self.t.is_finite() && self.theta.is_finite() && self.r.iter().all(|x| x.is_finite())
    }
    fn value(&self) -> [f64; 2] {
        self.r
    }
    /// Linear in the angle (no velocities are known).
    fn interpolate(a: &Self, b: &Self, s: f64, _dt: f64) -> [f64; 2] {
        [a.r[0] + s * (b.r[0] - a.r[0]), a.r[1] + s * (b.r[1] - a.r[1])]
    }
}

/// The most samples the history holds (8 MiB); older ones are dropped.
pub const MAX_SAMPLES: usize = 1 << 18;

/// The history buffer.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct History<S = Sample> {
    buf: VecDeque<S>,
}

impl<S> Default for History<S> {
    fn default() -> Self {
        History { buf: VecDeque::new() }
    }
}

impl<S: HistorySample> History<S> {
    /// Append a sample (angles must not decrease). Of three or more samples at one angle only
    /// the first and the newest can be the bracket of a lookup: the newest replaces the last.
    #[allow(clippy::float_cmp)] // exact: only samples at the identical angle are interchangeable
    pub fn push(&mut self, s: S) {
        debug_assert!(self.buf.back().is_none_or(|b| b.theta() <= s.theta()));
        let n = self.buf.len();
        if n >= 2 && self.buf[n - 1].theta() == s.theta() && self.buf[n - 2].theta() == s.theta() {
            self.buf[n - 1] = s;
        } else {
            self.buf.push_back(s);
        }
        if self.buf.len() > MAX_SAMPLES {
            self.buf.pop_front();
        }
    }

    /// Replace the newest sample (the present instant's values were set again); pushes when empty.
    pub fn set_newest(&mut self, s: S) {
        match self.buf.back_mut() {
            Some(b) => *b = s,
            None => self.buf.push_back(s),
        }
    }

    /// Drop samples no lookup at angle ≥ `theta_min` needs.
    pub fn prune(&mut self, theta_min: f64) {
        while self.buf.len() > 2 && self.buf[1].theta() <= theta_min {
            self.buf.pop_front();
        }
    }

    /// Are the samples usable by lookups: finite, at most [`MAX_SAMPLES`], times and
    /// angles non-decreasing? (A restored FMU state is checked with this.)
    pub fn validate(&self) -> Result<(), String> {
        if self.buf.len() > MAX_SAMPLES {
            return Err(format!("history holds {} samples, more than {MAX_SAMPLES}", self.buf.len()));
        }
        for (i, s) in self.buf.iter().enumerate() {
            if !s.is_finite() {
                return Err(format!("history sample {i} is not finite"));
            }
            if i > 0 && !(s.t() >= self.buf[i - 1].t() && s.theta() >= self.buf[i - 1].theta()) {
                return Err(format!("history sample {i} is out of order"));
            }
        }
        Ok(())
    }

    /// Number of stored samples.
    pub fn len(&self) -> usize {
        self.buf.len()
    }

    /// The newest sample.
    pub fn newest(&self) -> Option<&S> {
        self.buf.back()
    }

    /// Is the history empty?
    pub fn is_empty(&self) -> bool {
        self.buf.is_empty()
    }

    /// `(t*, x(t*))` where `θ(t*) = theta`; `None` if `theta` precedes the history (fresh surface).
    /// An angle past the newest sample returns the newest sample.
    pub fn at_angle(&self, theta: f64) -> Option<(f64, S::Value)> {
        let first = self.buf.front()?;
        if theta < first.theta() {
            return None;
        }
        // The plant and the process look up θ − 2π/Z right after pruning to it, so the bracket
        // is one of the first samples: scan those (O(1)), bisect only otherwise. Both find the
        // first sample past `theta`, so the result is the same.
        const SCAN: usize = 8;
        let i = match self.buf.iter().take(SCAN).position(|s| s.theta() > theta) {
            Some(i) => i,
            None => self.buf.partition_point(|s| s.theta() <= theta),
        };
        if i >= self.buf.len() {
            let last = self.buf.back()?;
            return Some((last.t(), last.value()));
        }
        let (a, b) = (&self.buf[i - 1], &self.buf[i]);
        let s = (theta - a.theta()) / (b.theta() - a.theta());
        let dt = b.t() - a.t();
        Some((a.t() + s * dt, S::interpolate(a, b, s, dt)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_interpolation_is_exact_for_cubics_and_angles_map_to_times() {
        let f = |t: f64| 1.0 + t - 2.0 * t * t + 0.5 * t * t * t;
        let df = |t: f64| 1.0 - 4.0 * t + 1.5 * t * t;
        let mut h = History::<Sample>::default();
        let omega = 10.0;
        for k in 0..20 {
            let t = 0.1 * k as f64;
            h.push(Sample { t, theta: omega * t, x: f(t), v: df(t) });
        }
        let (t, x) = h.at_angle(omega * 0.537).unwrap();
        assert!((t - 0.537).abs() < 1e-12);
        assert!((x - f(0.537)).abs() < 1e-12);
        assert!(h.at_angle(-0.1).is_none());
        h.prune(omega * 1.0);
        assert!(h.len() < 20 && h.at_angle(omega * 1.0).is_some());
        assert!(h.validate().is_ok());
    }

    #[test]
    fn samples_at_one_angle_do_not_accumulate_and_lookups_do_not_change() {
        // a run at speed, then a long stop (0 rpm: the angle stays), as the plant pushes it
        let mut all = History::<Sample>::default();
        let mut coalesced = History::<Sample>::default();
        let mut push = |s: Sample| {
            coalesced.push(s);
            all.buf.push_back(s);
        };
        for k in 0..100 {
            let t = 1e-3 * k as f64;
            push(Sample { t, theta: 10.0 * t.min(0.05), x: t.sin(), v: t.cos() });
        }
        assert!(coalesced.len() < 60, "{} samples", coalesced.len());
        for q in [0.0, 0.1, 0.25, 0.4999, 0.5, 0.7] {
            assert_eq!(format!("{:?}", all.at_angle(q)), format!("{:?}", coalesced.at_angle(q)), "angle {q}");
        }
        for k in 0..(2 * MAX_SAMPLES) {
            coalesced.push(Sample { t: 1.0 + k as f64, theta: 0.5, x: 0.0, v: 0.0 });
        }
        assert!(coalesced.len() < 60);
        assert!(coalesced.validate().is_ok());
    }

    #[test]
    fn the_history_never_exceeds_its_bound_and_bad_samples_are_found() {
        let mut h = History::<Sample>::default();
        for k in 0..(MAX_SAMPLES + 10) {
            h.push(Sample { t: k as f64, theta: k as f64, x: 0.0, v: 0.0 });
        }
        assert_eq!(h.len(), MAX_SAMPLES);
        h.buf[3].t = -1.0;
        assert!(h.validate().unwrap_err().contains("order"));
        h.buf[3].t = f64::NAN;
        assert!(h.validate().unwrap_err().contains("finite"));
    }

    #[test]
    fn two_axis_samples_interpolate_linearly_in_angle() {
        let mut h = History::<XySample>::default();
        h.push(XySample { t: 0.0, theta: 0.0, r: [0.0, 1.0] });
        h.push(XySample { t: 1.0, theta: 2.0, r: [2.0, -1.0] });
        let (t, r) = h.at_angle(0.5).unwrap();
        assert!((t - 0.25).abs() < 1e-15 && (r[0] - 0.5).abs() < 1e-15 && (r[1] - 0.5).abs() < 1e-15);
        assert_eq!(h.at_angle(3.0).unwrap().1.map(f64::to_bits), [2.0f64.to_bits(), (-1.0f64).to_bits()]);
        h.push(XySample { t: 2.0, theta: 2.5, r: [f64::NAN, 0.0] });
        assert!(h.validate().unwrap_err().contains("finite"));
    }
}
