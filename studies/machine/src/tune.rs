//! Controllers tuned for the user's machine: the seed's PSO and cost (`seed000::tuning`:
//! J = −min closed-loop critical depth over the speed set + penalty for saturation) with the
//! machine's closed loop and the machine's saturation check.
//!
//! * Closed-loop lobes: the 2-D receptance with the controller on the actuator
//!   ([`crate::models::ClosedLoop`]) in the zero-order solver (multi-frequency at low immersion),
//!   the minimum over the speed set refined by golden-section search.
//! * Saturation check (the seed's, on this machine): the structure's modes (cutting off) with
//!   the seed's disturbance (band-limited Gaussian force, 50 N RMS, 2 kHz, at the tool along the
//!   actuator axis), the actuator and the controller stepped sample by sample in the order of the
//!   machine's SSP (controller, actuator, structure) for 0.2 s; **exceeding** = the controller's
//!   unsaturated command passed the actuator's force limit at any sample (or the loop diverged).
//!   The gains are then checked on fresh noise seeds (101–110, which no tuning run used).

use crate::lobes::Method;
use crate::machine::Machine;
use crate::models::ClosedLoop;
use chatter_control::{Controller, ControllerParams, Structure};
use delay_stability::frequency::CriticalPoint;
use delay_stability::zero_order::speed_grid;
use machine_structure::{InertialActuator, ModalStructure, StructureInputs};
use seed000::tuning::{SaturationCheck, SaturationReport, SeedSweep, TuningPlant, TuningProblem, TuningRun};
use std::fmt::Write as _;
use std::sync::Arc;
use study_kit::optim::pso::PsoConfig;

/// A machine as a tuning plant.
#[derive(Clone, Debug)]
pub struct MachinePlant {
    machine: Arc<Machine>,
}

impl MachinePlant {
    /// The machine (it must have an actuator).
    pub fn new(machine: Machine) -> Result<MachinePlant, String> {
        if machine.actuator.is_none() {
            return Err("tuning needs the machine's [actuator] (its axis and force limit)".into());
        }
        Ok(MachinePlant { machine: Arc::new(machine) })
    }

    /// The machine.
    pub fn machine(&self) -> &Machine {
        &self.machine
    }
}

impl TuningPlant for MachinePlant {
    fn min_depth(&self, ctrl: &ControllerParams, speeds: &[f64]) -> Option<(f64, f64)> {
        let cl = ClosedLoop::new(&self.machine, ctrl).ok()?;
        let method = Method::for_immersion(&self.machine);
        let p = crate::lobes::min_depth(&self.machine, method, &|w| cl.receptance(w), speeds).ok()?;
        Some((p.depth, p.rpm))
    }

    fn saturation(&self, check: &SaturationCheck, ctrl: &ControllerParams) -> Result<SaturationReport, String> {
        saturation_check(&self.machine, check, ctrl)
    }
}

/// The saturation check on the machine's cores (module docs).
pub fn saturation_check(
    m: &Machine,
    check: &SaturationCheck,
    ctrl: &ControllerParams,
) -> Result<SaturationReport, String> {
    let f = m.fmu_parameters(1000.0, 0.0, Some(ctrl)).map_err(|e| e.to_string())?;
    let (act_params, _) = f.control.ok_or("the saturation check needs an actuator and a controller")?;
    let h = ctrl.ts;
    let mut sp = f.structure.clone();
    sp.internal_step = h;
    let d = &mut sp.disturbance;
    (d.noise, d.noise_rms, d.noise_bandwidth, d.direction_angle) =
        (true, check.noise_rms, check.noise_bandwidth, act_params.direction_angle);
    sp.seed = check.seed;
    let mut structure = ModalStructure::new(&sp).map_err(|e| e.to_string())?;
    let mut actuator = InertialActuator::new(&machine_structure::ActuatorParams { internal_step: h, ..act_params })
        .map_err(|e| e.to_string())?;
    let c = ControllerParams { u_max: ctrl.u_max * (1.0 - check.margin), ..*ctrl };
    let mut controller = Controller::new(&c)?;
    let axis = if act_params.direction_angle == 0.0 { 0 } else { 1 };
    let n = (check.duration / h).round().max(1.0) as usize;
    let mut rep = SaturationReport { exceeded: false, saturated_samples: 0, peak_u: 0.0, rms_x: 0.0 };
    let mut sx2 = 0.0;
    for _ in 0..n {
        let y = structure.outputs().tool[axis];
        let out = controller.sample(y, 0.0);
        rep.peak_u = rep.peak_u.max(out.u.abs());
        rep.saturated_samples += usize::from(out.saturated);
        let stepped = actuator.step(h, out.u).map_err(|e| e.to_string()).and_then(|()| {
            let inputs = StructureInputs { tool_force: [0.0; 2], actuator_force: actuator.outputs().force_xy };
            structure.step(h, &inputs).map_err(|e| e.to_string())
        });
        let x = structure.outputs().tool[axis];
        if stepped.is_err() || !x.is_finite() || x.abs() > 1.0 {
            rep.exceeded = true;
            rep.rms_x = f64::INFINITY;
            return Ok(rep);
        }
        sx2 += x * x;
    }
    rep.rms_x = (sx2 / n as f64).sqrt();
    rep.exceeded = rep.saturated_samples > 0;
    Ok(rep)
}

/// The controller structures `chatter tune --machine` tunes.
pub const STRUCTURES: [Structure; 3] = [Structure::Pid, Structure::Fopid, Structure::AdrcFopid];

