//! `chatter dsmc`: seed 003, Table 2 (per-axis MSE and reduction for none, DSMC, D-PID, DSMC-T1,
//! DSMC-T2) on the calibrated two-axis tool (CSV + Markdown table), then the same rows under
//! every reading of what the paper leaves open (the model of `A_dis`, T, the force limit, the
//! computation delay): the ranking and the reductions of each.

use anyhow::{Context, Result};
use clap::Args;
use model_kit::Choice;
use seed003::dsmc::{self, DsmcStudy};
use seed003::readings::{self, SweepSpec};
use sliding_fuzzy_control::{NominalModel, SlidingFuzzyParams};
use std::path::PathBuf;

#[derive(Args)]
pub struct DsmcArgs {
    /// Short runs (0.3 s, window 0.1–0.3 s) and a smaller readings grid (T = 1e-4 and 3e-4 s,
    /// the default force limit): a check in seconds.
    #[arg(long)]
    pub quick: bool,
    /// Controller sample period T [s] (of Table 2; the readings grid has its own).
    #[arg(long, default_value_t = 1e-4)]
    pub ts: f64,
    /// Sliding gain σ (normalised units).
    #[arg(long, default_value_t = 0.17)]
    pub sigma: f64,
    /// Damper force limit [N] (of Table 2; the readings grid has its own).
    #[arg(long, default_value_t = 2000.0)]
    pub u_max: f64,
    /// What the sliding-mode controllers know of A_dis (Eq. 22): exact_zoh, euler or identity.
    #[arg(long, default_value = "exact_zoh", value_parser = model_kit::parse_choice::<NominalModel>)]
    pub nominal_model: NominalModel,
    /// One sample of computation delay (the command of sample k acts from t_(k+1)).
    #[arg(long)]
    pub computation_delay: bool,
    /// Table 2 only, without the readings grid.
    #[arg(long)]
    pub no_readings: bool,
    /// Output directory (dsmc_table2.csv/.md, dsmc_readings.csv/.md).
    #[arg(long, default_value = "dsmc-out")]
    pub out: PathBuf,
}

pub fn dsmc(a: &DsmcArgs) -> Result<()> {
    let mut s = DsmcStudy {
        controller: SlidingFuzzyParams {
            sample_period: a.ts,
            sigma: a.sigma,
            force_limit: a.u_max,
            nominal_model: a.nominal_model,
            computation_delay: a.computation_delay,
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
    println!(
        "nominal model of A_dis: {}; computation delay: {}",
        a.nominal_model.name(),
        if a.computation_delay { "one sample" } else { "none (Eq. 19)" }
    );
    println!("{md}");
    println!("calibration check: open-loop MSE {:.6} / {:.6} um^2 (targets 0.3823 / 0.3702)", open[0], open[1]);
    println!("written: {}/dsmc_table2.{{csv,md}}", a.out.display());
    if a.no_readings {
        return Ok(());
    }
    let spec = if a.quick {
        SweepSpec { periods: vec![1e-4, 3e-4], force_limits: vec![2000.0], ..Default::default() }
    } else {
        SweepSpec::default()
    };
    // the grid varies the reading, T and the limit; σ and the rest are this command's
    let base = DsmcStudy { controller: SlidingFuzzyParams { sigma: a.sigma, ..Default::default() }, ..s };
    let points = readings::sweep(&base, &spec)?;
    std::fs::write(a.out.join("dsmc_readings.csv"), readings::csv(&points))?;
    let md = readings::markdown(&points);
    std::fs::write(a.out.join("dsmc_readings.md"), &md)?;
    println!(
        "\nTable 2 under every reading (MSE over 0.1 s - end, forcing calibrated per T; paper: T2 < T1 < D-PID < DSMC < none):\n"
    );
    println!("{md}");
    println!("written: {}/dsmc_readings.{{csv,md}}", a.out.display());
    Ok(())
}
