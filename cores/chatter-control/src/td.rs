//! Han's tracking differentiator (TD).
//!
//! The TD turns the reference `v` into a smooth trajectory `v1` and its derivative `v2`
//! (seed 000, Section 4.1; Han 2009, "From PID to active disturbance rejection control"):
//!
//! ```text
//! v1_{k+1} = v1_k + T·v2_k
//! v2_{k+1} = v2_k + T·fhan(v1_k − v_k, v2_k, r0, h0)
//!
//! fhan(x1, x2, r, h):  d = r h,  d0 = h d,  y = x1 + h x2,  a0 = √(d² + 8 r |y|)
//!                      a = x2 + (a0 − d)/2 · sign(y)   if |y| > d0,   else x2 + y/h
//!                      fhan = −r·sign(a)               if |a| > d,    else −r·a/d
//! ```
//!
//! `fhan` is the discrete time-optimal (bang-bang with acceleration bound `r0`) control that
//! brings `v1` to `v` without overshoot. Parameters: `r0` \[m/s²\] speed factor (the largest
//! acceleration of the trajectory), `h0` \[s\] filter factor (`h0 ≥ T`; larger smooths more).
//! The TD is nonlinear and acts on the reference only: with `r = 0` (the milling case) its
//! outputs stay zero and it drops out of the linear analysis. It starts at the first reference
//! value (`v1 = r`, `v2 = 0`) so that a constant reference causes no transient.

use serde::{Deserialize, Serialize};

/// Han's `fhan` (see the module documentation).
pub fn fhan(x1: f64, x2: f64, r: f64, h: f64) -> f64 {
    let d = r * h;
    let d0 = h * d;
    let y = x1 + h * x2;
    let a0 = (d * d + 8.0 * r * y.abs()).sqrt();
    let a = if y.abs() > d0 { x2 + (a0 - d) / 2.0 * y.signum() } else { x2 + y / h };
    if a.abs() > d { -r * a.signum() } else { -r * a / d }
}

/// Tracking differentiator state.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TrackingDifferentiator {
    r0: f64,
    h0: f64,
    ts: f64,
    v1: f64,
    v2: f64,
    started: bool,
}

impl TrackingDifferentiator {
    /// A restored TD: the factors `fresh` has, a finite state.
    pub(crate) fn check(&self, fresh: &Self) -> Result<(), String> {
        crate::restored::same(
            "tracking differentiator",
            &[self.r0, self.h0, self.ts],
            &[fresh.r0, fresh.h0, fresh.ts],
        )?;
        crate::restored::finite("tracking differentiator state", &[self.v1, self.v2])
    }

    /// TD with speed factor `r0` \[m/s²\] and filter factor `h0` \[s\] at sample period `ts`.
    pub fn new(r0: f64, h0: f64, ts: f64) -> Self {
        TrackingDifferentiator { r0, h0, ts, v1: 0.0, v2: 0.0, started: false }
    }

    /// One sample: returns `(v1_k, v2_k)` and advances the state.
    #[inline]
    pub fn step(&mut self, v: f64) -> (f64, f64) {
        if !self.started {
            self.v1 = v;
            self.v2 = 0.0;
            self.started = true;
        }
        let out = (self.v1, self.v2);
        let f = fhan(self.v1 - v, self.v2, self.r0, self.h0);
        self.v1 += self.ts * self.v2;
        self.v2 += self.ts * f;
        out
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    #[test]
    fn step_is_tracked_without_overshoot_and_ramp_slope_is_recovered() {
        let ts = 1e-5;
        let mut td = TrackingDifferentiator::new(100.0, 1e-4, ts);
        td.step(0.0);
        let target = 1e-6;
        let mut max = 0.0f64;
        let mut last = (0.0, 0.0);
        for _ in 0..2000 {
            last = td.step(target);
            max = max.max(last.0);
        }
        // time-optimal: 2√(d/r0) = 2e-4 s; after 20 ms settled, overshoot below 1 %
        assert!((last.0 - target).abs() < 1e-3 * target, "v1 = {}", last.0);
        assert!(max < 1.01 * target, "overshoot {max}");
        // ramp of slope 1e-3 m/s: v2 converges to the slope
        let mut td = TrackingDifferentiator::new(100.0, 1e-4, ts);
        for k in 0..5000 {
            last = td.step(1e-3 * ts * k as f64);
        }
        assert!((last.1 - 1e-3).abs() < 1e-5, "v2 = {}", last.1);
    }

    #[test]
    fn zero_reference_stays_zero() {
        let mut td = TrackingDifferentiator::new(100.0, 1e-4, 1e-5);
        for _ in 0..100 {
            let (a, b) = td.step(0.0);
            assert!(a.abs() < f64::MIN_POSITIVE && b.abs() < f64::MIN_POSITIVE);
        }
    }
}
