//! `chatter main-job`: the seed paper's nominal scenario over all controllers and noise seeds
//! (Table 5, Figures 6–7) through the FMUs in the Rust master.

use anyhow::{Context, Result};
use chatter_control::Structure;
use clap::Args;
use fmi_master::{Override, SystemFile};
use std::path::PathBuf;
use studies::main_job::{self, MainJobConfig};
use studies::scenario::closed_loop_system;

#[derive(Args)]
pub struct MainJobArgs {
    /// System to run (default: ClosedLoop.ssp of the FMU directory, else packaging's SSD with its FMUs).
    #[arg(long)]
    pub system: Option<PathBuf>,
    /// Output directory for CSVs, plots and the table.
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
}

pub fn main_job(a: &MainJobArgs) -> Result<()> {
    let fmu_dir = a.fmu_dir.clone().unwrap_or_else(packaging::fmu_dir);
    let sys = match &a.system {
        Some(p) => SystemFile::open(p, Some(&fmu_dir))?,
        None => closed_loop_system(&fmu_dir)?,
    };
    let mut cases = Vec::new();
    for c in &a.cases {
        let (label, item) = c.split_once('=').with_context(|| format!("--cases {c}: expected LABEL=STRUCTURE"))?;
        let structure = model_kit::parse_choice::<Structure>(item).map_err(|e| anyhow::anyhow!("--cases {c}: {e}"))?;
        cases.push((label.to_string(), structure));
    }
    if let Some(n) = a.threads {
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("configuring the thread pool")?;
    }
    let cfg = MainJobConfig {
        out: a.out.clone(),
        seeds: (a.first_seed..a.first_seed + a.seeds).collect(),
        stop: a.stop_time,
        step: a.step,
        csv_interval: a.csv_interval,
        cases,
        overrides: a.set.iter().map(|s| s.parse::<Override>()).collect::<Result<_, _>>()?,
        echo_fmu_log: a.fmu_log,
    };
    let report = main_job::run(&sys, &cfg)?;
    println!("{}", report.table_text);
    println!("wrote {}", report.written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join("\n      "));
    println!("total wall time: {:.1} s on {} threads", report.wall.as_secs_f64(), rayon::current_num_threads());
    Ok(())
}
