//! `chatter main-job`: the seed paper's nominal scenario over all controllers and noise seeds
//! (Table 5, Figures 6–7) through the FMUs in the Rust master.

use anyhow::{Context, Result};
use chatter_control::Structure;
use clap::Args;
use fmi_master::Override;
use seed000::main_job::{self, MainJob, MainJobSpec};
use std::path::PathBuf;

#[derive(Args)]
pub struct MainJobArgs {
    /// System to run (default: ClosedLoop.ssp of the FMU directory, else packaging's SSD with its FMUs).
    #[arg(long)]
    pub system: Option<PathBuf>,
    /// Output directory for CSVs, plots and the table (and the study's manifest and case results).
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Number of noise seeds per controller.
    #[arg(long, default_value_t = 10)]
    pub seeds: u32,
    /// First seed.
    #[arg(long, default_value_t = 1)]
    pub first_seed: u32,
    /// Stop time [s] (default: the system's, 30 s).
    #[arg(long)]
    pub stop_time: Option<f64>,
    /// Communication step [s] (default: the system's, 10 µs).
    #[arg(long)]
    pub step: Option<f64>,
    /// Output interval of the per-run CSV files [s].
    #[arg(long, default_value_t = 1e-3)]
    pub csv_interval: f64,
    /// Controller structures to compare, as label=structure (off, pid, fopid, adrc_fopid).
    #[arg(long, value_delimiter = ',', default_value = "Open loop=off,PID=pid,FOPID=fopid,ADRC-FOPID=adrc_fopid")]
    pub cases: Vec<String>,
    /// Extra overrides applied to every run (component.variable=value).
    #[arg(long = "set")]
    pub set: Vec<String>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Directory with MillingPlant.fmu, ChatterController.fmu and ClosedLoop.ssp (default: $FMU_DIR, else target/fmu).
    #[arg(long)]
    pub fmu_dir: Option<PathBuf>,
    /// Print the FMUs' log messages as they arrive.
    #[arg(long)]
    pub fmu_log: bool,
    /// Forget the results of an earlier run in OUT (its manifest and case results) and run
    /// every case again; without it, a re-run with the same settings completes only what is
    /// missing, and other settings are refused.
    #[arg(long)]
    pub fresh: bool,
}

impl MainJobArgs {
    /// The job's spec (absolute paths, so that workers in other folders read the same files).
    pub fn spec(&self) -> Result<MainJobSpec> {
        let absolute = |p: &PathBuf| std::path::absolute(p).with_context(|| format!("{}", p.display()));
        let fmu_dir = absolute(&self.fmu_dir.clone().unwrap_or_else(packaging::fmu_dir))?;
        let system = self.system.as_ref().map(absolute).transpose()?;
        let mut cases = Vec::new();
        for c in &self.cases {
            let (label, item) = c.split_once('=').with_context(|| format!("--cases {c}: expected LABEL=STRUCTURE"))?;
            model_kit::parse_choice::<Structure>(item).map_err(|e| anyhow::anyhow!("--cases {c}: {e}"))?;
            cases.push((label.to_string(), item.to_string()));
        }
        for o in &self.set {
            o.parse::<Override>().with_context(|| format!("--set {o}"))?;
        }
        Ok(MainJobSpec {
            system,
            fmu_dir,
            seeds: (self.first_seed..self.first_seed + self.seeds).collect(),
            stop: self.stop_time,
            step: self.step,
            csv_interval: self.csv_interval,
            cases,
            overrides: self.set.clone(),
        })
    }
}

pub fn main_job(a: &MainJobArgs) -> Result<()> {
    if let Some(n) = a.threads {
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("configuring the thread pool")?;
    }
    if a.fresh {
        study_kit::cases::forget_results(&a.out)?;
    }
    let mut job = MainJob::new(a.spec()?)?;
    job.echo_fmu_log = a.fmu_log;
    let report = main_job::run(&job, &a.out)?;
    println!("{}", report.table_text);
    println!("{}", report.timing);
    println!("wrote {}", report.written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join("\n      "));
    println!("total wall time: {:.1} s on {} threads", report.wall.as_secs_f64(), rayon::current_num_threads());
    Ok(())
}
