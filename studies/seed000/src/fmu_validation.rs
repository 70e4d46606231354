//! The lobes checked through the FMUs: the plant FMU (the machine of the lobes, as
//! [`quiet_release`] with the averaged cutting model and no feed) and the controller FMU, both
//! given their complete parameter sets as typed values through the adapters' tables, coupled by
//! the Rust FMI master exactly as in the shipped closed-loop system (Gauss–Seidel, controller first,
//! communication step = the controller's period `T`), released from a 1 µm tip displacement.
//! Saturation is lifted on both sides (`actuator.f_max`, `u_max` = 1e9 N) because the lobes are
//! those of the linear loop. [`FmuLoop::growth_ratio`] compares the peak |x| over the last fifth of
//! the run with the peak over the second fifth ([`GrowthWindows`], as
//! [`crate::validation::growth_ratio`] does on the cores): below 1 the cut is stable, above 1 it
//! chatters. [`FmuLoop::boundary`] bisects the depth at which the ratio crosses 1. The plant
//! parameters are those the lobe computation used, so the two always describe one machine.
//!
//! Timing: with the controller stepped first, the plant integrates `[t_k, t_k+1]` with the
//! command computed from `y(t_k)`, one sample earlier than the `e^{−iωT}` communication delay
//! that [`chatter_control::Controller::frequency_response`] (and so the lobes) assumes. At the
//! chatter frequencies (≈ 140 Hz, `ωT` ≈ 0.5°) this moves the boundary by far less than the
//! 3 % the check allows; the measured difference is what [`FmuLoop::boundary`] reports.

use crate::closed_loop::{AnyController, DEFAULT_STEP, RELEASE, quiet_release};
use crate::scenario::{Roles, roles, roles_with};
use chatter_control::{ControllerParams, Structure};
use fmi_master::{Observer, Override, Progress, RunConfig, SimError, Simulation, SystemFile};
use milling_plant::{CuttingModel, PlantInputs, PlantParams};
use model_description::Value;
use study_kit::StudyError;
use study_kit::fmu_params::overrides_of;
use study_kit::growth::GrowthWindows;

/// The closed loop of a system (plant and controller FMUs) set up for lobe validation of one
/// machine.
pub struct FmuLoop<'a> {
    sys: &'a SystemFile,
    roles: Roles,
    plant: PlantParams,
}

/// Feeds the plant's `x` of every recorded sample to [`GrowthWindows`].
struct Peaks {
    windows: GrowthWindows,
}

impl Observer for Peaks {
    fn start(&mut self, _names: &[String]) -> Result<(), SimError> {
        Ok(())
    }
    fn sample(&mut self, _t: f64, values: &[f64]) -> Result<(), SimError> {
        self.windows.push(values[0]);
        Ok(())
    }
    fn finish(&mut self) -> Result<(), SimError> {
        Ok(())
    }
}

impl<'a> FmuLoop<'a> {
    /// The loop of `sys` (its plant and controller components found by their FMUs) for the
    /// machine `plant`.
    pub fn new(sys: &'a SystemFile, plant: &PlantParams) -> Result<Self, StudyError> {
        Ok(FmuLoop { sys, roles: roles(sys)?, plant: plant.clone() })
    }

    /// The loop of a system whose controller is a `LinearController` (`Benchmark.ssp`).
    pub fn linear(sys: &'a SystemFile, plant: &PlantParams) -> Result<Self, StudyError> {
        use fmi2_export::Fmi2Model;
        let id = fmu_linear_controller::LinearController::description().model_identifier().unwrap_or_default();
        Ok(FmuLoop { sys, roles: roles_with(sys, id)?, plant: plant.clone() })
    }

    /// The typed overrides of one run: the whole plant parameter set (the machine, released
    /// quietly, averaged cutting at `depth`), its inputs at `rpm` without feed, and the whole
    /// controller parameter set with saturation lifted (`off` for the open loop).
    pub fn overrides(&self, ctrl: Option<&ControllerParams>, rpm: f64, depth: f64) -> Vec<Override> {
        self.overrides_with(ctrl.map(|c| AnyController::Chatter(*c)).as_ref(), rpm, depth)
    }

