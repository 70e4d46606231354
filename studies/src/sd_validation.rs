//! The semi-discretisation lobes checked in the time domain **through `MillingPlant.fmu`**: the
//! plant FMU with its mechanistic time-domain cutting force (teeth, engagement window, loss of
//! contact, angle-indexed regeneration) in the Rust master, controller off, at a depth 3 % below
//! and above the SD boundary.
//!
//! **What is measured.** With feed the plant has a forced τ-periodic motion `x*(t)` (the static
//! chip force); the stability of the cut is that of the perturbation `x − x*`. Since `x*` is
//! τ-periodic, `d(t) = x(t) − x(t − τ)` removes it exactly and behaves like the perturbation
//! (a flip multiplier −1 doubles it, a Hopf pair keeps its rate). [`SdFmuCheck::growth_ratio`]
//! feeds `|d|` (the recorded `x` at the communication points, `x(t − τ)` interpolated linearly
//! between them) to [`GrowthWindows`]: peak over the last fifth / peak over the second fifth;
//! below 1 the cut is stable, above 1 it chatters.
//!
//! **Linearity.** The SD linearises about `x*`; the time-domain model is exactly linear while
//! every engaged tooth has a positive chip. The release (1 µm) and the start-up transient scale
//! with the feed and stay about 1–2 % of the static chip `f_z sin φ`, so loss of contact is
//! confined to a sliver before `sin φ = 0`. The controller is off, so the master's one-step
//! coupling delay plays no part; the communication step (default 10 µs) is the recording grid.

use crate::StudyError;
use crate::closed_loop::{RELEASE, quiet_release};
use crate::fmu_params::overrides_of;
use crate::scenario::{Roles, roles};
use crate::validation::GrowthWindows;
use chatter_control::Structure;
use fmi_master::{Observer, Override, Progress, RunConfig, SimError, Simulation, SystemFile};
use milling_plant::{CuttingModel, PlantInputs, PlantParams};
use model_description::Value;
use std::collections::VecDeque;

/// The plant FMU of a system, set up for the time-domain check of one machine.
pub struct SdFmuCheck<'a> {
    sys: &'a SystemFile,
    roles: Roles,
    plant: PlantParams,
    /// Feed per tooth \[m\].
    pub feed: f64,
    /// Communication (and recording) step \[s\].
    pub step: f64,
}

/// `|x(t) − x(t − τ)|` of the recorded samples into [`GrowthWindows`].
struct Regen {
    windows: GrowthWindows,
    lag: f64,
    past: VecDeque<f64>,
}

impl Observer for Regen {
    fn start(&mut self, _names: &[String]) -> Result<(), SimError> {
        Ok(())
    }
    fn sample(&mut self, _t: f64, values: &[f64]) -> Result<(), SimError> {
        let x = values[0];
        let q = self.lag.floor() as usize;
        let frac = self.lag - q as f64;
        self.past.push_front(x);
        self.past.truncate(q + 2);
        // x(t − τ) from the samples q and q + 1 steps back (before the start: the history is 0)
        let at = |k: usize| self.past.get(k).copied().unwrap_or(0.0);
        let delayed = (1.0 - frac) * at(q) + frac * at(q + 1);
        self.windows.push(x - delayed);
        Ok(())
    }
    fn finish(&mut self) -> Result<(), SimError> {
        Ok(())
    }
}

impl<'a> SdFmuCheck<'a> {
    /// The check for machine `plant` in system `sys`, feed 0.1 mm, step 10 µs.
    pub fn new(sys: &'a SystemFile, plant: &PlantParams) -> Result<Self, StudyError> {
        Ok(SdFmuCheck { sys, roles: roles(sys)?, plant: plant.clone(), feed: 0.1e-3, step: 1e-5 })
    }

    /// The typed overrides of one run: the plant (quiet release, time-domain cutting at `depth`),
    /// its inputs (no command, `rpm`, the feed) and the controller off.
    pub fn overrides(&self, rpm: f64, depth: f64) -> Vec<Override> {
        let mut p = quiet_release(&self.plant);
        p.cutting.enabled = true;
        p.cutting.model = CuttingModel::TimeDomain;
        p.cutting.axial_depth = depth;
        let inputs = PlantInputs { u: 0.0, spindle_speed_rpm: rpm, feed_per_tooth: self.feed };
        let mut o = overrides_of(&self.roles.plant, fmu_plant::parameter_assignments(&p));
        o.extend(overrides_of(&self.roles.plant, fmu_plant::TABLE.input_assignments(&inputs)));
        o.push(Override::typed(
            format!("{}.structure", self.roles.controller),
            Value::Integer(model_kit::Choice::index(Structure::Off)),
        ));
        o
    }

    /// Late / mid peak of `|x(t) − x(t − τ)|` over `duration` seconds (module docs).
    pub fn growth_ratio(&self, rpm: f64, depth: f64, duration: f64) -> Result<f64, StudyError> {
        if !(rpm > 0.0 && depth >= 0.0 && duration > 0.0 && self.step > 0.0) {
            return Err(StudyError::Invalid(format!(
                "need rpm > 0, depth >= 0, duration > 0 (got {rpm}, {depth}, {duration})"
            )));
        }
        let cfg = RunConfig {
            start: Some(0.0),
            stop: Some(duration),
            step: Some(self.step),
            overrides: self.overrides(rpm, depth),
            record: Some(vec![format!("{}.x", self.roles.plant)]),
            ..RunConfig::default()
        };
        let mut sim = Simulation::new(self.sys, &cfg)?;
        let n = usize::try_from(sim.n_steps() + 1).unwrap_or(usize::MAX);
        let tau = 60.0 / (self.plant.cutting.teeth as f64 * rpm);
        let mut obs = Regen { windows: GrowthWindows::new(n), lag: tau / self.step, past: VecDeque::new() };
        match sim.run(&mut obs, Progress::Off) {
            // the plant stops with an error when |x| passes its limit: grown far beyond the release
            Err(SimError::Fmu(_)) if obs.windows.max > 100.0 * RELEASE => Ok(f64::INFINITY),
            Err(e) => Err(e.into()),
            Ok(_) => Ok(obs.windows.ratio()),
        }
    }

    /// The time-domain boundary: bisection in depth on `[lo, hi]` (ratio < 1 at `lo`, > 1 at
    /// `hi`, checked) to a relative bracket `rel_tol`.
    pub fn boundary(
        &self,
        rpm: f64,
        (mut lo, mut hi): (f64, f64),
        duration: f64,
        rel_tol: f64,
    ) -> Result<f64, StudyError> {
        for (d, grow) in [(lo, false), (hi, true)] {
            let r = self.growth_ratio(rpm, d, duration)?;
            if (r > 1.0) != grow {
                return Err(StudyError::Invalid(format!(
                    "bracket: depth {d:e} m at {rpm} rpm has growth ratio {r:.4}, expected {} 1",
                    if grow { "above" } else { "below" }
                )));
            }
        }
        while hi / lo - 1.0 > rel_tol {
            let mid = 0.5 * (lo + hi);
            if self.growth_ratio(rpm, mid, duration)? > 1.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Ok(0.5 * (lo + hi))
    }
}
