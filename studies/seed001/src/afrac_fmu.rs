//! # Seed 001 through the FMUs: the cases of [`crate::afrac`] run by the master
//!
//! `chatter afrac --fmu` runs each case of [`crate::afrac::AfracStudy::cases`] through the
//! packaged FMUs instead of the cores: a controlled case as `Afrac.ssd` (TurningProcess +
//! AfracController, Gauss–Seidel controller → plant, step = the sample period) with every
//! parameter of the case bound by name (`fmu_turning_process::parameter_assignments`,
//! `fmu_afrac_controller::parameter_assignments`), an open-loop case as `TurningProcess.fmu` alone.
//!
//! **Alignment with the core trace.** [`crate::afrac::run`] records at `t_k` the plant's state
//! and the command computed from it at `t_k`; the master records at `t_k` before the
//! controller's step, so the controller's outputs there are those of sample `k − 1`. The run
//! therefore goes one step further (`duration + τ`) and point `k` takes the plant's values at
//! index `k` and the controller's at index `k + 1`. With the same coupling and the same
//! arithmetic the traces, and so the summaries, are equal (tested bitwise in
//! `studies/seed001/tests/afrac_fmu.rs`).

use crate::afrac::{Case, Point};
use fmi_master::{Override, Progress, Recorder, RunConfig, Simulation, SystemFile};
use std::path::Path;
use study_kit::StudyError;

fn column(r: &Recorder, name: &str) -> Result<Vec<f64>, StudyError> {
    r.column(name).ok_or_else(|| StudyError::Invalid(format!("{name} was not recorded")))
}

/// Run one case through the FMUs of `fmu_dir` (`packaging::fmu_dir()` for the packaged ones).
pub fn run_fmu(case: &Case, fmu_dir: &Path) -> Result<Vec<Point>, StudyError> {
    let plant_sets = fmu_turning_process::parameter_assignments(&case.plant);
    match &case.controller {
        None => {
            let tau = 1e-4;
            let n = (case.duration / tau).round() as usize;
            let sys = SystemFile::open(&fmu_dir.join("TurningProcess.fmu"), None)?;
            let cfg = RunConfig {
                stop: Some(n as f64 * tau),
                step: Some(tau),
                overrides: plant_sets.into_iter().map(|(name, v)| Override::typed(name, v)).collect(),
                record: Some(["x", "v", "q", "spindle_speed", "feed"].map(String::from).to_vec()),
                ..RunConfig::default()
            };
            let r = record(&sys, &cfg)?;
            let (x, v, q, n_in, f_in) = (
                column(&r, "x")?,
                column(&r, "v")?,
                column(&r, "q")?,
                column(&r, "spindle_speed")?,
                column(&r, "feed")?,
            );
            Ok((0..=n)
                .map(|k| Point {
                    t: k as f64 * tau,
                    x: x[k],
                    v: v[k],
                    force: q[k],
                    speed: n_in[k],
                    feed: f_in[k],
                    beta: 0.0,
                })
                .collect())
        }
        Some(c) => {
            let tau = c.sample_period;
            let n = (case.duration / tau).round() as usize;
            let sys = SystemFile::from_text(packaging::AFRAC_SSD, "packaging/scenarios/Afrac.ssd", fmu_dir)?;
            let mut overrides: Vec<Override> =
                plant_sets.into_iter().map(|(name, v)| Override::typed(format!("plant.{name}"), v)).collect();
            overrides.extend(
                fmu_afrac_controller::parameter_assignments(c)
                    .into_iter()
                    .map(|(name, v)| Override::typed(format!("controller.{name}"), v)),
            );
            let rec =
                ["plant.x", "plant.v", "plant.q", "controller.spindle_speed", "controller.feed", "controller.beta"];
            let cfg = RunConfig {
                stop: Some((n + 1) as f64 * tau),
                step: Some(tau),
                overrides,
                record: Some(rec.map(String::from).to_vec()),
                ..RunConfig::default()
            };
            let r = record(&sys, &cfg)?;
            let [x, v, q, speed, feed, beta] = rec.map(|name| column(&r, name));
            let (x, v, q, speed, feed, beta) = (x?, v?, q?, speed?, feed?, beta?);
            Ok((0..=n)
                .map(|k| Point {
                    t: k as f64 * tau,
                    x: x[k],
                    v: v[k],
                    force: q[k],
                    speed: speed[k + 1],
                    feed: feed[k + 1],
                    beta: beta[k + 1],
                })
                .collect())
        }
    }
}

fn record(sys: &SystemFile, cfg: &RunConfig) -> Result<Recorder, StudyError> {
    let mut sim = Simulation::new(sys, cfg)?;
    let mut rec = Recorder::default();
    sim.run(&mut rec, Progress::Off)?;
    let expected = ((cfg.stop.unwrap_or(0.0)) / cfg.step.unwrap_or(1.0)).round() as usize + 1;
    if rec.time.len() != expected {
        return Err(StudyError::Invalid(format!("the master recorded {} points, expected {expected}", rec.time.len())));
    }
    Ok(rec)
}
