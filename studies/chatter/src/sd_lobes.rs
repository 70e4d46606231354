//! `chatter sd-lobes`: time-periodic lobes (multi-DOF; Hopf and flip) of the seed 000 plant
//! described by the `MillingPlant.fmu` parameter names, or of a seed 002 preset or design. By
//! default converged (`--method auto`: the spectral collocation of `delay_stability::spectral`,
//! its order raised until the boundary moves by less than `--tol`); `--method sd --m 40` is the
//! first-order semi-discretisation, `--method spectral --nodes N` a fixed order.
//!
//! ```text
//! chatter sd-lobes [--plant seed|ozsoy] [--set plant.NAME=VALUE]... [--rpm-min ..] [--rpm-max ..]
//! chatter sd-lobes --preset seed002-6.1|seed002-6.1-closed|seed002-6.2 [--method auto|sd|spectral] [--points 41]
//! ```

use crate::common::plant_by_name;
use crate::lobes::{file_name, machine_title};
use anyhow::{Context, Result, bail, ensure};
use clap::Args;
use delay_stability::zero_order::speed_grid;
use delay_stability::{LobeOptions, Method, SpectralOptions};
use fmi_master::{Override, SystemFile};
use indicatif::{ProgressBar, ProgressStyle};
use seed000::sd_lobes::{extremes, seed000_model, write_csv};
use seed002::presets::Preset;
use std::path::PathBuf;
use std::time::Instant;
use study_kit::fmu_params::{self, Resolved};

#[derive(Args)]
pub struct SdLobesArgs {
    /// Seed 002 case (`seed002-6.1`, `seed002-6.1-closed`, `seed002-6.2`) instead of the seed 000 plant.
    #[arg(long, conflicts_with = "design")]
    pub preset: Option<String>,
    /// Seed 002's spindle with a controller design: an SSP parameter set (.ssv) with the
    /// LinearController names (`chatter synth` writes them; `target/fmu/designs/`).
    #[arg(long)]
    pub design: Option<PathBuf>,
    /// Force exponent x_F of seed 002's cutter with `--design` (1: §6.1, 36000–38000 rpm by
    /// default; otherwise Table II's 34000–36000 rpm).
    #[arg(long, default_value_t = 0.744)]
    pub x_f: f64,
    /// Starting plant for the seed 000 family: `seed` or `ozsoy`.
    #[arg(long, default_value = "seed")]
    pub plant: String,
    /// Take the plant's parameters from this system's bindings (.ssp/.ssd).
    #[arg(long)]
    pub system: Option<PathBuf>,
    /// A parameter of the plant FMU, `plant.NAME=VALUE` (its variable names, SI units); repeatable.
    #[arg(long = "set", value_name = "plant.NAME=VALUE")]
    pub set: Vec<String>,
    /// Lowest speed [rpm] (default: 1000, or the preset's range).
    #[arg(long)]
    pub rpm_min: Option<f64>,
    /// Highest speed [rpm] (default: 3000, or the preset's range).
    #[arg(long)]
    pub rpm_max: Option<f64>,
    /// Number of speeds.
    #[arg(long, default_value_t = 41)]
    pub points: usize,
    /// The discretisation: `auto` (converged: spectral collocation, order raised to `--tol`),
    /// `sd` (first-order semi-discretisation, `--m` intervals) or `spectral` (`--nodes` per element).
    #[arg(long, default_value = "auto")]
    pub method: String,
    /// `--method auto`: relative tolerance of the boundary (the shift to the next order).
    #[arg(long, default_value_t = 1e-3)]
    pub tol: f64,
    /// `--method sd`: semi-discretisation intervals per tooth period.
    #[arg(long, default_value_t = 40)]
    pub m: usize,
    /// `--method spectral`: Gauss–Legendre nodes per element.
    #[arg(long, default_value_t = 12)]
    pub nodes: usize,
    /// First depth of the upward scan [mm].
    #[arg(long, default_value_t = 0.05)]
    pub start_mm: f64,
    /// Scan factor between depths.
    #[arg(long, default_value_t = 1.1)]
    pub growth: f64,
    /// Largest depth searched [mm].
    #[arg(long, default_value_t = 100.0)]
    pub max_mm: f64,
    /// Relative width of the final bisection bracket.
    #[arg(long, default_value_t = 1e-5)]
    pub rel_tol: f64,
    /// A fast, coarse run (5 speeds, bracket 1e-3; with `--method sd` m = 10) for tests.
    #[arg(long)]
    pub quick: bool,
    /// Speeds [rpm] at which to bisect the time-domain boundary through `MillingPlant.fmu`
    /// (seed 000 family only; `target/fmu`), printed beside the computed boundary.
    #[arg(long, value_delimiter = ',')]
    pub validate_rpm: Vec<f64>,
    /// Simulated time per time-domain run [s].
    #[arg(long, default_value_t = 1.5)]
    pub duration: f64,
    /// Output directory (sd_lobes.csv, sd_lobes.png).
    #[arg(long, default_value = "sd-lobes-out")]
    pub out: PathBuf,
}

