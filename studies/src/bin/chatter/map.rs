//! `chatter map`: seed 000 Section 5.6.6 (Figure 16), the speed × depth map through the FMUs.

use crate::common::*;
use anyhow::{Result, ensure};
use clap::Args;
use model_kit::Choice;
use std::fmt::Write as _;
use std::path::PathBuf;
use studies::batch::Windows;
use studies::figures::{Heat, heat_maps};
use studies::fmu_params::overrides_of;
use studies::map::{GROWTH, MapStudy, SEED_PEAKS, disagreements, matrix, seed_grid};
use studies::scenario::{closed_loop_system, roles};

#[derive(Args)]
pub struct MapArgs {
    /// Axial depths [mm] (default: the seed's 0.5:0.25:2.5).
    #[arg(long, value_delimiter = ',')]
    pub depths: Option<Vec<f64>>,
    /// Speed grid `lo,hi,step` [rpm].
    #[arg(long, value_delimiter = ',', default_value = "1000,2800,200")]
    pub rpm: Vec<f64>,
    /// Controllers.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains: `tuned` (the shipped defaults) or `table2` (the paper's Table 2).
    #[arg(long, default_value = "tuned")]
    pub preset: String,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: i32,
    /// Run length per cell [s] (the seed: 5); RMS over (1 s, stop], growth = last second / first.
    #[arg(long, default_value_t = 5.0)]
    pub stop_time: f64,
    /// Noise and drift off (the growth check against the lobes).
    #[arg(long)]
    pub quiet: bool,
    /// A short run for tests: 2 s per cell.
    #[arg(long)]
    pub quick: bool,
    /// Output directory (map.csv, map.md, map.png).
    #[arg(long, default_value = "results/map")]
    pub out: PathBuf,
}

pub fn map(a: &MapArgs) -> Result<()> {
    let depths: Vec<f64> = a.depths.clone().unwrap_or_else(|| seed_grid().0.iter().map(|d| d * 1e3).collect());
    ensure!(
        !depths.is_empty() && depths.iter().all(|d| d.is_finite() && *d > 0.0),
        "--depths {depths:?}: depths must be positive"
    );
    ensure!(
        a.rpm.len() == 3 && a.rpm.iter().all(|r| r.is_finite() && *r > 0.0) && a.rpm[0] <= a.rpm[1],
        "--rpm {:?}: give lo,hi,step with 0 < lo ≤ hi and step > 0 (empty speed range)",
        a.rpm
    );
    ensure!(a.stop_time.is_finite() && a.stop_time >= 2.0, "--stop-time {}: must be at least 2 s", a.stop_time);
    let rpm: Vec<f64> =
        (0..).map(|k| a.rpm[0] + a.rpm[2] * f64::from(k)).take_while(|r| *r <= a.rpm[1] + 1e-9).collect();
    let preset = controller_preset(&GainArgs { preset: a.preset.clone(), pid: None, fopid: None, adrc: None })?;
    let controllers = a.controllers.iter().map(|c| structure_by_name(c)).collect::<Result<Vec<_>>>()?;
    let sys = closed_loop_system(&packaging::fmu_dir())?;
    let r = roles(&sys)?;
    let stop = if a.quick { 2.0 } else { a.stop_time };
    let s = MapStudy {
        depths: depths.iter().map(|d| d * 1e-3).collect(),
        rpm,
        controllers,
        seed: a.seed,
        windows: Windows::rms(stop, 1.0),
        quiet: a.quiet,
        gains: overrides_of(&r.controller, fmu_controller::parameter_assignments(&preset)),
        out: a.out.clone(),
    };
    let began = std::time::Instant::now();
    let cells = studies::map::run(&sys, &s)?;
    let mut md = format!(
        "Speed × depth map (seed 000 Figure 16; {} gains; noise seed {}{}; {} cells per controller; {stop} s per cell, RMS over (1, {stop}] s; {:.0} s wall)\n\n| controller | peak raw RMS (µm) at (a_p mm, rpm) | cells > 35 µm | cells > 6 µm | growth check: cells where 'last/first > {GROWTH}' ≠ 'a_p > b_lim' (tolerated at the boundary) | seed Figure 16 |\n|---|---|---|---|---|---|\n",
        a.preset,
        a.seed,
        if a.quiet { ", noise and drift OFF" } else { ", noise and drift on" },
        s.depths.len() * s.rpm.len(),
        began.elapsed().as_secs_f64()
    );
    let mut panels = Vec::new();
    let mut vmax: f64 = 0.0;
    for &c in &s.controllers {
        let m = matrix(&s, &cells, c, |x| x.metrics.rms * 1e6);
        let peak = cells
            .iter()
            .filter(|x| x.controller == c)
            .max_by(|x, y| x.metrics.rms.total_cmp(&y.metrics.rms))
            .expect("cells");
        let count = |t: f64| cells.iter().filter(|x| x.controller == c && x.metrics.rms * 1e6 > t).count();
        let d = disagreements(&s, &cells, c);
        let bad = d.iter().filter(|x| !x.2).count();
        let seed = SEED_PEAKS.iter().find(|(x, _)| *x == c).map_or("–", |(_, v)| v);
        let _ = writeln!(
            md,
            "| {} | {:.2} at ({}, {}) | {} | {} | {} ({} tolerated) | {seed} |",
            c.name(),
            peak.metrics.rms * 1e6,
            s.depths[peak.i] * 1e3,
            s.rpm[peak.j],
            count(35.0),
            count(6.0),
            d.len(),
            d.len() - bad
        );
        vmax = vmax.max(peak.metrics.rms * 1e6);
        panels.push((c.name().to_string(), m));
    }
    let _ = write!(md, "\nLobe solver b_lim(N) (mm), per controller:\n\n| controller |");
    for r in &s.rpm {
        let _ = write!(md, " {r} |");
    }
    md.push_str(&format!("\n|---|{}\n", "---|".repeat(s.rpm.len())));
    for &c in &s.controllers {
        let _ = write!(md, "| {} |", c.name());
        for j in 0..s.rpm.len() {
            let b = cells.iter().find(|x| x.controller == c && x.j == j).map_or(f64::NAN, |x| x.b_lim * 1e3);
            let _ = write!(md, " {b:.3} |");
        }
        md.push('\n');
    }
    if s.depths.len() >= 2 && s.rpm.len() >= 2 {
        let heats: Vec<Heat<'_>> = panels.iter().map(|(t, v)| Heat { title: t.clone(), values: v }).collect();
        heat_maps(
            &a.out.join("map.png"),
            &format!("Raw RMS tip displacement (common colour scale 0–{vmax:.1} µm; cf. seed Figure 16)"),
            ("spindle speed [rpm]", &s.rpm),
            ("axial depth [mm]", &depths),
            &heats,
            vmax,
            "RMS [µm]",
        )?;
    }
    std::fs::write(a.out.join("map.md"), &md)?;
    println!("{md}");
    println!("wrote {} (and map.csv, map.png)", a.out.join("map.md").display());
    Ok(())
}
