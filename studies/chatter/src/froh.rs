//! `chatter froh`: seed 004, the FROH zero locus, the non-minimum-phase boundary in β and the
//! J(β) sweep of Section V for the three readings of the chip lag τ_c (CSV + Markdown table),
//! with either target of J (`--target froh|step`) and any initial model.

use anyhow::{Context, Result};
use clap::Args;
use model_kit::Choice;
use seed004::froh::{self, FrohStudy, Target};
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
    /// What J compares the force with: froh (the continuous reference model driven by the FROH
    /// of F_ref, changes with β) or step (its response to the F_ref step, the same for every β).
    #[arg(long, default_value = "froh", value_parser = model_kit::parse_choice::<Target>)]
    pub target: Target,
    /// The plant's CNC lag τ_s [s] (printed 0.1 ms; 0.1 would be 0.1 s).
    #[arg(long, default_value_t = 1e-4)]
    pub tau_s: f64,
    /// At β = 0 estimate three parameters (a, b0, b1) instead of the ZOH model's two.
    #[arg(long)]
    pub estimate_b1_at_zoh: bool,
    /// Instead of one sweep: the θ₀ sensitivity, the sweep for both targets × K̂/K_p ∈ {0.25,
    /// 0.5, 1, 2} × τ̂/τ_c ∈ {0.5, 1, 1.5, 2} (froh_theta0.csv, froh_theta0.md).
    #[arg(long)]
    pub theta0: bool,
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
        target: a.target,
        tau_s: a.tau_s,
        estimate_b1_at_zoh: a.estimate_b1_at_zoh,
        ..Default::default()
    };
    if a.quick {
        o.betas = froh::beta_grid(-0.6, 1.0, 0.2);
        o.locus_betas = froh::beta_grid(-1.0, 1.0, 0.25);
        o.substeps = 5;
        o.duration = 6.0;
    }
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    if a.theta0 {
        let rows = froh::theta0_sensitivity(&o, &[0.25, 0.5, 1.0, 2.0], &[0.5, 1.0, 1.5, 2.0])?;
        std::fs::write(a.out.join("froh_theta0.csv"), froh::theta0_csv(&rows))?;
        let md = froh::theta0_markdown(&rows);
        std::fs::write(a.out.join("froh_theta0.md"), &md)?;
        println!("the best beta (argmin J) and J(-0.2)/J(0) per initial model (K_hat, tau_hat) and J target:");
        println!("{md}");
        println!("written: {}/froh_theta0.{{csv,md}}", a.out.display());
        return Ok(());
    }
    let mut locus = Vec::new();
    let mut points = Vec::new();
    let mut rows = Vec::new();
    for (reading, tau_c) in froh::tau_c_readings() {
        locus.extend(froh::zero_locus(reading, tau_c, o.tau_s, &o.locus_betas)?);
        let (p, s) = froh::sweep(&o, reading, tau_c)?;
        points.extend(p);
        rows.push(s);
    }
    std::fs::write(a.out.join("froh_zeros.csv"), froh::locus_csv(&locus))?;
    std::fs::write(a.out.join("froh_sweep.csv"), froh::sweep_csv(&points))?;
    let md = froh::summary_markdown(&rows);
    std::fs::write(a.out.join("froh_summary.md"), &md)?;
    println!(
        "J target: {} ({}); initial model K = {} K_p(2 mm), tau = {} tau_c; tau_s = {} s; beta = 0 estimates {} parameters",
        o.target.name(),
        Target::ITEMS[o.target.index() as usize - 1].2,
        o.gain_factor,
        o.tau_factor,
        o.tau_s,
        if o.estimate_b1_at_zoh { 3 } else { 2 }
    );
    println!("{md}");
    println!("paper: minimum of J near beta = -0.2 (Figure 9), non-minimum phase below beta = -0.6");
    println!("written: {}/froh_{{zeros,sweep}}.csv, froh_summary.md", a.out.display());
    Ok(())
}
