//! # Seed 001: the AFrAC study (open loop, fixed β, the stepwise schedule, the GA of Table 4)
//!
//! The turning process core ([`turning_process::TurningProcess`]) and the AFrAC controller
//! core ([`afrac_control::Afrac`]) in one loop (Gauss–Seidel, communication step = the
//! controller's sample period `τ`: the controller reads `x, ẋ` at `t_k` and its speed and feed
//! are held by the plant over `[t_k, t_k + τ)`), the same loop `Afrac.ssd` runs on the FMUs.
//!
//! Per run:
//!
//! * the peak `|x|` and the times the envelope falls to 10 % and 1 % of it: the envelope at
//!   `t` is `max_{s ≥ t} |x(s)|` (so "reached" means "stays below from then on");
//! * the speed excursion `max |N − N₀|`, the final speed, the feed excursion `max |δf|`;
//! * the net work of the cutting force on the tool per window (0–0.5, 0.5–1, 1–1.5,
//!   1.5–2 s), `∫ΔF ẋ dt / k`, in mm²/s·s = mm² (the force is known as the deflection it
//!   causes, `ΔF cos α / k`: the paper's `k` is not given);
//! * the mean `|x|` over the run (the GA's objective).

use afrac_control::{Afrac, AfracError, AfracParams, Schedule};
use turning_process::{TurningError, TurningInputs, TurningParams, TurningProcess};

/// A failure of a run.
#[derive(Debug, thiserror::Error)]
pub enum AfracStudyError {
    /// The plant refused a step.
    #[error("turning process: {0}")]
    Plant(#[from] TurningError),
    /// The controller refused a sample.
    #[error("AFrAC controller: {0}")]
    Controller(#[from] AfracError),
}

/// One case: the plant at a depth, with or without the controller.
#[derive(Clone, Debug)]
pub struct Case {
    /// Label (CSV, tables).
    pub label: String,
    /// Plant parameters (depth inside).
    pub plant: TurningParams,
    /// Controller parameters, `None` for the open loop.
    pub controller: Option<AfracParams>,
    /// Duration [s].
    pub duration: f64,
}

/// One recorded instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Point {
    /// t [s].
    pub t: f64,
    /// x [mm].
    pub x: f64,
    /// ẋ [mm/s].
    pub v: f64,
    /// Force as deflection [mm].
    pub force: f64,
    /// Speed [rpm].
    pub speed: f64,
    /// Feed [mm/rev].
    pub feed: f64,
    /// β.
    pub beta: f64,
}

/// The summary of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Label.
    pub label: String,
    /// Peak |x| [mm].
    pub peak: f64,
    /// Time of the peak [s].
    pub t_peak: f64,
    /// Time the envelope stays below 10 % of the peak [s].
    pub t10: Option<f64>,
    /// Time the envelope stays below 1 % of the peak [s].
    pub t1: Option<f64>,
    /// max |N − N₀| [rpm].
    pub speed_excursion: f64,
    /// Final speed [rpm].
    pub final_speed: f64,
    /// max |f − f₀| [mm/rev].
    pub feed_excursion: f64,
    /// Mean |x| [mm].
    pub mean_abs_x: f64,
    /// Net work ∫ΔF ẋ dt/k per window 0–0.5, 0.5–1, 1–1.5, 1.5–2 s [mm²].
    pub work: [f64; 4],
    /// |x| at the end relative to the peak.
    pub final_ratio: f64,
}

/// Run one case; returns the trace at every communication point.
pub fn run(case: &Case) -> Result<Vec<Point>, AfracStudyError> {
    let mut plant = TurningProcess::new(&case.plant)?;
    let mut ctrl = case.controller.as_ref().map(Afrac::new).transpose()?;
    let tau = case.controller.as_ref().map_or(1e-4, |c| c.sample_period);
    let n = (case.duration / tau).round() as usize;
    let mut inputs = TurningInputs::default();
    if let Some(c) = &case.controller {
        inputs = TurningInputs { spindle_speed: c.initial_speed, feed: c.initial_feed };
    }
    let mut trace = Vec::with_capacity(n + 1);
    let mut beta = 0.0;
    for k in 0..=n {
        let o = plant.outputs();
        if let Some(c) = ctrl.as_mut() {
            let u = c.sample(o.x, o.v)?;
            inputs = TurningInputs { spindle_speed: u.spindle_speed, feed: u.feed };
            beta = u.beta;
        }
        trace.push(Point {
            t: k as f64 * tau,
            x: o.x,
            v: o.v,
            force: o.force,
            speed: inputs.spindle_speed,
            feed: inputs.feed,
            beta,
        });
        if k < n {
            plant.set_time(k as f64 * tau);
            plant.step(tau, &inputs)?;
        }
    }
    Ok(trace)
}

