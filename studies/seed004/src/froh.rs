//! # Seed 004: the FROH study (zero locus, non-minimum-phase boundary, J(β) sweep)
//!
//! For each reading of the chip time constant τ_c (the paper does not give it: one tooth period
//! `1/(N n)`, half a spindle period `T/2`, or `T`):
//!
//! * the **zero locus**: the largest zero of the FROH model of the plant
//!   `K_p/((τ_s s + 1)(τ_c s + 1))` at 2 mm against β, and the β at which it leaves the unit
//!   circle (bisection, [`milling_force_plant::froh::nmp_boundary`]);
//! * the **J(β) sweep** of Section V: the adaptive loop ([`froh_mrac::simulate`], plant and
//!   controller cores, communication step `T/M`) with `F_ref` = 1.2 kN on the depth profile, and
//!   `J = ∫|F_p − F_m| dt` over the first 30 spindle periods (2.52 s, before the first depth
//!   step) by the trapezoidal rule on the communication grid. Also J over 30 periods after each
//!   depth step and the overshoot `(max F_p − F_ref)/F_ref` in each depth segment.
//!
//! **The target `F_m` of J** is not given beyond "the continuous model reference system
//! response" ([`Target`]): the continuous reference model driven by the FROH of `F_ref` (the
//! controller's own `F_m`, which changes with β: default, the reading the study started with),
//! or its response to the `F_ref` step (the same for every β). At β = 0 the two coincide.
//!
//! The controller's initial model is the reading `K̂ = 0.5 K_p(2 mm)`, `τ̂ = 1.5 τ_c` (with the
//! τ_c of the reading; both factors are options), λ = 0.98, P₀ = 100 I; at β = 0 RLS estimates
//! the ZOH model's two parameters (`estimate_b1_at_zoh`: three, the former reading).

use froh_mrac::{ForceError, LoopSample, MracParams, simulate};
use milling_force_plant::ForcePlantParams;
use milling_force_plant::froh::{self, DiscreteTf, RampPropagator, StateSpace};
use model_kit::Choice;
use nalgebra::DVector;

model_kit::choice! {
    /// What J compares the force with.
    pub enum Target ("Target", "the reference force F_m of the cost J") {
        /// The continuous reference model driven by the FROH of F_ref (changes with β).
        Froh = "froh", "the continuous reference model driven by the FROH of F_ref (the controller's F_m; changes with beta)";
        /// The continuous reference model's response to the F_ref step (the same for every β).
        Step = "step", "the continuous reference model's response to the F_ref step (the same for every beta)";
    }
}

/// The chip-lag readings: (name, τ_c) for the default plant.
pub fn tau_c_readings() -> Vec<(&'static str, f64)> {
    let p = ForcePlantParams::default();
    let t = p.spindle_period();
    vec![("1/(Nn)", p.tooth_period()), ("T/2", t / 2.0), ("T", t)]
}

/// The β grid from `lo` to `hi` in steps of `step` (rounded to 1e-9).
pub fn beta_grid(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let n = ((hi - lo) / step + 1e-9).floor() as usize;
    (0..=n).map(|i| ((lo + i as f64 * step) * 1e9).round() / 1e9).collect()
}

/// One point of the zero locus.
#[derive(Clone, Debug, PartialEq)]
pub struct ZeroPoint {
    /// τ_c reading.
    pub reading: &'static str,
    /// β.
    pub beta: f64,
    /// The largest zero (real, imaginary part).
    pub zero: (f64, f64),
    /// Its modulus.
    pub modulus: f64,
}

/// One run of the sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoint {
    /// τ_c reading.
    pub reading: &'static str,
    /// β.
    pub beta: f64,
    /// J over the first 30 periods [N·s].
    pub j: f64,
    /// The sampled reading of J: `T Σ_{k<30} |F_p(kT) − F_m(kT)|` (the paper calls its J "a
    /// good approximation of the area", which reads as a sum over the samples) [N·s].
    pub j_samples: f64,
    /// J over the first 30 periods with the true (a, b₀, b₁) of the chip lag and no adaptation
    /// [N·s]: the part of J that is intersample mismatch (and the unmodelled τ_s), not
    /// estimation.
    pub j_true_model: f64,
    /// J over 30 periods after each depth step [N·s].
    pub j_after: Vec<f64>,
    /// Overshoot in each depth segment, relative to F_ref.
    pub overshoot: Vec<f64>,
    /// Samples at which the estimated zero was unstable and the previous controller was kept.
    pub design_skips: f64,
    /// Final estimates (a, b₀, b₁).
    pub theta: [f64; 3],
}

