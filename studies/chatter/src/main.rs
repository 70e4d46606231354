//! `chatter`: every study of the seed papers on the command line. `chatter --help` lists the
//! commands, `chatter COMMAND --help` their options; the docs book's CLI reference has them
//! with the pages that show their results. Every command (tested against the clap tree):
//!
//! | papers | commands |
//! |---|---|
//! | seed 000 (ADRC-FOPID): lobes and tuning | `chatter lobes`, `chatter sd-lobes`, `chatter tune`, `chatter tables`, `chatter table8`, `chatter check`, `chatter validate` |
//! | seed 000: the FMU studies | `chatter main-job`, `chatter robustness`, `chatter sweep`, `chatter map`, `chatter depth-study`, `chatter decomposed` |
//! | seed 001 (AFrAC) | `chatter afrac`, `chatter afrac-ga` |
//! | seed 002 (AMB spindle) | `chatter spindle`, `chatter synth` |
//! | seed 003 (DSMC, type-2 fuzzy) | `chatter dsmc` |
//! | seed 004 (FROH force control) | `chatter froh` |
//! | your own machine (a machine file) | `chatter machine`, `chatter lobes --machine`, `chatter tune --machine` |
//! | measured FRFs (a tap test) | `chatter frf` |
//! | studies as cases, on many machines | `chatter plan`, `chatter run`, `chatter collect` |
//! | every shipped system under both coupling orders | `chatter coupling-order` |
//!
//! Gains are force-equivalent SI values (`u` in N, `y` in m); `--adrc` takes the FOPID gains of
//! the ADRC loop in the same force units (converted by `b0` as in `chatter_control::params`).
//! Default gains: the seed's Table 2 preset (`--preset tuned`: the PSO-tuned FMU defaults).

mod afrac;
mod cases;
mod check;
mod common;
mod coupling;
mod decomposed;
mod dsmc;
mod frf;
mod froh;
mod lobes;
mod main_job;
mod own_machine;
mod sd_lobes;
mod spindle;
mod synth;
mod table8;
mod tables;
mod tune;
mod validate;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "chatter",
    version,
    about = "The studies of the seed papers: stability lobes, PSO tuning, tables, validation through the FMUs"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Seed 000's plant as process + structure + actuator FMUs vs the monolithic plant (open-loop RMS).
    Decomposed(decomposed::DecomposedArgs),
    /// Seed 000 Section 5.6.1: the nominal scenario at several depths, through the FMUs (Figures 9-10).
    DepthStudy(seed000::depth_study::DepthSpec),
    /// Seed 001: AFrAC on the turning process (open loop, fixed beta, Table 5 schedule): settling times, speed and feed excursions.
    Afrac(afrac::AfracArgs),
    /// Seed 001 Table 4: the genetic algorithm for the switch times of the stepwise beta schedule.
    AfracGa(afrac::AfracGaArgs),
    /// Seed 003: Table 2 (none, DSMC, D-PID, DSMC-T1, DSMC-T2) on the two-axis tool with the cubic law and the damper.
    Dsmc(dsmc::DsmcArgs),
    /// Seed 004: FROH zero locus, non-minimum-phase boundary and the J(beta) sweep for three chip-lag readings.
    Froh(froh::FrohArgs),
    /// Every shipped system (target/fmu/*.ssp) under Gauss-Seidel and Jacobi coupling: the headline metric of each, differences > 5 % flagged.
    CouplingOrder(coupling::CouplingArgs),
    /// Seed 000 Table 7 and Figures 11-13: the robustness sample (19 points x 2 noise seeds), through the FMUs.
    Robustness(seed000::robustness::RobustnessSpec),
    /// Seed 000 Figure 15: the feed or radial-engagement sweep through the FMUs, with the harmonic-balance and closed-form checks.
    Sweep(seed000::sweeps::SweepSpec),
    /// Seed 000 Figure 16: the speed x depth map (90 cells per controller) through the FMUs, heat maps on one colour scale.
    Map(seed000::map::MapSpec),
    /// The seed paper's nominal scenario over all controllers and noise seeds (Table 5, Figures 6-7), through the FMUs.
    MainJob(main_job::MainJobArgs),
    /// Lobe diagrams (CSV + PNG) for several controllers on common axes.
    Lobes(lobes::LobesArgs),
    /// Semi-discretisation lobes (time-periodic, multi-DOF, Hopf/flip): seed 000 plant or a seed 002 preset.
    SdLobes(sd_lobes::SdLobesArgs),
    /// Seed 002's spindle on the FMUs: closed-loop tool FRFs, growth/decay of Spindle.ssp around the SD boundary.
    #[command(subcommand)]
    Spindle(spindle::SpindleCmd),
    /// Seed 002 robust synthesis: §6.1 and Table II (n_c = 0, 2, 4) by D-K iteration with bisection, SD box checks, SSP parameter sets.
    Synth(synth::SynthArgs),
    /// PSO tuning (N runs per structure); best gains as JSON and CSV, Table A1 statistics.
    Tune(tune::TuneArgs),
    /// Seed 000 Table 8 complete: DVF, VPA, PID, LQR, H-infinity, mu, FOPID, ADRC-FOPID on the Ozsoy benchmark (calibrated and PSO), Figures 17-18, Table A1.
    Table8(table8::Table8Args),
    /// Table 6 (seed plant, open and closed loop) and the Table 8 uncontrolled row (Ozsoy plant).
    Tables(tables::TablesArgs),
    /// Time-domain checks of controllers: closed-loop decay and the saturation check over several noise seeds.
    Check(check::CheckArgs),
    /// The lobes against the FMUs in the Rust master: time-domain boundary by bisection vs the lobe.
    Validate(validate::ValidateArgs),
    /// Your own machine from a machine file: check it, write its SSP (lobes: `chatter lobes --machine`, tuning: `chatter tune --machine`).
    #[command(subcommand)]
    Machine(own_machine::MachineCmd),
    /// Measured FRFs (tap-test CSV or UFF 58): fit modes (stabilisation diagram, machine file, ModalStructure SSV), convert, synthesise.
    #[command(subcommand)]
    Frf(frf::FrfCmd),
    /// Plan a study as independent cases into a folder (manifest.json), to run anywhere.
    #[command(subcommand)]
    Plan(cases::PlanCmd),
    /// Run the cases of a planned study that have no result yet (all, a shard, an index, IDs).
    Run(cases::RunArgs),
    /// Merge the results of a planned study into its tables and figures.
    Collect(cases::CollectArgs),
}

