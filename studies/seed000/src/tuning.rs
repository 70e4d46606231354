//! Controller tuning by PSO under the actuator-saturation constraint (seed 000, Eq. 31,
//! Section 4.4, Table 3).
//!
//! # Cost
//!
//! ```text
//! J(p) = −min_{N ∈ {1000, 1050, …, 3000} rpm} b_crit(N; p) [mm]  +  α·I_sat(p)·(1 + s(p)),   α = 10⁴ mm
//! ```
//!
//! `s(p)` ∈ \[0, 1\] is the fraction of samples of the check during which the command
//! saturated (1 if the plant diverged): among feasible points the cost is exactly the seed's
//! Eq. 31; among infeasible ones the swarm is pushed towards less saturation instead of
//! wandering on a flat penalty plateau. Depths are capped at [`DEPTH_CAP_MM`] = 1 m < α, so any
//! feasible point beats any infeasible one, and a positive cost means "no feasible point
//! found" (this happens for ADRC-FOPID with the seed's fixed ω_o and b0, see the report).
//!
//! `b_crit` is the exact closed-loop critical depth of [`delay_stability::zero_order`] with
//! `Φ_cl = Φ/(1 − Φ G_a H_c)` ([`crate::loop_frf`]).
//!
//! # Saturation check `I_sat` ([`SaturationCheck`])
//!
//! Scenario: the plant core ([`milling_plant::Plant`], the physics of the plant FMU) with the
//! cutting force **off**, the stiffness drift off, and the seed's broadband disturbance on
//! (Gaussian, 50 N RMS, 4th-order Butterworth band limit 2 kHz, fixed noise seed 7), coupled
//! sample by sample with the controller core ([`chatter_control::Controller`], its period
//! `T`, `r = 0`): `y_k = x(t_k)`, `u_k = sample(y_k)`, plant advanced by `T` with `u_k` held.
//! Duration 0.2 s (25 periods of the first mode, 1.6 decay time constants `1/(ζω_n)`).
//! **Exceeding** means the controller's *unsaturated* command `|u_c|` exceeded `u_max` = 27 N at
//! any sample (its `saturated` flag), or the plant diverged. The cutting force is off because
//! its stability is what `b_crit` measures; the check guards the command the controller needs
//! against the disturbance alone (the seed's 50 N RMS, Section 3.4). An unstable closed loop
//! (without cutting) grows until it saturates and is therefore rejected by the same check.
//!
//! # Search space (Table 3)
//!
//! Gains that span decades (`Kp ∈ [1e2, 1e5]`, `Ki`, `Kd`) are searched on `log10`; the orders
//! λ, μ ∈ \[0.1, 2\] linearly; the 30 % velocity clamp applies in these coordinates. PID:
//! `Ki ∈ [1e-3, 1e2]`; FOPID and ADRC-FOPID: `Ki ∈ [1e-2, 1e4]`; `Kd ∈ [1e-1, 1e3]`. For
//! ADRC-FOPID the five gains are the force-equivalent FOPID gains, converted to the inner loop's
//! acceleration units by `b0` exactly as `chatter_control::params` does (`adrc.k = b0·k`); ω_o and
//! b0 stay at their preset values (the seed tunes only the five FOPID gains).

use crate::closed_loop::{AnyController, CoreLoop, Coupling};
use crate::loop_frf;
use chatter_control::{ControllerParams, Structure};
use delay_stability::zero_order::speed_grid;
use milling_plant::PlantParams;
use study_kit::optim::pso::{PsoConfig, PsoResult, minimize};

/// Penalty weight α \[mm\]; larger than [`DEPTH_CAP_MM`], so every feasible point beats every
/// infeasible one.
pub const PENALTY_MM: f64 = 1.0e4;

/// Critical depths above this count as this much in the cost \[mm\] (1 m: "no chatter at any
/// realistic depth"; keeps the cost finite when no chatter root exists in the band).
pub const DEPTH_CAP_MM: f64 = 1000.0;

