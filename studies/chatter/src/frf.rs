//! `chatter frf fit|convert|synth`: measured tool-point FRFs (a tap test's CSV or UFF 58 files)
//! to modes, a machine file and a `ModalStructure` parameter set; format conversion; a synthetic
//! tap test of a machine file (the `machine::frf` module).

use anyhow::{Context, Result, ensure};
use clap::{Args, Subcommand};
use machine::Machine;
use machine::frf::{MeasuredFrf, csv};
use machine::frf_fit::plots;
use machine::frf_fit::synth::{TapTest, tap_test};
use machine::frf_fit::{FitOptions, fit};
use std::path::{Path, PathBuf};

#[derive(Subcommand)]
pub enum FrfCmd {
    /// Fit modes to measured FRFs: stabilisation diagram, modes, overlay, machine file, ModalStructure SSV.
    Fit(FitArgs),
    /// Convert FRF files between CSV and UFF 58 (ASCII or binary).
    Convert(ConvertArgs),
    /// A synthetic tap test of a machine file's modes (noisy FRFs on a measurement grid).
    Synth(SynthArgs),
}

#[derive(Args)]
pub struct FitArgs {
    /// FRF files: .csv (frequency, real, imaginary per pair) or .uff/.unv (UFF 58); xx and yy required.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// The band to fit [Hz] (default: around the driving points' peaks, within the data).
    #[arg(long, value_delimiter = ',', num_args = 2, value_names = ["LOW", "HIGH"])]
    pub band: Option<Vec<f64>>,
    /// Highest model order of the stabilisation diagram (orders 4, 6, …).
    #[arg(long, default_value_t = 40)]
    pub max_order: usize,
    /// A machine file whose [structure] is replaced by the fit in `OUT/machine.toml`.
    #[arg(long)]
    pub machine: Option<PathBuf>,
    /// Output directory (fit.md, modes.csv, stabilisation.csv/.png, overlay.png, fitted.csv,
    /// structure.toml, structure.ssv, machine.toml with --machine).
    #[arg(long, default_value = "frf-fit")]
    pub out: PathBuf,
}

#[derive(Args)]
pub struct ConvertArgs {
    /// FRF files to read (.csv, .uff/.unv).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// The file to write: .csv or .uff (refused if it exists).
    #[arg(long)]
    pub out: PathBuf,
    /// Write UFF 58 binary (58b) instead of ASCII.
    #[arg(long)]
    pub binary: bool,
}

#[derive(Args)]
pub struct SynthArgs {
    /// The machine file whose modes are "measured".
    #[arg(long)]
    pub machine: PathBuf,
    /// Relative complex noise (0.05 = 5 %).
    #[arg(long, default_value_t = 0.05)]
    pub noise: f64,
    /// Seed of the noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Frequency resolution [Hz].
    #[arg(long, default_value_t = 1.0)]
    pub resolution: f64,
    /// Highest frequency [Hz] (from 0 Hz).
    #[arg(long, default_value_t = 5000.0)]
    pub max_hz: f64,
    /// The file to write: .csv or .uff (refused if it exists).
    #[arg(long)]
    pub out: PathBuf,
    /// Write UFF 58 binary (58b) instead of ASCII.
    #[arg(long)]
    pub binary: bool,
}

pub fn frf(cmd: &FrfCmd) -> Result<()> {
    match cmd {
        FrfCmd::Fit(a) => fit_cmd(a),
        FrfCmd::Convert(a) => {
            let m = MeasuredFrf::read(&a.files)?;
            machine::frf::write_new(&m, &a.out, a.binary)?;
            println!("wrote {} ({} FRFs, {} frequencies)", a.out.display(), m.h.len(), m.freq_hz.len());
            Ok(())
        }
        FrfCmd::Synth(a) => {
            let m = crate::own_machine::load(&a.machine)?;
            let t = TapTest { range_hz: (0.0, a.max_hz), resolution_hz: a.resolution, noise: a.noise, seed: a.seed };
            let frf = tap_test(&m, &t).map_err(anyhow::Error::msg)?;
            machine::frf::write_new(&frf, &a.out, a.binary)?;
            println!("wrote {}: {}", a.out.display(), frf.notes.join("; "));
            Ok(())
        }
    }
}

