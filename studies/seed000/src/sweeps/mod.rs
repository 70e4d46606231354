//! Seed 000, Section 5.6.5 (Figure 15): the feed and radial-engagement sweeps through the FMUs,
//! with two independent checks.
//!
//! **Feed.** f_z ∈ {0.025, 0.04, 0.055, 0.07, 0.085, 0.10, 0.12} mm at a_p = 1 mm and 2000 rpm;
//! the least-squares slope of the RMS against f_z (the seed: open loop and PID ≈ 39, FOPID ≈ 34,
//! ADRC-FOPID ≈ 32 µm/mm). Check (harmonic balance, noise and drift off): in the steady state
//! the displacement is periodic with the tooth period τ, so the regenerative chip `x(t) − x(t−τ)`
//! vanishes and the response is the forced one, harmonic by harmonic:
//!
//! ```text
//! X_k = |Φ_cl(k ω_tp)| · a_p K_t f_z · |c_k|,   ω_tp = Z Ω,
//! F(φ)/(a_p K_t f_z) = Σ_j g(φ_j) sin φ_j [(cos φ_j + k_r sin φ_j) d_x + (−sin φ_j + k_r cos φ_j) d_y]
//! ```
//!
//! (`c_k` the single-sided Fourier amplitudes of that tooth-periodic function, `g` the
//! engagement window, `d` the bending direction, exactly the plant core's force), and the RMS
//! about the mean is `√(Σ_{k=1..10} X_k²/2)`. `Φ_cl` is [`crate::loop_frf::LoopFrf`] with the
//! controller core's discrete response.
//!
//! **Engagement.** a_e ∈ {4, 6, 8, 10, 12, 14} mm, up-milling, φ_ex = arccos(1 − a_e/R) (the
//! seed's Eq. 9 "a_p" is a typo for a_e). Check: the lobe solver's minimum over 1000–3000 rpm
//! equals the closed form 2kζ(1 ± ζ)/(K_t |α₀(a_e)|) (+ for α₀ > 0, − for α₀ < 0) to 1e-6.

mod cases;

use crate::batch::{Metrics, RowSink, Windows, run_all, run_one};
use crate::loop_frf::{self, LoopFrf};
use crate::robustness::{base_plant, plant_overrides};
use crate::scenario::{Roles, roles};
pub use cases::*;
use chatter_control::{ControllerParams, Structure};
use delay_stability::zero_order::speed_grid;
use fmi_master::{Override, SystemFile};
use milling_plant::PlantParams;
use model_description::Value;
use model_kit::Choice;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::PathBuf;
use study_kit::StudyError;
use study_kit::fmu_params::{Resolved, resolve};

/// The seed's feed slopes (µm/mm).
pub const SEED_FEED_SLOPES: [(Structure, f64); 4] =
    [(Structure::Off, 39.0), (Structure::Pid, 39.0), (Structure::Fopid, 34.0), (Structure::AdrcFopid, 32.0)];

/// The seed's feeds per tooth \[mm\].
pub const FEEDS_MM: [f64; 7] = [0.025, 0.04, 0.055, 0.07, 0.085, 0.10, 0.12];

/// The seed's radial engagements \[mm\].
pub const ENGAGEMENTS_MM: [f64; 6] = [4.0, 6.0, 8.0, 10.0, 12.0, 14.0];

/// Which process parameter is swept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Feed per tooth.
    Feed,
    /// Radial engagement (up-milling).
    Engagement,
}

/// The sweep's settings.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// Feed or engagement.
    pub kind: Kind,
    /// Values \[m\].
    pub values: Vec<f64>,
    /// Controllers.
    pub controllers: Vec<Structure>,
    /// Noise seed.
    pub seed: i32,
    /// Windows (default 10 s, RMS over (1, 10] s).
    pub windows: Windows,
    /// Noise and drift off.
    pub quiet: bool,
    /// Controller gains as overrides.
    pub gains: Vec<Override>,
    /// Output directory.
    pub out: PathBuf,
}

/// One run of a sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepRow {
    /// Controller.
    pub controller: Structure,
    /// Swept value \[m\].
    pub value: f64,
    /// Through the FMUs.
    pub metrics: Metrics,
    /// Harmonic-balance RMS about the mean \[m\] (the forced response alone).
    pub harmonic: f64,
    /// Open-loop lobe minimum over 1000–3000 rpm from the solver \[m\] (engagement sweep).
    pub b_lim_solver: f64,
    /// The closed form 2kζ(1 ± ζ)/(K_t |α₀|) \[m\].
    pub b_lim_closed: f64,
}

