//! The run engine: fixed-step co-simulation of a system of FMUs.
//!
//! ## Life cycle
//! 1. [`assembly`]: open every component's FMU, check connectors and
//!    connections, resolve the time grid ([`config`]), the order, the
//!    recorded variables and the parameters (component bindings, system
//!    bindings, `--set`: later wins), instantiate, set up and initialize.
//! 2. Every connected output is read and every connected input set, so all
//!    inputs are consistent at `t0`.
//! 3. Steps `n = 0 … N−1` from `tₙ = t0 + n·h` (computed, never
//!    accumulated) to `tₙ₊₁`:
//!    * **Gauss–Seidel** (default): for each component in the sequence, set
//!      its inputs from the latest values of the outputs they are connected
//!      to, `fmi2DoStep(tₙ, h)`, read its outputs. A component later in the
//!      sequence sees outputs at `tₙ₊₁` of the ones before it and at `tₙ` of
//!      the ones after. For the closed loop the sequence is
//!      `controller plant`: read the plant's output at `tₙ` → set the
//!      controller's input → step the controller → read its command → set
//!      the plant's input → step the plant → read the plant's output at `tₙ₊₁`.
//!    * **Jacobi**: set every input from the outputs at `tₙ`, step every
//!      component, read every output.
//! 4. Recorded variables are sampled at `t0` and every `k` steps (the
//!    output interval divided by `h`, which must be an integer) and at the
//!    last step, and handed to an [`Observer`] (e.g. the streaming CSV
//!    writer): memory does not grow with the run length. Values move
//!    through preallocated [`ports`]: nothing is allocated per step.
//! 5. On success and on any failure, every instance is terminated (if it
//!    was initialized) and freed when the simulation is dropped, and all
//!    temporary directories are removed; the observer is finished (flushed)
//!    in both cases.

pub(crate) mod assembly;
pub mod config;
pub mod loops;
pub(crate) mod ports;

pub use crate::observer::{NoObserver, Observer, Recorder};
pub use crate::progress::Progress;
pub use config::{AlgebraicLoops, RunConfig};
pub use loops::{LOOP_TOLERANCE, MAX_LOOP_ITERATIONS};

use crate::error::{SetupError, SimError};
use crate::progress::Tracker;
use config::Timing;
use ports::{Api, Components, Probe, api_of};
use ssp::Order;
use std::time::Duration;

/// Statistics of a finished run.
#[derive(Clone, Copy, Debug)]
pub struct RunStats {
    /// Steps taken.
    pub steps: u64,
    /// Wall time of the stepping loop.
    pub wall: Duration,
}

/// A system ready to run: FMUs loaded, connections checked, instances initialized.
pub struct Simulation {
    comps: Components,
    sequence: Vec<usize>,
    order: Order,
    timing: Timing,
    probes: Vec<Probe>,
    record_names: Vec<String>,
    /// Solve an algebraic loop at every communication point ([`loops`]).
    iterate_loop: bool,
}

impl Simulation {
    /// Load and initialize the system.
    pub fn new(sys: &crate::system::SystemFile, cfg: &RunConfig) -> Result<Simulation, SimError> {
        let a = assembly::assemble(sys, cfg)?;
        let mut sim = Simulation {
            comps: a.comps,
            sequence: a.sequence,
            order: a.order,
            timing: a.timing,
            probes: a.probes,
            record_names: a.record_names,
            iterate_loop: a.algebraic_loop,
        };
        // Consistent inputs at t0.
        for i in 0..sim.comps.len() {
            sim.comps.read_outputs(i)?;
        }
        for i in 0..sim.comps.len() {
            sim.comps.set_inputs(i)?;
        }
        if sim.iterate_loop {
            sim.comps.solve_loop(sim.timing.start)?;
        }
        Ok(sim)
    }

    /// Column names of the recorded variables (without `time`).
    pub fn record_names(&self) -> &[String] {
        &self.record_names
    }

    /// Number of communication steps.
    pub fn n_steps(&self) -> u64 {
        self.timing.n_steps
    }

    /// The communication step.
    pub fn step(&self) -> f64 {
        self.timing.step
    }

    /// The start time.
    pub fn start_time(&self) -> f64 {
        self.timing.start
    }

    /// The stepping order in use.
    pub fn order(&self) -> Order {
        self.order
    }