/// Per reading: the boundary and the sweep's summary.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadingSummary {
    /// τ_c reading.
    pub reading: &'static str,
    /// τ_c [s].
    pub tau_c: f64,
    /// Non-minimum-phase boundary in β (None: no crossing on [−1, 0]).
    pub nmp_boundary: Option<f64>,
    /// argmin of J over the grid.
    pub argmin: f64,
    /// J(argmin), J(0) and J(−0.2) (NaN when not on the grid).
    pub j_min: f64,
    /// J(0).
    pub j0: f64,
    /// J(−0.2).
    pub j_m02: f64,
    /// Overshoot (first segment) at the argmin and at β = 0.
    pub overshoot_argmin: f64,
    /// Overshoot (first segment) at β = 0.
    pub overshoot_0: f64,
    /// argmin in [−0.45, 0.05] and J(argmin) < J(0).
    pub gate: bool,
    /// The sampled reading: argmin, J(argmin)/J(0), J(−0.2)/J(0).
    pub sampled: (f64, f64, f64),
}

/// Options of the study.
#[derive(Clone, Debug)]
pub struct FrohStudy {
    /// β values of the sweep.
    pub betas: Vec<f64>,
    /// β values of the zero locus.
    pub locus_betas: Vec<f64>,
    /// Communication steps per sample period.
    pub substeps: u32,
    /// Simulated time [s].
    pub duration: f64,
    /// Reference force [N].
    pub f_ref: f64,
    /// Spindle periods in the cost.
    pub periods: usize,
    /// Initial model: K̂ as a fraction of K_p at the first depth (paper reading 0.5).
    pub gain_factor: f64,
    /// Initial model: τ̂ as a multiple of τ_c (paper reading 1.5).
    pub tau_factor: f64,
    /// The target of J.
    pub target: Target,
    /// The plant's CNC lag τ_s [s] (printed 0.1 ms).
    pub tau_s: f64,
    /// At β = 0 estimate three parameters `(a, b₀, b₁)` instead of the ZOH model's two.
    pub estimate_b1_at_zoh: bool,
}

impl Default for FrohStudy {
    fn default() -> Self {
        FrohStudy {
            betas: beta_grid(-0.6, 1.0, 0.05),
            locus_betas: beta_grid(-1.0, 1.0, 0.05),
            substeps: 20,
            duration: 12.0,
            f_ref: 1200.0,
            periods: 30,
            gain_factor: 0.5,
            tau_factor: 1.5,
            target: Target::Froh,
            tau_s: ForcePlantParams::default().tau_s,
            estimate_b1_at_zoh: false,
        }
    }
}

/// ∫|F_p − F_m| dt over `[t0, t0 + len]` on the recorded grid (trapezoidal rule).
pub fn cost(run: &[LoopSample], t0: f64, len: f64) -> f64 {
    let e = |s: &LoopSample| (s.force - s.reference_force).abs();
    run.windows(2)
        .filter(|w| w[0].t >= t0 - 1e-9 && w[1].t <= t0 + len + 1e-9)
        .map(|w| 0.5 * (w[1].t - w[0].t) * (e(&w[0]) + e(&w[1])))
        .sum()
}

