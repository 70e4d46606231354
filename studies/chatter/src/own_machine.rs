//! `chatter machine check|ssp FILE`, `chatter lobes --machine FILE`, `chatter tune --machine
//! FILE`: a user's own machine from its machine file (the `machine` crate).

use anyhow::{Context, Result, ensure};
use clap::{Args, Subcommand};
use delay_stability::frequency::CriticalPoint;
use delay_stability::zero_order::speed_grid;
use indicatif::{ProgressBar, ProgressStyle};
use machine::Machine;
use machine::closed::{ClosedPoint, Limit, closed_loop_lobes};
use machine::lobes::{MachineLobes, MeasuredLobes, Method, discretisation};
use machine::tune::{MachinePlant, TuneOptions, controller_ssv, open_loop_minimum};
use machine::workflow::{controller_for, summary, validate};
use seed000::tuning::SaturationCheck;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use study_kit::output::{Series, plot_png};

/// Read a machine file; its error is one line naming the field and the fix.
pub fn load(path: &Path) -> Result<Machine> {
    Machine::from_file(path).map_err(|e| anyhow::anyhow!("{e}"))
}

#[derive(Subcommand)]
pub enum MachineCmd {
    /// Read and check a machine file; print what it describes (modes, static stiffness, cut).
    Check(CheckArgs),
    /// Write the machine's system as an SSP (MillingProcess + ModalStructure [+ InertialActuator + ChatterController]).
    Ssp(SspArgs),
}

#[derive(Args)]
pub struct CheckArgs {
    /// The machine file (TOML).
    pub file: PathBuf,
}

#[derive(Args)]
pub struct SspArgs {
    /// The machine file (TOML).
    pub file: PathBuf,
    /// Spindle speed [rpm] (default: the file's operation.spindle_speed).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Axial depth [mm] (default: the file's operation.axial_depth).
    #[arg(long)]
    pub depth_mm: Option<f64>,
    /// Stop time of the system's default experiment [s].
    #[arg(long, default_value_t = 1.0)]
    pub stop_time: f64,
    /// The .ssp to write (refused if it exists: no command overwrites a file).
    #[arg(long)]
    pub out: PathBuf,
}

pub fn machine(cmd: &MachineCmd) -> Result<()> {
    match cmd {
        MachineCmd::Check(a) => {
            let m = load(&a.file)?;
            println!("{}", summary(&m));
            Ok(())
        }
        MachineCmd::Ssp(a) => {
            let m = load(&a.file)?;
            let rpm =
                a.rpm.or(m.operation.spindle_speed_rpm).context("--rpm: the file has no operation.spindle_speed")?;
            let depth = a
                .depth_mm
                .map(|d| d * 1e-3)
                .or(m.operation.axial_depth)
                .context("--depth-mm: the file has no operation.axial_depth")?;
            ensure!(
                a.out.extension().is_some_and(|e| e == "ssp"),
                "--out {}: the system is written as an .ssp",
                a.out.display()
            );
            ensure!(!a.out.exists(), "--out {} exists: choose a new file (nothing is overwritten)", a.out.display());
            m.write_ssp(&a.out, &packaging::fmu_dir(), rpm, depth, a.stop_time)?;
            println!(
                "wrote {} ({} at {rpm} rpm, a_p = {} mm): run it with `cosim run {}`",
                a.out.display(),
                m.name,
                depth * 1e3,
                a.out.display()
            );
            Ok(())
        }
    }
}

/// The options of `chatter lobes --machine`.
#[derive(Args, Clone)]
pub struct MachineLobeOptions {
    /// The time-periodic boundary by the first-order semi-discretisation with this many steps per
    /// tooth period instead of the converged default (spectral collocation to 0.1 %)
    #[arg(long)]
    pub sd_m: Option<usize>,
    /// Check the time-periodic boundary at these speeds [rpm] in the time domain through the FMUs
    /// (decay at 0.97, growth at 1.03 of it).
    #[arg(long, value_delimiter = ',')]
    pub validate_rpm: Vec<f64>,
}

fn progress(n: usize, what: &str) -> ProgressBar {
    let pb = ProgressBar::new(n as u64);
    pb.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len}  ({elapsed})")
            .expect("valid template")
            .progress_chars("=> "),
    );
    pb.set_prefix(what.to_string());
    pb
}