    /// The Gauss–Seidel sequence (component names).
    pub fn sequence(&self) -> Vec<&str> {
        self.sequence.iter().map(|&i| self.comps[i].name.as_str()).collect()
    }

    /// Every component's instance name and FMU model identifier.
    pub fn components(&self) -> Vec<(&str, &str)> {
        self.comps
            .iter()
            .map(|c| (c.name.as_str(), c.fmu.model_description().model_identifier().unwrap_or("")))
            .collect()
    }

    /// Read a numeric variable (Real, Integer, Enumeration or Boolean) of a
    /// component now, as f64 (e.g. parameter values for reports: the plant's
    /// `cutting.teeth` is an Integer).
    pub fn get_number(&mut self, component: &str, variable: &str) -> Result<f64, SimError> {
        let i = self.comps.iter().position(|c| c.name == component).ok_or_else(|| SetupError::UnknownComponent {
            name: component.to_string(),
            known: self.comps.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", "),
        })?;
        let c = &mut self.comps[i];
        let v = c
            .fmu
            .model_description()
            .variable(variable)
            .ok_or_else(|| assembly::unknown_variable("get_number", &c.name, &c.fmu, variable))?;
        let vr = [v.value_reference];
        match api_of(v) {
            Some(Api::Real) => {
                let mut out = [0.0];
                c.inst.get_real(&vr, &mut out)?;
                Ok(out[0])
            }
            Some(Api::Integer) => {
                let mut out = [0];
                c.inst.get_integer(&vr, &mut out)?;
                Ok(f64::from(out[0]))
            }
            Some(Api::Boolean) => {
                let mut out = [false];
                c.inst.get_boolean(&vr, &mut out)?;
                Ok(f64::from(u8::from(out[0])))
            }
            None => {
                Err(SetupError::TypeMismatch(format!("{component}.{variable} is a String variable, not a number"))
                    .into())
            }
        }
    }

    /// Log lines an instance has kept (for reports).
    pub fn log_lines(&self, component: &str) -> Vec<String> {
        self.comps.iter().find(|c| c.name == component).map(|c| c.inst.log_lines()).unwrap_or_default()
    }

    fn sample(&mut self, t: f64, row: &mut Vec<f64>, obs: &mut dyn Observer) -> Result<(), SimError> {
        self.comps.sample(&self.probes, row)?;
        obs.sample(t, row)
    }

    /// Run from the start to the stop time. The observer is finished (flushed)
    /// whether the run succeeds or fails.
    pub fn run(&mut self, obs: &mut dyn Observer, progress: Progress) -> Result<RunStats, SimError> {
        let r = self.run_inner(obs, progress);
        let f = obs.finish();
        let stats = r?;
        f?;
        Ok(stats)
    }

    fn run_inner(&mut self, obs: &mut dyn Observer, progress: Progress) -> Result<RunStats, SimError> {
        obs.start(&self.record_names)?;
        let mut row = Vec::with_capacity(self.probes.len());
        self.sample(self.timing.start, &mut row, obs)?;
        let mut tracker = Tracker::new(progress, self.timing.n_steps);
        let (h, n_steps, every) = (self.timing.step, self.timing.n_steps, self.timing.sample_every);
        let seq = self.sequence.clone();
        // the next sampled step, counted instead of `done % every` (an integer division per step)
        let mut next_sample = every;
        for n in 0..n_steps {
            let t = self.timing.time(n);
            if self.iterate_loop && n > 0 {
                self.comps.solve_loop(t)?;
            }
            match self.order {
                Order::GaussSeidel => {
                    for &i in &seq {
                        self.comps.advance(i, t, h)?;
                    }
                }
                Order::Jacobi => {
                    for i in 0..self.comps.len() {
                        self.comps.set_inputs(i)?;
                    }
                    for i in 0..self.comps.len() {
                        self.comps.step(i, t, h)?;
                    }
                }
            }
            let done = n + 1;
            if done == next_sample || done == n_steps {
                next_sample = next_sample.saturating_add(every);
                self.sample(self.timing.time(done), &mut row, obs)?;
            }
            tracker.update(done);
        }
        let wall = tracker.elapsed();
        tracker.finish();
        Ok(RunStats { steps: n_steps, wall })
    }
}
