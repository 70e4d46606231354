//! Seed 000's plant decomposed (`DecomposedPlant.ssp`: MillingProcess + ModalStructure +
//! InertialActuator + ChatterController) against the monolithic `MillingPlant.fmu`
//! (`ClosedLoop.ssp`), open loop, at the nominal point (2000 rpm, a_p = 1 mm, f_z = 0.05 mm,
//! 50 N RMS noise, ±10 % drift), in the Rust master at the systems' 10 µs step.
//!
//! Both systems run with their shipped parameters; only the noise seed (the plant's `seed`,
//! the structure's `seed`: the same band-limited realization on the same grid) and the
//! controller's `structure = off` are set. Per seed the RMS of the workpiece displacement over
//! the communication points of `(from, stop]` (the main job's statistic).
//!
//! # Where the two differ
//!
//! The monolithic plant evaluates the cutting force at every RK4 stage from the displacement
//! of that stage. In the decomposed system the force crosses an FMU boundary once per
//! communication step: the process computes it at `t_k` from the displacement at `t_k`, and the
//! structure holds it over `[t_k, t_k + h]` (zero-order hold, exact otherwise). The force thus
//! acts on average `h/2` late, a phase lag `ω h/2` (0.0045 rad at 143 Hz and 10 µs) on a cutting
//! stiffness of ~1.5 % of the workpiece's: a small negative damping, plus the displacement
//! sampled at the communication points instead of inside the step for the regenerative
//! surface (linear instead of Hermite interpolation, exact at 2000 rpm where the tooth period is
//! a whole number of steps). Everything else (noise, drift, modal parameters) is the same
//! arithmetic up to rounding.

use crate::scenario::{closed_loop_system, roles};
use chatter_control::Structure;
use fmi_master::{Observer, Override, Progress, RunConfig, SimError, Simulation, SystemFile};
use model_description::Value;
use model_kit::Choice;
use rayon::prelude::*;
use std::path::Path;
use study_kit::StudyError;

type Result<T> = std::result::Result<T, StudyError>;

/// The decomposed system: `DecomposedPlant.ssp` in `fmu_dir` if it exists, else the SSD of
/// `packaging` with the FMUs of `fmu_dir`.
pub fn decomposed_system(fmu_dir: &Path) -> Result<SystemFile> {
    let ssp = fmu_dir.join("DecomposedPlant.ssp");
    Ok(if ssp.is_file() {
        SystemFile::open(&ssp, Some(fmu_dir))?
    } else {
        SystemFile::from_text(packaging::DECOMPOSED_PLANT_SSD, "DecomposedPlant.ssd", fmu_dir)?
    })
}

/// What to run.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// Noise seeds.
    pub seeds: Vec<u32>,
    /// Stop time [s].
    pub stop: f64,
    /// RMS over `(from, stop]` [s].
    pub from: f64,
}

impl Default for Comparison {
    /// The figure: 10 seeds × 30 s, RMS from 1 s.
    fn default() -> Self {
        Comparison { seeds: (1..=10).collect(), stop: 30.0, from: 1.0 }
    }
}

/// One seed's result.
#[derive(Clone, Copy, Debug)]
pub struct Row {
    /// Noise seed.
    pub seed: u32,
    /// RMS of the monolithic plant's `x` [m].
    pub monolithic: f64,
    /// RMS of the decomposed structure's `tool_x` [m].
    pub decomposed: f64,
}

impl Row {
    /// `decomposed / monolithic − 1`.
    pub fn relative_difference(&self) -> f64 {
        self.decomposed / self.monolithic - 1.0
    }
}

struct Rms {
    from: f64,
    sumsq: f64,
    n: u64,
}

impl Observer for Rms {
    fn start(&mut self, _: &[String]) -> std::result::Result<(), SimError> {
        Ok(())
    }
    fn sample(&mut self, t: f64, v: &[f64]) -> std::result::Result<(), SimError> {
        if t > self.from {
            self.sumsq += v[0] * v[0];
            self.n += 1;
        }
        Ok(())
    }
    fn finish(&mut self) -> std::result::Result<(), SimError> {
        Ok(())
    }
}

fn rms(sys: &SystemFile, c: &Comparison, overrides: Vec<Override>, signal: String) -> Result<f64> {
    let rc = RunConfig { stop: Some(c.stop), overrides, record: Some(vec![signal]), ..RunConfig::default() };
    let mut sim = Simulation::new(sys, &rc)?;
    let mut obs = Rms { from: c.from, sumsq: 0.0, n: 0 };
    sim.run(&mut obs, Progress::Off)?;
    if obs.n == 0 {
        return Err(StudyError::Invalid(format!("no samples after {} s (stop {} s)", c.from, c.stop)));
    }
    Ok((obs.sumsq / obs.n as f64).sqrt())
}

/// Run both systems open loop for every seed (in parallel), `on_done` after each seed.
pub fn run(fmu_dir: &Path, c: &Comparison, on_done: &(dyn Fn(&Row) + Sync)) -> Result<Vec<Row>> {
    let mono = closed_loop_system(fmu_dir)?;
    let r = roles(&mono)?;
    let dec = decomposed_system(fmu_dir)?;
    let off = Value::Integer(Structure::Off.index());
    c.seeds
        .par_iter()
        .map(|&seed| {
            let s = Value::Integer(seed as i32);
            let m = rms(
                &mono,
                c,
                vec![
                    Override::typed(format!("{}.structure", r.controller), off.clone()),
                    Override::typed(format!("{}.seed", r.plant), s.clone()),
                ],
                r.measured(),
            )?;
            let d = rms(
                &dec,
                c,
                vec![Override::typed("controller.structure", off.clone()), Override::typed("structure.seed", s)],
                "structure.tool_x".into(),
            )?;
            let row = Row { seed, monolithic: m, decomposed: d };
            on_done(&row);
            Ok(row)
        })
        .collect()
}

/// Mean RMS of both and the relative difference of the means.
pub fn summary(rows: &[Row]) -> (f64, f64, f64) {
    let n = rows.len() as f64;
    let m = rows.iter().map(|r| r.monolithic).sum::<f64>() / n;
    let d = rows.iter().map(|r| r.decomposed).sum::<f64>() / n;
    (m, d, d / m - 1.0)
}
