//! What several commands share: plant presets, controller gains, diagrams, loop checks.

use anyhow::{Context, Result, bail};
use chatter_control::{ControllerParams, Structure};
use clap::Args;
use delay_stability::zero_order::{CriticalPoint, Extremes};
use milling_plant::PlantParams;
use seed000::loop_frf;
use seed000::scenario::GainPreset;
use seed000::tuning::{self};

#[derive(Args, Clone)]
pub struct GainArgs {
    /// Base gains: `table2` (the paper's preset) or `tuned` (the shipped FMU defaults).
    #[arg(long, value_enum, default_value_t = GainPreset::Table2)]
    pub preset: GainPreset,
    /// PID gains `kp,ki,kd` [N/m, N/(m s), N s/m].
    #[arg(long, value_delimiter = ',')]
    pub pid: Option<Vec<f64>>,
    /// FOPID gains `kp,ki,kd,lambda,mu` (force units).
    #[arg(long, value_delimiter = ',')]
    pub fopid: Option<Vec<f64>>,
    /// ADRC-FOPID gains `kp,ki,kd,lambda,mu` (force-equivalent units), optionally followed by
    /// `omega_o,b0` (default: the preset's 2699.3 rad/s and 1/30 1/kg).
    #[arg(long, value_delimiter = ',')]
    pub adrc: Option<Vec<f64>>,
}

pub fn plant_by_name(name: &str) -> Result<PlantParams> {
    Ok(match name {
        "seed" => loop_frf::seed_plant(),
        "ozsoy" => loop_frf::ozsoy_plant(),
        _ => bail!("unknown plant {name:?} (seed | ozsoy)"),
    })
}

pub fn structure_by_name(name: &str) -> Result<Structure> {
    model_kit::parse_choice(name).map_err(|e| anyhow::anyhow!("unknown controller: {e}"))
}

/// The preset of `--preset` (Table 2 or the tuned defaults).
pub fn controller_preset(g: &GainArgs) -> Result<ControllerParams> {
    Ok(g.preset.params())
}

/// Controller parameters for a structure, Table 2 unless overridden.
pub fn controller(structure: Structure, g: &GainArgs) -> Result<ControllerParams> {
    controller_from(&controller_preset(g)?, structure, g)
}

/// Controller parameters for a structure from `base`, with the gains of `--pid/--fopid/--adrc`.
pub fn controller_from(base: &ControllerParams, structure: Structure, g: &GainArgs) -> Result<ControllerParams> {
    for (name, v, n) in [("--pid", &g.pid, [3, 3]), ("--fopid", &g.fopid, [5, 5]), ("--adrc", &g.adrc, [5, 7])] {
        if let Some(v) = v {
            anyhow::ensure!(n.contains(&v.len()), "{name} takes {n:?} comma-separated values, got {}", v.len());
        }
    }
    let base = *base;
    let over = match structure {
        Structure::Pid => g.pid.clone(),
        Structure::Fopid => g.fopid.clone(),
        Structure::AdrcFopid => g.adrc.clone(),
        Structure::Off => None,
    };
    let c = match over {
        Some(v) => tuning::apply(&base, structure, &v),
        None => ControllerParams { structure, ..base },
    };
    c.validate().map_err(anyhow::Error::msg)?;
    Ok(c)
}

pub fn diagram(plant: &PlantParams, ctrl: &ControllerParams, rpm: &[f64]) -> Result<(Vec<CriticalPoint>, Extremes)> {
    let rpm_min = rpm.iter().copied().fold(f64::INFINITY, f64::min);
    let p = loop_frf::problem(plant, Some(ctrl), rpm_min)?;
    let d = p.diagram(rpm);
    let ex = p.extremes(&d).context("empty speed grid")?;
    Ok((d, ex))
}

/// Time-domain checks of a controller: closed-loop decay without cutting (0.5 s) and the PSO's
/// saturation check (50 N RMS disturbance, 0.2 s).
pub fn loop_checks(plant: &PlantParams, c: &ControllerParams) -> Result<(String, String)> {
    if c.structure == Structure::Off {
        return Ok(("yes (open loop)".into(), "–".into()));
    }
    let d = loop_frf::closed_loop_decay(plant, c, 0.5).map_err(anyhow::Error::msg)?;
    let s = tuning::SaturationCheck::default().run(plant, c).map_err(anyhow::Error::msg)?;
    Ok((
        format!("{} (peak ratio {:.1e})", if d.stable { "yes" } else { "NO" }, d.late_peak / d.early_peak),
        format!("{} ({}), {:.2} N", if s.exceeded { "yes" } else { "no" }, s.saturated_samples, s.peak_u),
    ))
}

pub fn fmt_ex(ex: &Extremes) -> String {
    seed000::lobes_cases::fmt_extremes(ex)
}
