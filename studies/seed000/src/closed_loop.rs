//! The closed loop on the cores: the plant core ([`milling_plant::Plant`]) and the controller
//! core ([`chatter_control::Controller`]) coupled sample by sample, the way a master couples the
//! two FMUs with a communication step equal to the controller's period `T`.
//!
//! Sample `k` (time `t_k = k·T`):
//!
//! ```text
//! x_k  = plant.x(t_k)
//! o_k  = controller.sample(x_k, 0)            (the controller's output of this sample)
//! u_k  = o_k.u          (Gauss–Seidel: controller stepped first, its output used at once)
//!      = o_{k−1}.u      (Jacobi: every FMU stepped with the outputs at t_k; u_{−1} = 0)
//! plant advanced over [t_k, t_k+1] with u_k held
//! ```
//!
//! Jacobi is the one-sample communication delay `e^{−iωT}` that
//! [`chatter_control::Controller::frequency_response`] (and so the lobes) assume; Gauss–Seidel
//! is the shipped `ClosedLoop.ssp` order (controller, then plant). Without a controller
//! (`None` or structure `off`) the command is 0. Every analysis that needs the loop in the time
//! domain runs it through [`CoreLoop`]; the same loop through the FMUs is
//! [`crate::fmu_validation`].

use chatter_control::{Controller, ControllerOutput, ControllerParams, Structure};
use linear_control::{ControlInputs, LinearControlParams, LinearController};
use milling_plant::{Plant, PlantError, PlantInputs, PlantParams};

/// Either controller core of the project: `ChatterController`'s or `LinearController`'s (a
/// SISO design on `v_x → F_x`, stepped every [`DEFAULT_STEP`] as the FMU is by the shipped
/// systems).
#[derive(Clone, Debug, PartialEq)]
pub enum AnyController {
    /// `chatter_control` (PID, FOPID, ADRC-FOPID; `off` is the open loop).
    Chatter(ControllerParams),
    /// `linear_control` (the Table 8 benchmark designs).
    Linear(Box<LinearControlParams>),
}

impl AnyController {
    /// The command limit \[N\].
    pub fn limit(&self) -> f64 {
        match self {
            AnyController::Chatter(c) => c.u_max,
            AnyController::Linear(p) => p.saturation[0],
        }
    }

    /// The same controller with its command limit `u_max`.
    pub fn with_limit(&self, u_max: f64) -> AnyController {
        match self {
            AnyController::Chatter(c) => AnyController::Chatter(ControllerParams { u_max, ..*c }),
            AnyController::Linear(p) => {
                AnyController::Linear(Box::new(LinearControlParams { saturation: [u_max; 2], ..(**p).clone() }))
            }
        }
    }

    /// The open loop (`off`)?
    pub fn is_off(&self) -> bool {
        matches!(self, AnyController::Chatter(c) if c.structure == Structure::Off)
    }
}

/// A running controller core.
#[derive(Clone, Debug)]
enum Running {
    Chatter(Box<Controller>),
    /// The core (saturation lifted: the loop clips, so that it knows the unsaturated command),
    /// its limit and the time of its next step.
    Linear(Box<LinearController>, f64, f64),
}

/// Initial tip displacement of every time-domain stability check \[m\].
pub const RELEASE: f64 = 1e-6;

/// The plant of a linear, quiet release: noise, drift and the sine disturbance off, released
/// from [`RELEASE`], actuator saturation lifted (1e9 N). Cutting is left as `plant` has it.
pub fn quiet_release(plant: &PlantParams) -> PlantParams {
    let mut p = plant.clone();
    p.disturbance.noise = false;
    p.disturbance.drift = false;
    p.disturbance.sine_amplitude = 0.0;
    p.workpiece.initial_displacement = RELEASE;
    p.actuator.f_max = 1e9;
    p
}

/// Order in which the two cores exchange values (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coupling {
    /// Controller first; the plant uses the command computed from the same sample.
    GaussSeidel,
    /// Both with the values at the start of the step: one sample of communication delay.
    Jacobi,
}

/// What the loop did at one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Sample index `k`.
    pub k: usize,
    /// Tip displacement `x(t_k)` \[m\].
    pub x: f64,
    /// The controller's output of this sample (zero without a controller).
    pub out: ControllerOutput,
    /// The command applied over `[t_k, t_k+1]` \[N\].
    pub applied: f64,
}

/// The plant diverged or refused its inputs at sample `k`.
#[derive(Debug, thiserror::Error)]
#[error("the plant failed at sample {k}: {source}")]
pub struct Diverged {
    /// Sample index.
    pub k: usize,
    /// The plant's error.
    #[source]
    pub source: PlantError,
}

/// Plant core + optional controller core at a fixed spindle speed and feed.
#[derive(Clone, Debug)]
pub struct CoreLoop {
    plant: Plant,
    ctrl: Option<Running>,
    coupling: Coupling,
    ts: f64,
    inputs: PlantInputs,
    previous_u: f64,
    k: usize,
}

/// The sample period without a controller \[s\] (the shipped communication step).
pub const DEFAULT_STEP: f64 = 1e-5;

impl CoreLoop {
    /// A loop at `rpm` and feed per tooth `feed` \[m\]; the controller's period is the step
    /// ([`DEFAULT_STEP`] without a controller).
    pub fn new(
        plant: &PlantParams,
        ctrl: Option<&ControllerParams>,
        coupling: Coupling,
        rpm: f64,
        feed: f64,
    ) -> Result<CoreLoop, String> {
        CoreLoop::with(plant, ctrl.map(|c| AnyController::Chatter(*c)).as_ref(), coupling, rpm, feed)
    }

