//! `chatter check`: closed-loop decay and the saturation check over noise seeds.

use crate::common::*;
use anyhow::Result;
use chatter_control::Structure;
use clap::Args;
use seed000::loop_frf;
use seed000::tuning::{self};

#[derive(Args)]
pub struct CheckArgs {
    /// Plant: `seed` or `ozsoy`.
    #[arg(long, default_value = "seed")]
    pub plant: String,
    /// Controllers to check.
    #[arg(long, value_delimiter = ',', default_value = "pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    #[command(flatten)]
    pub gains: GainArgs,
    /// Number of noise seeds of the saturation check: first-seed, first-seed + 1, ….
    #[arg(long, default_value_t = 10)]
    pub seeds: u64,
    /// First noise seed (the tuning's check uses seed 7: give e.g. 101 for seeds not used in tuning).
    #[arg(long, default_value_t = 1)]
    pub first_seed: u64,
    /// Margin: a command above (1 − margin)·u_max counts as saturating.
    #[arg(long, default_value_t = 0.0)]
    pub margin: f64,
    /// Duration of the saturation check [s].
    #[arg(long, default_value_t = 0.2)]
    pub duration: f64,
    /// Workpiece modes of the plant (1, the FMU default, or 3: the plant of `tune --modes 3`).
    #[arg(long, default_value_t = 1)]
    pub modes: u32,
}

pub fn check(a: &CheckArgs) -> Result<()> {
    anyhow::ensure!(a.seeds > 0, "--seeds 0: give at least one seed");
    anyhow::ensure!((0.0..1.0).contains(&a.margin), "--margin {}: must be in [0, 1)", a.margin);
    let mut plant = plant_by_name(&a.plant)?;
    plant.workpiece.modes = a.modes;
    plant.validate().map_err(|e| anyhow::anyhow!("--modes {}: {e}", a.modes))?;
    println!(
        "| controller | decay (late/early peak) | saturation check passed ({} mode(s), seeds {}..={}, margin {}) | peak u over seeds (N) | max saturated samples |",
        a.modes,
        a.first_seed,
        a.first_seed + a.seeds - 1,
        a.margin
    );
    println!("|---|---|---|---|---|");
    for name in &a.controllers {
        let c = controller(structure_by_name(name)?, &a.gains)?;
        if c.structure == Structure::Off {
            continue;
        }
        let d = loop_frf::closed_loop_decay(&plant, &c, 0.5).map_err(anyhow::Error::msg)?;
        let ch = tuning::SaturationCheck { duration: a.duration, margin: a.margin, ..Default::default() };
        let s = ch.over_seeds(&plant, &c, a.first_seed..a.first_seed + a.seeds).map_err(anyhow::Error::msg)?;
        println!(
            "| {name} | {:.2e} ({}) | {}/{} | {:.2} | {} |",
            d.late_peak / d.early_peak,
            if d.stable { "stable" } else { "NOT stable" },
            s.passed,
            s.seeds,
            s.peak_u,
            s.worst_saturated
        );
    }
    Ok(())
}