/// The run with `F_m` replaced by the continuous reference model's response to the `F_ref`
/// step, propagated exactly on the run's grid (the controller's propagator: at β = 0 the result
/// is the FROH target to rounding).
pub fn with_step_target(run: &[LoopSample], ctrl: &MracParams, f_ref: f64) -> Result<Vec<LoopSample>, ForceError> {
    let sys = StateSpace::second_order(ctrl.zeta, ctrl.omega_n);
    let mut x = DVector::zeros(2);
    let mut cache: Option<(u64, RampPropagator)> = None;
    let mut out = Vec::with_capacity(run.len());
    for (i, s) in run.iter().enumerate() {
        if i > 0 {
            let h = s.t - run[i - 1].t;
            if cache.as_ref().is_none_or(|c| c.0 != h.to_bits()) {
                cache = Some((h.to_bits(), RampPropagator::new(&sys, h)?));
            }
            x = cache.as_ref().expect("just set").1.propagate(&x, f_ref, 0.0);
        }
        out.push(LoopSample { reference_force: x[0], ..*s });
    }
    Ok(out)
}

/// `T Σ |F_p − F_m|` over the samples `t_k = kT` in `[t0, t0 + len)` (`substeps` points per T).
pub fn sampled_cost(run: &[LoopSample], substeps: u32, t: f64, t0: f64, len: f64) -> f64 {
    run.iter()
        .step_by(substeps as usize)
        .filter(|s| s.t >= t0 - 1e-9 && s.t < t0 + len - 1e-9)
        .map(|s| t * (s.force - s.reference_force).abs())
        .sum()
}

/// The zero locus of the plant (at 2 mm) for one τ_c and the CNC lag τ_s.
pub fn zero_locus(reading: &'static str, tau_c: f64, tau_s: f64, betas: &[f64]) -> Result<Vec<ZeroPoint>, ForceError> {
    let p = ForcePlantParams { tau_c, tau_s, ..Default::default() };
    let sys = p.model(2.0);
    betas
        .iter()
        .map(|&beta| {
            let z = DiscreteTf::froh(&sys, p.spindle_period(), beta)?.dominant_zero().unwrap_or_default();
            Ok(ZeroPoint { reading, beta, zero: (z.re, z.im), modulus: z.norm() })
        })
        .collect()
}

/// One adaptive run of the sweep.
pub fn sweep_point(o: &FrohStudy, reading: &'static str, tau_c: f64, beta: f64) -> Result<SweepPoint, ForceError> {
    let plant = ForcePlantParams { tau_c, tau_s: o.tau_s, ..Default::default() };
    let ctrl = MracParams {
        beta,
        gain_estimate: o.gain_factor * plant.gain(plant.depth.b[0]),
        tau_estimate: o.tau_factor * tau_c,
        estimate_b1_at_zoh: o.estimate_b1_at_zoh,
        ..Default::default()
    };
    let t = ctrl.sample_period;
    let steps = (o.duration / t * o.substeps as f64).round() as usize;
    let target = |run: Vec<LoopSample>| match o.target {
        Target::Froh => Ok(run),
        Target::Step => with_step_target(&run, &ctrl, o.f_ref),
    };
    let run = target(simulate(&plant, &ctrl, o.f_ref, o.substeps, steps)?)?;
    let len = o.periods as f64 * t;
    let d = &plant.depth;
    let n = d.segments as usize;
    let j_after = (1..n).filter(|&i| d.t[i] + len <= o.duration + 1e-9).map(|i| cost(&run, d.t[i], len)).collect();
    let overshoot = (0..n)
        .filter(|&i| d.t[i] < o.duration)
        .map(|i| {
            let end = if i + 1 < n { d.t[i + 1] } else { f64::INFINITY };
            let max =
                run.iter().filter(|s| s.t >= d.t[i] && s.t < end).map(|s| s.force).fold(f64::NEG_INFINITY, f64::max);
            (max - o.f_ref) / o.f_ref
        })
        .collect();
    let last = run.last().expect("at least the start").controller;
    let exact = MracParams { adapt: false, gain_estimate: plant.gain(d.b[0]), tau_estimate: tau_c, ..ctrl };
    let first = (len / t * o.substeps as f64).round() as usize;
    let j_true_model = cost(&target(simulate(&plant, &exact, o.f_ref, o.substeps, first)?)?, 0.0, len);
    Ok(SweepPoint {
        reading,
        beta,
        j: cost(&run, 0.0, len),
        j_samples: sampled_cost(&run, o.substeps, t, 0.0, len),
        j_true_model,
        j_after,
        overshoot,
        design_skips: last.design_skips,
        theta: [last.a_hat, last.b0_hat, last.b1_hat],
    })
}

