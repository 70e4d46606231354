//! `cosim`: the command line of the FMI 2.0 co-simulation master.
//!
//! ```text
//! cosim run [SYSTEM] [--set c.v=x]... [--stop-time T] [--step H] [--order gauss-seidel|jacobi]
//!           [--record c.v,...] [--output-interval DT] [-o results.csv] [--fmu-dir DIR] [--preload LIB]
//! cosim main-job [--out results] [--seeds 10] [--stop-time 30] ...
//! cosim info FILE            # an .fmu's variables, or an .ssp/.ssd's structure
//! cosim plot CSV [--var v]... [-o plot.png] [--spectrum 400] [--mark 133.3=tooth-passing]...
//! cosim ssd                  # print the embedded closed-loop SystemStructure.ssd
//! ```
//! SYSTEM is an `.ssp`, an `.ssd` or a single `.fmu`; without it, the
//! embedded closed loop (`scenarios/ClosedLoop.ssd`) runs with the FMUs of
//! `--fmu-dir` (default `target/fmu`). Errors print a message (with the
//! FMU's own log lines for FMU failures), each cause once, and exit with status 1.

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use fmi_master::engine::{Progress, RunConfig, Simulation};
use fmi_master::mainjob::{self, MainJobConfig};
use fmi_master::overrides::Override;
use fmi_master::plot::Mark;
use fmi_master::ssp::Order;
use fmi_master::system::{SystemFile, default_fmu_dir};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "cosim", version, about = "FMI 2.0 co-simulation master with SSP 1.0 system files")]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run a system (.ssp, .ssd) or a single .fmu; results stream to CSV.
    Run(RunArgs),
    /// The seed paper's nominal scenario over all controllers and noise seeds (Table 5, Figures 6-7).
    MainJob(MainJobArgs),
    /// Describe an .fmu (variables) or a system (.ssp/.ssd).
    Info {
        /// The file.
        file: PathBuf,
    },
    /// Plot columns of a results CSV (time histories, optionally spectra).
    Plot(PlotArgs),
    /// Print the embedded closed-loop SystemStructure.ssd.
    Ssd,
}

#[derive(Args, Clone)]
struct Common {
    /// Directory with the project's FMUs, for component sources `resources/X.fmu` (default: $FMU_DIR, else target/fmu).
    #[arg(long)]
    fmu_dir: Option<PathBuf>,
    /// Load a shared library globally before any FMU (e.g. libpython for pythonfmu FMUs).
    #[arg(long)]
    preload: Vec<PathBuf>,
    /// Print the FMUs' log messages as they arrive.
    #[arg(long)]
    fmu_log: bool,
}

#[derive(Args)]
struct RunArgs {
    /// .ssp, .ssd or .fmu (default: the embedded closed loop with the FMUs of --fmu-dir).
    system: Option<PathBuf>,
    /// Override a parameter or input start value: component.variable=value (repeatable).
    #[arg(long = "set", value_name = "COMPONENT.VARIABLE=VALUE")]
    set: Vec<String>,
    /// Start time [s].
    #[arg(long)]
    start_time: Option<f64>,
    /// Stop time [s].
    #[arg(long)]
    stop_time: Option<f64>,
    /// Communication step [s].
    #[arg(long)]
    step: Option<f64>,
    /// Stepping order: gauss-seidel or jacobi.
    #[arg(long)]
    order: Option<String>,
    /// Gauss-Seidel sequence of components, e.g. controller,plant.
    #[arg(long, value_delimiter = ',')]
    sequence: Option<Vec<String>>,
    /// Variables to record (component.variable, comma separated); default: all outputs.
    #[arg(long, value_delimiter = ',')]
    record: Option<Vec<String>>,
    /// Output interval [s] (a multiple of the step); default: every step.
    #[arg(long)]
    output_interval: Option<f64>,
    /// Results CSV.
    #[arg(short, long, default_value = "results.csv")]
    output: PathBuf,
    /// No progress bar, no summary.
    #[arg(short, long)]
    quiet: bool,
    #[command(flatten)]
    common: Common,
}

