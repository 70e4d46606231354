//! `chatter coupling-order`: every shipped system (`<fmu dir>/*.ssp`, written by
//! `cargo run --release -p packaging`) under the two coupling orders of the Rust master,
//! Gauss–Seidel in the system's own sequence and Jacobi (every input from the outputs at the step
//! start), and the headline metric of each system under both. A difference above 5 % is flagged:
//! the result then depends on how the master couples the FMUs, which a user's master (FMPy's
//! `simulate_ssp` and libcosim step in Jacobi order) does not know.
//!
//! The metric of each system is the one its docs page reports (see [`HEADLINES`]); an `.ssp` of
//! the folder without an entry there is an error, so nothing shipped is left out silently.

use anyhow::{Context, Result, bail};
use clap::Args;
use fmi_master::ssp::Order;
use fmi_master::{Progress, Recorder, RunConfig, Simulation, SystemFile};
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct CouplingArgs {
    /// Short runs (see each system's quick stop time): a check in seconds.
    #[arg(long)]
    pub quick: bool,
    /// Folder of the systems (default: the packaged FMUs' folder, `$FMU_DIR` or target/fmu).
    #[arg(long)]
    pub fmu_dir: Option<PathBuf>,
    /// Output directory (coupling_order.csv, coupling_order.md).
    #[arg(long, default_value = "coupling-out")]
    pub out: PathBuf,
}

/// How a headline metric is computed from a run.
#[derive(Clone, Copy, Debug)]
pub enum Metric {
    /// RMS of a variable over the second half of the run.
    RmsSecondHalf(&'static str),
    /// Mean square of a variable from `t0` to the end, times `scale` (µm² from m: 1e12).
    MeanSquare(&'static str, f64, f64),
    /// `∫|a − b| dt` from 0 to `t1` (trapezoidal rule on the step grid).
    AbsDiffIntegral(&'static str, &'static str, f64),
}

impl Metric {
    /// The recorded variables it needs.
    pub fn variables(&self) -> Vec<&'static str> {
        match *self {
            Metric::RmsSecondHalf(v) | Metric::MeanSquare(v, _, _) => vec![v],
            Metric::AbsDiffIntegral(a, b, _) => vec![a, b],
        }
    }

    /// The metric of a recorded run that ended at `stop`.
    pub fn eval(&self, rec: &Recorder, stop: f64) -> Result<f64> {
        let col = |v: &str| rec.column(v).with_context(|| format!("{v} was not recorded"));
        let t = &rec.time;
        Ok(match *self {
            Metric::RmsSecondHalf(v) => mean_square(t, &col(v)?, 0.5 * stop).sqrt(),
            Metric::MeanSquare(v, t0, scale) => scale * mean_square(t, &col(v)?, t0),
            Metric::AbsDiffIntegral(a, b, t1) => {
                let e: Vec<f64> = col(a)?.iter().zip(col(b)?).map(|(x, y)| (x - y).abs()).collect();
                (1..t.len()).filter(|&i| t[i] <= t1 + 1e-9).map(|i| 0.5 * (t[i] - t[i - 1]) * (e[i] + e[i - 1])).sum()
            }
        })
    }
}

fn mean_square(t: &[f64], v: &[f64], t0: f64) -> f64 {
    let w: Vec<f64> = t.iter().zip(v).filter(|(s, _)| **s >= t0 - 1e-12).map(|(_, x)| x * x).collect();
    w.iter().sum::<f64>() / w.len().max(1) as f64
}

/// One shipped system's headline.
#[derive(Clone, Copy, Debug)]
pub struct Headline {
    /// File name in the FMU folder.
    pub ssp: &'static str,
    /// What the metric is (with its unit).
    pub label: &'static str,
    /// The metric.
    pub metric: Metric,
    /// Stop time of `--quick` (the full run uses the system's own DefaultExperiment).
    pub quick_stop: f64,
}

/// The headline metric of each shipped system: what its docs page reports.
pub const HEADLINES: [Headline; 9] = [
    Headline {
        ssp: "Afrac.ssp",
        label: "RMS of plant.x over the second half [m]",
        metric: Metric::RmsSecondHalf("plant.x"),
        quick_stop: 0.5,
    },
    Headline {
        ssp: "Benchmark.ssp",
        label: "RMS of plant.x over the second half [m]",
        metric: Metric::RmsSecondHalf("plant.x"),
        quick_stop: 1.0,
    },
    Headline {
        ssp: "ClosedLoop.ssp",
        label: "RMS of plant.x over the second half [m]",
        metric: Metric::RmsSecondHalf("plant.x"),
        quick_stop: 1.0,
    },
    Headline {
        ssp: "ClosedLoopTable2.ssp",
        label: "RMS of plant.x over the second half [m]",
        metric: Metric::RmsSecondHalf("plant.x"),
        quick_stop: 1.0,
    },
    Headline {
        ssp: "DecomposedPlant.ssp",
        label: "RMS of structure.tool_x over the second half [m]",
        metric: Metric::RmsSecondHalf("structure.tool_x"),
        quick_stop: 1.0,
    },
    Headline {
        ssp: "ForceControl.ssp",
        label: "J = integral of abs(F_p - F_m) over the first 2.52 s [N.s]",
        metric: Metric::AbsDiffIntegral("plant.F_p", "controller.F_m", 2.52),
        quick_stop: 3.0,
    },
    Headline {
        ssp: "SlidingModeFuzzy.ssp",
        label: "MSE of plant.x from 0.1 s [um^2]",
        metric: Metric::MeanSquare("plant.x", 0.1, 1e12),
        quick_stop: 0.2,
    },
    Headline {
        ssp: "SlidingModeFuzzy.ssp",
        label: "MSE of plant.y from 0.1 s [um^2]",
        metric: Metric::MeanSquare("plant.y", 0.1, 1e12),
        quick_stop: 0.2,
    },
    Headline {
        ssp: "Spindle.ssp",
        label: "RMS of spindle.tool_x over the second half [m]",
        metric: Metric::RmsSecondHalf("spindle.tool_x"),
        quick_stop: 0.01,
    },
];

/// One system × metric under both orders.
#[derive(Clone, Debug)]
pub struct Row {
    /// System file name.
    pub ssp: String,
    /// The metric.
    pub label: String,
    /// Stop time of the runs [s].
    pub stop: f64,
    /// Under Gauss–Seidel (the system's sequence) and Jacobi.
    pub gauss_seidel: f64,
    /// Under Jacobi.
    pub jacobi: f64,
}

impl Row {
    /// |Jacobi − Gauss–Seidel| / |Gauss–Seidel|.
    pub fn difference(&self) -> f64 {
        (self.jacobi - self.gauss_seidel).abs() / self.gauss_seidel.abs()
    }

