//! PSO tuning ([`crate::tuning`]) as independent cases ([`study_kit::batch_cases`]): one case per
//! structure × independent PSO run, with the run's seed (first seed + run index, exactly as
//! `chatter tune`), so `chatter plan tune …`, `chatter run` and `chatter collect` write the same
//! `table_a1.md` and `tuned_<structure>.json` as a local `chatter tune`, and `tuning_runs.csv`
//! with the same numbers (its last column is each run's own wall time).
//!
//! The files are written by the functions here for both ([`csv_line`], [`json_run`],
//! [`table_row`]).

use crate::tuning::{self, TuningProblem, TuningRun, mean_std};
use chatter_control::Structure;
use milling_plant::PlantParams;
use model_kit::Choice;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;
use study_kit::StudyError;
use study_kit::batch_cases::{Batch, RunBatch};
use study_kit::cases::Collected;
use study_kit::optim::pso::PsoConfig;

type Result<T> = std::result::Result<T, StudyError>;

/// Header of `tuning_runs.csv`.
pub const CSV_HEADER: &str = "structure,run_seed,kp,ki,kd,lambda,mu,omega_o,b0,b_min_mm,rpm_at_min,cost,saturated,peak_u_N,evaluations,seconds\n";

/// Header of `table_a1.md`.
pub const TABLE_HEADER: &str = "| controller | n_p | best J (mm) | mean J ± std (mm) | CV % | mean k_conv | best gains (kp, ki, kd, λ, μ) | b_min (mm) at rpm | peak u (N) | saturation check passed, fresh noise seeds 101..110 (margin 0) |\n|---|---|---|---|---|---|---|---|---|---|\n";

/// Everything that defines a tuning study (the `chatter tune` options).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TuneSpec {
    /// The tuning plant (with its workpiece modes).
    pub plant: PlantParams,
    /// Structure item names (`off` is skipped).
    pub structures: Vec<String>,
    /// Independent runs per structure.
    pub runs: usize,
    /// PSO seed of the first run (run r has seed + r).
    pub seed: u64,
    /// Swarm size.
    pub particles: usize,
    /// Iterations.
    pub iterations: usize,
    /// Duration of the saturation check [s].
    pub check_duration: f64,
    /// Saturation-check margin.
    pub margin: f64,
    /// Robust saturation constraint over noise seeds 1..=N (0: the seed's single check).
    pub check_seeds: u64,
    /// ADRC-FOPID: also tune ω_o and b0.
    pub adrc_observer: bool,
}

impl TuneSpec {
    /// The tuned structures (without `off`), in order.
    pub fn structures(&self) -> Result<Vec<(String, Structure)>> {
        let mut v = Vec::new();
        for name in &self.structures {
            let s = model_kit::parse_choice::<Structure>(name)
                .map_err(|e| StudyError::Invalid(format!("unknown controller: {e}")))?;
            if s != Structure::Off {
                v.push((name.clone(), s));
            }
        }
        Ok(v)
    }

    /// The tuning problem of one structure.
    pub fn problem(&self, structure: Structure) -> TuningProblem {
        let mut prob = TuningProblem::new(self.plant.clone(), structure);
        prob.check.duration = self.check_duration;
        prob.tune_observer = self.adrc_observer;
        prob.check.margin = self.margin;
        prob.check_seeds = (1..=self.check_seeds).collect();
        prob
    }

    /// The PSO settings of run `r` (0-based).
    pub fn pso(&self, r: usize) -> PsoConfig {
        PsoConfig {
            seed: self.seed + r as u64,
            particles: self.particles,
            iterations: self.iterations,
            ..Default::default()
        }
    }

    /// Check every choice.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(StudyError::Invalid(m));
        if ![1, 3].contains(&self.plant.workpiece.modes) {
            return bad(format!("--modes {}: 1 or 3", self.plant.workpiece.modes));
        }
        if !(0.0..1.0).contains(&self.margin) {
            return bad(format!("--margin {}: must be in [0, 1)", self.margin));
        }
        if self.runs == 0 || self.particles == 0 {
            return bad("--runs and --particles must be at least 1".into());
        }
        self.plant.validate().map_err(StudyError::Invalid)?;
        self.structures().map(|_| ())
    }
}

