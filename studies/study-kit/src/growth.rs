//! Growth or decay of a recorded response: the time-domain side of every stability check.
//!
//! [`GrowthWindows`] compares the peak |x| over the last fifth of a run with the peak over the
//! second fifth (the first fifth is left to the start-up transient): above 1 the response grows
//! (the cut chatters), below 1 it decays. [`Regen`] feeds it the regenerative difference
//! `|x(t) − x(t − τ)|` of recorded FMU outputs, which removes a forced τ-periodic motion exactly.

use fmi_master::{Observer, SimError};
use std::collections::VecDeque;

/// The growth ratio of `n` samples of |x|: peak over the last fifth divided by the peak over the
/// second fifth (the first fifth is left to the start-up transient). Also keeps the overall peak.
#[derive(Clone, Copy, Debug)]
pub struct GrowthWindows {
    n: usize,
    k: usize,
    mid: f64,
    late: f64,
    /// Largest |x| seen so far.
    pub max: f64,
}

impl GrowthWindows {
    /// Windows for a run of `n` samples.
    pub fn new(n: usize) -> Self {
        GrowthWindows { n, k: 0, mid: 0.0, late: 0.0, max: 0.0 }
    }

    /// The next sample.
    pub fn push(&mut self, x: f64) {
        let (x, fifth) = (x.abs(), self.n / 5);
        self.max = self.max.max(x);
        if (fifth..2 * fifth).contains(&self.k) {
            self.mid = self.mid.max(x);
        }
        if self.k + fifth >= self.n {
            self.late = self.late.max(x);
        }
        self.k += 1;
    }

    /// The largest value after the first fifth (the start-up transient left out).
    pub fn after_startup(&self) -> f64 {
        self.mid.max(self.late)
    }

    /// Late peak / mid peak (infinite if the late peak is not finite).
    pub fn ratio(&self) -> f64 {
        if self.late.is_finite() { self.late / self.mid } else { f64::INFINITY }
    }
}

/// `|x(t) − x(t − τ)|` of the recorded samples into [`GrowthWindows`]: the Euclidean norm over
/// the `N` recorded channels of each channel's difference (`N = 1`: the absolute difference),
/// `x(t − τ)` interpolated linearly between the samples `lag` steps back (before the start: 0).
pub struct Regen<const N: usize> {
    /// The growth windows the differences go to.
    pub windows: GrowthWindows,
    lag: f64,
    past: VecDeque<[f64; N]>,
}

impl<const N: usize> Regen<N> {
    /// Over `n` samples, with the delay `lag` in samples.
    pub fn new(n: usize, lag: f64) -> Self {
        Regen { windows: GrowthWindows::new(n), lag, past: VecDeque::new() }
    }
}

impl<const N: usize> Observer for Regen<N> {
    fn start(&mut self, _names: &[String]) -> Result<(), SimError> {
        Ok(())
    }
    fn sample(&mut self, _t: f64, values: &[f64]) -> Result<(), SimError> {
        let mut x = [0.0; N];
        x.copy_from_slice(&values[..N]);
        let q = self.lag.floor() as usize;
        let frac = self.lag - q as f64;
        self.past.push_front(x);
        self.past.truncate(q + 2);
        let at = |k: usize, i: usize| self.past.get(k).map_or(0.0, |v| v[i]);
        let norm = (0..N).fold(0.0_f64, |acc, i| acc.hypot(x[i] - ((1.0 - frac) * at(q, i) + frac * at(q + 1, i))));
        self.windows.push(norm);
        Ok(())
    }
    fn finish(&mut self) -> Result<(), SimError> {
        Ok(())
    }
}
