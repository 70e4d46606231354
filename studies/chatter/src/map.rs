//! `chatter map`: seed 000 Section 5.6.6 (Figure 16), the speed × depth map through the FMUs.

use anyhow::Result;
use clap::Args;
use seed000::map::{seed_grid, write_report};
use seed000::map_cases::MapSpec;
use seed000::scenario::{closed_loop_system, roles};
use std::path::PathBuf;

#[derive(Args)]
pub struct MapArgs {
    /// Axial depths [mm] (default: the seed's 0.5:0.25:2.5).
    #[arg(long, value_delimiter = ',')]
    pub depths: Option<Vec<f64>>,
    /// Speed grid `lo,hi,step` [rpm].
    #[arg(long, value_delimiter = ',', default_value = "1000,2800,200")]
    pub rpm: Vec<f64>,
    /// Controllers.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains: `tuned` (the shipped defaults) or `table2` (the paper's Table 2).
    #[arg(long, default_value = "tuned")]
    pub preset: String,
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
    pub quick: bool,
    /// Output directory (map.csv, map.md, map.png).
    #[arg(long, default_value = "results/map")]
    pub out: PathBuf,
}

impl MapArgs {
    /// The study's spec (what `chatter plan map` writes into the manifest).
    pub fn spec(&self) -> MapSpec {
        MapSpec {
            fmu_dir: std::path::absolute(packaging::fmu_dir()).unwrap_or_else(|_| packaging::fmu_dir()),
            depths_mm: self.depths.clone().unwrap_or_else(|| seed_grid().0.iter().map(|d| d * 1e3).collect()),
            rpm: self.rpm.clone(),
            controllers: self.controllers.clone(),
            preset: self.preset.clone(),
            seed: self.seed,
            stop_time: if self.quick { 2.0 } else { self.stop_time },
            quiet: self.quiet,
        }
    }
}

pub fn map(a: &MapArgs) -> Result<()> {
    let spec = a.spec();
    let sys = closed_loop_system(&spec.fmu_dir)?;
    let s = spec.study(&roles(&sys)?, &a.out)?;
    let began = std::time::Instant::now();
    let cells = seed000::map::run(&sys, &s)?;
    let title = format!("{} — {:.0} s wall", spec.title(&s), began.elapsed().as_secs_f64());
    let (md, _) = write_report(&s, &cells, &title)?;
    println!("{md}");
    println!("wrote {} (and map.csv, map.png)", a.out.join("map.md").display());
    Ok(())
}
