//! `chatter spindle`: seed 002's spindle on the new FMUs: the closed-loop tool FRFs (CSV + PNG)
//! and the time-domain growth/decay of `Spindle.ssp` around the semi-discretisation boundary.
//!
//! ```text
//! chatter spindle frf [--gains 697.1599,-1071.058 | --design synth-out/table2_nc2.ssv] [--rpm 37000] [--out spindle-out]
//! chatter spindle validate [--rpm 38000] [--closed | --design D.ssv [--x-f 0.744]] [--duration 0.25] [--ramp 0.01] [--quick]
//! ```
//!
//! A design (`--design`) is an SSP parameter set with the `LinearController` names, as `chatter
//! synth` writes them (`<case>.ssv`) and `target/fmu/designs/` ships them.

use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use delay_stability::presets::SEED002_GAINS;
use seed002::spindle::{
    SpindleCheck, closed_peak, design_params, frf_csv, sd_boundary, spindle_system, static_gain, tool_frf,
};
use std::path::PathBuf;
use std::time::Instant;
use study_kit::figures::plot_xy;

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
    #[arg(long, value_delimiter = ',', num_args = 2, conflicts_with = "design")]
    pub gains: Option<Vec<f64>>,
    /// A controller design: an SSP parameter set (.ssv) with the LinearController names.
    #[arg(long)]
    pub design: Option<PathBuf>,
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
    #[arg(long, conflicts_with = "design")]
    pub closed: bool,
    /// With a controller design: an SSP parameter set (.ssv) with the LinearController names.
    #[arg(long)]
    pub design: Option<PathBuf>,
    /// Force exponent x_F of the process and the boundary (1: §6.1; 0.744: §6.2, Table II),
    /// with the seed's coefficients for it.
    #[arg(long, default_value_t = 1.0)]
    pub x_f: f64,
    /// Simulated time per run [s].
    #[arg(long, default_value_t = 0.25)]
    pub duration: f64,
    /// Communication step [s].
    #[arg(long, default_value_t = 1e-6)]
    pub step: f64,
    /// Entry ramp of the process [s] (`process.depth_ramp_time`; 0: full depth at once, which
    /// rings the spindle with its static deflection and makes teeth leave the cut). At most a
    /// fifth of the duration.
    #[arg(long, default_value_t = 0.01)]
    pub ramp: f64,
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
    let (c, title) = match (&a.design, &a.gains) {
        (Some(path), _) => (design_params(path)?, format!("design {}", path.display())),
        (None, g) => {
            let g = g.as_ref().map_or(SEED002_GAINS, |g| (g[0], g[1]));
            (static_gain(Some(g)), format!("k1 = {}, k2 = {} N/mm", g.0, g.1))
        }
    };
    let hz: Vec<f64> = (0..=3000).map(|k| 200.0 + k as f64).collect();
    let rows = tool_frf(&c, a.rpm, &hz)?;
    std::fs::create_dir_all(&a.out).with_context(|| a.out.display().to_string())?;
    let csv = a.out.join("tool_frf.csv");
    std::fs::write(&csv, frf_csv(&rows)).with_context(|| csv.display().to_string())?;
    let curve = |name: &str, f: &dyn Fn(&seed002::spindle::FrfRow) -> f64| {
        (name.to_string(), rows.iter().map(|r| (r.hz, f(r) * 1e6)).collect::<Vec<_>>())
    };
    let png = a.out.join("tool_frf.png");
    plot_xy(
        &png,
        &format!("tool FRF, {title}, {} rpm", a.rpm),
        "frequency [Hz]",
        "|G| [um/N]",
        &[
            curve("open xx (= yy)", &|r| r.open[0].norm()),
            curve("closed xx", &|r| r.closed[0].norm()),
            curve("closed yy", &|r| r.closed[1].norm()),
        ],
    )?;
    let peak = |f: &dyn Fn(&seed002::spindle::FrfRow) -> f64| {
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
    check.ramp = a.ramp;
    check.x_f = a.x_f;
    let (label, c) = match &a.design {
        Some(path) => (format!("design {}", path.display()), Some(design_params(path)?)),
        None if a.closed => ("printed gains".to_string(), Some(static_gain(Some(SEED002_GAINS)))),
        None => ("open loop".to_string(), None),
    };
    let sd = sd_boundary(c.as_ref(), a.x_f, a.rpm, m)?;
    let c = c.unwrap_or_else(|| static_gain(None));
    let t0 = Instant::now();
    let below = check.growth_ratio(a.rpm, 0.97 * sd, &c, duration)?;
    let above = check.growth_ratio(a.rpm, 1.03 * sd, &c, duration)?;
    println!(
        "{label} at {} rpm, x_F = {}: SD boundary (m = {m}) {:.4} mm; growth ratio at 0.97: {below:.4}, at 1.03: {above:.4} ({:.1} s)",
        a.rpm,
        a.x_f,
        sd * 1e3,
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}
