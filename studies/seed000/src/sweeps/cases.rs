//! The feed and engagement sweeps ([`super`]) as independent cases
//! ([`study_kit::batch_cases`]): one case per controller × swept value, so `chatter plan sweep …`,
//! `chatter run` and `chatter collect` give the CSV, table and figure of a local `chatter sweep`.

use super::{
    ENGAGEMENTS_MM, FEEDS_MM, Kind, Sweep, SweepJob, SweepOutput, csv_header, csv_row, jobs, mm, report, row, run_job,
};
use crate::batch::{RowSink, Windows};
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

/// Everything that defines a sweep: the options of `chatter sweep` and `chatter plan sweep`,
/// and the spec a case manifest holds (without `quick` and `out`, which
/// [`SweepSpec::resolved`] has applied).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, clap::Args)]
pub struct SweepSpec {
    /// Where the FMUs are (`ClosedLoop.ssp` there, else packaging's SSD).
    #[arg(long, default_value_os_t = default_fmu_dir())]
    pub fmu_dir: PathBuf,
    /// What to sweep: `feed` (f_z) or `engagement` (a_e, up-milling).
    pub kind: String,
    /// Values [mm] (default: the seed's feeds 0.025–0.12 mm or engagements 4–14 mm).
    #[arg(long = "values", value_delimiter = ',')]
    pub values_mm: Vec<f64>,
    /// Controller structure item names.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains.
    #[arg(long, value_enum, default_value_t = GainPreset::Tuned)]
    pub preset: GainPreset,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: i32,
    /// Run length [s]; the RMS is over (1 s, stop].
    #[arg(long, default_value_t = 10.0)]
    pub stop_time: f64,
    /// Noise and drift off (the harmonic-balance check).
    #[arg(long)]
    pub quiet: bool,
    /// A short run for tests: 2 s per run, RMS over 1–2 s.
    #[arg(long)]
    #[serde(skip)]
    pub quick: bool,
    /// Output directory (sweep_<kind>.csv, .md, .png); the study folder of a plan.
    #[arg(long, default_value = "results/sweeps")]
    #[serde(skip)]
    pub out: PathBuf,
}

impl SweepSpec {
    /// The spec with the seed's values for its kind, `--quick` applied and the FMU folder
    /// absolute (what a plan writes); every choice checked.
    pub fn resolved(&self) -> Result<SweepSpec> {
        let mut s = self.clone();
        let defaults = match s.kind.as_str() {
            "feed" => &FEEDS_MM[..],
            "engagement" => &ENGAGEMENTS_MM[..],
            k => return Err(StudyError::Invalid(format!("sweep {k}: expected feed or engagement"))),
        };
        if !(s.stop_time.is_finite() && s.stop_time > 1.0) {
            return Err(StudyError::Invalid(format!("--stop-time {}: must be above 1 s", s.stop_time)));
        }
        if s.values_mm.is_empty() {
            s.values_mm = defaults.to_vec();
        }
        if s.quick {
            s.stop_time = 2.0;
            s.quick = false;
        }
        s.fmu_dir = std::path::absolute(&s.fmu_dir).unwrap_or(s.fmu_dir);
        Ok(s)
    }

    /// Run the sweep here (the runs in parallel) and write its report into `out`; returns the
    /// markdown.
    pub fn run_local(&self) -> Result<String> {
        let spec = self.resolved()?;
        let sys = closed_loop_system(&spec.fmu_dir)?;
        let s = spec.study(&roles(&sys)?, &self.out)?;
        let began = std::time::Instant::now();
        let rows = super::run(&sys, &s)?;
        report(&s, &rows, spec.preset.name(), Some(began.elapsed().as_secs_f64()))
    }

