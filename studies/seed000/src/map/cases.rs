//! The speed × depth map ([`super`]) as independent cases ([`study_kit::cases`]): one case
//! per controller × speed × depth, so `chatter plan map …`, `chatter run` (shards, Slurm array
//! tasks, Dask) and `chatter collect` give the tables and heat maps of a local `chatter map`.

use super::{CSV_HEADER, Cell, MapJob, MapStudy, csv_row, jobs, seed_grid, write_report};
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

/// Everything that defines a map: the options of `chatter map` and `chatter plan map`, and the
/// spec a case manifest holds (without `quick` and `out`, which [`MapSpec::resolved`] has
/// applied).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, clap::Args)]
pub struct MapSpec {
    /// Where the FMUs are (`ClosedLoop.ssp` there, else packaging's SSD).
    #[arg(long, default_value_os_t = default_fmu_dir())]
    pub fmu_dir: PathBuf,
    /// Axial depths [mm] (rows; default: the seed's 0.5:0.25:2.5).
    #[arg(long = "depths", value_delimiter = ',')]
    pub depths_mm: Vec<f64>,
    /// Speed grid `lo,hi,step` [rpm].
    #[arg(long, value_delimiter = ',', default_value = "1000,2800,200")]
    pub rpm: Vec<f64>,
    /// Controller structure item names.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains.
    #[arg(long, value_enum, default_value_t = GainPreset::Tuned)]
    pub preset: GainPreset,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: i32,
    /// Run length per cell [s] (the seed: 5); RMS over (1 s, stop], growth = last second / first.
    #[arg(long, default_value_t = 5.0)]
    pub stop_time: f64,
    /// Noise and drift off (the growth check against the lobes).
    #[arg(long)]
    pub quiet: bool,
    /// A short run for tests: 2 s per cell.
    #[arg(long)]
    #[serde(skip)]
    pub quick: bool,
    /// Output directory (map.csv, map.md, map.png); the study folder of a plan.
    #[arg(long, default_value = "results/map")]
    #[serde(skip)]
    pub out: PathBuf,
}

impl MapSpec {
    /// The spec with the defaults and `--quick` applied and the FMU folder absolute (what a plan
    /// writes).
    pub fn resolved(&self) -> MapSpec {
        let mut s = self.clone();
        if s.depths_mm.is_empty() {
            s.depths_mm = seed_grid().0.iter().map(|d| d * 1e3).collect();
        }
        if s.quick {
            s.stop_time = 2.0;
            s.quick = false;
        }
        s.fmu_dir = std::path::absolute(&s.fmu_dir).unwrap_or(s.fmu_dir);
        s
    }

    /// Run the map here (the cells in parallel) and write its report into `out`; returns the
    /// markdown.
    pub fn run_local(&self) -> Result<String> {
        let spec = self.resolved();
        let sys = closed_loop_system(&spec.fmu_dir)?;
        let s = spec.study(&roles(&sys)?, &self.out)?;
        let began = std::time::Instant::now();
        let cells = super::run(&sys, &s)?;
        let title = format!("{} — {:.0} s wall", spec.title(&s), began.elapsed().as_secs_f64());
        Ok(write_report(&s, &cells, &title)?.0)
    }

    /// The map (controller gains named by `roles`), writing into `out`; every choice checked.
    pub fn study(&self, roles: &Roles, out: &Path) -> Result<MapStudy> {
        let bad = |m: String| StudyError::Invalid(m);
        if self.depths_mm.is_empty() || !self.depths_mm.iter().all(|d| d.is_finite() && *d > 0.0) {
            return Err(bad(format!("depths {:?} mm: depths must be positive", self.depths_mm)));
        }
        let r = &self.rpm;
        if !(r.len() == 3 && r.iter().all(|x| x.is_finite() && *x > 0.0) && r[0] <= r[1]) {
            return Err(bad(format!("rpm {r:?}: give lo,hi,step with 0 < lo ≤ hi and step > 0 (empty speed range)")));
        }
        if !(self.stop_time.is_finite() && self.stop_time >= 2.0) {
            return Err(bad(format!("stop time {}: must be at least 2 s", self.stop_time)));
        }
        let rpm: Vec<f64> = (0..).map(|k| r[0] + r[2] * f64::from(k)).take_while(|x| *x <= r[1] + 1e-9).collect();
        let preset = self.preset.params();
        let controllers = self
            .controllers
            .iter()
            .map(|c| model_kit::parse_choice::<Structure>(c).map_err(|e| bad(format!("unknown controller: {e}"))))
            .collect::<Result<Vec<_>>>()?;
        Ok(MapStudy {
            depths: self.depths_mm.iter().map(|d| d * 1e-3).collect(),
            rpm,
            controllers,
            seed: self.seed,
            windows: Windows::rms(self.stop_time, 1.0),
            quiet: self.quiet,
            gains: overrides_of(&roles.controller, fmu_controller::parameter_assignments(&preset)),
            out: out.to_path_buf(),
        })
    }