/// One row of `tuning_runs.csv` (`seconds`: the run's wall time).
pub fn csv_line(name: &str, run: &TuningRun, seconds: f64) -> String {
    let g = &run.gains;
    let get = |i: usize| g.get(i).map_or(String::new(), |v| format!("{v:e}"));
    let sat = run.breakdown.saturation;
    format!(
        "{name},{},{},{},{},{},{},{},{},{:.6},{:.3},{:.6},{},{:.4},{},{:.2}\n",
        run.seed,
        get(0),
        get(1),
        get(2),
        get(3),
        get(4),
        get(5),
        get(6),
        run.breakdown.b_min_mm,
        run.breakdown.rpm_at_min,
        run.breakdown.cost,
        sat.is_none_or(|s| s.exceeded),
        sat.map_or(f64::NAN, |s| s.peak_u),
        run.pso.evaluations,
        seconds
    )
}

/// `tuned_<structure>.json` of a run.
pub fn json_run(r: &TuningRun, structure: Structure, names: &[tuning::ParamSpec]) -> String {
    let mut s = format!("{{\n  \"structure\": \"{}\",\n  \"seed\": {},\n  \"gains\": {{", structure.name(), r.seed);
    for (i, (n, v)) in names.iter().zip(&r.gains).enumerate() {
        let _ = write!(s, "{}\"{}\": {:e}", if i == 0 { "" } else { ", " }, n.name, v);
    }
    let sat = r.breakdown.saturation;
    let _ = write!(
        s,
        "}},\n  \"b_min_mm\": {:.6},\n  \"rpm_at_min\": {:.3},\n  \"cost\": {:.6},\n  \"saturated\": {},\n  \"peak_u_N\": {:.4}\n}}\n",
        r.breakdown.b_min_mm,
        r.breakdown.rpm_at_min,
        r.breakdown.cost,
        sat.is_none_or(|s| s.exceeded),
        sat.map_or(f64::NAN, |s| s.peak_u)
    );
    s
}

/// The Table A1 row of one structure's runs and its best run (the lowest cost; the first of
/// equal ones). The best controller's saturation check is repeated with noise seeds 101..110.
pub fn table_row<'a>(name: &str, prob: &TuningProblem, runs: &'a [TuningRun]) -> Result<(String, &'a TuningRun)> {
    let costs: Vec<f64> = runs.iter().map(|r| r.breakdown.cost).collect();
    let (m, s) = mean_std(&costs);
    let best = runs
        .iter()
        .min_by(|x, y| x.breakdown.cost.total_cmp(&y.breakdown.cost))
        .ok_or_else(|| StudyError::Invalid(format!("{name}: no runs")))?;
    // iteration at which the best cost is within 5 % of the run's final value (Table A1's k_conv)
    let kconv: Vec<f64> = runs
        .iter()
        .map(|r| {
            let f = r.pso.best_cost;
            r.pso.history.iter().position(|h| (h - f).abs() <= 0.05 * f.abs()).unwrap_or(0) as f64
        })
        .collect();
    // does the best controller also pass the check with other noise realizations?
    let other_seeds = tuning::SaturationCheck { margin: 0.0, ..prob.check }
        .over_seeds(&prob.plant, &best.params, 101..111)
        .map_or(0, |s| s.passed);
    let row = format!(
        "| {name} | {} | {:.4} | {:.4} ± {:.4} | {:.3} | {:.1} | {} | {:.4} at {:.0} | {:.2} | {other_seeds}/10 |\n",
        best.gains.len(),
        best.breakdown.cost,
        m,
        s,
        100.0 * s / m.abs(),
        mean_std(&kconv).0,
        best.gains.iter().map(|v| format!("{v:.4e}")).collect::<Vec<_>>().join(", "),
        best.breakdown.b_min_mm,
        best.breakdown.rpm_at_min,
        best.breakdown.saturation.map_or(f64::NAN, |s| s.peak_u)
    );
    Ok((row, best))
}