/// Summarise a trace (`speed0`, `feed0`: the initial commands).
pub fn summarise(label: &str, trace: &[Point], speed0: f64, feed0: f64) -> Summary {
    let mut env = vec![0.0f64; trace.len()];
    let mut m = 0.0f64;
    for i in (0..trace.len()).rev() {
        m = m.max(trace[i].x.abs());
        env[i] = m;
    }
    let (i_peak, peak) =
        trace.iter().enumerate().fold((0, 0.0f64), |b, (i, p)| if p.x.abs() > b.1 { (i, p.x.abs()) } else { b });
    let first_below = |frac: f64| (i_peak..trace.len()).find(|&i| env[i] <= frac * peak).map(|i| trace[i].t);
    let mut work = [0.0; 4];
    for w in trace.windows(2) {
        let (a, b) = (w[0], w[1]);
        let j = (a.t / 0.5).floor() as usize;
        if j < 4 {
            // the structure is pushed by −ΔF cos α: its work is −∫ q ẋ dt (k = 1)
            work[j] -= 0.5 * (a.force * a.v + b.force * b.v) * (b.t - a.t);
        }
    }
    let n = trace.len() as f64;
    Summary {
        label: label.to_string(),
        peak,
        t_peak: trace[i_peak].t,
        t10: first_below(0.1),
        t1: first_below(0.01),
        speed_excursion: trace.iter().map(|p| (p.speed - speed0).abs()).fold(0.0, f64::max),
        final_speed: trace.last().map_or(speed0, |p| p.speed),
        feed_excursion: trace.iter().map(|p| (p.feed - feed0).abs()).fold(0.0, f64::max),
        mean_abs_x: trace.iter().map(|p| p.x.abs()).sum::<f64>() / n,
        work,
        final_ratio: trace.last().map_or(0.0, |p| p.x.abs()) / peak,
    }
}

/// The study's settings.
#[derive(Clone, Debug)]
pub struct AfracStudy {
    /// Controller template (gains, sample period, band).
    pub controller: AfracParams,
    /// Plant template (depth set per case).
    pub plant: TurningParams,
    /// Duration [s].
    pub duration: f64,
    /// Fixed orders.
    pub betas: Vec<f64>,
}

impl Default for AfracStudy {
    fn default() -> Self {
        AfracStudy {
            controller: AfracParams::default(),
            plant: TurningParams::default(),
            duration: 3.0,
            betas: vec![1.0, 1.25, 1.5, 1.75],
        }
    }
}

impl AfracStudy {
    /// The cases: open loop at 5 and 2 mm, each fixed β at 5 mm, AFrAC (Table 5) and AFrAC
    /// bumpless.
    pub fn cases(&self) -> Vec<Case> {
        let plant = |w: f64| TurningParams { depth: w, ..self.plant.clone() };
        let ctrl =
            |s: Schedule, bumpless: bool| AfracParams { schedule: s, bumpless, depth: 5.0, ..self.controller.clone() };
        let mut cases = vec![
            Case { label: "open loop 5 mm".into(), plant: plant(5.0), controller: None, duration: self.duration },
            Case { label: "open loop 2 mm".into(), plant: plant(2.0), controller: None, duration: self.duration },
        ];
        for b in &self.betas {
            cases.push(Case {
                label: format!("beta = {b}"),
                plant: plant(5.0),
                controller: Some(ctrl(Schedule::fixed(*b), false)),
                duration: self.duration,
            });
        }
        cases.push(Case {
            label: "AFrAC (Table 5)".into(),
            plant: plant(5.0),
            controller: Some(ctrl(Schedule::default(), false)),
            duration: self.duration,
        });
        cases.push(Case {
            label: "AFrAC bumpless".into(),
            plant: plant(5.0),
            controller: Some(ctrl(Schedule::default(), true)),
            duration: self.duration,
        });
        cases
    }

    /// Run every case (in parallel) and summarise.
    pub fn run(&self) -> Result<Vec<(Summary, Vec<Point>)>, AfracStudyError> {
        use rayon::prelude::*;
        let (n0, f0) = (self.controller.initial_speed, self.controller.initial_feed);
        self.cases().par_iter().map(|c| run(c).map(|t| (summarise(&c.label, &t, n0, f0), t))).collect()
    }
}

fn opt(t: Option<f64>) -> String {
    t.map_or("never".into(), |t| format!("{t:.3}"))
}

