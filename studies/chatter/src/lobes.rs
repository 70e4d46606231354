//! `chatter lobes`: lobe diagrams of any machine for several controllers on common axes.
//!
//! The machine and the controller gains are described with the FMUs' own parameter names:
//! `--set plant.workpiece.mass=32 --set controller.fopid.kp=2e3` (exactly as `cosim run --set`),
//! or by pointing at a system (`--system my.ssp`) whose parameter bindings are read through the
//! FMUs' tables; `--plant seed|ozsoy` and `--preset table2|tuned` choose the starting point.
//! The lobes and a time-domain run of the FMUs then use one parameter set.

use crate::common::*;
use anyhow::{Context, Result, bail, ensure};
use chatter_control::ControllerParams;
use clap::Args;
use delay_stability::zero_order::speed_grid;
use fmi_master::{Override, SystemFile};
use milling_plant::PlantParams;
use seed000::lobes_cases::LobesSpec;
use std::path::{Path, PathBuf};
use std::time::Instant;
use study_kit::fmu_params::{self, Resolved};
use study_kit::output::{Series, plot_png, write_csv};

#[derive(Args)]
pub struct LobesArgs {
    /// Starting plant: `seed` (Tables 1, 4) or `ozsoy` (Section 5.7 benchmark).
    #[arg(long, default_value = "seed")]
    pub plant: String,
    /// Workpiece modes (1 or 3: the seed's higher modes at 895.8 and 2499.8 Hz); same as
    /// `--set plant.workpiece.modes=N`.
    #[arg(long)]
    pub modes: Option<u32>,
    /// Take the plant's and the controller's parameters from this system's bindings (.ssp/.ssd).
    #[arg(long)]
    pub system: Option<PathBuf>,
    /// A parameter of the plant or controller FMU: `plant.NAME=VALUE` or `controller.NAME=VALUE`
    /// (the FMUs' variable names, SI units, enumeration items by name); repeatable, applied last.
    #[arg(long = "set", value_name = "plant|controller.NAME=VALUE")]
    pub set: Vec<String>,
    /// Controllers to draw (`off` = open loop; default `off,pid,fopid,adrc_fopid`, with
    /// `--machine` the open loop and the file's controller).
    #[arg(long, value_delimiter = ',')]
    pub controllers: Option<Vec<String>>,
    #[command(flatten)]
    pub gains: GainArgs,
    /// Lowest speed [rpm] (default 1000; with `--machine` the file's speed range).
    #[arg(long)]
    pub rpm_min: Option<f64>,
    /// Highest speed [rpm] (default 3000).
    #[arg(long)]
    pub rpm_max: Option<f64>,
    /// Number of speeds (default 2001 over 1000–3000 rpm = 1 rpm steps; with `--machine` 200).
    #[arg(long)]
    pub points: Option<usize>,
    /// Your own machine: a machine file (TOML; see the docs' "Your own machine"). Its lobes by
    /// zero-order, multi-frequency and semi-discretisation side by side, closed-loop lobes with
    /// the actuator's limit.
    #[arg(long, conflicts_with_all = ["plant", "modes", "system", "set"])]
    pub machine: Option<PathBuf>,
    #[command(flatten)]
    pub machine_options: crate::own_machine::MachineLobeOptions,
    /// Output directory (lobes.csv, lobes.png).
    #[arg(long, default_value = "lobes-out")]
    pub out: PathBuf,
}

/// The plant and the base controller parameters: preset, system bindings, `--set`.
fn machine(a: &LobesArgs) -> Result<(PlantParams, ControllerParams)> {
    let mut plant: Resolved<_, _> = Resolved { params: plant_by_name(&a.plant)?, inputs: Default::default() };
    let mut ctrl: Resolved<_, _> = Resolved { params: controller_preset(&a.gains)?, inputs: Default::default() };
    if let Some(path) = &a.system {
        let sys = SystemFile::open(path, Some(&packaging::fmu_dir()))?;
        let roles = seed000::scenario::roles(&sys)?;
        plant = fmu_params::resolve::<fmu_plant::MillingPlant>(&sys, &roles.plant, &[])?;
        ctrl = fmu_params::resolve::<fmu_controller::ChatterController>(&sys, &roles.controller, &[])?;
    }
    for s in &a.set {
        let o: Override = s.parse()?;
        let (component, name) =
            o.target.split_once('.').with_context(|| format!("--set {s}: expected plant.NAME or controller.NAME"))?;
        let value = o.value.to_string();
        match component {
            "plant" => fmu_params::apply_text::<fmu_plant::MillingPlant>(&mut plant, name, &value),
            "controller" => fmu_params::apply_text::<fmu_controller::ChatterController>(&mut ctrl, name, &value),
            c => bail!("--set {s}: the component is `plant` or `controller`, not `{c}`"),
        }
        .map_err(|e| anyhow::anyhow!("--set {s}: {e}"))?;
    }
    if let Some(m) = a.modes {
        plant.params.workpiece.modes = m;
    }
    plant.params.validate().map_err(|e| anyhow::anyhow!("plant: {e}"))?;
    ctrl.params.validate().map_err(|e| anyhow::anyhow!("controller: {e}"))?;
    Ok((plant.params, ctrl.params))
}

