//! `chatter afrac` and `chatter afrac-ga`: seed 001, AFrAC on the turning process (open loop,
//! fixed β, the stepwise schedule of Table 5) and the genetic algorithm of Table 4.

use anyhow::{Context, Result};
use clap::Args;
use seed001::afrac::{self, AfracStudy, Ga};
use std::path::PathBuf;
use turning_process::stability_limit;

#[derive(Args)]
pub struct AfracArgs {
    /// Short runs (1.6 s, β ∈ {1, 1.75}): a check in seconds.
    #[arg(long)]
    pub quick: bool,
    /// Duration of each run [s].
    #[arg(long, default_value_t = 3.0)]
    pub duration: f64,
    /// Speed adaptation gain λ₃ (default: the reading of afrac_control).
    #[arg(long)]
    pub lambda_speed: Option<f64>,
    /// Feed adaptation gain λ₂.
    #[arg(long)]
    pub lambda_feed: Option<f64>,
    /// Output directory (afrac_summary.csv, afrac_traces.csv, afrac_summary.md).
    #[arg(long, default_value = "afrac-out")]
    pub out: PathBuf,
    /// Also run every case through the packaged FMUs (Afrac.ssd, TurningProcess.fmu from
    /// target/fmu) and check that the table is the core one (afrac_fmu_summary.md).
    #[arg(long)]
    pub fmu: bool,
}

fn study(quick: bool, duration: f64, ls: Option<f64>, lf: Option<f64>) -> AfracStudy {
    let mut s = AfracStudy { duration, ..Default::default() };
    if let Some(l) = ls {
        s.controller.lambda_speed = l;
    }
    if let Some(l) = lf {
        s.controller.lambda_feed = l;
    }
    if quick {
        s.duration = 1.6;
        s.betas = vec![1.0, 1.75];
    }
    s
}

pub fn afrac(a: &AfracArgs) -> Result<()> {
    let s = study(a.quick, a.duration, a.lambda_speed, a.lambda_feed);
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let p = &s.plant;
    let lim = stability_limit(p.omega_n(), p.a1(0.1, 450.0), 60.0 / 450.0).context("no stability limit")?;
    println!(
        "limit at 450 rpm: a2/wn^2 = {:.5} (2ζ(1+ζ) = {:.5}), chatter {:.2} Hz, w_lim = {:.4} mm",
        lim.a2 / p.omega_n().powi(2),
        2.0 * p.damping_ratio * (1.0 + p.damping_ratio),
        lim.omega / (2.0 * std::f64::consts::PI),
        lim.a2 / p.a2(0.1, 1.0)
    );
    println!("lambda_speed = {:e}, lambda_feed = {:e}", s.controller.lambda_speed, s.controller.lambda_feed);
    let runs = s.run()?;
    let rows: Vec<_> = runs.iter().map(|r| r.0.clone()).collect();
    std::fs::write(a.out.join("afrac_summary.csv"), afrac::summary_csv(&rows))?;
    std::fs::write(a.out.join("afrac_traces.csv"), afrac::traces_csv(&runs, 10))?;
    let md = afrac::summary_markdown(&rows);
    std::fs::write(a.out.join("afrac_summary.md"), &md)?;
    println!("{md}");
    println!(
        "paper: beta = 1.75 fastest with a dramatic speed change, beta = 1 slowest; AFrAC fully suppressed within 1.5 s"
    );
    println!("written: {}/afrac_{{summary,traces}}.csv, afrac_summary.md", a.out.display());
    if a.fmu {
        fmu_tables(&s, &rows, a)?;
    }
    Ok(())
}

/// The cases through the FMUs: the table must be the core one.
fn fmu_tables(s: &AfracStudy, core: &[afrac::Summary], a: &AfracArgs) -> Result<()> {
    use rayon::prelude::*;
    let dir = packaging::fmu_dir();
    packaging::packaged("AfracController.fmu");
    let (n0, f0) = (s.controller.initial_speed, s.controller.initial_feed);
    let rows: Vec<afrac::Summary> = s
        .cases()
        .par_iter()
        .map(|c| seed001::afrac_fmu::run_fmu(c, &dir).map(|t| afrac::summarise(&c.label, &t, n0, f0)))
        .collect::<Result<_, _>>()?;
    let md = afrac::summary_markdown(&rows);
    std::fs::write(a.out.join("afrac_fmu_summary.md"), &md)?;
    println!("through the FMUs (Afrac.ssd, TurningProcess.fmu in {}):\n{md}", dir.display());
    let same = rows == core;
    println!("FMU table equal to the core table: {}", if same { "yes (every summary bitwise)" } else { "NO" });
    anyhow::ensure!(same, "the FMU runs differ from the core loop");
    Ok(())
}

#[derive(Args)]
pub struct AfracGaArgs {
    /// Small GA (population 6, 3 generations, 1.6 s runs).
    #[arg(long)]
    pub quick: bool,
    /// Seed of the GA.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Population size.
    #[arg(long, default_value_t = 20)]
    pub population: usize,
    /// Most generations.
    #[arg(long, default_value_t = 40)]
    pub generations: usize,
    /// Bumpless switching in the evaluated controller.
    #[arg(long)]
    pub bumpless: bool,
    /// Duration of each run [s].
    #[arg(long, default_value_t = 3.0)]
    pub duration: f64,
}

pub fn afrac_ga(a: &AfracGaArgs) -> Result<()> {
    let s = study(a.quick, a.duration, None, None);
    let mut g = Ga { seed: a.seed, population: a.population, generations: a.generations, ..Default::default() };
    if a.quick {
        g.population = 6;
        g.generations = 3;
    }
    let r = afrac::ga(&s, &g, a.bumpless)?;
    let ordered = r.times.windows(2).all(|w| w[0] <= w[1]);
    println!(
        "GA (seed {}, population {}, bumpless {}): t1..t4 = {:.4} / {:.4} / {:.4} / {:.4} s, mean |x| = {:.4e} mm",
        a.seed, g.population, a.bumpless, r.times[0], r.times[1], r.times[2], r.times[3], r.objective
    );
    println!(
        "generations {}, evaluations {}, unanimous bits {:.1} %, ordered t1 <= t2 <= t3 <= t4: {ordered}",
        r.generations,
        r.evaluations,
        100.0 * r.converged
    );
    println!("paper (Table 5): 0.6935 / 0.7677 / 1.26871 / 1.6874 s, ordered");
    Ok(())
}