/// `chatter lobes --machine FILE`.
pub fn lobes(
    file: &Path,
    controllers: &[String],
    rpm: Option<(f64, f64)>,
    points: usize,
    o: &MachineLobeOptions,
    out: &Path,
) -> Result<()> {
    let m = load(file)?;
    let (lo, hi) = rpm.unwrap_or(m.operation.speed_range_rpm);
    ensure!(lo > 0.0 && hi > lo && points >= 2, "the speed range [{lo}, {hi}] rpm with {points} points is empty");
    let speeds = speed_grid(lo, hi, points);
    println!("{}", summary(&m));
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    if m.frf.is_some() {
        let measured = MeasuredLobes::compute(&m, &speeds)?;
        println!("Measured FRFs ({} speeds, {lo:.0}–{hi:.0} rpm):\n\n{}", speeds.len(), measured.report(&m));
        std::fs::write(out.join("measured_lobes.csv"), measured.csv())?;
        let mut series =
            vec![Series { name: "zero-order on the measured FRFs".into(), points: measured.measured.clone() }];
        if let Some(modal) = &measured.modal {
            series.push(Series { name: "zero-order on the modes".into(), points: modal.clone() });
        }
        plot_png(
            &out.join("measured_lobes.png"),
            &format!(
                "Stability lobes from measured FRFs: {} ({} teeth, a_e/D = {})",
                m.name, m.tool.teeth, m.operation.immersion
            ),
            &series,
            1200,
            800,
        )?;
        println!("wrote {}, {}", out.join("measured_lobes.csv").display(), out.join("measured_lobes.png").display());
        if m.modes.is_empty() {
            return Ok(());
        }
    }
    let method = discretisation(o.sd_m);
    let pb = progress(speeds.len(), "time-periodic");
    let open = MachineLobes::compute(&m, &speeds, method, &|d, _| pb.set_position(d as u64))?;
    pb.finish_and_clear();
    println!("Open loop ({} speeds, {lo:.0}–{hi:.0} rpm):\n\n{}", speeds.len(), open.report(&m));
    std::fs::write(out.join("lobes.csv"), open.csv())?;
    let mut series = vec![
        Series { name: "zero-order".into(), points: open.zero_order.clone() },
        Series { name: "multi-frequency".into(), points: open.multi_frequency.clone() },
        Series {
            name: format!("time-periodic, {method}"),
            points: open
                .sd
                .iter()
                .map(|p| CriticalPoint {
                    rpm: p.rpm,
                    depth: p.critical.value.unwrap_or(f64::INFINITY),
                    chatter_hz: f64::NAN,
                })
                .collect(),
        },
    ];
    let mut closed_csv = String::from("controller,rpm,stability_mm,saturation_mm,usable_mm,limit,method_unsafe\n");
    for name in controllers {
        let Some((label, c)) = controller_for(&m, name)? else { continue };
        let pts = closed_loop_lobes(&m, &c, &speeds, Some(&open))?;
        let sweep = SaturationCheck::default()
            .over_seeds(&MachinePlant::new(m.clone()).map_err(anyhow::Error::msg)?, &c, 101..111)
            .map_err(anyhow::Error::msg)?;
        report_closed(&label, &pts, sweep.passed, Method::for_immersion(&m));
        for p in &pts {
            let _ = writeln!(
                closed_csv,
                "{name},{:.3},{:.6},{:.6},{:.6},{},{}",
                p.rpm,
                p.stability * 1e3,
                p.saturation * 1e3,
                p.usable() * 1e3,
                if p.limit() == Limit::Saturation { "saturation" } else { "stability" },
                p.method_unsafe
            );
        }
        let usable = |keep: &dyn Fn(&ClosedPoint) -> bool| -> Vec<CriticalPoint> {
            pts.iter()
                .map(|p| CriticalPoint {
                    rpm: p.rpm,
                    depth: if keep(p) { p.usable() } else { f64::NAN },
                    chatter_hz: p.chatter_hz,
                })
                .collect()
        };
        series.push(Series { name: format!("{label}: closed loop"), points: usable(&|_| true) });
        if pts.iter().any(|p| p.limit() == Limit::Saturation) {
            series.push(Series {
                name: format!("{label}: limited by the actuator (±{} N)", c.u_max),
                points: usable(&|p| p.limit() == Limit::Saturation),
            });
        }
    }
    if controllers.iter().any(|c| c != "off") {
        std::fs::write(out.join("closed_loop.csv"), closed_csv)?;
    }
    plot_png(
        &out.join("lobes.png"),
        &format!("Stability lobes: {} ({} teeth, a_e/D = {})", m.name, m.tool.teeth, m.operation.immersion),
        &series,
        1200,
        800,
    )?;
    for &rpm in &o.validate_rpm {
        match validate(&m, rpm, method)? {
            Some(v) => println!("{}", v.line()),
            None => println!("{rpm:.0} rpm: stable up to 100 mm ({method}): nothing to validate"),
        }
    }
    let closed = if controllers.iter().any(|c| c != "off") {
        format!(", {}", out.join("closed_loop.csv").display())
    } else {
        String::new()
    };
    println!("wrote {}, {}{closed}", out.join("lobes.csv").display(), out.join("lobes.png").display());
    Ok(())
}