/// The time-domain saturation check (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SaturationCheck {
    /// Simulated duration \[s\].
    pub duration: f64,
    /// Disturbance RMS \[N\].
    pub noise_rms: f64,
    /// Disturbance bandwidth \[Hz\].
    pub noise_bandwidth: f64,
    /// Noise seed.
    pub seed: u64,
    /// Safety margin: the command counts as exceeding above `(1 − margin)·u_max` (0 = the seed).
    pub margin: f64,
}

impl Default for SaturationCheck {
    fn default() -> Self {
        SaturationCheck { duration: 0.2, noise_rms: 50.0, noise_bandwidth: 2000.0, seed: 7, margin: 0.0 }
    }
}

/// What tuning needs of a plant: its closed-loop lobes and its saturation check. Implemented
/// for the seed plant ([`PlantParams`]: the exact one-direction closed loop of
/// [`crate::loop_frf`] and the time-domain check on the plant core) and by a user's machine
/// (the `machine` crate: the 2-D closed loop and the check on the structure and actuator cores).
pub trait TuningPlant: Clone + Send + Sync {
    /// The smallest closed-loop critical depth over `speeds` \[m\] and its speed \[rpm\]
    /// (None if the loop cannot be evaluated).
    fn min_depth(&self, ctrl: &ControllerParams, speeds: &[f64]) -> Option<(f64, f64)>;
    /// The saturation check of `ctrl` on this plant.
    fn saturation(&self, check: &SaturationCheck, ctrl: &ControllerParams) -> Result<SaturationReport, String>;
}

impl TuningPlant for PlantParams {
    fn min_depth(&self, ctrl: &ControllerParams, speeds: &[f64]) -> Option<(f64, f64)> {
        let rpm_min = speeds.iter().copied().fold(f64::INFINITY, f64::min);
        let problem = loop_frf::problem(self, Some(ctrl), rpm_min).ok()?;
        let cp = problem.min_depth(speeds);
        Some((cp.depth, cp.rpm))
    }

    fn saturation(&self, check: &SaturationCheck, ctrl: &ControllerParams) -> Result<SaturationReport, String> {
        check.run(self, ctrl)
    }
}

/// Outcome of the saturation check.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SaturationReport {
    /// Did the unsaturated command exceed `u_max` (or the plant diverge)?
    pub exceeded: bool,
    /// Samples with `|u_c| > u_max`.
    pub saturated_samples: usize,
    /// Largest applied |u| \[N\].
    pub peak_u: f64,
    /// RMS of the tip displacement \[m\].
    pub rms_x: f64,
}

impl SaturationCheck {
    /// Run the check for a plant and controller.
    pub fn run(&self, plant: &PlantParams, ctrl: &ControllerParams) -> Result<SaturationReport, String> {
        self.run_with(plant, &AnyController::Chatter(*ctrl))
    }

    /// [`SaturationCheck::run`] for either controller core.
    pub fn run_with(&self, plant: &PlantParams, ctrl: &AnyController) -> Result<SaturationReport, String> {
        let mut p = plant.clone();
        p.cutting.enabled = false;
        p.disturbance.noise = true;
        p.disturbance.noise_rms = self.noise_rms;
        p.disturbance.noise_bandwidth = self.noise_bandwidth;
        p.disturbance.drift = false;
        p.disturbance.sine_amplitude = 0.0;
        p.seed = self.seed;
        // with a margin the controller's own limit is lowered: identical trajectory until the first
        // exceedance, which is all the check looks at
        let c = ctrl.with_limit(ctrl.limit() * (1.0 - self.margin));
        let mut lp = CoreLoop::with(&p, Some(&c), Coupling::GaussSeidel, 2000.0, 0.0)?;
        let n = lp.samples_in(self.duration);
        let mut rep = SaturationReport { exceeded: false, saturated_samples: 0, peak_u: 0.0, rms_x: 0.0 };
        let mut sx2 = 0.0;
        let run = lp.run(n, |s| {
            sx2 += s.x * s.x;
            rep.peak_u = rep.peak_u.max(s.out.u.abs());
            if s.out.saturated {
                rep.saturated_samples += 1;
            }
        });
        if run.is_err() {
            rep.exceeded = true;
            rep.rms_x = f64::INFINITY;
            return Ok(rep);
        }
        rep.rms_x = (sx2 / n.max(1) as f64).sqrt();
        rep.exceeded = rep.saturated_samples > 0;
        Ok(rep)
    }
}

