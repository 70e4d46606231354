//! The options of one run ([`RunConfig`]) and the time grid they resolve to
//! ([`Timing`]): start, stop and step come from the command line, else the
//! system description (`DefaultExperiment` and this master's annotation),
//! else, for a single FMU, its own `DefaultExperiment`. The stop time must
//! be a whole number of steps after the start, the output interval a whole
//! number of steps.

use crate::error::SetupError;
use crate::overrides::Override;
use model_description::DefaultExperiment;
use ssp::{Order, SystemDescription};

/// Options of one run. `None` fields come from the system description
/// (SSD `DefaultExperiment` and this master's annotation), else from the
/// FMU's `DefaultExperiment` for a single-FMU run.
#[derive(Clone, Debug, Default)]
pub struct RunConfig {
    /// Start time.
    pub start: Option<f64>,
    /// Stop time.
    pub stop: Option<f64>,
    /// Communication step.
    pub step: Option<f64>,
    /// Stepping order.
    pub order: Option<Order>,
    /// Gauss–Seidel sequence of component names.
    pub sequence: Option<Vec<String>>,
    /// `--set` overrides.
    pub overrides: Vec<Override>,
    /// Recorded variables (`component.variable`); None: all outputs.
    pub record: Option<Vec<String>>,
    /// Output interval (a multiple of the step); None: every step.
    pub output_interval: Option<f64>,
    /// Print the FMUs' log lines to stderr as they come.
    pub echo_fmu_log: bool,
    /// The most communication steps the run may take (None: [`DEFAULT_MAX_STEPS`]).
    pub max_steps: Option<u64>,
    /// What to do with an algebraic loop (outputs that depend directly on inputs, connected in
    /// a cycle): refuse it (default) or iterate it to a fixed point at every communication point.
    pub algebraic_loops: AlgebraicLoops,
}

/// What the master does with an algebraic loop among the connections.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AlgebraicLoops {
    /// Refuse the system before instantiating (the default).
    #[default]
    Refuse,
    /// Solve the loop by fixed-point iteration of its outputs and inputs at every communication
    /// point (at most [`crate::engine::MAX_LOOP_ITERATIONS`] passes, tolerance
    /// [`crate::engine::LOOP_TOLERANCE`]; an error if it does not converge).
    Iterate,
}

/// The most communication steps a run takes unless told otherwise (`--max-steps`): 10⁸, e.g.
/// 1000 s at 10 µs. A step/stop pair that asks for more (`--step 1e-300`) is refused before any
/// FMU is instantiated, as a too costly step is refused by the FMUs' work bounds: such a run
/// would never end and would fill the disk with its CSV.
pub const DEFAULT_MAX_STEPS: u64 = 100_000_000;

/// The resolved time grid: `tₙ = start + n·step`, `n = 0 … n_steps`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Timing {
    pub start: f64,
    pub stop: f64,
    pub step: f64,
    pub n_steps: u64,
    /// Record every this many steps (and at the last one).
    pub sample_every: u64,
}

