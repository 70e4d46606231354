//! The robustness sample ([`super`]) as independent cases ([`study_kit::cases`]): one
//! case per controller × point × noise seed, so `chatter plan robustness …`, `chatter run`
//! (shards, Slurm array tasks, Dask) and `chatter collect` give the tables and figure of a local
//! `chatter robustness` run. The spec holds the command's choices (not the resolved runs), so a
//! machine that reads the manifest rebuilds exactly the same runs from its own copy of the system.

use super::{CSV_HEADER, Group, Point, Robustness, Run, csv_row, runs, sample_with, write_report};
use crate::batch::{Metrics, RowSink, Windows, run_one};
use crate::scenario::{GainPreset, Roles, closed_loop_system, default_fmu_dir, roles};
use chatter_control::Structure;
use fmi_master::SystemFile;
use model_kit::Choice;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use study_kit::StudyError;
use study_kit::batch_cases::{Batch, RunBatch};
use study_kit::cases::Collected;
use study_kit::fmu_params::overrides_of;

type Result<T> = std::result::Result<T, StudyError>;

/// Everything that defines a robustness study: the options of `chatter robustness` and
/// `chatter plan robustness`, and the spec a case manifest holds (without `quick` and `out`,
/// which [`RobustnessSpec::resolved`] has applied).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, clap::Args)]
pub struct RobustnessSpec {
    /// Where the FMUs are (`ClosedLoop.ssp` there, else packaging's SSD).
    #[arg(long, default_value_os_t = default_fmu_dir())]
    pub fmu_dir: PathBuf,
    /// Controller structure item names (`off`, `pid`, `fopid`, `adrc_fopid`).
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains.
    #[arg(long, value_enum, default_value_t = GainPreset::Tuned)]
    pub preset: GainPreset,
    /// Noise seeds of every point (two: the 38-run reading of the seed's sample).
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    pub seeds: Vec<i32>,
    /// Run length [s]; the RMS is over (1 s, stop].
    #[arg(long, default_value_t = 30.0)]
    pub stop_time: f64,
    /// Groups of the sample to run: `plant`, `disturbance`, `speed`.
    #[arg(long, value_delimiter = ',', default_value = "plant,disturbance,speed")]
    pub groups: Vec<String>,
    /// Speeds of the k −15 % sweep [rpm].
    #[arg(long, value_delimiter = ',', default_value = "1000,1450,1900,2350,2800")]
    pub speeds: Vec<f64>,
    /// Noise and drift off at every point (the forced response alone).
    #[arg(long)]
    pub quiet: bool,
    /// A short run for tests: 2 s per run (RMS over 1–2 s), noise seed 1 only.
    #[arg(long)]
    #[serde(skip)]
    pub quick: bool,
    /// Output directory (robustness.csv, robustness.md, robustness.png); the study folder of a plan.
    #[arg(long, default_value = "results/robustness")]
    #[serde(skip)]
    pub out: PathBuf,
}

impl RobustnessSpec {
    /// The spec with `--quick` applied and the FMU folder absolute (what a plan writes).
    pub fn resolved(&self) -> RobustnessSpec {
        let mut s = self.clone();
        if s.quick {
            s.seeds.truncate(1);
            s.stop_time = 2.0;
            s.quick = false;
        }
        s.fmu_dir = std::path::absolute(&s.fmu_dir).unwrap_or(s.fmu_dir);
        s
    }

    /// Run the study here (the runs in parallel) and write its report into `out`; returns the
    /// markdown.
    pub fn run_local(&self) -> Result<String> {
        let spec = self.resolved();
        let sys = closed_loop_system(&spec.fmu_dir)?;
        let s = spec.study(&roles(&sys)?, &self.out)?;
        let began = std::time::Instant::now();
        let rows = super::run(&sys, &s)?;
        let title = format!("{} — {:.0} s wall", spec.title(&s), began.elapsed().as_secs_f64());
        Ok(write_report(&sys, &s, &rows, &title)?.0)
    }