/// The saturation check repeated over several noise seeds (a fresh-seed count).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeedSweep {
    /// Seeds checked.
    pub seeds: usize,
    /// Seeds whose check passed (no saturated sample).
    pub passed: usize,
    /// Largest applied |u| over the seeds \[N\].
    pub peak_u: f64,
    /// Most saturated samples of one seed.
    pub worst_saturated: usize,
}

impl SaturationCheck {
    /// This check (its `seed` replaced) for each of `seeds`.
    pub fn over_seeds<P: TuningPlant>(
        &self,
        plant: &P,
        ctrl: &ControllerParams,
        seeds: impl IntoIterator<Item = u64>,
    ) -> Result<SeedSweep, String> {
        let mut s = SeedSweep { seeds: 0, passed: 0, peak_u: 0.0, worst_saturated: 0 };
        for seed in seeds {
            let r = plant.saturation(&SaturationCheck { seed, ..*self }, ctrl)?;
            s.seeds += 1;
            s.passed += usize::from(!r.exceeded);
            s.peak_u = s.peak_u.max(r.peak_u);
            s.worst_saturated = s.worst_saturated.max(r.saturated_samples);
        }
        Ok(s)
    }

    /// [`SaturationCheck::over_seeds`] for either controller core on the seed's plant model.
    pub fn over_seeds_with(
        &self,
        plant: &PlantParams,
        ctrl: &AnyController,
        seeds: impl IntoIterator<Item = u64>,
    ) -> Result<SeedSweep, String> {
        let mut s = SeedSweep { seeds: 0, passed: 0, peak_u: 0.0, worst_saturated: 0 };
        for seed in seeds {
            let r = SaturationCheck { seed, ..*self }.run_with(plant, ctrl)?;
            s.seeds += 1;
            s.passed += usize::from(!r.exceeded);
            s.peak_u = s.peak_u.max(r.peak_u);
            s.worst_saturated = s.worst_saturated.max(r.saturated_samples);
        }
        Ok(s)
    }
}

/// The penalty of Eq. 31 as graded here (module docs): 0 if the check passed, `α(1 + s)` with
/// `s` the saturated fraction of `samples` if it failed, `2α` if it could not run or the plant
/// diverged.
pub fn penalty(sat: Option<&SaturationReport>, samples: f64) -> f64 {
    match sat {
        Some(s) if !s.exceeded => 0.0,
        Some(s) if s.rms_x.is_finite() => PENALTY_MM * (1.0 + s.saturated_samples as f64 / samples),
        _ => 2.0 * PENALTY_MM,
    }
}

/// The cost `−min(b, cap) + penalty` \[mm\] (module docs).
pub fn cost_of(b_mm: f64, penalty: f64) -> f64 {
    -b_mm.min(DEPTH_CAP_MM) + penalty
}

/// One tunable parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    /// Name (`kp`, `ki`, `kd`, `lambda`, `mu`).
    pub name: &'static str,
    /// Lower bound (physical units).
    pub lo: f64,
    /// Upper bound (physical units).
    pub hi: f64,
    /// Searched on log10?
    pub log: bool,
}