/// A new file (refused if it exists: no command overwrites a file).
fn create_new(path: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write;
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
        .with_context(|| format!("{}: not written (it exists, or its folder does not)", path.display()))?;
    f.write_all(bytes).with_context(|| format!("writing {}", path.display()))
}

const OUTPUTS: [&str; 10] = [
    "modal_table.csv",
    "fit.md",
    "modes.csv",
    "stabilisation.csv",
    "stabilisation.png",
    "overlay.png",
    "fitted.csv",
    "structure.toml",
    "structure.ssv",
    "machine.toml",
];

fn fit_cmd(a: &FitArgs) -> Result<()> {
    // never write over an input
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let out_dir = a.out.canonicalize()?;
    for input in a.files.iter().chain(&a.machine) {
        let c = input.canonicalize().with_context(|| format!("{}: cannot read", input.display()))?;
        ensure!(
            !OUTPUTS.iter().any(|o| out_dir.join(o) == c),
            "{}: an input would be overwritten by the fit's output of the same name; choose another --out",
            input.display()
        );
    }
    ensure!(
        a.machine.is_none() || !a.out.join("machine.toml").exists(),
        "{}: exists (a machine file is never overwritten): choose another --out",
        a.out.join("machine.toml").display()
    );
    let frf = MeasuredFrf::read(&a.files)?;
    let o = FitOptions { band_hz: a.band.as_ref().map(|b| (b[0], b[1])), max_order: a.max_order };
    let f = fit(&frf, &o).map_err(|e| anyhow::anyhow!("{}: {e}", frf.source))?;
    let report = f.report(&frf);
    println!("{report}");
    let w = |name: &str, text: &str| std::fs::write(a.out.join(name), text).with_context(|| format!("writing {name}"));
    w("fit.md", &report)?;
    w("modes.csv", &f.modes_csv())?;
    w("stabilisation.csv", &f.stabilisation_csv())?;
    w("fitted.csv", &csv::write(&f.fitted(&frf, false), "the fitted modes (no residual terms)"))?;
    let title = a
        .files
        .iter()
        .map(|p| p.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned()))
        .collect::<Vec<_>>()
        .join(", ");
    plots::overlay_png(&a.out.join("overlay.png"), &format!("Measured and fitted FRFs: {title}"), &frf, &f)?;
    plots::stabilisation_png(&a.out.join("stabilisation.png"), &format!("Stabilisation diagram: {title}"), &frf, &f)?;
    let files: Vec<String> =
        a.files.iter().map(|p| p.canonicalize().map(|c| c.display().to_string())).collect::<Result<_, _>>()?;
    let structure = f.structure_toml(&files);
    w("structure.toml", &structure)?;
    // the outputs written so far (OUTPUTS[1..8]); the SSV, its table and the machine file follow
    let mut written: Vec<&str> = OUTPUTS[1..8].to_vec();
    let base = a.machine.as_ref().map(|p| crate::own_machine::load(p)).transpose()?;
    let at_actuator = base.as_ref().is_some_and(|m| m.actuator.is_some());
    match machine::fmus::structure_ssv(&f.modes, at_actuator, "fitted modes", &out_dir.join("modal_table.csv")) {
        Ok((ssv, table)) => {
            w("structure.ssv", &ssv)?;
            written.push("structure.ssv");
            if let Some(t) = table {
                w("modal_table.csv", &t)?;
                written.push("modal_table.csv (named by structure.ssv's modal_table)");
            }
        }
        Err(e) => println!("structure.ssv not written: {e}"),
    }
    if let Some(path) = &a.machine {
        let text = std::fs::read_to_string(path)?;
        let mut table: toml::Table = text.parse().with_context(|| format!("{}", path.display()))?;
        let fitted: toml::Table = structure.parse().expect("the fit writes valid TOML");
        table.insert("structure".into(), fitted["structure"].clone());
        let new = toml::to_string(&table)?;
        let target = a.out.join("machine.toml");
        Machine::from_toml(&new, &target.display().to_string()).map_err(|e| anyhow::anyhow!("{e}"))?;
        create_new(
            &target,
            format!("# {} with the modes fitted by `chatter frf fit`\n{new}", path.display()).as_bytes(),
        )?;
        written.push("machine.toml");
    }
    println!("wrote {}: {}", a.out.display(), written.join(", "));
    Ok(())
}
