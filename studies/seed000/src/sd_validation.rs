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

use crate::closed_loop::{RELEASE, quiet_release};
use crate::scenario::{Roles, roles};
use chatter_control::Structure;
use fmi_master::{Override, Progress, RunConfig, SimError, Simulation, SystemFile};
use milling_plant::{CuttingModel, PlantInputs, PlantParams};
use milling_process::ProcessParams;
use model_description::Value;
use study_kit::StudyError;
use study_kit::fmu_params::overrides_of;
use study_kit::growth::Regen;

/// The plant FMU of a system (or the process + structure FMUs of the decomposed system), set up
/// for the time-domain check of one machine.
pub struct SdFmuCheck<'a> {
    sys: &'a SystemFile,
    target: Target,
    /// Feed per tooth \[m\].
    pub feed: f64,
    /// Communication (and recording) step \[s\].
    pub step: f64,
}

/// Which FMUs carry the machine.
enum Target {
    /// `MillingPlant.fmu` with the parameters `plant` (all set as typed overrides).
    Plant { roles: Roles, plant: PlantParams },
    /// `DecomposedPlant.ssp`: `process` (MillingProcess, these parameters), `structure`
    /// (ModalStructure with its shipped modes, disturbances off), `controller` off.
    Decomposed { process: ProcessParams },
}

impl<'a> SdFmuCheck<'a> {
    /// The check for machine `plant` in system `sys`, feed 0.1 mm, step 10 µs.
    pub fn new(sys: &'a SystemFile, plant: &PlantParams) -> Result<Self, StudyError> {
        let target = Target::Plant { roles: roles(sys)?, plant: plant.clone() };
        Ok(SdFmuCheck { sys, target, feed: 0.1e-3, step: 1e-5 })
    }

    /// The same check on the decomposed system `sys` (`DecomposedPlant.ssp`: components
    /// `process`, `structure`, `actuator`, `controller`), the process with the parameters
    /// `process` (its axial depth is set per run), feed 0.1 mm, step 10 µs. The structure's
    /// noise, sinusoid and drift are switched off; it starts at rest, so the perturbation is the
    /// start-up transient of the static cutting force (the plant check releases from 1 µm).
    pub fn decomposed(sys: &'a SystemFile, process: &ProcessParams) -> Result<Self, StudyError> {
        let names: Vec<&str> = sys.desc.components.iter().map(|c| c.name.as_str()).collect();
        for c in ["process", "structure", "controller"] {
            if !names.contains(&c) {
                return Err(StudyError::Invalid(format!("the decomposed system has no component {c:?} ({names:?})")));
            }
        }
        Ok(SdFmuCheck { sys, target: Target::Decomposed { process: process.clone() }, feed: 0.1e-3, step: 1e-5 })
    }

    /// The typed overrides of one run: the machine (quiet, time-domain cutting at `depth`), its
    /// inputs (no command, `rpm`, the feed) and the controller off.
    pub fn overrides(&self, rpm: f64, depth: f64) -> Vec<Override> {
        let (roles, plant) = match &self.target {
            Target::Plant { roles, plant } => (roles, plant),
            Target::Decomposed { process } => {
                let mut p = process.clone();
                p.axial_depth = depth;
                let mut o = overrides_of("process", fmu_milling_process::parameter_assignments(&p));
                o.push(Override::typed("process.spindle_speed", Value::Real(rpm)));
                o.push(Override::typed("process.feed_per_tooth", Value::Real(self.feed)));
                for flag in ["structure.disturbance.noise", "structure.disturbance.drift"] {
                    o.push(Override::typed(flag, Value::Boolean(false)));
                }
                o.push(Override::typed("structure.disturbance.sine_amplitude", Value::Real(0.0)));
                o.push(Override::typed(
                    "controller.structure",
                    Value::Integer(model_kit::Choice::index(Structure::Off)),
                ));
                return o;
            }
        };
        let mut p = quiet_release(plant);
        p.cutting.enabled = true;
        p.cutting.model = CuttingModel::TimeDomain;
        p.cutting.axial_depth = depth;
        let inputs = PlantInputs { u: 0.0, spindle_speed_rpm: rpm, feed_per_tooth: self.feed };
        let mut o = overrides_of(&roles.plant, fmu_plant::parameter_assignments(&p));
        o.extend(overrides_of(&roles.plant, fmu_plant::TABLE.input_assignments(&inputs)));
        o.push(Override::typed(
            format!("{}.structure", roles.controller),
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
            record: Some(vec![self.measured()]),
            ..RunConfig::default()
        };
        let mut sim = Simulation::new(self.sys, &cfg)?;
        let n = usize::try_from(sim.n_steps() + 1).unwrap_or(usize::MAX);
        let teeth = match &self.target {
            Target::Plant { plant, .. } => plant.cutting.teeth,
            Target::Decomposed { process } => process.teeth,
        };
        let tau = 60.0 / (f64::from(teeth) * rpm);
        let mut obs = Regen::<1>::new(n, tau / self.step);
        match sim.run(&mut obs, Progress::Off) {
            // the plant stops with an error when |x| passes its limit: grown far beyond the release
            Err(SimError::Fmu(_)) if obs.windows.max > 100.0 * RELEASE => Ok(f64::INFINITY),
            Err(e) => Err(e.into()),
            Ok(_) => Ok(obs.windows.ratio()),
        }
    }

    /// The recorded displacement: the plant's `x`, or the structure's `tool_x` (the decomposed
    /// system's structure is the workpiece: its "tool point" is the cutting point).
    fn measured(&self) -> String {
        match &self.target {
            Target::Plant { roles, .. } => roles.measured(),
            Target::Decomposed { .. } => "structure.tool_x".into(),
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