/// The sweep over `o.betas` for one reading, and its summary.
pub fn sweep(
    o: &FrohStudy,
    reading: &'static str,
    tau_c: f64,
) -> Result<(Vec<SweepPoint>, ReadingSummary), ForceError> {
    // β where the initial model's zero is already unstable cannot start (the paper leaves
    // these out): skipped, not in the results
    let mut pts = Vec::new();
    for &b in &o.betas {
        match sweep_point(o, reading, tau_c, b) {
            Ok(p) => pts.push(p),
            Err(ForceError::Design(_)) => {}
            Err(e) => return Err(e),
        }
    }
    if pts.is_empty() {
        return Err(ForceError::Design(format!("no β of the grid can start for τ_c = {tau_c}")));
    }
    let p = ForcePlantParams { tau_c, tau_s: o.tau_s, ..Default::default() };
    let nmp_boundary = froh::nmp_boundary(&p.model(2.0), p.spindle_period(), -1.0, 0.0)?;
    let best = pts.iter().min_by(|a, b| a.j.total_cmp(&b.j)).expect("a non-empty grid");
    let at = |beta: f64| pts.iter().find(|s| (s.beta - beta).abs() < 1e-9);
    let j0 = at(0.0).map_or(f64::NAN, |s| s.j);
    let best_s = pts.iter().min_by(|a, b| a.j_samples.total_cmp(&b.j_samples)).expect("a non-empty grid");
    let js0 = at(0.0).map_or(f64::NAN, |s| s.j_samples);
    let sampled = (best_s.beta, best_s.j_samples / js0, at(-0.2).map_or(f64::NAN, |s| s.j_samples) / js0);
    let summary = ReadingSummary {
        reading,
        tau_c,
        nmp_boundary,
        argmin: best.beta,
        j_min: best.j,
        j0,
        j_m02: at(-0.2).map_or(f64::NAN, |s| s.j),
        overshoot_argmin: best.overshoot[0],
        overshoot_0: at(0.0).map_or(f64::NAN, |s| s.overshoot[0]),
        gate: (-0.45..=0.05).contains(&best.beta) && best.j < j0,
        sampled,
    };
    Ok((pts, summary))
}

/// The zero locus as CSV.
pub fn locus_csv(points: &[ZeroPoint]) -> String {
    let mut s = String::from("reading,beta,zero_re,zero_im,modulus\n");
    for p in points {
        s += &format!("{},{},{:.12},{:.12},{:.12}\n", p.reading, p.beta, p.zero.0, p.zero.1, p.modulus);
    }
    s
}

/// The sweep as CSV.
pub fn sweep_csv(points: &[SweepPoint]) -> String {
    let mut s = String::from(
        "reading,beta,J_first30,J_first30_samples,J_first30_true_model,J_after_step1,J_after_step2,J_after_step3,overshoot_seg1,overshoot_seg2,overshoot_seg3,overshoot_seg4,design_skips,a_hat,b0_hat,b1_hat\n",
    );
    let col = |v: &[f64], i: usize| v.get(i).map_or(String::new(), |x| format!("{x:.9}"));
    for p in points {
        s += &format!(
            "{},{},{:.9},{:.9},{:.9},{},{},{},{},{},{},{},{},{:.9},{:.9},{:.9}\n",
            p.reading,
            p.beta,
            p.j,
            p.j_samples,
            p.j_true_model,
            col(&p.j_after, 0),
            col(&p.j_after, 1),
            col(&p.j_after, 2),
            col(&p.overshoot, 0),
            col(&p.overshoot, 1),
            col(&p.overshoot, 2),
            col(&p.overshoot, 3),
            p.design_skips,
            p.theta[0],
            p.theta[1],
            p.theta[2]
        );
    }
    s
}