#[derive(Args)]
struct MainJobArgs {
    /// System to run (default: target/fmu/ClosedLoop.ssp if it exists, else the embedded SSD with --fmu-dir).
    #[arg(long)]
    system: Option<PathBuf>,
    /// Output directory for CSVs, plots and the table.
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// Number of noise seeds per controller.
    #[arg(long, default_value_t = 10)]
    seeds: u32,
    /// First seed.
    #[arg(long, default_value_t = 1)]
    first_seed: u32,
    /// Stop time [s] (default: the system's, 30 s).
    #[arg(long)]
    stop_time: Option<f64>,
    /// Communication step [s] (default: the system's, 10 µs).
    #[arg(long)]
    step: Option<f64>,
    /// Output interval of the per-run CSV files [s].
    #[arg(long, default_value_t = 1e-3)]
    csv_interval: f64,
    /// Controller structures to compare, as label=item (items of the controller's structure enumeration).
    #[arg(long, value_delimiter = ',', default_value = "Open loop=off,PID=pid,FOPID=fopid,ADRC-FOPID=adrc_fopid")]
    cases: Vec<String>,
    /// Extra overrides applied to every run (component.variable=value).
    #[arg(long = "set")]
    set: Vec<String>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    #[command(flatten)]
    common: Common,
}

#[derive(Args)]
struct PlotArgs {
    /// A results CSV.
    csv: PathBuf,
    /// Columns to plot (default: all).
    #[arg(long = "var")]
    vars: Vec<String>,
    /// Output PNG (the spectrum goes next to it as <stem>_spectrum.png).
    #[arg(short, long, default_value = "plot.png")]
    output: PathBuf,
    /// Also plot single-sided amplitude spectra up to this frequency [Hz].
    #[arg(long)]
    spectrum: Option<f64>,
    /// Reference frequencies to mark: FREQ=LABEL (repeatable).
    #[arg(long = "mark")]
    marks: Vec<String>,
}

fn preload(c: &Common) -> Result<()> {
    for p in &c.preload {
        fmi_master::import::preload_global(p)?;
    }
    Ok(())
}

fn overrides(list: &[String]) -> Result<Vec<Override>> {
    list.iter().map(|s| s.parse::<Override>().map_err(anyhow::Error::from)).collect()
}

fn open_system(path: Option<&PathBuf>, fmu_dir: Option<&PathBuf>) -> Result<SystemFile> {
    let dir = fmu_dir.cloned().unwrap_or_else(default_fmu_dir);
    Ok(match path {
        Some(p) => SystemFile::open(p, Some(&dir))?,
        None => SystemFile::from_text(fmi_master::CLOSED_LOOP_SSD, "embedded scenarios/ClosedLoop.ssd", &dir)?,
    })
}

fn run(a: RunArgs) -> Result<()> {
    preload(&a.common)?;
    let sys = open_system(a.system.as_ref(), a.common.fmu_dir.as_ref())?;
    let order = match &a.order {
        None => None,
        Some(s) => Some(Order::parse(s).with_context(|| format!("--order {s}: expected gauss-seidel or jacobi"))?),
    };
    let cfg = RunConfig {
        start: a.start_time,
        stop: a.stop_time,
        step: a.step,
        order,
        sequence: a.sequence.clone(),
        overrides: overrides(&a.set)?,
        record: a.record.clone(),
        output_interval: a.output_interval,
        echo_fmu_log: a.common.fmu_log,
    };
    let mut sim = Simulation::new(&sys, &cfg)?;
    let mut csv = fmi_master::csv::CsvWriter::create(&a.output)?;
    let progress = if a.quiet { Progress::Off } else { Progress::Auto };
    let stats = sim.run(&mut csv, progress)?;
    if !a.quiet {
        let comps: Vec<String> = sim.components().iter().map(|(n, id)| format!("{n} ({id})")).collect();
        eprintln!(
            "{}: {} steps of {} s ({}{}) in {:.3} s ({:.0} steps/s); {} rows → {}",
            sys.origin,
            stats.steps,
            sim.step(),
            sim.order().as_str(),
            if sim.order() == Order::GaussSeidel {
                format!(": {}", sim.sequence().join(" → "))
            } else {
                String::new()
            },
            stats.wall.as_secs_f64(),
            stats.steps as f64 / stats.wall.as_secs_f64().max(1e-9),
            csv.rows(),
            a.output.display()
        );
        eprintln!("components: {}", comps.join(", "));
    }
    Ok(())
}

