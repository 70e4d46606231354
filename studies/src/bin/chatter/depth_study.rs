//! `chatter depth-study`: seed 000 Section 5.6.1 (Figures 9–10) through the FMUs.

use crate::common::*;
use anyhow::{Result, ensure};
use clap::Args;
use std::fmt::Write as _;
use std::path::PathBuf;
use studies::depth_study::{DepthStudy, SEED_FIGURE9};
use studies::fmu_params::overrides_of;
use studies::scenario::{closed_loop_system, roles};

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

pub fn depth_study(a: &DepthStudyArgs) -> Result<()> {
    ensure!(
        a.depths.iter().all(|d| d.is_finite() && *d >= 0.0),
        "--depths {:?}: depths must not be negative",
        a.depths
    );
    let gains = GainArgs { preset: a.preset.clone(), pid: None, fopid: None, adrc: None };
    let preset = controller_preset(&gains)?;
    let sys = closed_loop_system(&packaging::fmu_dir())?;
    let r = roles(&sys)?;
    let mut s = DepthStudy {
        depths: a.depths.iter().map(|d| d * 1e-3).collect(),
        controllers: a.controllers.iter().map(|c| structure_by_name(c)).collect::<Result<_>>()?,
        seed: a.seed,
        overrides: overrides_of(&r.controller, fmu_controller::parameter_assignments(&preset)),
        out: a.out.clone(),
        ..DepthStudy::default()
    };
    if a.quick {
        (s.stop, s.spectrum_from, s.window) = (1.2, 0.2, (1.0, 1.2));
    }
    let rows = studies::depth_study::run(&sys, &s)?;
    let mut md = format!(
        "Depth study (seed 000 Section 5.6.1, 2000 rpm, {} gains, noise seed {}, {} s runs; spectrum from {} s; window {}–{} s)\n\n| controller | a_p (mm) | (a) peak 100–200 Hz (µm) | (b) band-integrated (µm) | (c) window RMS (µm) | (d) saturation duty | seed Figure 9 (µm) |\n|---|---|---|---|---|---|---|\n",
        a.preset, a.seed, s.stop, s.spectrum_from, s.window.0, s.window.1
    );
    for r in &rows {
        let k = s.depths.iter().position(|d| d.to_bits() == r.depth.to_bits()).unwrap_or(0);
        let seed = SEED_FIGURE9
            .iter()
            .find(|(c, _)| *c == r.controller)
            .and_then(|(_, v)| v.get(k).copied())
            .filter(|v| v.is_finite() && s.depths.len() == 3)
            .map_or("–".to_string(), |v| format!("{v:.2}"));
        let _ = writeln!(
            md,
            "| {} | {:.2} | {:.3} | {:.3} | {:.3} | {:.1} % | {seed} |",
            model_kit::Choice::name(r.controller),
            r.depth * 1e3,
            r.band_peak * 1e6,
            r.band_integrated * 1e6,
            r.window_rms * 1e6,
            100.0 * r.saturation_duty
        );
    }
    std::fs::write(a.out.join("depth_study.md"), &md)?;
    println!("{md}");
    println!("wrote {} and depth_study.csv", a.out.join("depth_study.md").display());
    Ok(())
}