    /// More than 5 % apart (or not finite under one order).
    pub fn flagged(&self) -> bool {
        let d = self.difference();
        d.is_nan() || d > 0.05
    }
}

fn run_one(path: &Path, dir: &Path, order: Order, stop: Option<f64>, record: &[&str]) -> Result<(Recorder, f64)> {
    let sys = SystemFile::open(path, Some(dir))?;
    let cfg = RunConfig {
        order: Some(order),
        stop,
        record: Some(record.iter().map(|s| s.to_string()).collect()),
        ..RunConfig::default()
    };
    let mut sim = Simulation::new(&sys, &cfg).with_context(|| format!("{}", path.display()))?;
    let mut rec = Recorder::default();
    sim.run(&mut rec, Progress::Off).with_context(|| format!("{} ({})", path.display(), order.as_str()))?;
    let end = *rec.time.last().context("no samples")?;
    Ok((rec, end))
}

/// Every `.ssp` of `dir` (sorted) under both orders; the systems without an entry in
/// [`HEADLINES`] are an error (a shipped system must say what its headline is).
pub fn rows(dir: &Path, quick: bool, mut sink: impl FnMut(&Row) -> Result<()>) -> Result<Vec<Row>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("reading {} (build the FMUs: cargo run --release -p packaging)", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "ssp"))
        .collect();
    files.sort();
    if files.is_empty() {
        bail!("no .ssp in {} (build them: cargo run --release -p packaging)", dir.display());
    }
    let mut out = Vec::new();
    for path in files {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default().to_string();
        let heads: Vec<&Headline> = HEADLINES.iter().filter(|h| h.ssp == name).collect();
        if heads.is_empty() {
            bail!("{name}: no headline metric in chatter's coupling table (add it to HEADLINES)");
        }
        let vars: Vec<&str> = heads.iter().flat_map(|h| h.metric.variables()).collect();
        let stop = quick.then_some(heads[0].quick_stop);
        let (gs, end) = run_one(&path, dir, Order::GaussSeidel, stop, &vars)?;
        let (jc, _) = run_one(&path, dir, Order::Jacobi, stop, &vars)?;
        for h in heads {
            let r = Row {
                ssp: name.clone(),
                label: h.label.to_string(),
                stop: end,
                gauss_seidel: h.metric.eval(&gs, end)?,
                jacobi: h.metric.eval(&jc, end)?,
            };
            sink(&r)?;
            out.push(r);
        }
    }
    Ok(out)
}