/// Table 3 search space for a structure (empty for `off`).
pub fn search_space(structure: Structure) -> Vec<ParamSpec> {
    let kp = ParamSpec { name: "kp", lo: 1e2, hi: 1e5, log: true };
    let kd = ParamSpec { name: "kd", lo: 1e-1, hi: 1e3, log: true };
    let lambda = ParamSpec { name: "lambda", lo: 0.1, hi: 2.0, log: false };
    let mu = ParamSpec { name: "mu", lo: 0.1, hi: 2.0, log: false };
    match structure {
        Structure::Off => vec![],
        Structure::Pid => vec![kp, ParamSpec { name: "ki", lo: 1e-3, hi: 1e2, log: true }, kd],
        Structure::Fopid | Structure::AdrcFopid => {
            vec![kp, ParamSpec { name: "ki", lo: 1e-2, hi: 1e4, log: true }, kd, lambda, mu]
        }
    }
}

/// Optional extension (not in the seed, which fixes ω_o = 3ω_1 and b0 = 1/M_w): the ADRC
/// observer bandwidth `omega_o` ∈ \[1e2, 1e4\] rad/s and the input gain `b0` ∈ \[1/3000, 1/3\] 1/kg,
/// both on log10, appended to the ADRC-FOPID search space by [`TuningProblem::tune_observer`].
pub const OBSERVER_SPACE: [ParamSpec; 2] = [
    ParamSpec { name: "omega_o", lo: 1e2, hi: 1e4, log: true },
    ParamSpec { name: "b0", lo: 1.0 / 3000.0, hi: 1.0 / 3.0, log: true },
];

/// Physical parameter values → controller parameters (on top of `base`). For ADRC-FOPID, two
/// extra values (ω_o, b0) may follow the five gains (see [`OBSERVER_SPACE`]).
pub fn apply(base: &ControllerParams, structure: Structure, values: &[f64]) -> ControllerParams {
    let mut c = *base;
    c.structure = structure;
    match structure {
        Structure::Off => {}
        Structure::Pid => {
            c.pid.kp = values[0];
            c.pid.ki = values[1];
            c.pid.kd = values[2];
        }
        Structure::Fopid => {
            c.fopid.kp = values[0];
            c.fopid.ki = values[1];
            c.fopid.kd = values[2];
            c.fopid.lambda = values[3];
            c.fopid.mu = values[4];
        }
        Structure::AdrcFopid => {
            if values.len() >= 7 {
                c.adrc.omega_o = values[5];
                c.adrc.b0 = values[6];
            }
            let b0 = c.adrc.b0;
            c.adrc.fopid.kp = b0 * values[0];
            c.adrc.fopid.ki = b0 * values[1];
            c.adrc.fopid.kd = b0 * values[2];
            c.adrc.fopid.lambda = values[3];
            c.adrc.fopid.mu = values[4];
        }
    }
    c
}

/// The force-equivalent gains of a controller in the order of [`search_space`].
pub fn gains_of(c: &ControllerParams) -> Vec<f64> {
    match c.structure {
        Structure::Off => vec![],
        Structure::Pid => vec![c.pid.kp, c.pid.ki, c.pid.kd],
        Structure::Fopid => vec![c.fopid.kp, c.fopid.ki, c.fopid.kd, c.fopid.lambda, c.fopid.mu],
        Structure::AdrcFopid => {
            let g = c.adrc.fopid;
            let b0 = c.adrc.b0;
            vec![g.kp / b0, g.ki / b0, g.kd / b0, g.lambda, g.mu]
        }
    }
}

/// Breakdown of one cost evaluation.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CostBreakdown {
    /// Minimum closed-loop critical depth over the speed set \[mm\].
    pub b_min_mm: f64,
    /// Speed of that minimum \[rpm\].
    pub rpm_at_min: f64,
    /// Saturation check result (None if the check could not run).
    pub saturation: Option<SaturationReport>,
    /// The cost J.
    pub cost: f64,
}

