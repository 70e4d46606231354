//! The depth study ([`super`]) as independent cases ([`study_kit::batch_cases`]): one
//! case per controller × axial depth, so `chatter plan depth-study …`, `chatter run` and
//! `chatter collect` give the CSV and table of a local `chatter depth-study`.

use super::{CSV_HEADER, DepthRow, DepthStudy, csv_row, jobs, one, report};
use crate::batch::RowSink;
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

/// Everything that defines a depth study: the options of `chatter depth-study` and
/// `chatter plan depth-study`, and the spec a case manifest holds (without `out`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, clap::Args)]
pub struct DepthSpec {
    /// Where the FMUs are (`ClosedLoop.ssp` there, else packaging's SSD).
    #[arg(long, default_value_os_t = default_fmu_dir())]
    pub fmu_dir: PathBuf,
    /// Axial depths [mm].
    #[arg(long = "depths", value_delimiter = ',', default_value = "1,1.5,2")]
    pub depths_mm: Vec<f64>,
    /// Controller structure item names.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains.
    #[arg(long, value_enum, default_value_t = GainPreset::Tuned)]
    pub preset: GainPreset,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: i32,
    /// A short run (1.2 s; spectrum from 0.2 s, window 1.0–1.2 s) for tests.
    #[arg(long)]
    pub quick: bool,
    /// Output directory (depth_study.csv, depth_study.md); the study folder of a plan.
    #[arg(long, default_value = "results/depth_study")]
    #[serde(skip)]
    pub out: PathBuf,
}

impl DepthSpec {
    /// The spec with the FMU folder absolute (what a plan writes).
    pub fn resolved(&self) -> DepthSpec {
        DepthSpec { fmu_dir: std::path::absolute(&self.fmu_dir).unwrap_or(self.fmu_dir.clone()), ..self.clone() }
    }

    /// Run the study here (the runs in parallel) and write its report into `out`; returns the
    /// markdown.
    pub fn run_local(&self) -> Result<String> {
        let spec = self.resolved();
        let sys = closed_loop_system(&spec.fmu_dir)?;
        let s = spec.study(&roles(&sys)?, &self.out)?;
        let rows = super::run(&sys, &s)?;
        report(&s, &rows, spec.preset.name())
    }

    /// The study (controller gains named by `roles`), writing into `out`; every choice checked.
    pub fn study(&self, roles: &Roles, out: &Path) -> Result<DepthStudy> {
        if !self.depths_mm.iter().all(|d| d.is_finite() && *d >= 0.0) {
            return Err(StudyError::Invalid(format!("--depths {:?}: depths must not be negative", self.depths_mm)));
        }
        let preset = self.preset.params();
        let controllers = self
            .controllers
            .iter()
            .map(|c| {
                model_kit::parse_choice::<Structure>(c)
                    .map_err(|e| StudyError::Invalid(format!("unknown controller: {e}")))
            })
            .collect::<Result<Vec<_>>>()?;
        let mut s = DepthStudy {
            depths: self.depths_mm.iter().map(|d| d * 1e-3).collect(),
            controllers,
            seed: self.seed,
            overrides: overrides_of(&roles.controller, fmu_controller::parameter_assignments(&preset)),
            out: out.to_path_buf(),
            ..DepthStudy::default()
        };
        if self.quick {
            (s.stop, s.spectrum_from, s.window) = (1.2, 0.2, (1.0, 1.2));
        }
        Ok(s)
    }
}

/// The depth study's runs, ready to run as cases.
pub struct DepthRuns {
    spec: DepthSpec,
    sys: SystemFile,
    roles: Roles,
    study: DepthStudy,
    jobs: Vec<(Structure, f64)>,
}

/// The depth study as a [`CaseStudy`](study_kit::cases::CaseStudy).
pub type DepthCases = Batch<DepthRuns>;

/// One run: a controller at one depth.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DepthCase {
    /// Controller item name.
    pub controller: String,
    /// Index of the depth.
    pub k: usize,
    /// The depth [mm] (for readers of the manifest).
    pub depth_mm: f64,
}

impl RunBatch for DepthRuns {
    const KIND: &'static str = "depth-study";
    type Spec = DepthSpec;
    type Job = (Structure, f64);
    type Case = DepthCase;
    type Output = DepthRow;

    fn spec(&self) -> &DepthSpec {
        &self.spec
    }

    fn from_spec(spec: DepthSpec) -> Result<Self> {
        let sys = closed_loop_system(&spec.fmu_dir)?;
        let roles = roles(&sys)?;
        let study = spec.study(&roles, Path::new("."))?;
        let jobs = jobs(&study)?;
        Ok(DepthRuns { spec, sys, roles, study, jobs })
    }

    fn jobs(&self) -> &[(Structure, f64)] {
        &self.jobs
    }

    fn case_of(&self, &(c, d): &(Structure, f64)) -> (String, DepthCase) {
        let k = self.study.depths.iter().position(|x| x.to_bits() == d.to_bits()).unwrap_or(usize::MAX);
        let case = DepthCase { controller: c.name().to_string(), k, depth_mm: d * 1e3 };
        (format!("{}-d{k:02}", case.controller), case)
    }

    fn run_job(&self, &(c, d): &(Structure, f64)) -> Result<DepthRow> {
        one(&self.sys, &self.roles, &self.study, c, d)
    }

    fn describe(&self, _: &(Structure, f64), r: &DepthRow) -> String {
        format!("{} mm: window RMS {:.3} µm", r.depth * 1e3, r.window_rms * 1e6)
    }

    fn report(&self, dir: &Path, runs: &[(&(Structure, f64), &DepthRow)]) -> Result<Collected> {
        let study = DepthStudy { out: dir.to_path_buf(), ..self.study.clone() };
        let rows: Vec<DepthRow> = runs.iter().map(|(_, r)| **r).collect();
        let csv = RowSink::create(&dir.join("depth_study.csv"), CSV_HEADER)?;
        for r in &rows {
            csv.row(&csv_row(r))?;
        }
        csv.complete()?;
        let md = report(&study, &rows, self.spec.preset.name())?;
        Ok(Collected { text: md, written: vec![csv.path().to_path_buf(), dir.join("depth_study.md")] })
    }
}
