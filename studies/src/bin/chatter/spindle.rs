//! `chatter spindle`: seed 002's spindle on the new FMUs: the closed-loop tool FRFs (CSV + PNG)
//! and the time-domain growth/decay of `Spindle.ssp` around the semi-discretisation boundary.
//!
//! ```text
//! chatter spindle frf [--gains 697.1599,-1071.058] [--rpm 37000] [--out spindle-out]
//! chatter spindle validate [--rpm 38000] [--closed] [--duration 0.25] [--quick]
//! ```

use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use delay_stability::presets::SEED002_GAINS;
use delay_stability::{BisectionOptions, critical_value};
use std::path::PathBuf;
use std::time::Instant;
use studies::figures::plot_xy;
use studies::sd_lobes::Preset;
use studies::seed002::{SpindleCheck, closed_peak, frf_csv, spindle_system, static_gain, tool_frf};

#[derive(Subcommand)]
pub enum SpindleCmd {
    /// Open- and closed-loop tool FRFs (x and y) with a static Pyragas gain (CSV + PNG).
    Frf(FrfArgs),
    /// Growth ratio of Spindle.ssp in the Rust master at 0.97 and 1.03 of the SD boundary.
    Validate(ValidateArgs),
}

#[derive(Args)]
pub struct FrfArgs {
    /// Gains k1,k2 [N/mm] of D_c = [[k1, -k2], [k2, k1]] (default: the printed §6.1 gains).
    #[arg(long, value_delimiter = ',', num_args = 2)]
    pub gains: Option<Vec<f64>>,
    /// Spindle speed [rpm] (sets τ of the Pyragas difference).
    #[arg(long, default_value_t = 37_000.0)]
    pub rpm: f64,
    /// Output directory (tool_frf.csv, tool_frf.png).
    #[arg(long, default_value = "spindle-out")]
    pub out: PathBuf,
}

#[derive(Args)]
pub struct ValidateArgs {
    /// Spindle speed [rpm].
    #[arg(long, default_value_t = 38_000.0)]
    pub rpm: f64,
    /// With the printed §6.1 gains (else open loop).
    #[arg(long)]
    pub closed: bool,
    /// Simulated time per run [s].
    #[arg(long, default_value_t = 0.25)]
    pub duration: f64,
    /// Communication step [s].
    #[arg(long, default_value_t = 1e-6)]
    pub step: f64,
    /// Semi-discretisation intervals per period for the boundary.
    #[arg(long, default_value_t = 40)]
    pub m: usize,
    /// A shorter run (0.1 s, m = 20) for tests.
    #[arg(long)]
    pub quick: bool,
}

pub fn spindle(c: &SpindleCmd) -> Result<()> {
    match c {
        SpindleCmd::Frf(a) => frf(a),
        SpindleCmd::Validate(a) => validate(a),
    }
}

fn frf(a: &FrfArgs) -> Result<()> {
    let gains = match &a.gains {
        Some(g) => (g[0], g[1]),
        None => SEED002_GAINS,
    };
    let hz: Vec<f64> = (0..=3000).map(|k| 200.0 + k as f64).collect();
    let rows = tool_frf(&static_gain(Some(gains)), a.rpm, &hz)?;
    std::fs::create_dir_all(&a.out).with_context(|| a.out.display().to_string())?;
    let csv = a.out.join("tool_frf.csv");
    std::fs::write(&csv, frf_csv(&rows)).with_context(|| csv.display().to_string())?;
    let curve = |name: &str, f: &dyn Fn(&studies::seed002::FrfRow) -> f64| {
        (name.to_string(), rows.iter().map(|r| (r.hz, f(r) * 1e6)).collect::<Vec<_>>())
    };
    let png = a.out.join("tool_frf.png");
    plot_xy(
        &png,
        &format!("tool FRF, k1 = {}, k2 = {} N/mm, {} rpm", gains.0, gains.1, a.rpm),
        "frequency [Hz]",
        "|G| [um/N]",
        &[
            curve("open xx (= yy)", &|r| r.open[0].norm()),
            curve("closed xx", &|r| r.closed[0].norm()),
            curve("closed yy", &|r| r.closed[1].norm()),
        ],
    )?;
    let peak = |f: &dyn Fn(&studies::seed002::FrfRow) -> f64| {
        rows.iter().map(|r| (r.hz, f(r))).fold((0.0, 0.0), |m, p| if p.1 > m.1 { p } else { m })
    };
    let (ho, go) = peak(&|r| r.open[0].norm());
    let (hc, gc) = peak(&|r| r.closed[0].norm());
    println!("open-loop |G_xx| peak {go:.4e} m/N at {ho} Hz; closed-loop {gc:.4e} m/N at {hc} Hz");
    if let Some(p) = closed_peak(&rows) {
        println!("closed-loop peak frequency {p} Hz");
    }
    println!("wrote {} and {}", csv.display(), png.display());
    Ok(())
}

fn validate(a: &ValidateArgs) -> Result<()> {
    let (duration, m) = if a.quick { (0.1, 20) } else { (a.duration, a.m) };
    let dir = packaging::fmu_dir();
    let sys = spindle_system(&dir)?;
    let mut check = SpindleCheck::new(&sys);
    check.step = a.step;
    let (preset, gains) =
        if a.closed { (Preset::Seed002Closed61, Some(SEED002_GAINS)) } else { (Preset::Seed002Open61, None) };
    let model = preset.model()?;
    let o = BisectionOptions { m, start: 0.3e-3, growth: 1.1, max: 0.02, rel_tol: 1e-5 };
    let sd = critical_value(|d| model.at(a.rpm, d), &o)?.value.context("stable up to 20 mm")?;
    let c = static_gain(gains);
    let t0 = Instant::now();
    let below = check.growth_ratio(a.rpm, 0.97 * sd, &c, duration)?;
    let above = check.growth_ratio(a.rpm, 1.03 * sd, &c, duration)?;
    println!(
        "{} at {} rpm: SD boundary (m = {m}) {:.4} mm; growth ratio at 0.97: {below:.4}, at 1.03: {above:.4} ({:.1} s)",
        if a.closed { "printed gains" } else { "open loop" },
        a.rpm,
        sd * 1e3,
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}