/// Single-sided amplitudes `|c_k|`, k = 1..=kmax, of the tooth-periodic force per unit
/// `a_p K_t f_z` along the beam (see the module documentation), by an M-point DFT over one
/// tooth period.
pub fn force_harmonics(p: &PlantParams, kmax: usize) -> Vec<f64> {
    let c = &p.cutting;
    let z = c.teeth as usize;
    let pitch = 2.0 * PI / z as f64;
    let kr = c.kr / c.kt;
    let (st, ex) = p.engagement();
    let (ux, uy) = p.direction();
    let m = 8192;
    let f: Vec<f64> = (0..m)
        .map(|i| {
            let th = pitch * i as f64 / m as f64;
            (0..z)
                .map(|j| {
                    let phi = (th + j as f64 * pitch).rem_euclid(2.0 * PI);
                    if phi < st || phi > ex {
                        return 0.0;
                    }
                    let (s, co) = phi.sin_cos();
                    if s <= 0.0 {
                        return 0.0;
                    }
                    s * ((co + kr * s) * ux + (-s + kr * co) * uy)
                })
                .sum()
        })
        .collect();
    (1..=kmax)
        .map(|k| {
            let (mut re, mut im) = (0.0, 0.0);
            for (i, v) in f.iter().enumerate() {
                let a = 2.0 * PI * (k * i) as f64 / m as f64;
                re += v * a.cos();
                im -= v * a.sin();
            }
            2.0 * (re * re + im * im).sqrt() / m as f64
        })
        .collect()
}

/// The forced response's RMS about the mean \[m\] at `rpm` and feed `feed` \[m\], harmonics
/// 1–10 of the tooth-passing frequency, open loop (`ctrl` None or `off`) or closed loop.
pub fn harmonic_rms(p: &PlantParams, ctrl: Option<&ControllerParams>, rpm: f64, feed: f64) -> Result<f64, StudyError> {
    let frf = LoopFrf::new(p, ctrl).map_err(StudyError::Invalid)?;
    let w_tp = f64::from(p.cutting.teeth) * rpm / 60.0 * 2.0 * PI;
    let scale = p.cutting.axial_depth * p.cutting.kt * feed;
    let s2: f64 = force_harmonics(p, 10)
        .iter()
        .enumerate()
        .map(|(i, c)| (frf.eval((i + 1) as f64 * w_tp).norm() * scale * c).powi(2) / 2.0)
        .sum();
    Ok(s2.sqrt())
}

/// The open-loop lobe minimum over 1000–3000 rpm from the solver, and the closed form
/// 2kζ(1 ± ζ)/(K_t |α₀|) of the first mode \[m\].
pub fn lobe_minimum(p: &PlantParams) -> Result<(f64, f64), StudyError> {
    let rpm = speed_grid(1000.0, 3000.0, 2001);
    let problem = loop_frf::problem(p, None, 1000.0).map_err(|e| StudyError::Invalid(e.to_string()))?;
    let ex = problem.extremes(&problem.diagram(&rpm)).ok_or_else(|| StudyError::Invalid("no lobe minimum".into()))?;
    let m = &p.workpiece.first;
    let a0 = p.directional_coefficient();
    let z = m.damping_ratio;
    let closed = 2.0 * m.stiffness * z * (1.0 + z.copysign(a0)) / (p.cutting.kt * a0.abs());
    Ok((ex.min.depth, closed))
}

/// A length \[m\] in mm, rounded to the nm (so 0.12 mm prints as `0.12`).
pub fn mm(v: f64) -> f64 {
    (v * 1e9).round() / 1e6
}

/// Least-squares slope of `y` against `x`.
pub fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

impl Kind {
    /// `feed` or `engagement` (file names, CSV header, titles).
    pub fn name(self) -> &'static str {
        match self {
            Kind::Feed => "feed",
            Kind::Engagement => "engagement",
        }
    }
}

/// One run of a sweep, resolved.
#[derive(Clone, Debug)]
pub struct SweepJob {
    /// Controller.
    pub controller: Structure,
    /// Swept value \[m\].
    pub value: f64,
    /// Every override of the run.
    pub overrides: Vec<Override>,
    /// The plant as the FMU resolves it.
    pub plant: Resolved<PlantParams, milling_plant::PlantInputs>,
    /// The controller as the FMU resolves it.
    pub ctrl: ControllerParams,
}