/// `chatter plan lobes`: the lobes' options and the chunk size.
#[derive(Args)]
pub struct LobesPlanArgs {
    #[command(flatten)]
    pub lobes: LobesArgs,
    /// Speeds per case.
    #[arg(long, default_value_t = 200)]
    pub chunk: usize,
}

impl LobesPlanArgs {
    /// The study's spec (what `chatter plan lobes` writes into the manifest).
    pub fn spec(&self) -> Result<LobesSpec> {
        let a = &self.lobes;
        check_range(a)?;
        let (plant, base) = machine(a)?;
        ensure!(
            a.machine.is_none(),
            "chatter plan lobes takes the seed plant (--plant, --set, --system); run `chatter lobes --machine` locally"
        );
        let controllers = controller_names(a)
            .iter()
            .map(|n| Ok((n.clone(), controller_from(&base, structure_by_name(n)?, &a.gains)?)))
            .collect::<Result<Vec<_>>>()?;
        Ok(LobesSpec {
            title: title(a),
            plant,
            controllers,
            rpm_min: a.rpm_min.unwrap_or(RPM_MIN),
            rpm_max: a.rpm_max.unwrap_or(RPM_MAX),
            points: a.points.unwrap_or(POINTS),
            chunk: self.chunk,
        })
    }
}

/// The figure's title: the machine actually analysed (the system file's name or the plant
/// preset, with every change to it) and, on a second line, where the controllers' gains come from.
fn title(a: &LobesArgs) -> String {
    let machine = machine_title(&a.plant, a.system.as_deref(), a.modes, &a.set);
    let gains = match &a.system {
        Some(p) => format!("controllers: the parameters of {}{}", file_name(p), gains_overrides(&a.gains)),
        None => gains_title(&a.gains),
    };
    format!("Stability lobes: {machine}\n{gains}")
}

/// A file's name (its path without the folders).
pub fn file_name(p: &Path) -> String {
    p.file_name().map_or_else(|| p.display().to_string(), |f| f.to_string_lossy().into_owned())
}

/// The machine a lobe command analyses: the plant of `system` or the preset `plant`, with
/// `--modes` and the `--set` overrides.
pub fn machine_title(plant: &str, system: Option<&Path>, modes: Option<u32>, set: &[String]) -> String {
    let base = match system {
        Some(p) => format!("the plant of {}", file_name(p)),
        None => match plant {
            "seed" => "seed 000 plant (Tables 1, 4)".to_string(),
            "ozsoy" => "Ozsoy et al. benchmark plant".to_string(),
            other => format!("{other} plant"),
        },
    };
    let changes: Vec<String> =
        modes.map(|m| format!("plant.workpiece.modes={m}")).into_iter().chain(set.iter().cloned()).collect();
    if changes.is_empty() { base } else { format!("{base} with {}", changes.join(", ")) }
}

/// Where the gains come from: `--preset` and any `--pid`, `--fopid`, `--adrc`.
pub fn gains_title(g: &GainArgs) -> String {
    format!("gains: --preset {}{}", g.preset, gains_overrides(g))
}

fn gains_overrides(g: &GainArgs) -> String {
    let join = |v: &Vec<f64>| v.iter().map(f64::to_string).collect::<Vec<_>>().join(",");
    [("--pid", &g.pid), ("--fopid", &g.fopid), ("--adrc", &g.adrc)]
        .iter()
        .filter_map(|(flag, v)| v.as_ref().map(|v| format!(", {flag} {}", join(v))))
        .collect()
}