/// Errors print as one line (the error and its causes, `: `-separated) and exit with status 1.
fn main() -> std::process::ExitCode {
    match run(&Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(cli: &Cli) -> Result<()> {
    match &cli.cmd {
        Cmd::MainJob(a) => main_job::main_job(a),
        Cmd::Decomposed(a) => decomposed::decomposed(a),
        Cmd::DepthStudy(s) => report(s.run_local()?, &s.out.join("depth_study.md"), "depth_study.csv"),
        Cmd::Froh(a) => froh::froh(a),
        Cmd::CouplingOrder(a) => coupling::coupling_order(a),
        Cmd::Afrac(a) => afrac::afrac(a),
        Cmd::AfracGa(a) => afrac::afrac_ga(a),
        Cmd::Dsmc(a) => dsmc::dsmc(a),
        Cmd::Lobes(a) => lobes::lobes(a),
        Cmd::SdLobes(a) => sd_lobes::sd_lobes_cmd(a),
        Cmd::Spindle(c) => spindle::spindle(c),
        Cmd::Synth(a) => synth::synth(a),
        Cmd::Tune(a) => tune::tune(a),
        Cmd::Table8(a) => table8::table8(a),
        Cmd::Tables(a) => tables::tables(a),
        Cmd::Check(a) => check::check(a),
        Cmd::Validate(a) => validate::validate(a),
        Cmd::Machine(c) => own_machine::machine(c),
        Cmd::Frf(c) => frf::frf(c),
        Cmd::Plan(c) => cases::plan(c),
        Cmd::Run(a) => cases::run(a),
        Cmd::Collect(a) => cases::collect(a),
        Cmd::Robustness(s) => report(s.run_local()?, &s.out.join("robustness.md"), "robustness.csv, robustness.png"),
        Cmd::Sweep(s) => {
            let md = s.out.join(format!("sweep_{}.md", s.kind));
            report(s.run_local()?, &md, ".csv, .png")
        }
        Cmd::Map(s) => report(s.run_local()?, &s.out.join("map.md"), "map.csv, map.png"),
    }
}

/// Print a study's markdown report and where it went.
fn report(md: String, written: &std::path::Path, also: &str) -> Result<()> {
    println!("{md}");
    println!("wrote {} (and {also})", written.display());
    Ok(())
}
