//! Seed 000's Table 8 with all nine rows, Figures 17–18 and Table A1 (`chatter table8`).
//!
//! Two modes per controller on the Ozsoy plant ([`crate::loop_frf::ozsoy_plant`]):
//!
//! * **calibrated**: the controller's one parameter ([`crate::benchmark::calibration`]; PID: K_d
//!   with K_p, K_i at Table 3's lower bounds) set so that b_crit over 1000–3000 rpm (50 rpm) is
//!   [8]'s published value; b_max and the peak receptance are then predictions;
//! * **PSO**: the seed's cost (Eq. 31, [`crate::tuning`]) under the robust saturation check
//!   (noise seeds 1..=N, margin), `runs` independent runs; the best run is the row, the runs give
//!   Table A1 (mean J ± std, CV, iteration within 5 % of the final cost).
//!
//! Every row reports b_crit and b_max over 1000–3000 and 500–3000 rpm, the peak closed-loop
//! receptance (Figure 17) and the seed's saturation check (margin 0) on the fresh noise seeds
//! 101–110. Files: `table8.md`, `table_a1.md`, `fig17_receptance.{csv,png}`,
//! `fig18_lobes_{500,1000}.{csv,png}`, and each benchmark design as a `LinearController`
//! parameter set `benchmark_<controller>_{calibrated,pso}.ssv`.

use crate::benchmark::{self, ALL, Benchmark, BenchmarkProblem, Designed, Response};
use crate::closed_loop::AnyController;
use crate::loop_frf::{self, LoopFrf};
use crate::table8::SEED_TABLE8;
use crate::tuning::{SaturationCheck, TuningProblem, mean_std};
use chatter_control::{ControllerParams, Structure};
use delay_stability::zero_order::speed_grid;
use milling_plant::PlantParams;
use std::fmt::Write as _;
use std::path::Path;
use study_kit::StudyError;
use study_kit::figures::{Curve, plot_xy};
use study_kit::optim::pso::PsoConfig;
use study_kit::output::{Series, plot_png, write_csv};

/// The study's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Table8Spec {
    /// PSO runs per controller.
    pub runs: usize,
    /// Swarm size.
    pub particles: usize,
    /// Iterations.
    pub iterations: usize,
    /// Robust saturation constraint: noise seeds 1..=N.
    pub check_seeds: u64,
    /// Saturation margin of the constraint.
    pub margin: f64,
    /// Speeds of each lobe diagram.
    pub points: usize,
    /// First PSO seed.
    pub seed: u64,
}

impl Table8Spec {
    /// The seed's settings (40 × 60, 10 runs) with the robust constraint of the shipped gains.
    pub fn full() -> Table8Spec {
        Table8Spec { runs: 10, particles: 40, iterations: 60, check_seeds: 5, margin: 0.1, points: 2001, seed: 1 }
    }

    /// A small run for the tests (2 runs of 6 × 3, one check seed, 201 speeds).
    pub fn quick() -> Table8Spec {
        Table8Spec { runs: 2, particles: 6, iterations: 3, check_seeds: 1, margin: 0.1, points: 201, seed: 1 }
    }
}

/// One row: its label, the mode, the controller (None: uncontrolled), the design's variables.
struct Row {
    label: String,
    mode: &'static str,
    ctrl: Option<AnyController>,
    variables: String,
    design: Option<Designed>,
}

/// PID with K_p, K_i at Table 3's lower bounds and `kd` (force units).
fn pid(kd: f64) -> ControllerParams {
    let mut c = ControllerParams { structure: Structure::Pid, ..ControllerParams::paper_table2() };
    c.pid.kp = 1e2;
    c.pid.ki = 1e-3;
    c.pid.kd = kd;
    c
}