impl Timing {
    /// Resolve the grid (see the module documentation).
    pub(crate) fn resolve(
        cfg: &RunConfig,
        desc: &SystemDescription,
        fmu_default: Option<&DefaultExperiment>,
    ) -> Result<Timing, SetupError> {
        let start = cfg.start.or(desc.start_time).or(fmu_default.and_then(|d| d.start_time)).unwrap_or(0.0);
        let stop = cfg.stop.or(desc.stop_time).or(fmu_default.and_then(|d| d.stop_time)).ok_or_else(|| {
            SetupError::Invalid("no stop time: the system has no DefaultExperiment stopTime; pass --stop-time".into())
        })?;
        let step = cfg.step.or(desc.master.step_size).or(fmu_default.and_then(|d| d.step_size)).ok_or_else(|| {
            SetupError::Invalid("no communication step in the system description; pass --step".into())
        })?;
        if !(step > 0.0 && step.is_finite()) {
            return Err(SetupError::Value(format!("the step must be positive and finite, not {step}")));
        }
        if stop.partial_cmp(&start) != Some(std::cmp::Ordering::Greater) {
            return Err(SetupError::Value(format!("the stop time {stop} must be after the start time {start}")));
        }
        let span = stop - start;
        let n_steps = (span / step).round();
        let max_steps = cfg.max_steps.unwrap_or(DEFAULT_MAX_STEPS);
        if n_steps > max_steps as f64 {
            return Err(SetupError::Value(format!(
                "stop time − start time ({span} s) in steps of {step} s is {n_steps:e} communication steps, more than \
                 the limit of {max_steps} (pass a larger --step, or raise the limit with --max-steps)"
            )));
        }
        if (n_steps * step - span).abs() > 1e-9 * span.max(step) || n_steps < 1.0 {
            return Err(SetupError::Value(format!(
                "stop time − start time ({span}) is not a whole number of steps of {step}"
            )));
        }
        let sample_every = match cfg.output_interval {
            None => 1,
            Some(dt) => {
                let k = (dt / step).round();
                if dt.is_nan() || dt <= 0.0 || k < 1.0 || (k * step - dt).abs() > 1e-9 * dt {
                    return Err(SetupError::Value(format!(
                        "the output interval {dt} must be a positive multiple of the step {step}"
                    )));
                }
                k as u64
            }
        };
        Ok(Timing { start, stop, step, n_steps: n_steps as u64, sample_every })
    }

    /// The communication point `n`, computed (never accumulated).
    #[inline]
    pub(crate) fn time(&self, n: u64) -> f64 {
        self.start + n as f64 * self.step
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn resolve(cfg: RunConfig) -> Result<Timing, SetupError> {
        let mut d = SystemDescription::new("s");
        d.stop_time = Some(1.0);
        d.master.step_size = Some(1e-3);
        Timing::resolve(&cfg, &d, None)
    }

    #[test]
    fn the_grid_comes_from_the_system_unless_overridden() {
        let t = resolve(RunConfig::default()).unwrap();
        assert_eq!((t.start, t.n_steps, t.sample_every), (0.0, 1000, 1));
        let t = resolve(RunConfig { stop: Some(0.5), output_interval: Some(0.01), ..Default::default() }).unwrap();
        assert_eq!((t.n_steps, t.sample_every), (500, 10));
        assert_eq!(t.time(3).to_bits(), (3.0f64 * 1e-3).to_bits());
    }

    #[test]
    fn inconsistent_grids_are_refused() {
        let e = resolve(RunConfig { step: Some(3e-4), ..Default::default() }).unwrap_err().to_string();
        assert!(e.contains("is not a whole number of steps"), "{e}");
        let e = resolve(RunConfig { output_interval: Some(1.5e-3), ..Default::default() }).unwrap_err().to_string();
        assert!(e.contains("must be a positive multiple of the step"), "{e}");
        let e = resolve(RunConfig { start: Some(2.0), ..Default::default() }).unwrap_err().to_string();
        assert!(e.contains("must be after the start time"), "{e}");
        let e = resolve(RunConfig { step: Some(-1.0), ..Default::default() }).unwrap_err().to_string();
        assert!(e.contains("positive and finite"), "{e}");
    }

    /// `--stop-time 0.01 --step 1e-300` planned 1e298 steps and wrote 361 MB of CSV in 12 s
    /// before it was killed: the grid is refused before any FMU runs.
    #[test]
    fn a_grid_beyond_the_step_limit_is_refused() {
        let e = resolve(RunConfig { stop: Some(0.01), step: Some(1e-300), ..Default::default() }).unwrap_err();
        let e = e.to_string();
        assert!(
            e.contains("communication steps, more than the limit of 100000000") && e.contains("--max-steps"),
            "{e}"
        );
        let at = |n: u64, max: Option<u64>| {
            resolve(RunConfig { stop: Some(n as f64 * 1e-3), max_steps: max, ..Default::default() })
        };
        assert_eq!(at(DEFAULT_MAX_STEPS / 1000, None).unwrap().n_steps, DEFAULT_MAX_STEPS / 1000);
        assert!(at(2000, Some(1999)).is_err());
        assert_eq!(at(2000, Some(2000)).unwrap().n_steps, 2000);
    }
}