fn info(file: &Path) -> Result<()> {
    let ext = file.extension().and_then(|e| e.to_str()).unwrap_or("");
    if ext.eq_ignore_ascii_case("fmu") {
        let md = fmi_master::import::read_model_description(file)?;
        println!(
            "{}: model {} (modelIdentifier {}), GUID {}",
            file.display(),
            md.model_name,
            md.model_identifier().unwrap_or(""),
            md.guid
        );
        if let Some(g) = &md.generation_tool {
            println!("generated by {g}");
        }
        if let Some(d) = &md.default_experiment {
            println!("default experiment: start {:?} stop {:?} step {:?}", d.start_time, d.stop_time, d.step_size);
        }
        println!("{:<32} {:<20} {:<11} {:<12} {:>14} unit", "variable", "causality", "variability", "type", "start");
        for v in md.variables() {
            let start = v.start_value().map(|s| format!("{s:?}")).unwrap_or_default();
            println!(
                "{:<32} {:<20} {:<11} {:<12} {:>14} {}",
                v.name,
                format!("{:?}", v.causality),
                format!("{:?}", v.variability),
                format!("{:?}", v.scalar_type()),
                start,
                v.unit().unwrap_or("")
            );
        }
    } else {
        let sys = SystemFile::open(file, None)?;
        let d = &sys.desc;
        println!("system {} ({} components, {} connections)", d.system_name, d.components.len(), d.connections.len());
        for c in &d.components {
            println!("  component {} ← {}", c.name, c.source);
            for p in &c.parameters {
                println!("    parameter {} = {}", p.name, p.value);
            }
        }
        for p in &d.parameters {
            println!("  system parameter {} = {}", p.name, p.value);
        }
        for c in &d.connections {
            println!("  connection {}", c.label());
        }
        println!(
            "  default experiment: start {:?} stop {:?}; step {:?}, order {:?}, sequence {:?}",
            d.start_time, d.stop_time, d.master.step_size, d.master.order, d.master.sequence
        );
    }
    Ok(())
}

fn plot(a: PlotArgs) -> Result<()> {
    let marks = a
        .marks
        .iter()
        .map(|m| {
            let (f, l) = m.split_once('=').unwrap_or((m.as_str(), ""));
            Ok(Mark {
                freq: f.parse().with_context(|| format!("--mark {m}: '{f}' is not a frequency"))?,
                label: l.to_string(),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    fmi_master::plot::plot_csv(&a.csv, &a.vars, &a.output, a.spectrum.map(|f| (f, marks)))?;
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

fn main_job(a: MainJobArgs) -> Result<()> {
    preload(&a.common)?;
    let fmu_dir = a.common.fmu_dir.clone().unwrap_or_else(default_fmu_dir);
    let system = match &a.system {
        Some(p) => Some(p.clone()),
        None => {
            let ssp = fmu_dir.join("ClosedLoop.ssp");
            ssp.exists().then_some(ssp)
        }
    };
    let sys = open_system(system.as_ref(), Some(&fmu_dir))?;
    let mut cases = Vec::new();
    for c in &a.cases {
        let (label, item) = c.split_once('=').with_context(|| format!("--cases {c}: expected LABEL=ITEM"))?;
        cases.push((label.to_string(), item.to_string()));
    }
    if let Some(n) = a.threads {
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("configuring the thread pool")?;
    }
    let cfg = MainJobConfig {
        out: a.out.clone(),
        seeds: (a.first_seed..a.first_seed + a.seeds).collect(),
        stop: a.stop_time,
        step: a.step,
        csv_interval: a.csv_interval,
        cases,
        overrides: overrides(&a.set)?,
        echo_fmu_log: a.common.fmu_log,
    };
    let report = mainjob::run(&sys, &cfg)?;
    println!("{}", report.table_text);
    println!("wrote {}", report.written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join("\n      "));
    println!("total wall time: {:.1} s on {} threads", report.wall.as_secs_f64(), rayon::current_num_threads());
    Ok(())
}

/// The error and its causes, `: `-separated, skipping a cause whose text the
/// message already contains (an I/O error quoted by the error that wraps it).
fn report(e: &anyhow::Error) -> String {
    let mut msg = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if msg.contains(&text) {
            continue;
        }
        if !msg.is_empty() {
            msg.push_str(": ");
        }
        msg.push_str(&text);
    }
    msg
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let r = match cli.cmd {
        Cmd::Run(a) => run(a),
        Cmd::MainJob(a) => main_job(a),
        Cmd::Info { file } => info(&file),
        Cmd::Plot(a) => plot(a),
        Cmd::Ssd => {
            print!("{}", fmi_master::CLOSED_LOOP_SSD);
            Ok(())
        }
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", report(&e));
            ExitCode::FAILURE
        }
    }
}
