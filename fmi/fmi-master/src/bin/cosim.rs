//! `cosim`: the command line of the FMI 2.0 co-simulation master.
//!
//! ```text
//! cosim run [SYSTEM] [--set c.v=x]... [--stop-time T] [--step H] [--order gauss-seidel|jacobi]
//!           [--record c.v,...] [--output-interval DT] [-o results.csv] [--fmu-dir DIR] [--preload LIB]
//! cosim info FILE            # an .fmu's variables, or an .ssp/.ssd's structure
//! cosim plot CSV [--system SYSTEM] [--var v]... [-o plot.png] [--spectrum 400] [--mark 133.3=tooth-passing]...
//! cosim ssd SYSTEM           # print a system's SystemStructure.ssd (as this master reads it)
//! ```
//! SYSTEM is an `.ssp`, an `.ssd` or a single `.fmu`; an `.ssd`'s component
//! sources `resources/X.fmu` are looked up in `--fmu-dir` (default `$FMU_DIR`). Errors print a message (with the
//! FMU's own log lines for FMU failures), each cause once, and exit with status 1.
//!
//! `run` streams its CSV with a sidecar `<csv>.incomplete` that is removed only
//! when the run succeeds (see `fmi_master::csv`). An FMU calling `exit()` during
//! the run ends `cosim` with status 3 (`EXIT_DURING_RUN`) and an error message;
//! SIGINT/SIGTERM/SIGHUP end it with 128 + the signal. On every path the process
//! survives, the extraction directories are removed.

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use fmi_master::engine::{AlgebraicLoops, Progress, RunConfig, Simulation};
use fmi_master::import::process::{RunInProgress, install_exit_guard, install_signal_cleanup};
use fmi_master::overrides::Override;
use fmi_master::plot::Mark;
use fmi_master::ssp::Order;
use fmi_master::system::SystemFile;
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
    /// Describe an .fmu (variables) or a system (.ssp/.ssd).
    Info {
        /// The file.
        file: PathBuf,
    },
    /// Plot columns of a results CSV (time histories, optionally spectra).
    Plot(PlotArgs),
    /// Print a system's SystemStructure.ssd as this master reads it (bindings resolved into it).
    Ssd {
        /// The .ssp or .ssd.
        system: PathBuf,
        #[command(flatten)]
        common: Common,
    },
}

#[derive(Args, Clone)]
struct Common {
    /// Directory of the FMUs an .ssd names as `resources/X.fmu` (default: $FMU_DIR).
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
    /// .ssp, .ssd or .fmu.
    system: PathBuf,
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
    /// Results CSV (refused if it is an input of the run, a directory, an FMU/SSP archive, or a
    /// CSV another run is writing now).
    #[arg(short, long, default_value = "results.csv")]
    output: PathBuf,
    /// The most communication steps the run may take (default 100000000).
    #[arg(long)]
    max_steps: Option<u64>,
    /// An algebraic loop (connections through declared direct feedthrough) is refused (refuse,
    /// the default) or solved by fixed-point iteration at every communication point (iterate).
    #[arg(long, value_name = "refuse|iterate", default_value = "refuse")]
    algebraic_loops: String,
    /// No progress bar, no summary.
    #[arg(short, long)]
    quiet: bool,
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
    /// Also plot single-sided amplitude spectra of the frequencies up to this one [Hz]; the range
    /// drawn is chosen within it from the marks and where the spectra have energy (the 0 Hz bin,
    /// the mean, is not drawn).
    #[arg(long)]
    spectrum: Option<f64>,
    /// Reference frequencies to mark: FREQ=LABEL (repeatable).
    #[arg(long = "mark")]
    marks: Vec<String>,
    /// The system (.ssp, .ssd, .fmu) the CSV is a run of: the axes take each variable's unit and
    /// the panels its description from the model descriptions of its FMUs.
    #[arg(long)]
    system: Option<PathBuf>,
    /// Directory of the FMUs an .ssd names as `resources/X.fmu` (default: $FMU_DIR).
    #[arg(long)]
    fmu_dir: Option<PathBuf>,
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

fn open_system(path: &Path, fmu_dir: Option<&PathBuf>) -> Result<SystemFile> {
    let dir = fmu_dir.cloned().or_else(|| std::env::var_os("FMU_DIR").map(PathBuf::from));
    Ok(SystemFile::open(path, dir.as_deref())?)
}

fn run(a: RunArgs) -> Result<()> {
    preload(&a.common)?;
    let sys = open_system(&a.system, a.common.fmu_dir.as_ref())?;
    let order = match &a.order {
        None => None,
        Some(s) => Some(Order::parse(s).with_context(|| format!("--order {s}: expected gauss-seidel or jacobi"))?),
    };
    let algebraic_loops = match a.algebraic_loops.as_str() {
        "refuse" => AlgebraicLoops::Refuse,
        "iterate" => AlgebraicLoops::Iterate,
        other => anyhow::bail!("--algebraic-loops {other}: expected refuse or iterate"),
    };
    fmi_master::csv::check_output(&a.output, &[a.system.as_path()])?;
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
        max_steps: a.max_steps,
        algebraic_loops,
    };
    let mut sim = Simulation::new(&sys, &cfg)?;
    let mut csv = fmi_master::csv::CsvWriter::create(&a.output)?;
    let progress = if a.quiet { Progress::Off } else { Progress::Auto };
    let stats = {
        // An FMU's exit() from here on ends cosim with an error, not success.
        let _running = RunInProgress::start();
        sim.run(&mut csv, progress)
    };
    let stats = match stats {
        Ok(stats) => {
            csv.complete()?;
            stats
        }
        Err(e) => {
            let e = anyhow::Error::from(e);
            // The marker stays either way; this only adds the reason to it.
            let _ = csv.mark_failed(&report(&e));
            return Err(e);
        }
    };
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
        if let Some(w) = md.work_bound() {
            println!(
                "work bound: at most {:e} internal steps per fmi2DoStep, a step h costs h / {} + {}",
                w.max_internal_steps_per_call, w.internal_step_parameter, w.extra_internal_steps_per_call
            );
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
    let same =
        |x: &Path| std::fs::canonicalize(x).ok().is_some_and(|x| Some(x) == std::fs::canonicalize(&a.output).ok());
    if same(&a.csv) || a.system.as_deref().is_some_and(same) {
        anyhow::bail!(
            "-o {}: is an input of this command; writing the plot there would destroy it",
            a.output.display()
        );
    }
    let sys = a.system.as_ref().map(|s| open_system(s, a.fmu_dir.as_ref())).transpose()?;
    fmi_master::plot::plot_csv(&a.csv, &a.vars, &a.output, a.spectrum.map(|f| (f, marks)), sys.as_ref())?;
    eprintln!("wrote {}", a.output.display());
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
    install_exit_guard();
    if !install_signal_cleanup() {
        eprintln!("warning: no signal handlers: an interrupted run may leave temporary directories behind");
    }
    let r = match cli.cmd {
        Cmd::Run(a) => run(a),
        Cmd::Info { file } => info(&file),
        Cmd::Plot(a) => plot(a),
        Cmd::Ssd { system, common } => open_system(&system, common.fmu_dir.as_ref())
            .and_then(|sys| Ok(sys.desc.to_xml()?))
            .map(|xml| print!("{xml}")),
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", report(&e));
            ExitCode::FAILURE
        }
    }
}