    /// [`CoreLoop::new`] for either controller core (a `LinearController` is stepped every
    /// [`DEFAULT_STEP`] with `v_x = x`, its `F_x` the command).
    pub fn with(
        plant: &PlantParams,
        ctrl: Option<&AnyController>,
        coupling: Coupling,
        rpm: f64,
        feed: f64,
    ) -> Result<CoreLoop, String> {
        let (ctrl, ts) = match ctrl {
            Some(AnyController::Chatter(c)) if c.structure != Structure::Off => {
                (Some(Running::Chatter(Box::new(Controller::new(c)?))), c.ts)
            }
            Some(AnyController::Linear(p)) => {
                let lifted = LinearControlParams { saturation: [f64::MAX.sqrt(); 2], ..(**p).clone() };
                let core = LinearController::new(&lifted).map_err(|e| e.to_string())?;
                (Some(Running::Linear(Box::new(core), p.saturation[0], 0.0)), DEFAULT_STEP)
            }
            _ => (None, DEFAULT_STEP),
        };
        Ok(CoreLoop {
            plant: Plant::new(plant).map_err(|e| e.to_string())?,
            ctrl,
            coupling,
            ts,
            inputs: PlantInputs { u: 0.0, spindle_speed_rpm: rpm, feed_per_tooth: feed },
            previous_u: 0.0,
            k: 0,
        })
    }

    /// The sample period \[s\].
    pub fn step_size(&self) -> f64 {
        self.ts
    }

    /// The number of samples in `duration` seconds.
    pub fn samples_in(&self, duration: f64) -> usize {
        (duration / self.ts).round() as usize
    }

    /// The plant core.
    pub fn plant(&self) -> &Plant {
        &self.plant
    }

    /// Sample `k`: read `x_k` and run the controller (the plant has not advanced yet).
    fn next(&mut self) -> Sample {
        let x = self.plant.outputs().x;
        let ts = self.ts;
        let out = match self.ctrl.as_mut() {
            None => ControllerOutput::default(),
            Some(Running::Chatter(c)) => c.sample(x, 0.0),
            Some(Running::Linear(c, limit, t)) => {
                let inputs = ControlInputs { v: [x, 0.0], spindle_speed: 1.0 };
                let uc = match c.step(*t, ts, &inputs) {
                    Ok(()) => c.outputs().force[0],
                    Err(_) => f64::NAN,
                };
                *t += ts;
                let limit = *limit;
                ControllerOutput {
                    u: uc.clamp(-limit, limit),
                    e: -x,
                    saturated: uc.is_nan() || uc.abs() > limit,
                    ..Default::default()
                }
            }
        };
        let applied = match self.coupling {
            Coupling::GaussSeidel => out.u,
            Coupling::Jacobi => self.previous_u,
        };
        Sample { k: self.k, x, out, applied }
    }

    /// Advance the plant over `[t_k, t_k+1]` with the command of `s`.
    fn advance(&mut self, s: &Sample) -> Result<(), Diverged> {
        self.inputs.u = s.applied;
        self.previous_u = s.out.u;
        self.k += 1;
        self.plant.step(self.ts, &self.inputs).map_err(|source| Diverged { k: s.k, source })
    }

    /// One sample: read `x_k`, run the controller, advance the plant by `T`.
    pub fn step(&mut self) -> Result<Sample, Diverged> {
        let s = self.next();
        self.advance(&s)?;
        Ok(s)
    }

    /// Run `n` samples, handing each to `visit` before the plant advances (so the sample at
    /// which the plant diverges is visited too).
    pub fn run(&mut self, n: usize, mut visit: impl FnMut(&Sample)) -> Result<(), Diverged> {
        for _ in 0..n {
            let s = self.next();
            visit(&s);
            self.advance(&s)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Jacobi delays the command by exactly one sample relative to Gauss–Seidel's first step.
    #[test]
    fn jacobi_applies_the_previous_samples_command() {
        let plant = quiet_release(&PlantParams::default());
        let c = ControllerParams { structure: Structure::Pid, ..ControllerParams::paper_table2() };
        let mut gs = Vec::new();
        let mut jac = Vec::new();
        CoreLoop::new(&plant, Some(&c), Coupling::GaussSeidel, 2000.0, 0.0).unwrap().run(5, |s| gs.push(*s)).unwrap();
        CoreLoop::new(&plant, Some(&c), Coupling::Jacobi, 2000.0, 0.0).unwrap().run(5, |s| jac.push(*s)).unwrap();
        assert_eq!(gs[0].out, jac[0].out, "same x_0, same controller");
        assert_eq!(gs[0].applied.to_bits(), gs[0].out.u.to_bits());
        assert_eq!(jac[0].applied.to_bits(), 0.0f64.to_bits());
        for k in 1..5 {
            assert_eq!(jac[k].applied.to_bits(), jac[k - 1].out.u.to_bits());
        }
        assert_ne!(gs[1].x.to_bits(), jac[1].x.to_bits(), "the orders give different trajectories");
    }

    #[test]
    fn without_a_controller_the_command_is_zero_and_the_step_is_the_default() {
        let plant = quiet_release(&PlantParams::default());
        let mut l = CoreLoop::new(&plant, None, Coupling::GaussSeidel, 2000.0, 0.0).unwrap();
        assert_eq!(l.step_size().to_bits(), DEFAULT_STEP.to_bits());
        let s = l.step().unwrap();
        assert_eq!((s.k, s.x.to_bits(), s.applied.to_bits()), (0, RELEASE.to_bits(), 0.0f64.to_bits()));
    }
}