    /// The report's title (no timing: collected results are reproducible).
    pub fn title(&self, s: &MapStudy) -> String {
        let stop = s.windows.stop;
        format!(
            "Speed × depth map (seed 000 Figure 16; {} gains; noise seed {}{}; {} cells per controller; {stop} s per cell, RMS over (1, {stop}] s)",
            self.preset,
            self.seed,
            if self.quiet { ", noise and drift OFF" } else { ", noise and drift on" },
            s.depths.len() * s.rpm.len(),
        )
    }
}

/// The map's runs, ready to run as cases.
pub struct MapRuns {
    spec: MapSpec,
    sys: SystemFile,
    roles: Roles,
    study: MapStudy,
    jobs: Vec<MapJob>,
}

/// The map as a [`CaseStudy`](study_kit::cases::CaseStudy).
pub type MapCases = Batch<MapRuns>;

/// One cell of one controller.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapCase {
    /// Controller item name.
    pub controller: String,
    /// Depth index (row).
    pub i: usize,
    /// Speed index (column).
    pub j: usize,
    /// The depth [mm] and speed [rpm] (for readers of the manifest).
    pub at: (f64, f64),
}

impl RunBatch for MapRuns {
    const KIND: &'static str = "map";
    type Spec = MapSpec;
    type Job = MapJob;
    type Case = MapCase;
    type Output = Metrics;

    fn spec(&self) -> &MapSpec {
        &self.spec
    }

    fn from_spec(spec: MapSpec) -> Result<Self> {
        let sys = closed_loop_system(&spec.fmu_dir)?;
        let roles = roles(&sys)?;
        let study = spec.study(&roles, Path::new("."))?;
        let jobs = jobs(&sys, &study)?;
        Ok(MapRuns { spec, sys, roles, study, jobs })
    }

    fn jobs(&self) -> &[MapJob] {
        &self.jobs
    }

    fn case_of(&self, x: &MapJob) -> (String, MapCase) {
        let c = MapCase {
            controller: x.controller.name().to_string(),
            i: x.i,
            j: x.j,
            at: (self.study.depths[x.i] * 1e3, self.study.rpm[x.j]),
        };
        (format!("{}-d{:02}-n{:02}", c.controller, c.i, c.j), c)
    }

    fn run_job(&self, job: &MapJob) -> Result<Metrics> {
        run_one(&self.sys, &self.roles, job.overrides.clone(), &self.study.windows)
    }

    fn describe(&self, x: &MapJob, m: &Metrics) -> String {
        format!("{} mm, {} rpm: RMS {:.3} µm", self.study.depths[x.i] * 1e3, self.study.rpm[x.j], m.rms * 1e6)
    }

    fn report(&self, dir: &Path, runs: &[(&MapJob, &Metrics)]) -> Result<Collected> {
        let study = MapStudy { out: dir.to_path_buf(), ..self.study.clone() };
        let cells: Vec<Cell> = runs
            .iter()
            .map(|(x, m)| Cell { controller: x.controller, i: x.i, j: x.j, metrics: **m, b_lim: x.b_lim })
            .collect();
        let csv = RowSink::create(&dir.join("map.csv"), CSV_HEADER)?;
        for c in &cells {
            csv.row(&csv_row(&study, c))?;
        }
        csv.complete()?;
        let (md, mut written) = write_report(&study, &cells, &self.spec.title(&study))?;
        written.insert(0, csv.path().to_path_buf());
        Ok(Collected { text: md, written })
    }
}