/// A tuning problem: plant, structure, base controller parameters, speeds, saturation check.
#[derive(Clone, Debug)]
pub struct TuningProblem<P: TuningPlant = PlantParams> {
    /// Plant.
    pub plant: P,
    /// Structure to tune.
    pub structure: Structure,
    /// Fixed parameters (period, u_max, ω_o, b0, fractional settings).
    pub base: ControllerParams,
    /// Speed set \[rpm\].
    pub speeds: Vec<f64>,
    /// Saturation check.
    pub check: SaturationCheck,
    /// ADRC-FOPID only: also tune ω_o and b0 ([`OBSERVER_SPACE`]; an extension of the seed).
    pub tune_observer: bool,
    /// Noise seeds of the robust saturation constraint: a candidate is feasible only if the
    /// check passes for every one of them (empty: the seed's single check, `check.seed`).
    pub check_seeds: Vec<u64>,
}

impl<P: TuningPlant> TuningProblem<P> {
    /// The seed's problem: speeds 1000, 1050, …, 3000 rpm; base = Table 2 preset.
    pub fn new(plant: P, structure: Structure) -> TuningProblem<P> {
        TuningProblem {
            plant,
            structure,
            base: ControllerParams::paper_table2(),
            speeds: speed_grid(1000.0, 3000.0, 41),
            check: SaturationCheck::default(),
            tune_observer: false,
            check_seeds: Vec::new(),
        }
    }

    /// The parameters searched (Table 3, plus [`OBSERVER_SPACE`] if `tune_observer`).
    pub fn space(&self) -> Vec<ParamSpec> {
        let mut sp = search_space(self.structure);
        if self.tune_observer && self.structure == Structure::AdrcFopid {
            sp.extend_from_slice(&OBSERVER_SPACE);
        }
        sp
    }

    /// Search-space coordinates → physical values.
    pub fn decode(&self, x: &[f64]) -> Vec<f64> {
        self.space().iter().zip(x).map(|(s, &v)| if s.log { 10f64.powf(v) } else { v }).collect()
    }

    /// Bounds in search coordinates.
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let sp = self.space();
        let f = |s: &ParamSpec, v: f64| if s.log { v.log10() } else { v };
        (sp.iter().map(|s| f(s, s.lo)).collect(), sp.iter().map(|s| f(s, s.hi)).collect())
    }

    /// Evaluate the cost of controller parameters.
    pub fn evaluate(&self, ctrl: &ControllerParams) -> CostBreakdown {
        let bad = CostBreakdown { b_min_mm: 0.0, rpm_at_min: f64::NAN, saturation: None, cost: 2.0 * PENALTY_MM };
        if ctrl.validate().is_err() {
            return bad;
        }
        let Some((depth, rpm_at_min)) = self.plant.min_depth(ctrl, &self.speeds) else {
            return bad;
        };
        let b = depth * 1e3;
        let sat = if ctrl.structure == Structure::Off { None } else { self.saturation(ctrl) };
        let n = (self.check.duration / ctrl.ts).round().max(1.0) * self.check_seeds.len().max(1) as f64;
        // graded among infeasible points: α·(1 + fraction of saturated samples)
        let penalty = if ctrl.structure == Structure::Off { 0.0 } else { penalty(sat.as_ref(), n) };
        CostBreakdown { b_min_mm: b, rpm_at_min, saturation: sat, cost: cost_of(b, penalty) }
    }

    /// The saturation check over [`TuningProblem::check_seeds`] (or `check.seed` alone):
    /// exceeded if any seed exceeds, saturated samples summed, peak |u| and RMS x the largest.
    pub fn saturation(&self, ctrl: &ControllerParams) -> Option<SaturationReport> {
        let seeds = if self.check_seeds.is_empty() { vec![self.check.seed] } else { self.check_seeds.clone() };
        let mut all: Option<SaturationReport> = None;
        for seed in seeds {
            let r = self.plant.saturation(&SaturationCheck { seed, ..self.check }, ctrl).ok()?;
            all = Some(match all {
                None => r,
                Some(a) => SaturationReport {
                    exceeded: a.exceeded || r.exceeded,
                    saturated_samples: a.saturated_samples + r.saturated_samples,
                    peak_u: a.peak_u.max(r.peak_u),
                    rms_x: a.rms_x.max(r.rms_x),
                },
            });
        }
        all
    }

    /// Cost at search coordinates `x`.
    pub fn cost(&self, x: &[f64]) -> f64 {
        self.evaluate(&apply(&self.base, self.structure, &self.decode(x))).cost
    }

    /// One PSO run; `on_iteration(k, best_cost)` after each iteration.
    pub fn run<F: Fn(usize, f64)>(&self, cfg: &PsoConfig, on_iteration: F) -> TuningRun {
        let (lo, hi) = self.bounds();
        let r = minimize(|x| self.cost(x), &lo, &hi, cfg, on_iteration);
        let gains = self.decode(&r.best_x);
        let params = apply(&self.base, self.structure, &gains);
        TuningRun { seed: cfg.seed, gains, params, breakdown: self.evaluate(&params), pso: r }
    }
}