/// What one run measures: the FMU metrics, the harmonic balance and the lobe minimum by solver
/// and closed form (NaN for the feed sweep), SI units.
pub type SweepOutput = (Metrics, f64, f64, f64);

/// Every run of the sweep (controller × value).
pub fn jobs(sys: &SystemFile, s: &Sweep) -> Result<Vec<SweepJob>, StudyError> {
    if s.values.is_empty() || s.controllers.is_empty() {
        return Err(StudyError::Invalid("the sweep needs at least one value and one controller".into()));
    }
    if let Some(v) = s.values.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        return Err(StudyError::Invalid(format!("sweep value {v} m: values must be positive")));
    }
    s.windows.validate()?;
    let roles = roles(sys)?;
    let base = base_plant(sys, &roles)?;
    let name = s.kind.name();
    let mut jobs = Vec::new();
    for &c in &s.controllers {
        for &v in &s.values {
            let (mut p, mut i) = base.clone();
            match s.kind {
                Kind::Feed => i.feed_per_tooth = v,
                Kind::Engagement => {
                    p.cutting.radial_engagement = v;
                    p.cutting.milling = milling_plant::MillingMode::Up;
                }
            }
            if s.quiet {
                p.disturbance.noise = false;
                p.disturbance.drift = false;
            }
            p.seed = u64::try_from(s.seed).unwrap_or(0);
            p.validate().map_err(|e| StudyError::Invalid(format!("{name} {v} m: {e}")))?;
            let mut o = s.gains.clone();
            o.extend(plant_overrides(&roles, &(p, i)));
            o.push(Override::typed(format!("{}.structure", roles.controller), Value::Integer(c.index())));
            let plant = resolve::<fmu_plant::MillingPlant>(sys, &roles.plant, &o)?;
            let ctrl = resolve::<fmu_controller::ChatterController>(sys, &roles.controller, &o)?.params;
            jobs.push(SweepJob { controller: c, value: v, overrides: o, plant, ctrl });
        }
    }
    Ok(jobs)
}

/// Run one job through the FMUs, with its two checks.
pub fn run_job(sys: &SystemFile, roles: &Roles, s: &Sweep, j: &SweepJob) -> Result<SweepOutput, StudyError> {
    let metrics = run_one(sys, roles, j.overrides.clone(), &s.windows)?;
    let i = &j.plant.inputs;
    let harmonic = harmonic_rms(&j.plant.params, Some(&j.ctrl), i.spindle_speed_rpm, i.feed_per_tooth)?;
    let (b_lim_solver, b_lim_closed) = match s.kind {
        Kind::Engagement => lobe_minimum(&j.plant.params)?,
        Kind::Feed => (f64::NAN, f64::NAN),
    };
    Ok((metrics, harmonic, b_lim_solver, b_lim_closed))
}

/// A job and its output as a row.
pub fn row(j: &SweepJob, (metrics, harmonic, b_lim_solver, b_lim_closed): &SweepOutput) -> SweepRow {
    SweepRow {
        controller: j.controller,
        value: j.value,
        metrics: *metrics,
        harmonic: *harmonic,
        b_lim_solver: *b_lim_solver,
        b_lim_closed: *b_lim_closed,
    }
}

/// The header of `sweep_<kind>.csv`.
pub fn csv_header(kind: Kind) -> String {
    format!(
        "controller,{}_mm,rms_um,rms_detrended_um,harmonic_balance_um,saturation_duty,b_lim_solver_mm,b_lim_closed_form_mm",
        kind.name()
    )
}

/// One row of `sweep_<kind>.csv`.
pub fn csv_row(r: &SweepRow) -> String {
    format!(
        "{},{},{:.6},{:.6},{:.6},{:.6},{:.12e},{:.12e}",
        r.controller.name(),
        mm(r.value),
        r.metrics.rms * 1e6,
        r.metrics.rms_detrended * 1e6,
        r.harmonic * 1e6,
        r.metrics.saturation_duty,
        r.b_lim_solver * 1e3,
        r.b_lim_closed * 1e3
    )
}

