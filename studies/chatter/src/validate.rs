//! `chatter validate`: the lobes against the FMUs in the Rust master.

use crate::common::*;
use anyhow::{Context, Result};
use chatter_control::Structure;
use clap::Args;
use delay_stability::zero_order::speed_grid;
use indicatif::ProgressBar;
use milling_plant::PlantParams;
use seed000::loop_frf;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args)]
pub struct ValidateArgs {
    /// Controllers to validate (`off` = open loop).
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    #[command(flatten)]
    pub gains: GainArgs,
    /// Speeds [rpm] (default: each diagram's b_min speed and 2000 rpm).
    #[arg(long, value_delimiter = ',')]
    pub rpm: Option<Vec<f64>>,
    /// Simulated time per run [s].
    #[arg(long, default_value_t = 1.5)]
    pub duration: f64,
    /// Relative width of the bisection's final bracket.
    #[arg(long, default_value_t = 1e-3)]
    pub tol: f64,
    /// Directory with MillingPlant.fmu, ChatterController.fmu (default: $FMU_DIR, else target/fmu).
    #[arg(long)]
    pub fmu_dir: Option<PathBuf>,
}

pub fn validate(a: &ValidateArgs) -> Result<()> {
    use rayon::prelude::*;
    let plant = PlantParams::default();
    let dir = a.fmu_dir.clone().unwrap_or_else(packaging::fmu_dir);
    let sys = seed000::scenario::closed_loop_system(&dir)?;
    let fl = seed000::fmu_validation::FmuLoop::new(&sys, &plant)?;
    let mut points = Vec::new();
    for name in &a.controllers {
        let c = controller(structure_by_name(name)?, &a.gains)?;
        let speeds = match &a.rpm {
            Some(v) => v.clone(),
            None => vec![diagram(&plant, &c, &speed_grid(1000.0, 3000.0, 2001))?.1.min.rpm, 2000.0],
        };
        for rpm in speeds {
            let b = loop_frf::problem(&plant, Some(&c), rpm.min(1000.0))?.critical_depth(rpm).depth;
            points.push((name.clone(), c, rpm, b));
        }
    }
    let started = Instant::now();
    let bar = ProgressBar::new(points.len() as u64).with_message("bisections through the FMUs");
    let rows: Vec<Result<String>> = points
        .par_iter()
        .map(|(name, c, rpm, b)| {
            let ctrl = (c.structure != Structure::Off).then_some(c);
            let td = fl
                .boundary(ctrl, *rpm, (0.9 * b, 1.1 * b), a.duration, a.tol)
                .with_context(|| format!("{name} at {rpm} rpm"))?;
            bar.inc(1);
            Ok(format!("| {name} | {rpm:.1} | {:.4} | {:.4} | {:+.2} |", b * 1e3, td * 1e3, (td / b - 1.0) * 100.0))
        })
        .collect();
    bar.finish_and_clear();
    println!(
        "Lobes vs the FMU closed loop in the Rust master (averaged cutting, noise off, {} s runs, bisection to {:.1} %)",
        a.duration,
        a.tol * 100.0
    );
    println!();
    println!("| controller | speed (rpm) | lobe b_crit (mm) | time-domain boundary (mm) | difference % |");
    println!("|---|---|---|---|---|");
    for r in rows {
        println!("{}", r?);
    }
    println!();
    println!("{} bisections in {:.1} s", points.len(), started.elapsed().as_secs_f64());
    Ok(())
}
