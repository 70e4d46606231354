//! `chatter table8`: seed 000's Table 8 with all nine rows (calibrated and PSO modes), Figures
//! 17–18 and Table A1 on the Ozsoy benchmark (`seed000::benchmark_table`).

use anyhow::Result;
use clap::Args;
use seed000::benchmark_table::{Table8Spec, run};
use std::path::PathBuf;

#[derive(Args)]
pub struct Table8Args {
    /// A small run (2 PSO runs of 6 particles × 3 iterations, one check seed): for tests.
    #[arg(long)]
    pub quick: bool,
    /// PSO runs per controller.
    #[arg(long)]
    pub runs: Option<usize>,
    /// Swarm size.
    #[arg(long)]
    pub particles: Option<usize>,
    /// Iterations.
    #[arg(long)]
    pub iterations: Option<usize>,
    /// Robust saturation constraint: noise seeds 1..=N.
    #[arg(long)]
    pub check_seeds: Option<u64>,
    /// Output directory.
    #[arg(long, default_value = "results/table8")]
    pub out: PathBuf,
}

pub fn table8(a: &Table8Args) -> Result<()> {
    let mut spec = if a.quick { Table8Spec::quick() } else { Table8Spec::full() };
    spec.runs = a.runs.unwrap_or(spec.runs);
    spec.particles = a.particles.unwrap_or(spec.particles);
    spec.iterations = a.iterations.unwrap_or(spec.iterations);
    spec.check_seeds = a.check_seeds.unwrap_or(spec.check_seeds);
    anyhow::ensure!(spec.runs > 0 && spec.particles > 0, "--runs and --particles must be at least 1");
    let md = run(&spec, &a.out, &|m| eprintln!("{m}"))?;
    println!("{md}");
    println!("wrote {}/table8.md, table_a1.md, fig17_receptance.*, fig18_lobes_*.*, *.ssv", a.out.display());
    Ok(())
}
