//! `chatter robustness`: seed 000 Table 7 and Figures 11–13 through the FMUs.

use crate::common::*;
use anyhow::{Result, ensure};
use clap::Args;
use std::path::PathBuf;
use studies::batch::Windows;
use studies::fmu_params::overrides_of;
use studies::robustness::{Group, Point, Robustness, base_plant, report, sample_with, speed_peak};
use studies::scenario::{closed_loop_system, roles};

#[derive(Args)]
pub struct RobustnessArgs {
    /// Controllers.
    #[arg(long, value_delimiter = ',', default_value = "off,pid,fopid,adrc_fopid")]
    pub controllers: Vec<String>,
    /// Controller gains: `tuned` (the shipped defaults) or `table2` (the paper's Table 2).
    #[arg(long, default_value = "tuned")]
    pub preset: String,
    /// Noise seeds of every point (two: the 38-run reading of the seed's sample).
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    pub seeds: Vec<i32>,
    /// Run length [s]; the RMS is over (1 s, stop].
    #[arg(long, default_value_t = 30.0)]
    pub stop_time: f64,
    /// Groups of the sample to run: plant, disturbance, speed.
    #[arg(long, value_delimiter = ',', default_value = "plant,disturbance,speed")]
    pub groups: Vec<String>,
    /// Speeds of the k −15 % sweep [rpm].
    #[arg(long, value_delimiter = ',', default_value = "1000,1450,1900,2350,2800")]
    pub speeds: Vec<f64>,
    /// Noise and drift off at every point (the forced response alone).
    #[arg(long)]
    pub quiet: bool,
    /// A short run for tests: 2 s per run (RMS over 1–2 s), noise seed 1 only.
    #[arg(long)]
    pub quick: bool,
    /// Output directory (robustness.csv, robustness.md, robustness.png).
    #[arg(long, default_value = "results/robustness")]
    pub out: PathBuf,
}

pub fn robustness(a: &RobustnessArgs) -> Result<()> {
    ensure!(!a.seeds.is_empty() && a.seeds.iter().all(|s| *s >= 0), "--seeds {:?}: give seeds ≥ 0", a.seeds);
    ensure!(a.stop_time.is_finite() && a.stop_time > 1.0, "--stop-time {}: must be above 1 s", a.stop_time);
    let preset = controller_preset(&GainArgs { preset: a.preset.clone(), pid: None, fopid: None, adrc: None })?;
    let controllers = a.controllers.iter().map(|c| structure_by_name(c)).collect::<Result<Vec<_>>>()?;
    ensure!(
        !a.speeds.is_empty() && a.speeds.iter().all(|r| r.is_finite() && *r > 0.0),
        "--speeds {:?}: give positive speeds",
        a.speeds
    );
    let mut groups = Vec::new();
    for g in &a.groups {
        groups.push(match g.as_str() {
            "plant" => Group::Plant,
            "disturbance" => Group::Disturbance,
            "speed" => Group::Speed,
            _ => anyhow::bail!("--groups {g}: expected plant, disturbance or speed"),
        });
    }
    let points: Vec<_> = sample_with(&a.speeds)
        .into_iter()
        .filter(|p| groups.contains(&p.group))
        .map(|p| Point { quiet: a.quiet, ..p })
        .collect();
    let sys = closed_loop_system(&packaging::fmu_dir())?;
    let r = roles(&sys)?;
    let mut s = Robustness {
        controllers,
        seeds: a.seeds.clone(),
        windows: Windows::rms(a.stop_time, 1.0),
        gains: overrides_of(&r.controller, fmu_controller::parameter_assignments(&preset)),
        out: a.out.clone(),
        points,
    };
    if a.quick {
        s.windows = Windows::rms(2.0, 1.0);
        s.seeds.truncate(1);
    }
    let began = std::time::Instant::now();
    let rows = studies::robustness::run(&sys, &s)?;
    let title = format!(
        "Robustness sample (seed 000 Table 7; {} gains; {} points{} × seeds {:?}; {} s runs, RMS over (1, {}] s; {:.0} s wall)",
        a.preset,
        s.points.len(),
        if a.quiet { ", noise and drift OFF" } else { "" },
        s.seeds,
        s.windows.stop,
        s.windows.stop,
        began.elapsed().as_secs_f64()
    );
    let mut md = report(&s, &rows, &title);
    let base = base_plant(&sys, &r)?;
    for &c in &s.controllers {
        if let Some((peak, res)) = speed_peak(&s, &rows, c, &base) {
            md.push_str(&format!(
                "\nk −15 % speed sweep, {}: largest RMS at {peak:.0} rpm; the first mode meets tooth passing (h = 1) at {:.0} rpm and its 2nd harmonic at {:.0} rpm.",
                model_kit::Choice::name(c),
                res[0],
                res[1]
            ));
        }
    }
    md.push('\n');
    studies::figures::plot_points(
        &a.out.join("robustness.png"),
        "Robustness sample: raw RMS per point (mean over seeds)",
        &s.points.iter().map(|p| p.name.clone()).collect::<Vec<_>>(),
        &s.controllers
            .iter()
            .map(|&c| {
                let v = (0..s.points.len())
                    .map(|k| {
                        let v: Vec<f64> = rows
                            .iter()
                            .filter(|r| r.0.controller == c && r.0.point == k)
                            .map(|r| r.1.rms * 1e6)
                            .collect();
                        v.iter().sum::<f64>() / v.len().max(1) as f64
                    })
                    .collect();
                (model_kit::Choice::name(c).to_string(), v)
            })
            .collect::<Vec<_>>(),
        "RMS x [µm]",
    )?;
    std::fs::write(a.out.join("robustness.md"), &md)?;
    println!("{md}");
    println!("wrote {} (and robustness.csv, robustness.png)", a.out.join("robustness.md").display());
    Ok(())
}
