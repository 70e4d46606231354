//! `chatter depth-study`: seed 000 Section 5.6.1 (Figures 9–10) through the FMUs.

use anyhow::Result;
use clap::Args;
use seed000::depth_cases::DepthSpec;
use seed000::scenario::{closed_loop_system, roles};
use std::path::PathBuf;

#[derive(Args)]
pub struct DepthStudyArgs {
    /// Axial depths [mm].
    #[arg(long, value_delimiter = ',', default_value = "1,1.5,2")]
    pub depths: Vec<f64>,
    /// Controllers.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains: `tuned` (the shipped defaults) or `table2` (the paper's Table 2).
    #[arg(long, default_value = "tuned")]
    pub preset: String,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: i32,
    /// A short run (1.2 s; spectrum from 0.2 s, window 1.0–1.2 s) for tests.
    #[arg(long)]
    pub quick: bool,
    /// Output directory (depth_study.csv, depth_study.md).
    #[arg(long, default_value = "results/depth_study")]
    pub out: PathBuf,
}

impl DepthStudyArgs {
    /// The study's spec (what `chatter plan depth-study` writes into the manifest).
    pub fn spec(&self) -> DepthSpec {
        DepthSpec {
            fmu_dir: std::path::absolute(packaging::fmu_dir()).unwrap_or_else(|_| packaging::fmu_dir()),
            depths_mm: self.depths.clone(),
            controllers: self.controllers.clone(),
            preset: self.preset.clone(),
            seed: self.seed,
            quick: self.quick,
        }
    }
}

pub fn depth_study(a: &DepthStudyArgs) -> Result<()> {
    let spec = a.spec();
    let sys = closed_loop_system(&spec.fmu_dir)?;
    let s = spec.study(&roles(&sys)?, &a.out)?;
    let rows = seed000::depth_study::run(&sys, &s)?;
    let md = seed000::depth_study::report(&s, &rows, &a.preset)?;
    println!("{md}");
    println!("wrote {} and depth_study.csv", a.out.join("depth_study.md").display());
    Ok(())
}