    /// The study (controller gains named by `roles`), writing into `out`; every choice checked.
    pub fn study(&self, roles: &Roles, out: &Path) -> Result<Robustness> {
        let bad = |m: String| StudyError::Invalid(m);
        if self.seeds.is_empty() || self.seeds.iter().any(|s| *s < 0) {
            return Err(bad(format!("seeds {:?}: give seeds ≥ 0", self.seeds)));
        }
        if !(self.stop_time.is_finite() && self.stop_time > 1.0) {
            return Err(bad(format!("stop time {}: must be above 1 s", self.stop_time)));
        }
        if self.speeds.is_empty() || !self.speeds.iter().all(|r| r.is_finite() && *r > 0.0) {
            return Err(bad(format!("speeds {:?}: give positive speeds", self.speeds)));
        }
        let preset = self.preset.params();
        let controllers = self
            .controllers
            .iter()
            .map(|c| model_kit::parse_choice::<Structure>(c).map_err(|e| bad(format!("unknown controller: {e}"))))
            .collect::<Result<Vec<_>>>()?;
        let groups = self
            .groups
            .iter()
            .map(|g| match g.as_str() {
                "plant" => Ok(Group::Plant),
                "disturbance" => Ok(Group::Disturbance),
                "speed" => Ok(Group::Speed),
                _ => Err(bad(format!("group {g}: expected plant, disturbance or speed"))),
            })
            .collect::<Result<Vec<_>>>()?;
        let points: Vec<Point> = sample_with(&self.speeds)
            .into_iter()
            .filter(|p| groups.contains(&p.group))
            .map(|p| Point { quiet: self.quiet, ..p })
            .collect();
        Ok(Robustness {
            controllers,
            points,
            seeds: self.seeds.clone(),
            windows: Windows::rms(self.stop_time, 1.0),
            gains: overrides_of(&roles.controller, fmu_controller::parameter_assignments(&preset)),
            out: out.to_path_buf(),
        })
    }

    /// The report's title (no timing: collected results are reproducible).
    pub fn title(&self, s: &Robustness) -> String {
        format!(
            "Robustness sample (seed 000 Table 7; {} gains; {} points{} × seeds {:?}; {} s runs, RMS over (1, {}] s)",
            self.preset,
            s.points.len(),
            if self.quiet { ", noise and drift OFF" } else { "" },
            s.seeds,
            s.windows.stop,
            s.windows.stop,
        )
    }
}

/// The robustness study's runs, ready to run as cases.
pub struct RobustnessRuns {
    spec: RobustnessSpec,
    sys: SystemFile,
    roles: Roles,
    study: Robustness,
    runs: Vec<Run>,
}

/// The robustness sample as a [`CaseStudy`](study_kit::cases::CaseStudy).
pub type RobustnessCases = Batch<RobustnessRuns>;

/// One case: a controller at a point with a noise seed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobustnessCase {
    /// Controller item name.
    pub controller: String,
    /// Index of the point in the sample.
    pub point: usize,
    /// The point's name (for readers of the manifest).
    pub point_name: String,
    /// Noise seed.
    pub seed: i32,
}

impl RunBatch for RobustnessRuns {
    const KIND: &'static str = "robustness";
    type Spec = RobustnessSpec;
    type Job = Run;
    type Case = RobustnessCase;
    type Output = Metrics;

    fn spec(&self) -> &RobustnessSpec {
        &self.spec
    }

    fn from_spec(spec: RobustnessSpec) -> Result<Self> {
        let sys = closed_loop_system(&spec.fmu_dir)?;
        let roles = roles(&sys)?;
        // the output folder is the study folder given to collect; the study itself never writes
        let study = spec.study(&roles, Path::new("."))?;
        let runs = runs(&sys, &study)?;
        Ok(RobustnessRuns { spec, sys, roles, study, runs })
    }

    fn jobs(&self) -> &[Run] {
        &self.runs
    }

    fn case_of(&self, r: &Run) -> (String, RobustnessCase) {
        let c = RobustnessCase {
            controller: r.controller.name().to_string(),
            point: r.point,
            point_name: self.study.points[r.point].name.clone(),
            seed: r.seed,
        };
        (format!("{}-p{:02}-s{}", c.controller, c.point, c.seed), c)
    }

    fn run_job(&self, run: &Run) -> Result<Metrics> {
        run_one(&self.sys, &self.roles, run.overrides.clone(), &self.study.windows)
    }

    fn describe(&self, r: &Run, m: &Metrics) -> String {
        format!("{} at {}: RMS {:.3} µm", r.controller.name(), self.study.points[r.point].name, m.rms * 1e6)
    }

    fn report(&self, dir: &Path, runs: &[(&Run, &Metrics)]) -> Result<Collected> {
        let study = Robustness { out: dir.to_path_buf(), ..self.study.clone() };
        let rows: Vec<(Run, Metrics)> = runs.iter().map(|(r, m)| ((*r).clone(), **m)).collect();
        let csv = RowSink::create(&dir.join("robustness.csv"), CSV_HEADER)?;
        for (r, m) in &rows {
            csv.row(&csv_row(&study, r, m))?;
        }
        csv.complete()?;
        let (md, mut written) = write_report(&self.sys, &study, &rows, &self.spec.title(&study))?;
        written.insert(0, csv.path().to_path_buf());
        Ok(Collected { text: md, written })
    }
}
