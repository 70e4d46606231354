//! The order β(t) of the integrators: fixed, or the stepwise schedule of Eq. 30.
//!
//! Stepwise (Eq. 30, Tables 4–5): `β = β₀` before `t₁`, `β_i` on `[t_i, t_{i+1})`, and `β = 1`
//! from `t_end`; the paper's orders are `β₀ = 1.9`, `(β₁…β₄) = (1.75, 1.5, 1.25, 1.15)`, the
//! Table 5 times `(0.6935, 0.7677, 1.26871, 1.6874)` s and `t_end = 2.4` s. Figure 6's selector
//! reads as one integrator per order, all fed with the same law and running in parallel, the
//! output switched to the current order. The switch is a jump of the output unless the
//! bumpless option is set: then at each switch the difference (old − new output) is added to an
//! offset, so the commanded speed and feed are continuous. Times need not be ordered (the GA
//! does not constrain them); the order at `t` is that of the latest time `≤ t`.

use serde::{Deserialize, Serialize};

model_kit::choice! {
    /// How β(t) is chosen.
    #[derive(Serialize, Deserialize)]
    pub enum BetaMode ("BetaMode", "how the order of the integrators is chosen") {
        /// One order for all time.
        Fixed = "fixed", "one order β for all time";
        /// Eq. 30: stepwise down from β₀ to 1.
        Stepwise = "stepwise", "stepwise schedule β0 → β1…β4 at t1…t4 → 1 at t_end";
    }
}

/// A β schedule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Schedule {
    /// Mode.
    pub mode: BetaMode,
    /// Fixed order (mode fixed).
    pub beta: f64,
    /// Initial order β₀ (stepwise).
    pub beta0: f64,
    /// Orders β₁…β₄ (stepwise).
    pub betas: [f64; 4],
    /// Switch times t₁…t₄ [s] (stepwise).
    pub times: [f64; 4],
    /// From this time β = 1 [s] (stepwise).
    pub end: f64,
}

impl Default for Schedule {
    /// The paper's AFrAC (Table 5).
    fn default() -> Self {
        Schedule {
            mode: BetaMode::Stepwise,
            beta: 1.0,
            beta0: 1.9,
            betas: [1.75, 1.5, 1.25, 1.15],
            times: [0.6935, 0.7677, 1.26871, 1.6874],
            end: 2.4,
        }
    }
}

impl Schedule {
    /// A fixed order.
    pub fn fixed(beta: f64) -> Self {
        Schedule { mode: BetaMode::Fixed, beta, ..Default::default() }
    }

    /// Every order the schedule can select, in selection order (distinct values).
    pub fn orders(&self) -> Vec<f64> {
        let all: Vec<f64> = match self.mode {
            BetaMode::Fixed => vec![self.beta],
            BetaMode::Stepwise => [self.beta0].into_iter().chain(self.betas).chain([1.0]).collect(),
        };
        let mut out: Vec<f64> = Vec::new();
        for b in all {
            if !out.iter().any(|o| o.to_bits() == b.to_bits()) {
                out.push(b);
            }
        }
        out
    }

    /// β(t).
    pub fn beta_at(&self, t: f64) -> f64 {
        match self.mode {
            BetaMode::Fixed => self.beta,
            BetaMode::Stepwise => {
                if t >= self.end {
                    return 1.0;
                }
                let mut latest: Option<(f64, f64)> = None;
                for (ti, bi) in self.times.iter().zip(self.betas) {
                    if *ti <= t && latest.is_none_or(|(tl, _)| *ti >= tl) {
                        latest = Some((*ti, bi));
                    }
                }
                latest.map_or(self.beta0, |(_, b)| b)
            }
        }
    }

    /// Check ranges (orders in [1, 2], times finite).
    pub fn validate(&self) -> Result<(), String> {
        for b in self.orders() {
            if !(b.is_finite() && (1.0..=2.0).contains(&b)) {
                return Err(format!("order β = {b} is outside [1, 2]"));
            }
        }
        if !self.times.iter().chain([&self.end]).all(|t| t.is_finite() && t.abs() <= 1e9) {
            return Err("schedule times must be finite".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::float_cmp)] // the schedule returns the table's values exactly
    fn the_paper_schedule_steps_down_and_ends_at_one() {
        let s = Schedule::default();
        let at: Vec<f64> = [0.0, 0.7, 0.8, 1.3, 1.7, 2.39, 2.4, 5.0].iter().map(|t| s.beta_at(*t)).collect();
        assert_eq!(at, vec![1.9, 1.75, 1.5, 1.25, 1.15, 1.15, 1.0, 1.0]);
        assert_eq!(s.orders(), vec![1.9, 1.75, 1.5, 1.25, 1.15, 1.0]);
        // unordered times: the latest switch wins
        let u = Schedule { times: [1.0, 0.5, 2.0, 2.0], ..Default::default() };
        assert_eq!(u.beta_at(0.7), 1.5);
        assert_eq!(u.beta_at(1.2), 1.75);
        assert!(Schedule::fixed(2.5).validate().is_err());
    }
}
