//! `chatter sweep feed|engagement`: seed 000 Section 5.6.5 (Figure 15) through the FMUs.

use anyhow::{Result, bail, ensure};
use clap::Args;
use seed000::scenario::{closed_loop_system, roles};
use seed000::sweep_cases::SweepSpec;
use seed000::sweeps::{ENGAGEMENTS_MM, FEEDS_MM};
use std::path::PathBuf;

#[derive(Args)]
pub struct SweepArgs {
    /// What to sweep: `feed` (f_z) or `engagement` (a_e, up-milling).
    pub kind: String,
    /// Values [mm] (default: the seed's feeds 0.025–0.12 mm or engagements 4–14 mm).
    #[arg(long, value_delimiter = ',')]
    pub values: Option<Vec<f64>>,
    /// Controllers.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains: `tuned` (the shipped defaults) or `table2` (the paper's Table 2).
    #[arg(long, default_value = "tuned")]
    pub preset: String,
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
    pub quick: bool,
    /// Output directory (sweep_<kind>.csv, .md, .png).
    #[arg(long, default_value = "results/sweeps")]
    pub out: PathBuf,
}

impl SweepArgs {
    /// The study's spec (what `chatter plan sweep` writes into the manifest).
    pub fn spec(&self) -> Result<SweepSpec> {
        let defaults = match self.kind.as_str() {
            "feed" => &FEEDS_MM[..],
            "engagement" => &ENGAGEMENTS_MM[..],
            k => bail!("sweep {k}: expected feed or engagement"),
        };
        ensure!(
            self.stop_time.is_finite() && self.stop_time > 1.0,
            "--stop-time {}: must be above 1 s",
            self.stop_time
        );
        Ok(SweepSpec {
            fmu_dir: std::path::absolute(packaging::fmu_dir()).unwrap_or_else(|_| packaging::fmu_dir()),
            kind: self.kind.clone(),
            values_mm: self.values.clone().unwrap_or_else(|| defaults.to_vec()),
            controllers: self.controllers.clone(),
            preset: self.preset.clone(),
            seed: self.seed,
            stop_time: if self.quick { 2.0 } else { self.stop_time },
            quiet: self.quiet,
        })
    }
}

pub fn sweep(a: &SweepArgs) -> Result<()> {
    let spec = a.spec()?;
    let sys = closed_loop_system(&spec.fmu_dir)?;
    let s = spec.study(&roles(&sys)?, &a.out)?;
    let began = std::time::Instant::now();
    let rows = seed000::sweeps::run(&sys, &s)?;
    let md = seed000::sweeps::report(&s, &rows, &a.preset, Some(began.elapsed().as_secs_f64()))?;
    println!("{md}");
    println!("wrote {} (and .csv, .png)", a.out.join(format!("sweep_{}.md", s.kind.name())).display());
    Ok(())
}