/// Result of one tuning run.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct TuningRun {
    /// PSO seed.
    pub seed: u64,
    /// Best gains (physical, force-equivalent, order of [`TuningProblem::space`]).
    pub gains: Vec<f64>,
    /// Best controller parameters.
    pub params: ControllerParams,
    /// Cost breakdown of the best parameters.
    pub breakdown: CostBreakdown,
    /// The PSO result.
    pub pso: PsoResult,
}

/// Mean and (sample) standard deviation.
pub fn mean_std(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let m = v.iter().sum::<f64>() / n;
    let s = if v.len() > 1 { (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt() } else { 0.0 };
    (m, s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decode_apply_roundtrip() {
        for s in [Structure::Pid, Structure::Fopid, Structure::AdrcFopid] {
            let t = TuningProblem::new(loop_frf::seed_plant(), s);
            let (lo, hi) = t.bounds();
            let mid: Vec<f64> = lo.iter().zip(&hi).map(|(a, b)| 0.5 * (a + b)).collect();
            let g = t.decode(&mid);
            let c = apply(&t.base, s, &g);
            let back = gains_of(&c);
            for (a, b) in g.iter().zip(&back) {
                assert!((a - b).abs() <= 1e-12 * a.abs());
            }
        }
    }

    #[test]
    fn table2_pid_does_not_saturate_and_huge_derivative_does() {
        let plant = loop_frf::seed_plant();
        let check = SaturationCheck { duration: 0.02, ..Default::default() };
        let c = ControllerParams { structure: Structure::Pid, ..ControllerParams::paper_table2() };
        let r = check.run(&plant, &c).unwrap();
        assert!(!r.exceeded, "{r:?}");
        let mut big = c;
        big.pid.kd = 1e5;
        let r = check.run(&plant, &big).unwrap();
        assert!(r.exceeded, "{r:?}");
    }

    /// Issue 11 item 4: the shipped defaults pass the ±27 N saturation check on at least 9 of
    /// the 10 noise seeds 101..=110, which no tuning run used (tuning checks seeds 1..=N, or 7),
    /// on the FMU's default 1-mode plant and on the 3-mode plant they were tuned on.
    #[test]
    fn shipped_defaults_pass_the_saturation_check_on_fresh_noise_seeds() {
        let mut failures = Vec::new();
        for modes in [1, 3] {
            let mut plant = loop_frf::seed_plant();
            plant.workpiece.modes = modes;
            for s in [Structure::Pid, Structure::Fopid, Structure::AdrcFopid] {
                let c = ControllerParams { structure: s, ..ControllerParams::default() };
                let sweep = SaturationCheck::default().over_seeds(&plant, &c, 101..=110).unwrap();
                let (passed, peak) = (sweep.passed, sweep.peak_u);
                eprintln!("{s:?}, {modes} mode(s): {passed}/10 fresh seeds pass, peak |u| {peak:.2} N");
                if passed < 9 {
                    failures.push(format!("{s:?} on {modes} mode(s): {passed}/10"));
                }
            }
        }
        assert!(failures.is_empty(), "shipped defaults saturate: {failures:?}");
    }
}
