//! `chatter tune`: PSO tuning, Table A1 statistics.

use crate::common::*;
use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use seed000::tune_cases::{CSV_HEADER, TABLE_HEADER, TuneSpec, csv_line, json_run, table_row};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args)]
pub struct TuneArgs {
    /// Plant: `seed` or `ozsoy`.
    #[arg(long, default_value = "seed")]
    pub plant: String,
    /// Structures to tune.
    #[arg(long, value_delimiter = ',', default_value = "pid,fopid,adrc_fopid")]
    pub structures: Vec<String>,
    /// Independent runs per structure (seeds seed, seed+1, ...).
    #[arg(long, default_value_t = 10)]
    pub runs: usize,
    /// First PSO seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Swarm size.
    #[arg(long, default_value_t = 40)]
    pub particles: usize,
    /// Iterations.
    #[arg(long, default_value_t = 60)]
    pub iterations: usize,
    /// Duration of the saturation check [s].
    #[arg(long, default_value_t = 0.2)]
    pub check_duration: f64,
    /// Saturation-check margin: exceeding means |u_c| > (1 − margin)·u_max (default 0, the
    /// seed's check; with `--machine` 0.1).
    #[arg(long)]
    pub margin: Option<f64>,
    /// Robust saturation constraint: the check must pass for noise seeds 1..=N (default 0: the
    /// seed's single check with noise seed 7; with `--machine` 5).
    #[arg(long)]
    pub check_seeds: Option<u64>,
    /// Workpiece modes of the tuning plant (1 or 3: lobes and check on the 3-mode plant).
    #[arg(long, default_value_t = 1)]
    pub modes: u32,
    /// ADRC-FOPID: also tune ω_o and b0 (an extension; the seed fixes them).
    #[arg(long)]
    pub adrc_observer: bool,
    /// Output directory.
    #[arg(long, default_value = "stability-out")]
    pub out: PathBuf,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Your own machine: tune each structure on a machine file's closed loop and actuator limit
    /// and write `tuned_<structure>.ssv` parameter sets for ChatterController.
    #[arg(long, conflicts_with_all = ["plant", "modes"])]
    pub machine: Option<PathBuf>,
    /// With `--machine`: speeds of the cost's minimum over the file's speed range.
    #[arg(long, default_value_t = 41)]
    pub speeds: usize,
}

impl TuneArgs {
    /// The study's spec (what `chatter plan tune` writes into the manifest).
    pub fn spec(&self) -> Result<TuneSpec> {
        let mut plant = plant_by_name(&self.plant)?;
        plant.workpiece.modes = self.modes;
        let spec = TuneSpec {
            plant,
            structures: self.structures.clone(),
            runs: self.runs,
            seed: self.seed,
            particles: self.particles,
            iterations: self.iterations,
            check_duration: self.check_duration,
            margin: self.margin.unwrap_or(0.0),
            check_seeds: self.check_seeds.unwrap_or(0),
            adrc_observer: self.adrc_observer,
        };
        spec.validate()?;
        Ok(spec)
    }
}

pub fn tune(a: &TuneArgs) -> Result<()> {
    if let Some(file) = &a.machine {
        let o = machine::tune::TuneOptions {
            structures: a.structures.iter().map(|n| structure_by_name(n)).collect::<Result<_>>()?,
            runs: a.runs,
            seed: a.seed,
            pso: study_kit::optim::pso::PsoConfig {
                particles: a.particles,
                iterations: a.iterations,
                ..Default::default()
            },
            check_seeds: a.check_seeds.unwrap_or(5),
            margin: a.margin.unwrap_or(0.1),
            check_duration: a.check_duration,
            speeds: a.speeds,
        };
        return crate::own_machine::tune(file, &o, &a.out, a.quiet);
    }
    let spec = a.spec()?;
    std::fs::create_dir_all(&a.out)?;
    let mut csv = String::from(CSV_HEADER);
    let mut table = String::from(TABLE_HEADER);
    for (name, structure) in spec.structures()? {
        let prob = spec.problem(structure);
        let mut runs = Vec::new();
        for r in 0..a.runs {
            let cfg = spec.pso(r);
            let pb = if a.quiet { ProgressBar::hidden() } else { ProgressBar::new(a.iterations as u64) };
            pb.set_style(
                ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} it  {msg}  ({elapsed})")
                    .expect("valid template")
                    .progress_chars("=> "),
            );
            pb.set_prefix(format!("{name} run {}/{}", r + 1, a.runs));
            let t = Instant::now();
            let run = prob.run(&cfg, |k, best| {
                pb.set_position(k as u64);
                pb.set_message(format!("best J {best:.4} mm"));
            });
            pb.finish_and_clear();
            let secs = t.elapsed().as_secs_f64();
            csv.push_str(&csv_line(&name, &run, secs));
            println!(
                "{name} run {} (seed {}): J = {:.4} mm, b_min = {:.4} mm at {:.0} rpm, gains {:?}, {:.1} s",
                r + 1,
                cfg.seed,
                run.breakdown.cost,
                run.breakdown.b_min_mm,
                run.breakdown.rpm_at_min,
                run.gains,
                secs
            );
            runs.push(run);
        }
        let (row, best) = table_row(&name, &prob, &runs).context("no runs")?;
        std::fs::write(a.out.join(format!("tuned_{name}.json")), json_run(best, structure, &prob.space()))?;
        table.push_str(&row);
    }
    std::fs::write(a.out.join("tuning_runs.csv"), &csv)?;
    std::fs::write(a.out.join("table_a1.md"), &table)?;
    println!("\nTable A1 style (J = −min b_crit over 1000..3000 rpm step 50 + penalty):\n{table}");
    println!("wrote {}/tuned_*.json, tuning_runs.csv, table_a1.md", a.out.display());
    Ok(())
}
