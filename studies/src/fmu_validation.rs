//! The lobes checked through the FMUs: the plant FMU (averaged cutting model, noise, drift and
//! the sine disturbance off, static feed force off) and the controller FMU, coupled by the Rust
//! FMI master exactly as in the shipped closed-loop system (Gauss–Seidel, controller first,
//! communication step = the controller's period `T`), released from a 1 µm tip displacement.
//! Saturation is lifted on both sides (`actuator.f_max`, `u_max` = 1e9 N) because the lobes are
//! those of the linear loop. [`cosim_growth_ratio`] compares the peak |x| over the last fifth of
//! the run with the peak over the second fifth ([`GrowthWindows`], as
//! [`crate::validation::growth_ratio`] does on the cores): below 1 the cut is stable, above 1 it
//! chatters. [`time_domain_boundary`] bisects the depth at which the ratio crosses 1. The plant
//! overrides are those of [`crate::closed_loop::quiet_release`] written as FMU parameters.
//!
//! Timing: with the controller stepped first, the plant integrates `[t_k, t_k+1]` with the
//! command computed from `y(t_k)`, one sample earlier than the `e^{−iωT}` communication delay
//! that [`chatter_control::Controller::frequency_response`] (and so the lobes) assumes. At the
//! chatter frequencies (≈ 140 Hz, `ωT` ≈ 0.5°) this moves the boundary by far less than the
//! 3 % the check allows; the measured difference is what [`time_domain_boundary`] reports.

use crate::closed_loop::RELEASE;
use crate::validation::GrowthWindows;
use chatter_control::{ControllerParams, Structure};
use fmi_master::params::Override;
use fmi_master::{Observer, Progress, RunConfig, SimError, Simulation, SystemFile};
use fmu_controller::parameter_assignments;
use model_description::Value;

/// The closed-loop system of the project: `ClosedLoop.ssp` in `fmu_dir` if it exists, else the
/// embedded SSD with the FMUs of `fmu_dir`.
pub fn closed_loop_system(fmu_dir: &std::path::Path) -> Result<SystemFile, SimError> {
    let ssp = fmu_dir.join("ClosedLoop.ssp");
    if ssp.is_file() {
        SystemFile::open(&ssp, Some(fmu_dir))
    } else {
        SystemFile::from_text(fmi_master::CLOSED_LOOP_SSD, "ClosedLoop.ssd", fmu_dir)
    }
}

fn text(v: &Value) -> String {
    match v {
        Value::Real(x) => format!("{x:e}"),
        Value::Integer(i) => i.to_string(),
        Value::Boolean(b) => b.to_string(),
        Value::String(s) => s.clone(),
    }
}

/// The `--set` overrides of one validation run (see the module documentation).
pub fn overrides(ctrl: Option<&ControllerParams>, rpm: f64, depth: f64) -> Vec<Override> {
    let mut sets: Vec<(String, String)> = [
        ("cutting.enabled", "true".to_string()),
        ("cutting.model", "averaged".into()),
        ("cutting.axial_depth", format!("{depth:e}")),
        ("spindle_speed", format!("{rpm:e}")),
        ("feed_per_tooth", "0".into()),
        ("disturbance.noise", "false".into()),
        ("disturbance.drift", "false".into()),
        ("disturbance.sine_amplitude", "0".into()),
        ("workpiece.initial_displacement", format!("{RELEASE:e}")),
        ("actuator.f_max", "1e9".into()),
    ]
    .into_iter()
    .map(|(k, v)| (format!("plant.{k}"), v))
    .collect();
    match ctrl {
        Some(c) if c.structure != Structure::Off => {
            let c = ControllerParams { u_max: 1e9, ..*c };
            sets.extend(parameter_assignments(&c).iter().map(|(k, v)| (format!("controller.{k}"), text(v))));
        }
        _ => sets.push(("controller.structure".into(), "off".into())),
    }
    sets.into_iter().map(|(target, value)| Override { target, value }).collect()
}

/// Feeds `plant.x` of every recorded sample to [`GrowthWindows`].
struct Peaks {
    col: usize,
    windows: GrowthWindows,
}

impl Observer for Peaks {
    fn start(&mut self, names: &[String]) -> Result<(), SimError> {
        self.col = names.iter().position(|n| n == "plant.x").unwrap_or(0);
        Ok(())
    }
    fn sample(&mut self, _t: f64, values: &[f64]) -> Result<(), SimError> {
        self.windows.push(values[self.col]);
        Ok(())
    }
    fn finish(&mut self) -> Result<(), SimError> {
        Ok(())
    }
}

/// Growth ratio (late peak / early peak of |x|) of the FMU closed loop at `rpm` and axial depth
/// `depth` \[m\] over `duration` seconds; `ctrl = None` (or structure `off`) is the open loop.
/// The communication step is the controller's period (10 µs for the open loop).
pub fn cosim_growth_ratio(
    sys: &SystemFile,
    ctrl: Option<&ControllerParams>,
    rpm: f64,
    depth: f64,
    duration: f64,
) -> Result<f64, SimError> {
    let step = ctrl.map_or(1e-5, |c| c.ts);
    let cfg = RunConfig {
        start: Some(0.0),
        stop: Some(duration),
        step: Some(step),
        overrides: overrides(ctrl, rpm, depth),
        record: Some(vec!["plant.x".into()]),
        ..RunConfig::default()
    };
    let mut sim = Simulation::new(sys, &cfg)?;
    let n = usize::try_from(sim.n_steps() + 1).unwrap_or(usize::MAX);
    let mut peaks = Peaks { col: 0, windows: GrowthWindows::new(n) };
    match sim.run(&mut peaks, Progress::Off) {
        // The plant FMU stops with an error when |x| passes 1 m; a run that has grown a hundredfold
        // from the 1 µm release before failing is unstable, anything else is a real failure.
        Err(SimError::Fmu(_)) if peaks.windows.max > 100.0 * RELEASE => Ok(f64::INFINITY),
        Err(e) => Err(e),
        Ok(_) => Ok(peaks.windows.ratio()),
    }
}

/// The depth \[m\] where the FMU closed loop turns from decaying to growing, by bisection on
/// `[lo, hi]` (growth ratio < 1 at `lo`, > 1 at `hi`) to a relative width `rel_tol`.
pub fn time_domain_boundary(
    sys: &SystemFile,
    ctrl: Option<&ControllerParams>,
    rpm: f64,
    (mut lo, mut hi): (f64, f64),
    duration: f64,
    rel_tol: f64,
) -> anyhow::Result<f64> {
    let check = |d: f64, want_growth: bool| -> anyhow::Result<()> {
        let r = cosim_growth_ratio(sys, ctrl, rpm, d, duration)?;
        anyhow::ensure!(
            (r > 1.0) == want_growth,
            "bisection bracket: depth {d:e} m at {rpm} rpm has growth ratio {r:.4}, expected {} 1",
            if want_growth { "above" } else { "below" }
        );
        Ok(())
    };
    check(lo, false)?;
    check(hi, true)?;
    while hi / lo - 1.0 > rel_tol {
        let mid = 0.5 * (lo + hi);
        if cosim_growth_ratio(sys, ctrl, rpm, mid, duration)? > 1.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}