/// The tuning study's runs, ready to run as cases.
pub struct TuneRuns {
    spec: TuneSpec,
    structures: Vec<(String, Structure)>,
    jobs: Vec<(usize, usize)>,
}

/// PSO tuning as a [`CaseStudy`](study_kit::cases::CaseStudy).
pub type TuneCases = Batch<TuneRuns>;

/// One PSO run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TuneCase {
    /// Structure item name.
    pub structure: String,
    /// Run index (0-based).
    pub run: usize,
    /// Its PSO seed.
    pub seed: u64,
}

impl RunBatch for TuneRuns {
    const KIND: &'static str = "tune";
    type Spec = TuneSpec;
    /// (structure index, run index)
    type Job = (usize, usize);
    type Case = TuneCase;
    /// The run and its wall time [s].
    type Output = (TuningRun, f64);

    fn spec(&self) -> &TuneSpec {
        &self.spec
    }

    fn from_spec(spec: TuneSpec) -> Result<Self> {
        spec.validate()?;
        let structures = spec.structures()?;
        let jobs = (0..structures.len()).flat_map(|s| (0..spec.runs).map(move |r| (s, r))).collect();
        Ok(TuneRuns { spec, structures, jobs })
    }

    fn jobs(&self) -> &[(usize, usize)] {
        &self.jobs
    }

    fn case_of(&self, &(s, r): &(usize, usize)) -> (String, TuneCase) {
        let c = TuneCase { structure: self.structures[s].0.clone(), run: r, seed: self.spec.pso(r).seed };
        (format!("{}-r{r:02}-s{}", c.structure, c.seed), c)
    }

    fn run_job(&self, &(s, r): &(usize, usize)) -> Result<(TuningRun, f64)> {
        let t = std::time::Instant::now();
        let run = self.spec.problem(self.structures[s].1).run(&self.spec.pso(r), |_, _| {});
        Ok((run, t.elapsed().as_secs_f64()))
    }

    fn describe(&self, _: &(usize, usize), (run, secs): &(TuningRun, f64)) -> String {
        format!(
            "J = {:.4} mm, b_min = {:.4} mm at {:.0} rpm, {secs:.1} s",
            run.breakdown.cost, run.breakdown.b_min_mm, run.breakdown.rpm_at_min
        )
    }

    fn report(&self, dir: &Path, runs: &[(&(usize, usize), &(TuningRun, f64))]) -> Result<Collected> {
        std::fs::create_dir_all(dir).map_err(|e| StudyError::io(dir, e))?;
        let (mut csv, mut table, mut written) = (String::from(CSV_HEADER), String::from(TABLE_HEADER), Vec::new());
        for (k, (name, structure)) in self.structures.iter().enumerate() {
            let mine: Vec<&(TuningRun, f64)> = runs.iter().filter(|(j, _)| j.0 == k).map(|(_, o)| *o).collect();
            for (run, secs) in &mine {
                csv.push_str(&csv_line(name, run, *secs));
            }
            let prob = self.spec.problem(*structure);
            let tuned: Vec<TuningRun> = mine.iter().map(|(r, _)| r.clone()).collect();
            let (row, best) = table_row(name, &prob, &tuned)?;
            table.push_str(&row);
            let path = dir.join(format!("tuned_{name}.json"));
            std::fs::write(&path, json_run(best, *structure, &prob.space())).map_err(|e| StudyError::io(&path, e))?;
            written.push(path);
        }
        for (f, text) in [("tuning_runs.csv", &csv), ("table_a1.md", &table)] {
            let path = dir.join(f);
            std::fs::write(&path, text).map_err(|e| StudyError::io(&path, e))?;
            written.push(path);
        }
        Ok(Collected {
            text: format!("\nTable A1 style (J = −min b_crit over 1000..3000 rpm step 50 + penalty):\n{table}"),
            written,
        })
    }
}