/// The seed plant's default speed range and grid.
const RPM_MIN: f64 = 1000.0;
const RPM_MAX: f64 = 3000.0;
const POINTS: usize = 2001;

/// The controllers of `--controllers` (default: all four).
fn controller_names(a: &LobesArgs) -> Vec<String> {
    a.controllers.clone().unwrap_or_else(|| ["off", "pid", "fopid", "adrc_fopid"].map(String::from).to_vec())
}

fn check_range(a: &LobesArgs) -> Result<()> {
    let (lo, hi, n) = (a.rpm_min.unwrap_or(RPM_MIN), a.rpm_max.unwrap_or(RPM_MAX), a.points.unwrap_or(POINTS));
    ensure!(
        lo.is_finite() && lo > 0.0 && hi.is_finite() && hi > lo,
        "the speed range [{lo}, {hi}] rpm is empty or not positive (need 0 < --rpm-min < --rpm-max)"
    );
    ensure!(n >= 2, "--points {n}: need at least 2 speeds");
    Ok(())
}

pub fn lobes(a: &LobesArgs) -> Result<()> {
    if let Some(file) = &a.machine {
        let m = crate::own_machine::load(file)?;
        let controllers = a.controllers.clone().unwrap_or_else(|| {
            let mut c = vec!["off".to_string()];
            c.extend(m.controller.as_ref().map(|c| c.structure.clone()).filter(|s| s != "off"));
            c
        });
        let range = match (a.rpm_min, a.rpm_max) {
            (None, None) => None,
            (lo, hi) => {
                Some((lo.unwrap_or(m.operation.speed_range_rpm.0), hi.unwrap_or(m.operation.speed_range_rpm.1)))
            }
        };
        return crate::own_machine::lobes(
            file,
            &controllers,
            range,
            a.points.unwrap_or(200),
            &a.machine_options,
            &a.out,
        );
    }
    check_range(a)?;
    let (plant, base) = machine(a)?;
    println!(
        "MillingPlant's model: the workpiece bends along one direction (zero-order lobes of that direction). For a machine with modes in x and y, use `chatter lobes --machine FILE`."
    );
    let rpm = speed_grid(a.rpm_min.unwrap_or(RPM_MIN), a.rpm_max.unwrap_or(RPM_MAX), a.points.unwrap_or(POINTS));
    let mut series = Vec::new();
    for name in &controller_names(a) {
        let c = controller_from(&base, structure_by_name(name)?, &a.gains)?;
        let t = Instant::now();
        let (d, ex) = diagram(&plant, &c, &rpm)?;
        let secs = t.elapsed().as_secs_f64();
        let (stable, sat) = loop_checks(&plant, &c)?;
        println!("{name:>11}: {}  [{} speeds in {secs:.2} s]", fmt_ex(&ex), rpm.len());
        println!("{:>11}  closed loop stable without cutting: {stable}; saturation check exceeded: {sat}", "");
        series.push(Series { name: name.clone(), points: d });
    }
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let csv = a.out.join("lobes.csv");
    let png = a.out.join("lobes.png");
    write_csv(&csv, &series)?;
    plot_png(&png, &title(a), &series, 1200, 800)?;
    println!("wrote {} and {}", csv.display(), png.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        lobes: LobesArgs,
    }

    fn title_of(args: &[&str]) -> String {
        title(&Cli::parse_from(std::iter::once("lobes").chain(args.iter().copied())).lobes)
    }

    #[test]
    fn the_title_names_the_machine_that_was_run() {
        assert_eq!(title_of(&[]), "Stability lobes: seed 000 plant (Tables 1, 4)\ngains: --preset table2");
        // a changed plant is no longer "the seed plant": every change is named
        assert_eq!(
            title_of(&[
                "--plant",
                "ozsoy",
                "--modes",
                "3",
                "--set",
                "plant.workpiece.mass=32",
                "--pid",
                "2300,0.012,180"
            ]),
            "Stability lobes: Ozsoy et al. benchmark plant with plant.workpiece.modes=3, plant.workpiece.mass=32\n\
             gains: --preset table2, --pid 2300,0.012,180"
        );
        // a system by its file name (not its folders), its controller parameters with it
        let t = title_of(&["--system", "/home/someone/machines/mill 7.ssp", "--preset", "tuned"]);
        assert_eq!(t, "Stability lobes: the plant of mill 7.ssp\ncontrollers: the parameters of mill 7.ssp");
    }
}