/// The machine's controller parameters as an SSP parameter set for `ChatterController` (every
/// value that differs from the FMU's start value, the structure included).
pub fn controller_ssv(name: &str, c: &ControllerParams) -> Result<String, String> {
    use fmi2_export::Fmi2Model;
    let md = fmu_controller::ChatterController::description();
    let base = fmu_controller::parameter_assignments(&ControllerParams::tuned());
    let params: Vec<ssp::Parameter> = fmu_controller::parameter_assignments(c)
        .into_iter()
        .filter(|(n, v)| n == "structure" || base.iter().find(|(b, _)| b == n).is_none_or(|(_, bv)| bv != v))
        .map(|(n, v)| ssp::fmu_parameter(md, &n, v, ssp::Enumerations::Integers))
        .collect::<Result<_, _>>()?;
    ssp::ssv_xml(name, &params).map_err(|e| e.to_string())
}

/// The settings of a tuning on a machine.
#[derive(Clone, Debug)]
pub struct TuneOptions {
    /// Structures to tune.
    pub structures: Vec<Structure>,
    /// Independent PSO runs per structure (seeds `seed`, `seed + 1`, …).
    pub runs: usize,
    /// First PSO seed.
    pub seed: u64,
    /// Swarm settings (its seed is replaced per run).
    pub pso: PsoConfig,
    /// Noise seeds 1..=N of the robust saturation constraint during tuning.
    pub check_seeds: u64,
    /// Safety margin of the saturation check during tuning.
    pub margin: f64,
    /// Duration of the saturation check \[s\].
    pub check_duration: f64,
    /// Speeds of the cost's minimum over the machine's speed range.
    pub speeds: usize,
}

impl Default for TuneOptions {
    /// Every structure, 10 runs, the seed's swarm (40 × 60), the robust check of the shipped
    /// gains (seeds 1–5, 10 % margin, 0.2 s), 41 speeds.
    fn default() -> Self {
        TuneOptions {
            structures: STRUCTURES.to_vec(),
            runs: 10,
            seed: 1,
            pso: PsoConfig::default(),
            check_seeds: 5,
            margin: 0.1,
            check_duration: SaturationCheck::default().duration,
            speeds: 41,
        }
    }
}

/// The outcome for one structure.
#[derive(Clone, Debug)]
pub struct Tuned {
    /// The structure.
    pub structure: Structure,
    /// Every run, in seed order.
    pub runs: Vec<TuningRun>,
    /// The run with the lowest cost.
    pub best: TuningRun,
    /// The best gains' saturation check on the fresh noise seeds 101–110.
    pub fresh: SeedSweep,
}

/// Tune every structure of `o` on the machine; `progress(structure, run, iteration)`.
pub fn tune(
    m: &Machine,
    o: &TuneOptions,
    progress: &(dyn Fn(Structure, usize, usize) + Sync),
) -> Result<Vec<Tuned>, String> {
    m.require_modes("tuning").map_err(|e| e.to_string())?;
    let plant = MachinePlant::new(m.clone())?;
    let a = m.actuator.as_ref().ok_or("tuning needs the machine's [actuator]")?;
    let (lo, hi) = m.operation.speed_range_rpm;
    let mut out = Vec::new();
    for &s in &o.structures {
        if !STRUCTURES.contains(&s) {
            return Err(format!("{}: tune pid, fopid or adrc_fopid", model_kit::Choice::name(s)));
        }
        let mut prob = TuningProblem::new(plant.clone(), s);
        prob.base = ControllerParams { structure: s, u_max: a.force_limit, ..ControllerParams::tuned() };
        prob.speeds = speed_grid(lo, hi, o.speeds);
        prob.check = SaturationCheck { margin: o.margin, duration: o.check_duration, ..SaturationCheck::default() };
        prob.check_seeds = (1..=o.check_seeds).collect();
        let runs: Vec<TuningRun> = (0..o.runs)
            .map(|r| prob.run(&PsoConfig { seed: o.seed + r as u64, ..o.pso }, |k, _| progress(s, r, k)))
            .collect();
        let best = runs.iter().min_by(|a, b| a.breakdown.cost.total_cmp(&b.breakdown.cost)).ok_or("no runs")?.clone();
        let fresh = SaturationCheck::default().over_seeds(&plant, &best.params, 101..111)?;
        out.push(Tuned { structure: s, runs, best, fresh });
    }
    Ok(out)
}

/// The open-loop smallest critical depth over the machine's speed range (`speeds` speeds), by
/// the method the tuning uses.
pub fn open_loop_minimum(m: &Machine, speeds: usize) -> Result<CriticalPoint, String> {
    m.require_modes("the open-loop minimum").map_err(|e| e.to_string())?;
    let (lo, hi) = m.operation.speed_range_rpm;
    let frf = |w: f64| m.receptance(w);
    crate::lobes::min_depth(m, Method::for_immersion(m), &frf, &speed_grid(lo, hi, speeds)).map_err(|e| e.to_string())
}

/// The results as a markdown table beside the open loop's minimum.
pub fn table(results: &[Tuned], open: &CriticalPoint) -> String {
    let mut t = String::from(
        "| structure | runs | best J (mm) | closed-loop b_min (mm) | at (rpm) | open-loop b_min (mm) | fresh seeds 101–110 passed | peak u (N) |\n|---|---|---|---|---|---|---|---|\n",
    );
    for r in results {
        let b = &r.best.breakdown;
        let _ = writeln!(
            t,
            "| {} | {} | {:.4} | {:.4} | {:.0} | {:.4} | {}/10 | {:.2} |",
            model_kit::Choice::name(r.structure),
            r.runs.len(),
            b.cost,
            b.b_min_mm,
            b.rpm_at_min,
            open.depth * 1e3,
            r.fresh.passed,
            r.fresh.peak_u
        );
    }
    t
}
