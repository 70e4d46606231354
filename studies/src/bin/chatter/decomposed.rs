//! `chatter decomposed`: seed 000's plant as process + structure + actuator FMUs against the
//! monolithic MillingPlant.fmu, open loop at the nominal point (issue 12).

use anyhow::{Result, ensure};
use clap::Args;
use studies::decomposed::{Comparison, run, summary};

#[derive(Args)]
pub struct DecomposedArgs {
    /// Number of noise seeds (1..=N).
    #[arg(long, default_value_t = 10)]
    pub seeds: u32,
    /// Stop time [s].
    #[arg(long, default_value_t = 30.0)]
    pub stop_time: f64,
    /// RMS from this time [s].
    #[arg(long, default_value_t = 1.0)]
    pub from: f64,
}

pub fn decomposed(a: &DecomposedArgs) -> Result<()> {
    ensure!(a.seeds >= 1 && a.stop_time > a.from, "need at least one seed and stop-time > from");
    let c = Comparison { seeds: (1..=a.seeds).collect(), stop: a.stop_time, from: a.from };
    let started = std::time::Instant::now();
    let rows = run(&packaging::fmu_dir(), &c, &|r| {
        eprintln!(
            "seed {:2}: monolithic {:.4} µm, decomposed {:.4} µm ({:+.3} %)",
            r.seed,
            r.monolithic * 1e6,
            r.decomposed * 1e6,
            100.0 * r.relative_difference()
        )
    })?;
    let (m, d, rel) = summary(&rows);
    let worst = rows.iter().map(|r| r.relative_difference().abs()).fold(0.0, f64::max);
    println!(
        "open-loop RMS over ({}, {}] s, {} seeds: monolithic {:.4} µm, decomposed {:.4} µm, difference of the means {:+.3} %, largest per seed {:.3} % ({:.0} s)",
        a.from,
        a.stop_time,
        rows.len(),
        m * 1e6,
        d * 1e6,
        100.0 * rel,
        100.0 * worst,
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
