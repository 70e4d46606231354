//! `chatter dsmc`: seed 003, Table 2 (per-axis MSE and reduction for none, DSMC, D-PID, DSMC-T1,
//! DSMC-T2) on the calibrated two-axis tool (CSV + Markdown table).

use anyhow::{Context, Result};
use clap::Args;
use seed003::dsmc::{self, DsmcStudy};
use sliding_fuzzy_control::SlidingFuzzyParams;
use std::path::PathBuf;

#[derive(Args)]
pub struct DsmcArgs {
    /// Short run (0.3 s, window 0.1–0.3 s): a check in seconds.
    #[arg(long)]
    pub quick: bool,
    /// Controller sample period T [s].
    #[arg(long, default_value_t = 1e-4)]
    pub ts: f64,
    /// Sliding gain σ (normalised units).
    #[arg(long, default_value_t = 0.17)]
    pub sigma: f64,
    /// Damper force limit [N].
    #[arg(long, default_value_t = 2000.0)]
    pub u_max: f64,
    /// Output directory (dsmc_table2.csv, dsmc_table2.md).
    #[arg(long, default_value = "dsmc-out")]
    pub out: PathBuf,
}

pub fn dsmc(a: &DsmcArgs) -> Result<()> {
    let mut s = DsmcStudy {
        controller: SlidingFuzzyParams {
            sample_period: a.ts,
            sigma: a.sigma,
            force_limit: a.u_max,
            ..Default::default()
        },
        ..Default::default()
    };
    if a.quick {
        s.t_end = 0.3;
    }
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let (amp, open) = dsmc::calibrate(&s)?;
    let rows = dsmc::run(&s, amp)?;
    std::fs::write(a.out.join("dsmc_table2.csv"), dsmc::csv(&rows))?;
    let md = dsmc::markdown(&rows, amp, a.ts);
    std::fs::write(a.out.join("dsmc_table2.md"), &md)?;
    println!("{md}");
    println!("calibration check: open-loop MSE {:.6} / {:.6} um^2 (targets 0.3823 / 0.3702)", open[0], open[1]);
    println!("written: {}/dsmc_table2.{{csv,md}}", a.out.display());
    Ok(())
}