/// The rows as a Markdown table.
pub fn markdown(rows: &[Row]) -> String {
    let mut s = String::from(
        "| system | headline metric | stop [s] | Gauss-Seidel | Jacobi | difference | > 5 % |\n|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {:.3} | {:.4e} | {:.4e} | {:.1} % | {} |\n",
            r.ssp,
            r.label,
            r.stop,
            r.gauss_seidel,
            r.jacobi,
            100.0 * r.difference(),
            if r.flagged() { "**yes**" } else { "no" }
        );
    }
    s
}

pub fn coupling_order(a: &CouplingArgs) -> Result<()> {
    let dir = a.fmu_dir.clone().unwrap_or_else(packaging::fmu_dir);
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let csv_path = a.out.join("coupling_order.csv");
    let mut csv = std::fs::File::create(&csv_path).with_context(|| format!("creating {}", csv_path.display()))?;
    writeln!(csv, "ssp,metric,stop_s,gauss_seidel,jacobi,difference,flagged")?;
    let rows = rows(&dir, a.quick, |r| {
        writeln!(
            csv,
            "{},{},{},{:.9e},{:.9e},{:.6},{}",
            r.ssp,
            r.label.replace(',', ";"),
            r.stop,
            r.gauss_seidel,
            r.jacobi,
            r.difference(),
            r.flagged()
        )?;
        csv.flush()?;
        Ok(())
    })?;
    let md = markdown(&rows);
    std::fs::write(a.out.join("coupling_order.md"), &md)?;
    println!("every shipped system under both coupling orders of the Rust master ({}):", dir.display());
    println!("{md}");
    let n = rows.iter().filter(|r| r.flagged()).count();
    println!("{n} of {} metrics differ by more than 5 % between the orders", rows.len());
    println!("written: {}/coupling_order.{{csv,md}}", a.out.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recorder(f: impl Fn(f64) -> [f64; 2], n: usize, h: f64) -> Recorder {
        let time: Vec<f64> = (0..=n).map(|i| i as f64 * h).collect();
        let rows = time.iter().map(|&t| f(t).to_vec()).collect();
        Recorder { names: vec!["a.x".into(), "b.y".into()], time, rows }
    }

    #[test]
    fn the_metrics_of_known_signals() {
        // x = 0 in the first half, 3 in the second: RMS over the second half 3
        let r = recorder(|t| [if t >= 0.5 { 3.0 } else { 0.0 }, 1.0], 100, 0.01);
        assert!((Metric::RmsSecondHalf("a.x").eval(&r, 1.0).unwrap() - 3.0).abs() < 1e-12);
        // mean square from 0.2 in µm² of 2e-6 m: 4
        let r = recorder(|t| [if t >= 0.2 { 2e-6 } else { 1.0 }, 0.0], 100, 0.01);
        assert!((Metric::MeanSquare("a.x", 0.2, 1e12).eval(&r, 1.0).unwrap() - 4.0).abs() < 1e-9);
        // ∫|x − y| over [0, 0.5] with x − y = t: 0.125 (trapezoidal: exact for a line)
        let r = recorder(|t| [t + 1.0, 1.0], 100, 0.01);
        assert!((Metric::AbsDiffIntegral("a.x", "b.y", 0.5).eval(&r, 1.0).unwrap() - 0.125).abs() < 1e-12);
        assert!(Metric::RmsSecondHalf("c.z").eval(&r, 1.0).is_err());
    }

    #[test]
    fn more_than_five_percent_apart_is_flagged() {
        let row = |gs, jacobi| Row { ssp: String::new(), label: String::new(), stop: 1.0, gauss_seidel: gs, jacobi };
        assert!(!row(1.0, 1.049).flagged() && !row(1.0, 0.951).flagged());
        assert!(row(1.0, 1.051).flagged() && row(1.0, 0.949).flagged() && row(1.0, f64::NAN).flagged());
    }
}