/// Markdown table of the summaries.
pub fn summary_markdown(rows: &[Summary]) -> String {
    let mut s = String::from(
        "| case | peak abs(x) [mm] | t peak [s] | t 10 % [s] | t 1 % [s] | max abs(N − 450) [rpm] | final N [rpm] | max abs(δf) [mm/rev] | mean abs(x) [mm] | work 0–0.5 / 0.5–1 / 1–1.5 / 1.5–2 s [mm²] |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {:.3e} | {:.3} | {} | {} | {:.1} | {:.1} | {:.4} | {:.3e} | {:.2e} / {:.2e} / {:.2e} / {:.2e} |\n",
            r.label,
            r.peak,
            r.t_peak,
            opt(r.t10),
            opt(r.t1),
            r.speed_excursion,
            r.final_speed,
            r.feed_excursion,
            r.mean_abs_x,
            r.work[0],
            r.work[1],
            r.work[2],
            r.work[3]
        );
    }
    s
}

/// CSV of the traces, every `every`-th point.
pub fn traces_csv(runs: &[(Summary, Vec<Point>)], every: usize) -> String {
    let mut s = String::from("case,t,x,v,force,speed,feed,beta\n");
    for (sum, trace) in runs {
        for p in trace.iter().step_by(every.max(1)) {
            s +=
                &format!("{},{},{:e},{:e},{:e},{},{},{}\n", sum.label, p.t, p.x, p.v, p.force, p.speed, p.feed, p.beta);
        }
    }
    s
}

/// CSV of the summaries.
pub fn summary_csv(rows: &[Summary]) -> String {
    let mut s = String::from(
        "case,peak,t_peak,t10,t1,speed_excursion,final_speed,feed_excursion,mean_abs_x,work_0,work_1,work_2,work_3,final_ratio\n",
    );
    for r in rows {
        let o = |t: Option<f64>| t.map_or(String::new(), |t| t.to_string());
        s += &format!(
            "{},{:e},{},{},{},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e}\n",
            r.label,
            r.peak,
            r.t_peak,
            o(r.t10),
            o(r.t1),
            r.speed_excursion,
            r.final_speed,
            r.feed_excursion,
            r.mean_abs_x,
            r.work[0],
            r.work[1],
            r.work[2],
            r.work[3],
            r.final_ratio
        );
    }
    s
}

/// The genetic algorithm of Table 4 ([`study_kit::optim::ga`]) on the switch times `(t₁…t₄)`
/// of the stepwise schedule.
///
/// Table 4: four design variables of 6 bits each on `[0.02, 2.4]` s (64 levels, step
/// 2.38/63 s), uniform crossover with p = 0.5, independent mutation of every allele with
/// p = 0.01, stop when 99 % of the bits have converged (read as: the fraction of bit
/// positions on which the whole population agrees reaches 99 %), objective the mean `|x|`. Not given, chosen:
/// population 20, binary tournament selection, one elite kept, at most 40 generations,
/// ChaCha8 seeded (reproducible). A switch time's order is that of the latest time ≤ t
/// ([`afrac_control::Schedule::beta_at`]): the GA does not constrain their sequence.
pub use study_kit::optim::ga::Ga;

/// 6-bit code to a time in [0.02, 2.4] s.
pub fn decode(bits: u32) -> f64 {
    0.02 + (2.4 - 0.02) * (bits & 63) as f64 / 63.0
}

/// A GA result.
#[derive(Clone, Debug, PartialEq)]
pub struct GaResult {
    /// Best times (t₁…t₄) [s].
    pub times: [f64; 4],
    /// Its mean |x| [mm].
    pub objective: f64,
    /// Generations run.
    pub generations: usize,
    /// Fraction of unanimous bits at the end.
    pub converged: f64,
    /// Objective evaluations.
    pub evaluations: usize,
    /// Best objective per generation.
    pub history: Vec<f64>,
}

/// Run the GA on `study`'s 5 mm AFrAC case (its controller template, `bumpless` as given).
pub fn ga(study: &AfracStudy, ga: &Ga, bumpless: bool) -> Result<GaResult, AfracStudyError> {
    let eval = |g: u32| -> Result<f64, AfracStudyError> {
        let times = [0, 1, 2, 3].map(|i| decode(g >> (6 * i)));
        let case = Case {
            label: "ga".into(),
            plant: TurningParams { depth: 5.0, ..study.plant.clone() },
            controller: Some(AfracParams {
                schedule: Schedule { times, ..Schedule::default() },
                bumpless,
                depth: 5.0,
                ..study.controller.clone()
            }),
            duration: study.duration,
        };
        let trace = run(&case)?;
        Ok(trace.iter().map(|p| p.x.abs()).sum::<f64>() / trace.len() as f64)
    };
    let r = ga.minimise(24, eval)?;
    Ok(GaResult {
        times: [0, 1, 2, 3].map(|i| decode(r.best >> (6 * i))),
        objective: r.fitness,
        generations: r.generations,
        converged: r.converged,
        evaluations: r.evaluations,
        history: r.history,
    })
}