fn report_closed(label: &str, pts: &[ClosedPoint], fresh_passed: usize, method: Method) {
    let worst = pts.iter().min_by(|a, b| a.usable().total_cmp(&b.usable()));
    let Some(w) = worst else { return };
    let sat = pts.iter().filter(|p| p.limit() == Limit::Saturation).count();
    let unsafe_n = pts.iter().filter(|p| p.method_unsafe).count();
    println!(
        "{label}: closed loop ({}) smallest usable depth {:.3} mm at {:.0} rpm, limited by {}; saturation-limited at {sat} of {} speeds; the disturbance check (50 N RMS) passes on {fresh_passed}/10 fresh noise seeds{}",
        method.name(),
        w.usable() * 1e3,
        w.rpm,
        if w.limit() == Limit::Saturation { "the actuator" } else { "stability" },
        pts.len(),
        if unsafe_n > 0 {
            format!(
                "; at {unsafe_n} speeds the open-loop {} lies above SD, so this closed-loop value may be unsafe there",
                method.name()
            )
        } else {
            String::new()
        }
    );
    if fresh_passed < 9 {
        println!(
            "  WARNING: {label} saturates under the disturbance alone on {} of 10 seeds: its lobe assumes a linear loop it does not have; tune it for this machine (`chatter tune --machine`)",
            10 - fresh_passed
        );
    }
}

/// `chatter tune --machine FILE`: each structure tuned by PSO on the machine; SSV parameter sets.
pub fn tune(file: &Path, o: &TuneOptions, out: &Path, quiet: bool) -> Result<()> {
    let m = load(file)?;
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let open = open_loop_minimum(&m, o.speeds).map_err(anyhow::Error::msg)?;
    println!(
        "{}: open-loop smallest critical depth {:.3} mm at {:.0} rpm ({})",
        m.name,
        open.depth * 1e3,
        open.rpm,
        Method::for_immersion(&m).name()
    );
    let pb = if quiet { ProgressBar::hidden() } else { progress(o.pso.iterations, "PSO") };
    let results = machine::tune::tune(&m, o, &|s, r, k| {
        pb.set_prefix(format!("{} run {}/{}", model_kit::Choice::name(s), r + 1, o.runs));
        pb.set_position(k as u64);
    })
    .map_err(anyhow::Error::msg)?;
    pb.finish_and_clear();
    for r in &results {
        let name = model_kit::Choice::name(r.structure);
        for run in &r.runs {
            let b = &run.breakdown;
            println!(
                "{name} seed {}: J = {:.4} mm, closed-loop b_min {:.4} mm at {:.0} rpm, gains {:?}",
                run.seed, b.cost, b.b_min_mm, b.rpm_at_min, run.gains
            );
        }
        let ssv = out.join(format!("tuned_{name}.ssv"));
        ensure!(!ssv.exists(), "{} exists: choose a new --out folder (nothing is overwritten)", ssv.display());
        std::fs::write(&ssv, controller_ssv(&format!("tuned_{name}"), &r.best.params).map_err(anyhow::Error::msg)?)?;
        println!(
            "{name}: wrote {} (fresh seeds 101–110: {}/10 pass the saturation check)",
            ssv.display(),
            r.fresh.passed
        );
    }
    let table = machine::tune::table(&results, &open);
    std::fs::write(out.join("tuning.md"), &table)?;
    println!(
        "\n{table}\nUse a parameter set in the machine file: [controller] structure = \"...\", parameters = \"{}/tuned_<structure>.ssv\"",
        out.display()
    );
    Ok(())
}
