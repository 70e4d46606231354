//! `chatter robustness`: seed 000 Table 7 and Figures 11–13 through the FMUs.

use anyhow::Result;
use clap::Args;
use seed000::robustness::write_report;
use seed000::robustness_cases::RobustnessSpec;
use seed000::scenario::{closed_loop_system, roles};
use std::path::PathBuf;

#[derive(Args)]
pub struct RobustnessArgs {
    /// Controllers.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains: `tuned` (the shipped defaults) or `table2` (the paper's Table 2).
    #[arg(long, default_value = "tuned")]
    pub preset: String,
    /// Noise seeds of every point (two: the 38-run reading of the seed's sample).
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    pub seeds: Vec<i32>,
    /// Run length [s]; the RMS is over (1 s, stop].
    #[arg(long, default_value_t = 30.0)]
    pub stop_time: f64,
    /// Groups of the sample to run: plant, disturbance, speed.
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
    pub quick: bool,
    /// Output directory (robustness.csv, robustness.md, robustness.png).
    #[arg(long, default_value = "results/robustness")]
    pub out: PathBuf,
}

impl RobustnessArgs {
    /// The study's spec (what `chatter plan robustness` writes into the manifest).
    pub fn spec(&self) -> RobustnessSpec {
        let mut seeds = self.seeds.clone();
        if self.quick {
            seeds.truncate(1);
        }
        RobustnessSpec {
            fmu_dir: std::path::absolute(packaging::fmu_dir()).unwrap_or_else(|_| packaging::fmu_dir()),
            controllers: self.controllers.clone(),
            preset: self.preset.clone(),
            seeds,
            stop_time: if self.quick { 2.0 } else { self.stop_time },
            groups: self.groups.clone(),
            speeds: self.speeds.clone(),
            quiet: self.quiet,
        }
    }
}

pub fn robustness(a: &RobustnessArgs) -> Result<()> {
    let spec = a.spec();
    let sys = closed_loop_system(&spec.fmu_dir)?;
    let s = spec.study(&roles(&sys)?, &a.out)?;
    let began = std::time::Instant::now();
    let rows = seed000::robustness::run(&sys, &s)?;
    let title = format!("{} — {:.0} s wall", spec.title(&s), began.elapsed().as_secs_f64());
    let (md, _) = write_report(&sys, &s, &rows, &title)?;
    println!("{md}");
    println!("wrote {} (and robustness.csv, robustness.png)", a.out.join("robustness.md").display());
    Ok(())
}