    /// The sweep (controller gains named by `roles`), writing into `out`; every choice checked.
    pub fn study(&self, roles: &Roles, out: &Path) -> Result<Sweep> {
        let bad = |m: String| StudyError::Invalid(m);
        let kind = match self.kind.as_str() {
            "feed" => Kind::Feed,
            "engagement" => Kind::Engagement,
            k => return Err(bad(format!("sweep {k}: expected feed or engagement"))),
        };
        if self.values_mm.is_empty() || !self.values_mm.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err(bad(format!("--values {:?}: give positive values in mm", self.values_mm)));
        }
        if !(self.stop_time.is_finite() && self.stop_time > 1.0) {
            return Err(bad(format!("--stop-time {}: must be above 1 s", self.stop_time)));
        }
        let preset = self.preset.params();
        let controllers = self
            .controllers
            .iter()
            .map(|c| model_kit::parse_choice::<Structure>(c).map_err(|e| bad(format!("unknown controller: {e}"))))
            .collect::<Result<Vec<_>>>()?;
        Ok(Sweep {
            kind,
            values: self.values_mm.iter().map(|v| v * 1e-3).collect(),
            controllers,
            seed: self.seed,
            windows: Windows::rms(self.stop_time, 1.0),
            quiet: self.quiet,
            gains: overrides_of(&roles.controller, fmu_controller::parameter_assignments(&preset)),
            out: out.to_path_buf(),
        })
    }
}

/// A sweep's runs, ready to run as cases.
pub struct SweepRuns {
    spec: SweepSpec,
    sys: SystemFile,
    roles: Roles,
    sweep: Sweep,
    jobs: Vec<SweepJob>,
}

/// A sweep as a [`CaseStudy`](study_kit::cases::CaseStudy).
pub type SweepCases = Batch<SweepRuns>;

/// One run: a controller at one swept value.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepCase {
    /// Controller item name.
    pub controller: String,
    /// Index of the value.
    pub k: usize,
    /// The value [mm] (for readers of the manifest).
    pub value_mm: f64,
}

impl RunBatch for SweepRuns {
    const KIND: &'static str = "sweep";
    type Spec = SweepSpec;
    type Job = SweepJob;
    type Case = SweepCase;
    type Output = SweepOutput;

    fn spec(&self) -> &SweepSpec {
        &self.spec
    }

    fn from_spec(spec: SweepSpec) -> Result<Self> {
        let sys = closed_loop_system(&spec.fmu_dir)?;
        let roles = roles(&sys)?;
        let sweep = spec.study(&roles, Path::new("."))?;
        let jobs = jobs(&sys, &sweep)?;
        Ok(SweepRuns { spec, sys, roles, sweep, jobs })
    }

    fn jobs(&self) -> &[SweepJob] {
        &self.jobs
    }

    fn case_of(&self, j: &SweepJob) -> (String, SweepCase) {
        let k = self.sweep.values.iter().position(|v| v.to_bits() == j.value.to_bits()).unwrap_or(usize::MAX);
        let c = SweepCase { controller: j.controller.name().to_string(), k, value_mm: mm(j.value) };
        (format!("{}-{}-v{k:02}", c.controller, self.sweep.kind.name()), c)
    }

    fn run_job(&self, j: &SweepJob) -> Result<SweepOutput> {
        run_job(&self.sys, &self.roles, &self.sweep, j)
    }

    fn describe(&self, j: &SweepJob, o: &SweepOutput) -> String {
        format!("{} mm: RMS {:.3} µm", mm(j.value), o.0.rms * 1e6)
    }

    fn report(&self, dir: &Path, runs: &[(&SweepJob, &SweepOutput)]) -> Result<Collected> {
        let sweep = Sweep { out: dir.to_path_buf(), ..self.sweep.clone() };
        let rows: Vec<_> = runs.iter().map(|(j, o)| row(j, o)).collect();
        let name = sweep.kind.name();
        let csv = RowSink::create(&dir.join(format!("sweep_{name}.csv")), &csv_header(sweep.kind))?;
        for r in &rows {
            csv.row(&csv_row(r))?;
        }
        csv.complete()?;
        let md = report(&sweep, &rows, self.spec.preset.name(), None)?;
        let written = ["csv", "md", "png"].iter().map(|e| dir.join(format!("sweep_{name}.{e}"))).collect();
        Ok(Collected { text: md, written })
    }
}