/// The summary as a Markdown table.
pub fn summary_markdown(rows: &[ReadingSummary]) -> String {
    let mut s = String::from(
        "| τ_c reading | τ_c [ms] | NMP boundary β | argmin J | J(argmin)/J(0) | J(−0.2)/J(0) | J(0) [N·s] | overshoot argmin / β=0 | gate | sampled J: argmin, J(argmin)/J(0), J(−0.2)/J(0) |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {:.2} | {} | {:.2} | {:.3} | {:.3} | {:.2} | {:.1} % / {:.1} % | {} | {:.2}, {:.3}, {:.3} |\n",
            r.reading,
            r.tau_c * 1e3,
            r.nmp_boundary.map_or("none".into(), |b| format!("{b:.3}")),
            r.argmin,
            r.j_min / r.j0,
            r.j_m02 / r.j0,
            r.j0,
            100.0 * r.overshoot_argmin,
            100.0 * r.overshoot_0,
            if r.gate { "pass" } else { "finding" },
            r.sampled.0,
            r.sampled.1,
            r.sampled.2
        );
    }
    s
}

/// One cell of the θ₀ sensitivity: the sweep's result for one target, initial model and τ_c
/// reading (`None`: no β of the grid can start from this initial model).
#[derive(Clone, Debug)]
pub struct Theta0Row {
    /// The target of J.
    pub target: Target,
    /// K̂ / K_p(2 mm).
    pub gain_factor: f64,
    /// τ̂ / τ_c.
    pub tau_factor: f64,
    /// τ_c reading.
    pub reading: &'static str,
    /// The sweep's summary.
    pub summary: Option<ReadingSummary>,
}

/// The sweep for every target × initial model (`K̂ = g K_p(2 mm)`, `τ̂ = f τ_c`) × τ_c reading:
/// the initial model θ₀ is not printed in the paper.
pub fn theta0_sensitivity(o: &FrohStudy, gains: &[f64], taus: &[f64]) -> Result<Vec<Theta0Row>, ForceError> {
    let mut rows = Vec::new();
    for target in [Target::Froh, Target::Step] {
        for &gain_factor in gains {
            for &tau_factor in taus {
                let s = FrohStudy { target, gain_factor, tau_factor, ..o.clone() };
                for (reading, tau_c) in tau_c_readings() {
                    let summary = match sweep(&s, reading, tau_c) {
                        Ok((_, r)) => Some(r),
                        Err(ForceError::Design(_)) => None,
                        Err(e) => return Err(e),
                    };
                    rows.push(Theta0Row { target, gain_factor, tau_factor, reading, summary });
                }
            }
        }
    }
    Ok(rows)
}

/// The θ₀ sensitivity as a Markdown table: one row per target and initial model, the argmin
/// and J(−0.2)/J(0) per τ_c reading.
pub fn theta0_markdown(rows: &[Theta0Row]) -> String {
    let readings = tau_c_readings();
    let mut s = String::from("| J target | K̂/K_p | τ̂/τ_c |");
    for (r, _) in &readings {
        s += &format!(" {r}: argmin, J(−0.2)/J(0) |");
    }
    s += "\n|---|---|---|";
    s += &"---|".repeat(readings.len());
    for chunk in rows.chunks(readings.len()) {
        let h = &chunk[0];
        s += &format!("\n| {} | {} | {} |", h.target.name(), h.gain_factor, h.tau_factor);
        for r in chunk {
            s += &match &r.summary {
                Some(x) => format!(" {:.2}, {:.3} |", x.argmin, x.j_m02 / x.j0),
                None => " no β starts |".into(),
            };
        }
    }
    s + "\n"
}

/// The θ₀ sensitivity as CSV.
pub fn theta0_csv(rows: &[Theta0Row]) -> String {
    let mut s = String::from("target,gain_factor,tau_factor,reading,argmin,J_argmin,J0,J_m02\n");
    for r in rows {
        let v = r
            .summary
            .as_ref()
            .map_or(",,,".into(), |x| format!("{},{:.9},{:.9},{:.9}", x.argmin, x.j_min, x.j0, x.j_m02));
        s += &format!("{},{},{},{},{v}\n", r.target.name(), r.gain_factor, r.tau_factor, r.reading);
    }
    s
}