fn seed000_params(a: &SdLobesArgs) -> Result<milling_plant::PlantParams> {
    let mut plant: Resolved<_, _> = Resolved { params: plant_by_name(&a.plant)?, inputs: Default::default() };
    if let Some(path) = &a.system {
        let sys = SystemFile::open(path, Some(&packaging::fmu_dir()))?;
        let roles = seed000::scenario::roles(&sys)?;
        plant = fmu_params::resolve::<fmu_plant::MillingPlant>(&sys, &roles.plant, &[])?;
    }
    for s in &a.set {
        let o: Override = s.parse()?;
        let (component, name) = o.target.split_once('.').with_context(|| format!("--set {s}: expected plant.NAME"))?;
        ensure!(component == "plant", "--set {s}: sd-lobes takes plant parameters only (open loop)");
        fmu_params::apply_text::<fmu_plant::MillingPlant>(&mut plant, name, &o.value.to_string())
            .map_err(|e| anyhow::anyhow!("--set {s}: {e}"))?;
    }
    Ok(plant.params)
}

/// The method of `--method` (`--quick` takes m = 10 for `sd`).
fn method(a: &SdLobesArgs) -> Result<Method> {
    Ok(match a.method.as_str() {
        "auto" => Method::Auto { tol: a.tol },
        "sd" => Method::Sd { m: if a.quick { 10 } else { a.m } },
        "spectral" => Method::Spectral(SpectralOptions::new(a.nodes)),
        other => bail!("--method {other}: one of auto, sd, spectral"),
    })
}

/// The boundary and the time-domain boundary through the plant FMU at each speed of `--validate-rpm`.
fn validate(a: &SdLobesArgs, plant: &milling_plant::PlantParams, o: &LobeOptions) -> Result<()> {
    let model = seed000_model(plant)?;
    let sys = seed000::scenario::closed_loop_system(&packaging::fmu_dir())?;
    let check = seed000::sd_validation::SdFmuCheck::new(&sys, plant)?;
    for &rpm in &a.validate_rpm {
        let c = delay_stability::critical(|d| model.at(rpm, d), o).map_err(|e| anyhow::anyhow!("{e}"))?;
        let Some(sd) = c.value else {
            println!("{rpm} rpm: stable up to {} mm, nothing to validate", a.max_mm);
            continue;
        };
        let t = Instant::now();
        let fmu = check.boundary(rpm, (0.9 * sd, 1.1 * sd), a.duration, 2e-3)?;
        println!(
            "{rpm} rpm: computed {:.4} mm ({}), MillingPlant.fmu time domain {:.4} mm ({:+.2} %) [{:.1} s]",
            sd * 1e3,
            c.kind().map_or("none", |k| k.name()),
            fmu * 1e3,
            (fmu / sd - 1.0) * 100.0,
            t.elapsed().as_secs_f64()
        );
    }
    Ok(())
}