/// K_d of the calibrated PID (bisection on log K_d for b_crit = `target`).
fn calibrate_pid(plant: &PlantParams, target: f64, speeds: &[f64]) -> Result<f64, String> {
    let b = |kd: f64| benchmark::min_depth(plant, &AnyController::Chatter(pid(kd)), speeds).map_or(0.0, |m| m.0);
    let (mut lo, mut hi) = (1.0, 1e4);
    if !(b(lo) < target && b(hi) > target) {
        return Err(format!("PID: K_d in [{lo}, {hi}] does not bracket b_crit = {target}"));
    }
    while hi / lo - 1.0 > 1e-8 {
        let mid = (lo * hi).sqrt();
        if b(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok((lo * hi).sqrt())
}

/// \[8\]'s b_crit of a row \[m\].
fn reference(label: &str) -> f64 {
    SEED_TABLE8.iter().find(|r| r.0 == label).map_or(f64::NAN, |r| r.2 * 1e-3)
}

/// A design's `LinearController` parameter set as an SSP `.ssv` (every value that differs from
/// the FMU's start value).
pub fn design_ssv(name: &str, d: &Designed) -> Result<String, String> {
    use fmi2_export::Fmi2Model;
    let md = fmu_linear_controller::LinearController::description();
    let base = fmu_linear_controller::parameter_assignments(&Default::default());
    let params: Vec<ssp::Parameter> = fmu_linear_controller::parameter_assignments(&d.params)
        .into_iter()
        .zip(base)
        .filter(|((_, v), (_, b))| v != b)
        .map(|((n, v), _)| ssp::fmu_parameter(md, &n, v, ssp::Enumerations::ItemNames))
        .collect::<Result<_, _>>()?;
    ssp::ssv_xml(name, &params).map_err(|e| e.to_string())
}

/// The levels and bounds an H∞ or μ design reports (`benchmark_control::designs::Report`), for
/// the table's variables column; empty for the other controllers.
fn bounds(d: &Designed) -> String {
    let r = &d.report;
    match d.kind {
        Benchmark::Hinf => {
            format!("; γ_opt {:.4}, γ {:.4}, achieved ‖[W_S S; W_T T]‖∞ {:.4}", r.gamma_opt, r.gamma, r.achieved)
        }
        Benchmark::Mu => {
            format!(
                "; μ upper bound RP {:.4}, RS {:.4}, γ {:.4}, {} D–K steps",
                r.mu_peak, r.mu_rs, r.gamma, r.dk_steps
            )
        }
        _ => String::new(),
    }
}

/// Table A1 statistics of one controller's runs: (n_p, mean, std, CV %, mean k_conv).
fn a1(costs: &[f64], histories: &[&[f64]], n_p: usize) -> (usize, f64, f64, f64, f64) {
    let (m, s) = mean_std(costs);
    let k: Vec<f64> = histories
        .iter()
        .map(|h| {
            let f = *h.last().unwrap_or(&0.0);
            h.iter().position(|x| (x - f).abs() <= 0.05 * f.abs()).unwrap_or(0) as f64
        })
        .collect();
    (n_p, m, s, 100.0 * s / m.abs(), mean_std(&k).0)
}

/// Run the study into `out` and return its markdown (module docs).
pub fn run(spec: &Table8Spec, out: &Path, progress: &dyn Fn(&str)) -> Result<String, StudyError> {
    let err = |e: String| StudyError::Invalid(e);
    std::fs::create_dir_all(out).map_err(|e| StudyError::io(out, e))?;
    let plant = loop_frf::ozsoy_plant();
    let speeds = speed_grid(1000.0, 3000.0, 41);
    let mut rows =
        vec![Row { label: "uncontrolled".into(), mode: "–", ctrl: None, variables: String::new(), design: None }];
    // calibrated mode
    for kind in ALL {
        let target = reference(kind.label());
        progress(&format!("calibrating {} to {:.2} mm", kind.label(), target * 1e3));
        let (x, d) = benchmark::calibrate(&plant, kind, target, &speeds, Response::Fmu).map_err(err)?;
        let variables = format!("{} = {x:.5e}{}", benchmark::calibration(kind).0, bounds(&d));
        rows.push(Row {
            label: kind.label().into(),
            mode: "calibrated",
            ctrl: Some(AnyController::Linear(Box::new(d.params.clone()))),
            variables,
            design: Some(d),
        });
        if kind == Benchmark::Vpa {
            let kd = calibrate_pid(&plant, reference("PID"), &speeds).map_err(err)?;
            rows.push(Row {
                label: "PID".into(),
                mode: "calibrated",
                ctrl: Some(AnyController::Chatter(pid(kd))),
                variables: format!("K_d = {kd:.5e} N·s/m (K_p 100, K_i 1e-3)"),
                design: None,
            });
        }
    }
    // PSO mode
    let mut a1_rows = String::from(
        "| controller | n_p | best J (mm) | mean J ± std (mm) | CV % | mean k_conv | seed Table A1 J̄ / CV % / k_conv |\n|---|---|---|---|---|---|---|\n",
    );
    let seed_a1 = [
        ("DVF", "0.660 / 0.02 / 35"),
        ("VPA", "0.550 / 0.04 / 38"),
        ("PID", "0.451 / 0.05 / 44"),
        ("LQR", "0.403 / 0.13 / 47"),
        ("H∞", "0.304 / 0.12 / 52"),
        ("μ", "0.275 / 0.31 / 53"),
        ("FOPID", "0.218 / 0.72 / 58"),
        ("ADRC-FOPID", "0.188 / 0.59 / 59"),
    ];
    let pso = |r: usize| PsoConfig {
        seed: spec.seed + r as u64,
        particles: spec.particles,
        iterations: spec.iterations,
        ..Default::default()
    };
    let mut a1_line = |label: &str, costs: &[f64], hist: &[&[f64]], n_p: usize| {
        let (n, m, s, cv, k) = a1(costs, hist, n_p);
        let best = costs.iter().copied().fold(f64::INFINITY, f64::min);
        let seed = seed_a1.iter().find(|x| x.0 == label).map_or("–", |x| x.1);
        let _ = writeln!(a1_rows, "| {label} | {n} | {best:.4} | {m:.4} ± {s:.4} | {cv:.3} | {k:.1} | {seed} |");
    };
    let order: [(&str, Option<Benchmark>, Option<Structure>); 8] = [
        ("DVF", Some(Benchmark::Dvf), None),
        ("VPA", Some(Benchmark::Vpa), None),
        ("PID", None, Some(Structure::Pid)),
        ("LQR", Some(Benchmark::Lqr), None),
        ("H∞", Some(Benchmark::Hinf), None),
        ("μ", Some(Benchmark::Mu), None),
        ("FOPID", None, Some(Structure::Fopid)),
        ("ADRC-FOPID", None, Some(Structure::AdrcFopid)),
    ];
    for (label, kind, structure) in order {
        progress(&format!("PSO: {label}, {} runs of {} × {}", spec.runs, spec.particles, spec.iterations));
        if let Some(kind) = kind {
            let prob = BenchmarkProblem::new(plant.clone(), kind, spec.check_seeds, spec.margin);
            let runs: Vec<_> = (0..spec.runs).map(|r| prob.run(&pso(r))).collect::<Result<_, _>>().map_err(err)?;
            let costs: Vec<f64> = runs.iter().map(|r| r.breakdown.cost).collect();
            let hist: Vec<&[f64]> = runs.iter().map(|r| r.pso.history.as_slice()).collect();
            a1_line(label, &costs, &hist, benchmark::search_space(kind).len());
            let best = runs.iter().min_by(|a, b| a.breakdown.cost.total_cmp(&b.breakdown.cost)).expect("runs");
            let names = benchmark::search_space(kind);
            let variables = names
                .iter()
                .zip(&best.best.values)
                .map(|(s, v)| format!("{} {v:.4e}", s.name))
                .collect::<Vec<_>>()
                .join(", ");
            rows.push(Row {
                label: label.into(),
                mode: "PSO",
                ctrl: Some(AnyController::Linear(Box::new(best.best.params.clone()))),
                variables: format!("{variables}; J = {:.4}{}", best.breakdown.cost, bounds(&best.best)),
                design: Some(best.best.clone()),
            });
        } else if let Some(s) = structure {
            let mut prob = TuningProblem::new(plant.clone(), s);
            prob.check.margin = spec.margin;
            prob.check_seeds = (1..=spec.check_seeds).collect();
            prob.tune_observer = s == Structure::AdrcFopid;
            let runs: Vec<_> = (0..spec.runs).map(|r| prob.run(&pso(r), |_, _| {})).collect();
            let costs: Vec<f64> = runs.iter().map(|r| r.breakdown.cost).collect();
            let hist: Vec<&[f64]> = runs.iter().map(|r| r.pso.history.as_slice()).collect();
            a1_line(label, &costs, &hist, prob.space().len());
            let best = runs.iter().min_by(|a, b| a.breakdown.cost.total_cmp(&b.breakdown.cost)).expect("runs");
            let variables = prob
                .space()
                .iter()
                .zip(&best.gains)
                .map(|(s, v)| format!("{} {v:.4e}", s.name))
                .collect::<Vec<_>>()
                .join(", ");
            rows.push(Row {
                label: label.into(),
                mode: "PSO",
                ctrl: Some(AnyController::Chatter(best.params)),
                variables: format!("{variables}; J = {:.4}", best.breakdown.cost),
                design: None,
            });
        }
    }
    // every row: lobes over both ranges, the peak, the fresh-seed check
    progress("lobes, peaks and fresh-seed checks of every row");
    let mut md = String::from(
        "| controller | mode | b_crit 1000–3000 (mm) | b_crit seed / [8] (mm) | b_max 1000–3000 (mm) | b_max seed / [8] (mm) | b_crit / b_max 500–3000 (mm) | peak \\|Φ_cl\\| (µm/N) at Hz | seed check passed, fresh seeds 101–110 | variables |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut fig17: Vec<Curve> = Vec::new();
    let mut fig18: [Vec<Series>; 2] = [Vec::new(), Vec::new()];
    let freqs: Vec<f64> = (0..600).map(|i| 100.0 + 0.15 * i as f64).collect();
    for row in &rows {
        let seed = SEED_TABLE8.iter().find(|r| r.0 == row.label);
        let seed_cols = seed.map_or(("–".to_string(), "–".to_string()), |r| {
            let f = |x: f64| if x.is_nan() { "novel".to_string() } else { format!("{x:.2}") };
            (format!("{:.2} / {}", r.1, f(r.2)), format!("{:.2} / {}", r.3, f(r.4)))
        });
        let mut ranges = Vec::new();
        for (k, (lo, hi)) in [(1000.0, 3000.0), (500.0, 3000.0)].into_iter().enumerate() {
            let n = ((hi - lo) as usize).max(spec.points - 1) + 1;
            let problem = loop_frf::problem_with(&plant, row.ctrl.as_ref(), lo).map_err(|e| err(e.to_string()))?;
            let d = problem.diagram(&speed_grid(lo, hi, n));
            let ex = problem.extremes(&d).ok_or_else(|| err(format!("{}: no lobes", row.label)))?;
            ranges.push(ex);
            if row.mode != "calibrated" {
                fig18[k].push(Series { name: row.label.clone(), points: d });
            }
        }
        let (peak, hz) = benchmark::peak_receptance(&plant, row.ctrl.as_ref(), 4000).map_err(err)?;
        let passed = match &row.ctrl {
            None => "–".to_string(),
            Some(c) => {
                let s = SaturationCheck::default().over_seeds_with(&plant, c, 101..=110).map_err(err)?;
                format!("{}/10 (peak {:.1} N)", s.passed, s.peak_u)
            }
        };
        let _ = writeln!(
            md,
            "| {} | {} | {:.3} | {} | {:.2} | {} | {:.3} / {:.2} | {:.3} at {hz:.1} | {passed} | {} |",
            row.label,
            row.mode,
            ranges[0].min.depth * 1e3,
            seed_cols.0,
            ranges[0].max.depth * 1e3,
            seed_cols.1,
            ranges[1].min.depth * 1e3,
            ranges[1].max.depth * 1e3,
            peak * 1e6,
            row.variables
        );
        if row.mode != "calibrated" {
            let frf = LoopFrf::with(&plant, row.ctrl.as_ref()).map_err(err)?;
            let w = |f: f64| frf.eval(2.0 * std::f64::consts::PI * f).norm() * 1e6;
            fig17.push((row.label.clone(), freqs.iter().map(|&f| (f, w(f))).collect()));
        }
        if let Some(d) = &row.design {
            let name = format!(
                "benchmark_{}_{}",
                model_kit::Choice::name(d.kind),
                if row.mode == "PSO" { "pso" } else { "calibrated" }
            );
            let path = out.join(format!("{name}.ssv"));
            let text = design_ssv(&name, d).map_err(err)?;
            std::fs::write(&path, text).map_err(|e| StudyError::io(&path, e))?;
        }
    }
    let write = |name: &str, text: &str| -> Result<(), StudyError> {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(|e| StudyError::io(&p, e))
    };
    let mut csv = String::from("frequency_hz");
    for (n, _) in &fig17 {
        let _ = write!(csv, ",receptance_um_per_N_{}", n.replace('∞', "inf").replace('μ', "mu"));
    }
    csv.push('\n');
    for (i, f) in freqs.iter().enumerate() {
        let _ = write!(csv, "{f}");
        for (_, c) in &fig17 {
            let _ = write!(csv, ",{:e}", c[i].1);
        }
        csv.push('\n');
    }
    write("fig17_receptance.csv", &csv)?;
    let plot = |e: fmi_master::plot::PlotError| StudyError::Invalid(e.to_string());
    plot_xy(
        &out.join("fig17_receptance.png"),
        "Figure 17: closed-loop receptance on the Ozsoy benchmark (PSO rows)",
        "frequency (Hz)",
        "|Φ_cl| (µm/N)",
        &fig17,
    )
    .map_err(plot)?;
    for (k, lo) in [1000, 500].into_iter().enumerate() {
        write_csv(&out.join(format!("fig18_lobes_{lo}.csv")), &fig18[k])?;
        plot_png(
            &out.join(format!("fig18_lobes_{lo}.png")),
            &format!("Figure 18: lobes on the Ozsoy benchmark, {lo}–3000 rpm (PSO rows)"),
            &fig18[k],
            1200,
            800,
        )
        .map_err(plot)?;
    }
    write("table8.md", &md)?;
    write("table_a1.md", &a1_rows)?;
    Ok(format!(
        "Table 8 (Ozsoy plant; PSO {} runs of {} × {}, constraint: noise seeds 1..={}, margin {}):\n\n{md}\nTable A1:\n\n{a1_rows}",
        spec.runs, spec.particles, spec.iterations, spec.check_seeds, spec.margin
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The calibrated designs packaging ships (`designs/benchmark_*_calibrated.ssv`, and the DVF
    /// gain `Benchmark.ssp` binds) are the ones the calibration gives now: read through the
    /// LinearController's table, their responses equal the fresh designs' to 1e-6.
    #[test]
    fn shipped_calibrated_designs_are_the_calibration() {
        let plant = loop_frf::ozsoy_plant();
        let speeds = speed_grid(1000.0, 3000.0, 41);
        for kind in ALL {
            let (x, d) = benchmark::calibrate(&plant, kind, reference(kind.label()), &speeds, Response::Fmu).unwrap();
            if kind == Benchmark::Dvf {
                assert!((x / packaging::BENCHMARK_DVF_GAIN - 1.0).abs() < 1e-5, "DVF gain {x}");
            }
            let file = format!("benchmark_{}_calibrated.ssv", model_kit::Choice::name(kind));
            let (_, xml) = packaging::BENCHMARK_DESIGNS.iter().find(|(n, _)| *n == file).unwrap();
            let mut r = study_kit::fmu_params::Resolved::default();
            for p in ssp::parse_ssv(xml, &file, "").unwrap() {
                study_kit::fmu_params::apply_ssp::<fmu_linear_controller::LinearController>(&mut r, &p.name, &p.value)
                    .unwrap();
            }
            let (a, b) = (
                linear_control::LinearController::new(&r.params).unwrap(),
                linear_control::LinearController::new(&d.params).unwrap(),
            );
            for w in [30.0, 892.8, 3000.0] {
                let (fa, fb) = (a.frequency_response(w, 0.0)[0][0], b.frequency_response(w, 0.0)[0][0]);
                assert!((fa - fb).norm() <= 1e-6 * fb.norm(), "{file} at {w}: {fa} vs {fb}");
            }
        }
    }
}
