//! `chatter froh`: seed 004, the FROH zero locus, the non-minimum-phase boundary in β and the
//! J(β) sweep of Section V for the three readings of the chip lag τ_c (CSV + Markdown table).

use anyhow::{Context, Result};
use clap::Args;
use seed004::froh::{self, FrohStudy};
use std::path::PathBuf;

#[derive(Args)]
pub struct FrohArgs {
    /// Coarse grid (β step 0.2, 5 communication steps per period, 6 s): a check in seconds.
    #[arg(long)]
    pub quick: bool,
    /// β step of the sweep (from −0.6 to 1.0).
    #[arg(long, default_value_t = 0.05)]
    pub beta_step: f64,
    /// Communication steps per sample period (the cost's quadrature grid).
    #[arg(long, default_value_t = 20)]
    pub substeps: u32,
    /// Initial model: K̂ as a fraction of K_p(2 mm) (the θ₀ sensitivity; reading 0.5).
    #[arg(long, default_value_t = 0.5)]
    pub gain_factor: f64,
    /// Initial model: τ̂ as a multiple of τ_c (reading 1.5).
    #[arg(long, default_value_t = 1.5)]
    pub tau_factor: f64,
    /// Output directory (froh_zeros.csv, froh_sweep.csv, froh_summary.md).
    #[arg(long, default_value = "froh-out")]
    pub out: PathBuf,
}

pub fn froh(a: &FrohArgs) -> Result<()> {
    let mut o = FrohStudy {
        betas: froh::beta_grid(-0.6, 1.0, a.beta_step),
        substeps: a.substeps,
        gain_factor: a.gain_factor,
        tau_factor: a.tau_factor,
        ..Default::default()
    };
    if a.quick {
        o.betas = froh::beta_grid(-0.6, 1.0, 0.2);
        o.locus_betas = froh::beta_grid(-1.0, 1.0, 0.25);
        o.substeps = 5;
        o.duration = 6.0;
    }
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let mut locus = Vec::new();
    let mut points = Vec::new();
    let mut rows = Vec::new();
    for (reading, tau_c) in froh::tau_c_readings() {
        locus.extend(froh::zero_locus(reading, tau_c, &o.locus_betas)?);
        let (p, s) = froh::sweep(&o, reading, tau_c)?;
        points.extend(p);
        rows.push(s);
    }
    std::fs::write(a.out.join("froh_zeros.csv"), froh::locus_csv(&locus))?;
    std::fs::write(a.out.join("froh_sweep.csv"), froh::sweep_csv(&points))?;
    let md = froh::summary_markdown(&rows);
    std::fs::write(a.out.join("froh_summary.md"), &md)?;
    println!("{md}");
    println!("paper: minimum of J near beta = -0.2 (Figure 9), non-minimum phase below beta = -0.6");
    println!("written: {}/froh_{{zeros,sweep}}.csv, froh_summary.md", a.out.display());
    Ok(())
}