pub fn sd_lobes_cmd(a: &SdLobesArgs) -> Result<()> {
    let (model, range, (label, machine)) = match (&a.preset, &a.design) {
        (_, Some(path)) => {
            if !a.set.is_empty() || a.system.is_some() {
                bail!("--design runs seed 002's spindle; --set and --system apply to the seed 000 plant");
            }
            let c = seed002::spindle::sd_controller(&seed002::spindle::design_params(path)?);
            let cutter = delay_stability::presets::seed002_cutter(a.x_f).map_err(|e| anyhow::anyhow!("{e}"))?;
            let model = delay_stability::milling::MillingModel::new(
                &delay_stability::presets::seed002_structure(),
                cutter,
                Some(&c),
            )
            .map_err(|e| anyhow::anyhow!("{e}"))?;
            let range = if (a.x_f - 1.0).abs() < 1e-12 { (36_000.0, 38_000.0) } else { (34_000.0, 36_000.0) };
            let n_c = c.ac.nrows();
            let machine = format!("seed 002 spindle, design {} (n_c = {n_c}, x_F = {})", file_name(path), a.x_f);
            (model, range, (format!("design {} (n_c = {n_c}, x_F = {})", path.display(), a.x_f), machine))
        }
        (Some(name), None) => {
            if !a.set.is_empty() || a.system.is_some() {
                bail!("--preset {name} describes its own machine; --set and --system apply to the seed 000 plant");
            }
            let p = Preset::by_name(name)?;
            (p.model()?, p.speed_range(), (name.clone(), format!("--preset {name}")))
        }
        (None, None) => {
            // the figure names the machine run: the system or the preset, with every --set
            let machine = machine_title(&a.plant, a.system.as_deref(), None, &a.set);
            (seed000_model(&seed000_params(a)?)?, (1000.0, 3000.0), (format!("{} plant", a.plant), machine))
        }
    };
    let rpm_min = a.rpm_min.unwrap_or(range.0);
    let rpm_max = a.rpm_max.unwrap_or(range.1);
    ensure!(
        rpm_min.is_finite() && rpm_min > 0.0 && rpm_max.is_finite() && rpm_max > rpm_min,
        "the speed range [{rpm_min}, {rpm_max}] rpm is empty or not positive"
    );
    let (points, rel_tol) = if a.quick { (5, 1e-3) } else { (a.points, a.rel_tol) };
    ensure!(points >= 2, "--points {points}: need at least 2 speeds");
    let method = method(a)?;
    let o = LobeOptions { method, start: a.start_mm * 1e-3, growth: a.growth, max: a.max_mm * 1e-3, rel_tol };
    let speeds = speed_grid(rpm_min, rpm_max, points);
    let bar = ProgressBar::new(speeds.len() as u64);
    bar.set_style(ProgressStyle::with_template("sd-lobes [{bar:30}] {pos}/{len} speeds ({elapsed})")?);
    let t = Instant::now();
    let pts =
        delay_stability::lobes_with(&speeds, |rpm, d| model.at(rpm, d), &o, &|done, _| bar.set_position(done as u64))
            .map_err(|e| anyhow::anyhow!("{e}"))?;
    bar.finish_and_clear();
    let secs = t.elapsed().as_secs_f64();
    let evals: usize = pts.iter().map(|p| p.critical.evaluations).sum();
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let csv = a.out.join("sd_lobes.csv");
    write_csv(&csv, &pts)?;
    println!(
        "{label}: {} speeds {rpm_min}–{rpm_max} rpm, {}, state {}: {evals} monodromy operators in {secs:.2} s",
        speeds.len(),
        method,
        model.dim(),
    );
    if let Method::Sd { m } = method {
        println!("semi-discretisation: monodromy dimension {}", model.dim() + m * delayed_outputs(&model));
    } else {
        let nodes: Vec<usize> = pts
            .iter()
            .filter_map(|p| match p.critical.method {
                Method::Spectral(s) => Some(s.nodes),
                _ => None,
            })
            .collect();
        let worst = pts.iter().filter_map(|p| p.critical.error).fold(0.0, f64::max);
        println!(
            "spectral collocation: {}–{} nodes per element{}",
            nodes.iter().min().unwrap_or(&0),
            nodes.iter().max().unwrap_or(&0),
            if matches!(method, Method::Auto { .. }) {
                format!(", largest error estimate {worst:.1e} (relative, to the next order)")
            } else {
                String::new()
            }
        );
    }
    match extremes(&pts) {
        Some((lo, hi)) => {
            let kind = |p: &delay_stability::LobePoint| p.critical.kind().map_or("none", |k| k.name());
            println!(
                "a_lim min {:.4} mm at {:.1} rpm ({}), max {:.4} mm at {:.1} rpm ({})",
                lo.critical.value.unwrap_or(f64::NAN) * 1e3,
                lo.rpm,
                kind(&lo),
                hi.critical.value.unwrap_or(f64::NAN) * 1e3,
                hi.rpm,
                kind(&hi)
            );
            let flips = pts.iter().filter(|p| p.critical.kind() == Some(delay_stability::Bifurcation::Flip)).count();
            println!("{flips} of {} speeds end in a flip (period doubling), the rest in Hopf/fold", pts.len());
        }
        None => println!("stable up to {} mm at every speed", a.max_mm),
    }
    let png = a.out.join("sd_lobes.png");
    let curve: Vec<(f64, f64)> = pts.iter().filter_map(|p| p.critical.value.map(|v| (p.rpm, v * 1e3))).collect();
    study_kit::figures::plot_xy(
        &png,
        &format!("Stability lobes: {machine}\n{} speeds {rpm_min}–{rpm_max} rpm, {}", speeds.len(), method),
        "spindle speed [rpm]",
        "limiting depth a_lim [mm]",
        &[("a_lim".to_string(), curve)],
    )?;
    println!("wrote {} and {}", csv.display(), png.display());
    if !a.validate_rpm.is_empty() {
        ensure!(a.preset.is_none(), "--validate-rpm runs MillingPlant.fmu: the seed 000 family only");
        validate(a, &seed000_params(a)?, &LobeOptions { rel_tol: 1e-5, ..o })?;
    }
    Ok(())
}

/// Number of delayed outputs r of the model (the semi-discretisation's dimension is n + r m).
fn delayed_outputs(model: &delay_stability::milling::MillingModel) -> usize {
    use delay_stability::PeriodicDde;
    model.at(1000.0, 0.0).map_or(0, |s| s.delayed_output().nrows())
}
