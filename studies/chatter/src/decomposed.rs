//! `chatter decomposed`: seed 000's plant as process + structure + actuator FMUs against the
//! monolithic MillingPlant.fmu, open loop at the nominal point (issue 12).

use anyhow::{Result, ensure};
use clap::Args;
use seed000::decomposed::{Comparison, run, summary};

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
    /// Instead of the RMS comparison: the time-domain stability boundary of both systems at
    /// this spindle speed [rpm] (bisection in depth through the FMUs, feed 0.1 mm, noise off).
    #[arg(long)]
    pub boundary: Option<f64>,
}

pub fn decomposed(a: &DecomposedArgs) -> Result<()> {
    if let Some(rpm) = a.boundary {
        return boundary(rpm);
    }
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

/// Both time-domain boundaries at `rpm`, bracketed ±8 % around the SD boundary of the seed plant.
fn boundary(rpm: f64) -> Result<()> {
    use delay_stability::{BisectionOptions, critical_value};
    use seed000::sd_validation::SdFmuCheck;
    ensure!(rpm > 0.0, "--boundary needs a positive spindle speed");
    let dir = packaging::fmu_dir();
    let plant = milling_plant::PlantParams::default();
    let model = seed000::sd_lobes::seed000_model(&plant)?;
    let o = BisectionOptions { m: 40, start: 0.3e-3, growth: 1.1, max: 0.1, rel_tol: 1e-5 };
    let sd = critical_value(|x| model.at(rpm, x), &o)?
        .value
        .ok_or_else(|| anyhow::anyhow!("no SD boundary below 100 mm at {rpm} rpm"))?;
    let bracket = (0.92 * sd, 1.08 * sd);
    let started = std::time::Instant::now();
    let mono = seed000::scenario::closed_loop_system(&dir)?;
    let dec = seed000::decomposed::decomposed_system(&dir)?;
    let b_mono = SdFmuCheck::new(&mono, &plant)?.boundary(rpm, bracket, 1.5, 1e-3)?;
    let b_dec =
        SdFmuCheck::decomposed(&dec, &milling_process::ProcessParams::default())?.boundary(rpm, bracket, 1.5, 1e-3)?;
    println!(
        "{rpm} rpm: SD {:.4} mm, monolithic MillingPlant.fmu {:.4} mm, decomposed FMUs {:.4} mm ({:+.2} %) ({:.0} s)",
        sd * 1e3,
        b_mono * 1e3,
        b_dec * 1e3,
        100.0 * (b_dec / b_mono - 1.0),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
