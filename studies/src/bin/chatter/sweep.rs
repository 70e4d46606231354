//! `chatter sweep feed|engagement`: seed 000 Section 5.6.5 (Figure 15) through the FMUs.

use crate::common::*;
use anyhow::{Result, bail, ensure};
use clap::Args;
use model_kit::Choice;
use std::fmt::Write as _;
use std::path::PathBuf;
use studies::batch::Windows;
use studies::fmu_params::overrides_of;
use studies::scenario::{closed_loop_system, roles};
use studies::sweeps::{ENGAGEMENTS_MM, FEEDS_MM, Kind, SEED_FEED_SLOPES, Sweep, mm, slope};

#[derive(Args)]
pub struct SweepArgs {
    /// What to sweep: `feed` (f_z) or `engagement` (a_e, up-milling).
    pub kind: String,
    /// Values [mm] (default: the seed's feeds 0.025–0.12 mm or engagements 4–14 mm).
    #[arg(long, value_delimiter = ',')]
    pub values: Option<Vec<f64>>,
    /// Controllers.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains: `tuned` (the shipped defaults) or `table2` (the paper's Table 2).
    #[arg(long, default_value = "tuned")]
    pub preset: String,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: i32,
    /// Run length [s]; the RMS is over (1 s, stop].
    #[arg(long, default_value_t = 10.0)]
    pub stop_time: f64,
    /// Noise and drift off (the harmonic-balance check).
    #[arg(long)]
    pub quiet: bool,
    /// A short run for tests: 2 s per run, RMS over 1–2 s.
    #[arg(long)]
    pub quick: bool,
    /// Output directory (sweep_<kind>.csv, .md, .png).
    #[arg(long, default_value = "results/sweeps")]
    pub out: PathBuf,
}

pub fn sweep(a: &SweepArgs) -> Result<()> {
    let (kind, defaults, name) = match a.kind.as_str() {
        "feed" => (Kind::Feed, &FEEDS_MM[..], "feed"),
        "engagement" => (Kind::Engagement, &ENGAGEMENTS_MM[..], "engagement"),
        k => bail!("sweep {k}: expected feed or engagement"),
    };
    let values = a.values.clone().unwrap_or_else(|| defaults.to_vec());
    ensure!(
        !values.is_empty() && values.iter().all(|v| v.is_finite() && *v > 0.0),
        "--values {values:?}: give positive values in mm"
    );
    ensure!(a.stop_time.is_finite() && a.stop_time > 1.0, "--stop-time {}: must be above 1 s", a.stop_time);
    let preset = controller_preset(&GainArgs { preset: a.preset.clone(), pid: None, fopid: None, adrc: None })?;
    let controllers = a.controllers.iter().map(|c| structure_by_name(c)).collect::<Result<Vec<_>>>()?;
    let sys = closed_loop_system(&packaging::fmu_dir())?;
    let r = roles(&sys)?;
    let stop = if a.quick { 2.0 } else { a.stop_time };
    let s = Sweep {
        kind,
        values: values.iter().map(|v| v * 1e-3).collect(),
        controllers,
        seed: a.seed,
        windows: Windows::rms(stop, 1.0),
        quiet: a.quiet,
        gains: overrides_of(&r.controller, fmu_controller::parameter_assignments(&preset)),
        out: a.out.clone(),
    };
    let began = std::time::Instant::now();
    let mut rows = studies::sweeps::run(&sys, &s)?;
    rows.sort_by(|x, y| (x.controller.index(), x.value).partial_cmp(&(y.controller.index(), y.value)).expect("finite"));
    let mut md = format!(
        "Sweep of the {name} (seed 000 Figure 15; {} gains; noise seed {}{}; {stop} s runs, RMS over (1, {stop}] s; {:.0} s wall)\n\n| controller | {name} (mm) | raw RMS (µm) | detrended RMS (µm) | harmonic balance (µm) | Δ % | saturation duty |{}\n|---|---|---|---|---|---|---|{}\n",
        a.preset,
        a.seed,
        if a.quiet { ", noise and drift OFF" } else { ", noise and drift on" },
        began.elapsed().as_secs_f64(),
        if kind == Kind::Engagement { " open-loop b_lim solver / closed form (mm) |" } else { "" },
        if kind == Kind::Engagement { "---|" } else { "" },
    );
    for x in &rows {
        let _ = write!(
            md,
            "| {} | {} | {:.3} | {:.3} | {:.3} | {:+.2} | {:.1} % |",
            x.controller.name(),
            mm(x.value),
            x.metrics.rms * 1e6,
            x.metrics.rms_detrended * 1e6,
            x.harmonic * 1e6,
            100.0 * (x.metrics.rms_detrended / x.harmonic - 1.0),
            100.0 * x.metrics.saturation_duty
        );
        if kind == Kind::Engagement {
            let _ = write!(md, " {:.6} / {:.6} |", x.b_lim_solver * 1e3, x.b_lim_closed * 1e3);
        }
        md.push('\n');
    }
    let mut curves = Vec::new();
    for &c in &s.controllers {
        let pts: Vec<(f64, f64)> =
            rows.iter().filter(|x| x.controller == c).map(|x| (mm(x.value), x.metrics.rms * 1e6)).collect();
        if kind == Kind::Feed && pts.len() > 1 {
            let (fx, fy): (Vec<f64>, Vec<f64>) = pts.iter().copied().unzip();
            let seed = SEED_FEED_SLOPES.iter().find(|(x, _)| *x == c).map_or("–".into(), |(_, v)| format!("{v:.0}"));
            let _ = write!(
                md,
                "\nRMS slope against f_z, {}: {:.1} µm/mm (seed ≈ {seed} µm/mm).",
                c.name(),
                slope(&fx, &fy)
            );
        }
        curves.push((c.name().to_string(), pts));
    }
    md.push('\n');
    studies::figures::plot_xy(
        &a.out.join(format!("sweep_{name}.png")),
        &format!("RMS tip displacement against the {name} (cf. seed Figure 15)"),
        &format!("{name} [mm]"),
        "RMS x [µm]",
        &curves,
    )?;
    std::fs::write(a.out.join(format!("sweep_{name}.md")), &md)?;
    println!("{md}");
    println!("wrote {} (and .csv, .png)", a.out.join(format!("sweep_{name}.md")).display());
    Ok(())
}
