//! `chatter synth`: seed 002's robust synthesis, §6.1 and Table II (n_c = 0, 2, 4), each design
//! checked by semi-discretisation over the box and written as an SSP parameter set.
//!
//! ```text
//! chatter synth [--case all|6.1|table2] [--max-order 4] [--quick] [--seed 1] [--out synth-out]
//! ```

use anyhow::{Context, Result, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use seed002::multistart as ms;
use seed002::synth::{Case, Design, SynthOptions, design, initial, markdown, write};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args)]
pub struct SynthArgs {
    /// Which designs: `6.1`, `table2` or `all`.
    #[arg(long, default_value = "all")]
    pub case: String,
    /// Highest Table II order (0, 2 or 4); the orders are synthesised in sequence, each from the last.
    #[arg(long, default_value_t = 4)]
    pub max_order: usize,
    /// Coarse frequency grid, coarse ā_p bisection (0.3 mm), SD m = 12 on 5 speeds: a check in about a minute per case.
    #[arg(long)]
    pub quick: bool,
    /// Frequency points of the design grid (20–8000 Hz).
    #[arg(long)]
    pub points: Option<usize>,
    /// Bisection resolution [mm].
    #[arg(long)]
    pub resolution_mm: Option<f64>,
    /// Seed of the initial dynamic parts and of the gradient sampling.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Instead of the designs: Table II n_c = 4 from N independent starts (start 0 = the plain
    /// run's; then from the n_c = 2 design with a random second block, its D_c with random
    /// dynamics, and from scratch), the distribution of a_p,max (multistart.csv, streamed and
    /// resumed; multistart.md).
    #[arg(long, value_name = "N")]
    pub multistart: Option<usize>,
    /// The n_c = 2 design the multi-start builds on (a `chatter synth` .ssv).
    #[arg(long, default_value = "packaging/designs/table2_nc2.ssv")]
    pub base: PathBuf,
    /// Output directory (<case>.ssv, synth.csv, synth.md).
    #[arg(long, default_value = "synth-out")]
    pub out: PathBuf,
}

pub fn synth(a: &SynthArgs) -> Result<()> {
    let mut o = if a.quick { SynthOptions::quick(a.seed) } else { SynthOptions::full(a.seed) };
    o.dk.k.seed = a.seed;
    if let Some(p) = a.points {
        o.dk.freqs_hz = robust_synthesis::dk::DkOptions::grid(20.0, 8000.0, p);
    }
    if let Some(r) = a.resolution_mm {
        o.resolution = r * 1e-3;
    }
    if let Some(n) = a.multistart {
        return multistart(a, n, &o);
    }
    let mut cases = Vec::new();
    match a.case.as_str() {
        "6.1" => cases.push(Case::Sec61),
        "table2" => {}
        "all" => cases.push(Case::Sec61),
        other => bail!("--case {other}: one of 6.1, table2, all"),
    }
    if a.case != "6.1" {
        if !a.max_order.is_multiple_of(2) || a.max_order > 8 {
            bail!("--max-order {}: an even order up to 8", a.max_order);
        }
        cases.extend((0..=a.max_order).step_by(2).map(|nc| Case::Table2 { nc }));
    }
    let bar = ProgressBar::new_spinner();
    bar.set_style(ProgressStyle::with_template("synth {spinner} [{elapsed}] {msg}")?);
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    let t = Instant::now();
    let mut designs: Vec<Design> = Vec::new();
    for case in cases {
        let prev = designs.iter().rev().find(|d| matches!(d.case, Case::Table2 { .. })).map(|d| d.theta.clone());
        let theta0 = initial(case, prev.as_deref(), a.seed);
        let tc = Instant::now();
        let d = design(case, &theta0, &o, &|s: &str| {
            bar.set_message(s.to_string());
            if bar.is_hidden() {
                eprintln!("{s}");
            } else {
                bar.println(s);
            }
        })
        .with_context(|| format!("synthesis of {}", case.name()))?;
        say(
            &bar,
            format!(
                "{}: ā_p {:.3} mm, μ̂ {:.4} (fine grid {:.4}), a_p,max {:.3} mm, SD box {} [{:.1} s]",
                case.name(),
                d.abar * 1e3,
                d.mu,
                d.mu_check.0,
                d.ap_max.0 * 1e3,
                if d.box_stable() { "stable" } else { "NOT stable" },
                tc.elapsed().as_secs_f64()
            ),
        );
        if case == Case::Sec61 {
            let k = &d.controller.dc;
            say(
                &bar,
                format!(
                    "§6.1 gains: k1 = {:.4} N/mm, k2 = {:.4} N/mm (paper 697.1599, -1071.058)",
                    k[(0, 0)] * 1e-3,
                    k[(1, 0)] * 1e-3
                ),
            );
        }
        designs.push(d);
        write(&a.out, &designs)?;
    }
    bar.finish_and_clear();
    println!("{}", markdown(&designs));
    println!("wall time {:.1} s; wrote {}", t.elapsed().as_secs_f64(), a.out.display());
    Ok(())
}

fn multistart(a: &SynthArgs, n: usize, o: &SynthOptions) -> Result<()> {
    let text = std::fs::read_to_string(&a.base).with_context(|| format!("reading {}", a.base.display()))?;
    let nc2 = ms::theta_from_ssv(&text, &a.base.display().to_string())?;
    anyhow::ensure!(nc2.len() == 16, "{}: not an n_c = 2 design", a.base.display());
    let starts = ms::starts(n, &nc2, a.seed);
    let t = Instant::now();
    let out = ms::run(&a.out, &starts, a.seed, o, &|s: &str| eprintln!("{s}"))?;
    let md = ms::markdown(&out);
    std::fs::write(a.out.join("multistart.md"), &md)?;
    println!("Table II n_c = 4 from {} starts (seed {}), paper a_p,max 2.399 mm:", out.len(), a.seed);
    println!("{md}");
    println!("wall time {:.1} s; wrote {}/multistart.{{csv,md}}", t.elapsed().as_secs_f64(), a.out.display());
    Ok(())
}

/// A line above the bar, or on stderr when the bar is hidden (not a terminal).
fn say(bar: &ProgressBar, line: String) {
    if bar.is_hidden() {
        eprintln!("{line}");
    } else {
        bar.println(line);
    }
}