    /// [`FmuLoop::overrides`] for either controller FMU (a `LinearController` set gets its
    /// saturation lifted).
    pub fn overrides_with(&self, ctrl: Option<&AnyController>, rpm: f64, depth: f64) -> Vec<Override> {
        let mut p = quiet_release(&self.plant);
        p.cutting.enabled = true;
        p.cutting.model = CuttingModel::Averaged;
        p.cutting.axial_depth = depth;
        let inputs = PlantInputs { u: 0.0, spindle_speed_rpm: rpm, feed_per_tooth: 0.0 };
        let mut o = overrides_of(&self.roles.plant, fmu_plant::parameter_assignments(&p));
        o.extend(overrides_of(&self.roles.plant, fmu_plant::TABLE.input_assignments(&inputs)));
        match ctrl {
            Some(AnyController::Linear(p)) => {
                let mut p = (**p).clone();
                p.saturation = [1e9; 2];
                o.extend(overrides_of(&self.roles.controller, fmu_linear_controller::parameter_assignments(&p)));
            }
            Some(AnyController::Chatter(c)) if c.structure != Structure::Off => {
                let c = ControllerParams { u_max: 1e9, ..*c };
                o.extend(overrides_of(&self.roles.controller, fmu_controller::parameter_assignments(&c)));
            }
            _ => o.push(Override::typed(
                format!("{}.structure", self.roles.controller),
                Value::Integer(model_kit::Choice::index(Structure::Off)),
            )),
        }
        o
    }

    /// Growth ratio (late peak / early peak of |x|) at `rpm` and axial depth `depth` \[m\] over
    /// `duration` seconds; `ctrl = None` (or structure `off`) is the open loop. The communication
    /// step is the controller's period (10 µs for the open loop).
    pub fn growth_ratio(
        &self,
        ctrl: Option<&ControllerParams>,
        rpm: f64,
        depth: f64,
        duration: f64,
    ) -> Result<f64, StudyError> {
        self.growth_ratio_with(ctrl.map(|c| AnyController::Chatter(*c)).as_ref(), rpm, depth, duration)
    }

    /// [`FmuLoop::growth_ratio`] for either controller FMU (a `LinearController` is stepped every
    /// 10 µs).
    pub fn growth_ratio_with(
        &self,
        ctrl: Option<&AnyController>,
        rpm: f64,
        depth: f64,
        duration: f64,
    ) -> Result<f64, StudyError> {
        let step = match ctrl {
            Some(AnyController::Chatter(c)) => c.ts,
            _ => DEFAULT_STEP,
        };
        let cfg = RunConfig {
            start: Some(0.0),
            stop: Some(duration),
            step: Some(step),
            overrides: self.overrides_with(ctrl, rpm, depth),
            record: Some(vec![format!("{}.x", self.roles.plant)]),
            ..RunConfig::default()
        };
        let mut sim = Simulation::new(self.sys, &cfg)?;
        let n = usize::try_from(sim.n_steps() + 1).unwrap_or(usize::MAX);
        let mut peaks = Peaks { windows: GrowthWindows::new(n) };
        match sim.run(&mut peaks, Progress::Off) {
            // The plant FMU stops with an error when |x| passes 1 m; a run that has grown a
            // hundredfold from the 1 µm release before failing is unstable, anything else is a
            // real failure.
            Err(SimError::Fmu(_)) if peaks.windows.max > 100.0 * RELEASE => Ok(f64::INFINITY),
            Err(e) => Err(e.into()),
            Ok(_) => Ok(peaks.windows.ratio()),
        }
    }

    /// The depth \[m\] where the loop turns from decaying to growing, by bisection on
    /// `[lo, hi]` (growth ratio < 1 at `lo`, > 1 at `hi`) to a relative width `rel_tol`.
    pub fn boundary(
        &self,
        ctrl: Option<&ControllerParams>,
        rpm: f64,
        (mut lo, mut hi): (f64, f64),
        duration: f64,
        rel_tol: f64,
    ) -> Result<f64, StudyError> {
        let check = |d: f64, want_growth: bool| -> Result<(), StudyError> {
            let r = self.growth_ratio(ctrl, rpm, d, duration)?;
            if (r > 1.0) != want_growth {
                return Err(StudyError::Invalid(format!(
                    "bisection bracket: depth {d:e} m at {rpm} rpm has growth ratio {r:.4}, expected {} 1",
                    if want_growth { "above" } else { "below" }
                )));
            }
            Ok(())
        };
        check(lo, false)?;
        check(hi, true)?;
        while hi / lo - 1.0 > rel_tol {
            let mid = 0.5 * (lo + hi);
            if self.growth_ratio(ctrl, rpm, mid, duration)? > 1.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Ok(0.5 * (lo + hi))
    }
}