/// Run the sweep through the FMUs (rows streamed to `<out>/sweep_<kind>.csv`).
pub fn run(sys: &SystemFile, s: &Sweep) -> Result<Vec<SweepRow>, StudyError> {
    let jobs = jobs(sys, s)?;
    let roles = roles(sys)?;
    let name = s.kind.name();
    let sink = RowSink::create(&s.out.join(format!("sweep_{name}.csv")), &csv_header(s.kind))?;
    run_all(
        &jobs,
        name,
        &sink,
        |j| format!("{} at {name} {} mm", j.controller.name(), j.value * 1e3),
        |j| Ok(row(j, &run_job(sys, &roles, s, j)?)),
        |_, r| csv_row(r),
    )
}

/// `sweep_<kind>.md` and `.png` in `s.out` from the rows (sorted by controller and value): the
/// table (the harmonic-balance deviation, the engagement sweep's lobe minima), the feed slopes
/// beside the seed's, the figure. `preset` names the gains; `wall` (the local command's run
/// time \[s\]) goes into the title. Returns the markdown.
pub fn report(s: &Sweep, rows: &[SweepRow], preset: &str, wall: Option<f64>) -> Result<String, StudyError> {
    let (kind, name, stop) = (s.kind, s.kind.name(), s.windows.stop);
    let mut rows = rows.to_vec();
    rows.sort_by(|x, y| (x.controller.index(), x.value).partial_cmp(&(y.controller.index(), y.value)).expect("finite"));
    let eng = kind == Kind::Engagement;
    let mut md = format!(
        "Sweep of the {name} (seed 000 Figure 15; {preset} gains; noise seed {}{}; {stop} s runs, RMS over (1, {stop}] s{})\n\n| controller | {name} (mm) | raw RMS (µm) | detrended RMS (µm) | harmonic balance (µm) | Δ % | saturation duty |{}\n|---|---|---|---|---|---|---|{}\n",
        s.seed,
        if s.quiet { ", noise and drift OFF" } else { ", noise and drift on" },
        wall.map_or(String::new(), |w| format!("; {w:.0} s wall")),
        if eng { " open-loop b_lim solver / closed form (mm) |" } else { "" },
        if eng { "---|" } else { "" },
    );
    for x in &rows {
        let _ = write!(
            md,
            "| {} | {} | {:.3} | {:.3} | {:.3} | {:+.2} | {:.1} % |",
            x.controller.name(),
            mm(x.value),
            x.metrics.rms * 1e6,
            x.metrics.rms_detrended * 1e6,
            x.harmonic * 1e6,
            100.0 * (x.metrics.rms_detrended / x.harmonic - 1.0),
            100.0 * x.metrics.saturation_duty
        );
        if eng {
            let _ = write!(md, " {:.6} / {:.6} |", x.b_lim_solver * 1e3, x.b_lim_closed * 1e3);
        }
        md.push('\n');
    }
    let mut curves = Vec::new();
    for &c in &s.controllers {
        let pts: Vec<(f64, f64)> =
            rows.iter().filter(|x| x.controller == c).map(|x| (mm(x.value), x.metrics.rms * 1e6)).collect();
        if kind == Kind::Feed && pts.len() > 1 {
            let (fx, fy): (Vec<f64>, Vec<f64>) = pts.iter().copied().unzip();
            let seed = SEED_FEED_SLOPES.iter().find(|(x, _)| *x == c).map_or("–".into(), |(_, v)| format!("{v:.0}"));
            let _ = write!(
                md,
                "\nRMS slope against f_z, {}: {:.1} µm/mm (seed ≈ {seed} µm/mm).",
                c.name(),
                slope(&fx, &fy)
            );
        }
        curves.push((c.name().to_string(), pts));
    }
    md.push('\n');
    study_kit::figures::plot_xy(
        &s.out.join(format!("sweep_{name}.png")),
        &format!("RMS tip displacement against the {name} (cf. seed Figure 15)"),
        &format!("{name} [mm]"),
        "RMS x [µm]",
        &curves,
    )?;
    let path = s.out.join(format!("sweep_{name}.md"));
    std::fs::write(&path, &md).map_err(|e| StudyError::io(&path, e))?;
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Half-immersion up-milling along the feed: the mean of the force function is the static
    /// coefficient, and the first harmonic is of the same order.
    #[test]
    fn force_harmonics_are_consistent_with_the_static_coefficient() {
        let p = PlantParams::default();
        let c = force_harmonics(&p, 4);
        assert!(c[0] > 0.1 * p.static_force_coefficient().abs() && c[0] < 10.0 * p.static_force_coefficient().abs());
        assert!((slope(&[1.0, 2.0, 3.0], &[2.0, 4.0, 6.1]) - 2.05).abs() < 1e-12);
    }
}
