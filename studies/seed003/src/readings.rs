//! # Seed 003: Table 2 under every plausible reading of what the paper leaves open
//!
//! Table 2 ([`crate::dsmc`]) depends on choices the paper does not make for us:
//!
//! * **what the controller knows of `A_dis`** (Eq. 22 calls `A_dis` and `B_dis` unknown): the
//!   exact ZOH model of the true axis (our default), the Euler prediction `ĵ = p + T ṗ`, or
//!   nothing (`ĵ = p`), see [`sliding_fuzzy_control::params`];
//! * **the sample period T** (not given; 1e-4 s by default): 1, 2, 3 and 5 × 1e-4 s (the D-PID's
//!   gains, in mm, lose stability between 3e-4 and 5e-4 s);
//! * **the force limit** (not given; 2 kN by default): 200 N, 2 kN, 20 kN;
//! * **the computation time** (Eq. 19: none): one sample of computation delay, with the
//!   controller's one-step prediction.
//!
//! [`sweep`] runs the none / DSMC / D-PID (mm) / DSMC-T1 / DSMC-T2 rows of Table 2 for every
//! combination, each with the forcing calibrated on Table 2's open loop at its T (the MSE is
//! taken on the sample grid, so the calibration depends on T), and reports the ranking and the
//! reductions per axis. A run that diverges (the D-PID beyond its stable T, the cutting law's
//! subcritical growth) is reported as such, not dropped. No reading is chosen to hit a number
//! of the paper; the default is argued on the seed's page.

use crate::dsmc::{self, DsmcStudy};
use sliding_fuzzy_control::{ControlMode, NominalModel, SlidingFuzzyError, SlidingFuzzyParams, ToolParams, simulate};

/// One reading of the controller's knowledge and timing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reading {
    /// Name in the tables.
    pub label: &'static str,
    /// What the controller knows of `A_dis`.
    pub nominal_model: NominalModel,
    /// One sample of computation delay.
    pub computation_delay: bool,
}

/// The readings of the sweep: the three models of `A_dis` without delay, and the default model
/// with one sample of computation delay.
pub fn readings() -> Vec<Reading> {
    let r = |label, nominal_model, computation_delay| Reading { label, nominal_model, computation_delay };
    vec![
        r("exact ZOH (default)", NominalModel::ExactZoh, false),
        r("Euler (j = p + T v)", NominalModel::Euler, false),
        r("identity (j = p)", NominalModel::Identity, false),
        r("exact ZOH + 1-sample delay", NominalModel::ExactZoh, true),
    ]
}

/// The sweep's grid.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSpec {
    /// Readings.
    pub readings: Vec<Reading>,
    /// Sample periods T [s].
    pub periods: Vec<f64>,
    /// Force limits [N].
    pub force_limits: Vec<f64>,
}

impl Default for SweepSpec {
    fn default() -> Self {
        SweepSpec {
            readings: readings(),
            periods: vec![1e-4, 2e-4, 3e-4, 5e-4],
            force_limits: vec![200.0, 2000.0, 2e4],
        }
    }
}

/// The controllers of the sweep: (label, mode). The D-PID's error is in mm (the reading under
/// which Eq. 63's gains act); it does not depend on the model of `A_dis`.
pub const CONTROLLERS: [(&str, ControlMode); 5] = [
    ("none", ControlMode::Off),
    ("dsmc", ControlMode::Dsmc),
    ("dpid", ControlMode::Dpid),
    ("dsmc_t1", ControlMode::DsmcT1),
    ("dsmc_t2", ControlMode::DsmcT2),
];

/// One point of the grid: the reading, T, the force limit and the five controllers' MSE.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoint {
    /// The reading.
    pub reading: Reading,
    /// Sample period [s].
    pub period: f64,
    /// Force limit [N].
    pub force_limit: f64,
    /// The calibrated forcing amplitudes (x, y) [N].
    pub amplitude: [f64; 2],
    /// MSE (x, y) [µm²] per controller of [`CONTROLLERS`]; `None`: the run diverged.
    pub mse: Vec<Option<[f64; 2]>>,
}

impl SweepPoint {
    /// The MSE of controller `label` on axis `a` (NaN if diverged or absent).
    pub fn mse_of(&self, label: &str, a: usize) -> f64 {
        CONTROLLERS.iter().position(|c| c.0 == label).and_then(|i| self.mse[i]).map_or(f64::NAN, |m| m[a])
    }

    /// Reduction of `label` against no control on axis `a` [%].
    pub fn reduction(&self, label: &str, a: usize) -> f64 {
        100.0 * (1.0 - self.mse_of(label, a) / self.mse_of("none", a))
    }

    /// The controllers best first on axis `a` (the diverged ones last, marked).
    pub fn ranking(&self, a: usize) -> Vec<String> {
        let mut v: Vec<(f64, &str)> = CONTROLLERS.iter().map(|c| (self.mse_of(c.0, a), c.0)).collect();
        v.sort_by(|p, q| p.0.total_cmp(&q.0));
        v.iter().map(|(m, n)| if m.is_nan() { format!("{n} (diverges)") } else { (*n).to_string() }).collect()
    }
}

/// The controller parameters of a reading at `(T, u_max)` (the rest from `base`).
pub fn params(base: &SlidingFuzzyParams, r: &Reading, period: f64, force_limit: f64) -> SlidingFuzzyParams {
    SlidingFuzzyParams {
        sample_period: period,
        force_limit,
        nominal_model: r.nominal_model,
        computation_delay: r.computation_delay,
        ..base.clone()
    }
}

/// MSE (x, y) in µm² over the study's window, `None` when the loop leaves the finite range.
pub fn mse_or_diverged(s: &DsmcStudy, tool: &ToolParams, p: &SlidingFuzzyParams) -> Option<[f64; 2]> {
    match simulate(tool, p, s.t_end) {
        Ok((r, _)) => {
            let m = r.mse_mm(s.window_start, s.t_end).map(|v| v * 1e6);
            m.iter().all(|v| v.is_finite()).then_some(m)
        }
        Err(_) => None,
    }
}

/// The grid: every reading × T × force limit. The calibration is per T (the open loop does
/// not depend on the reading or the limit).
pub fn sweep(s: &DsmcStudy, spec: &SweepSpec) -> Result<Vec<SweepPoint>, SlidingFuzzyError> {
    let mut out = Vec::new();
    for &period in &spec.periods {
        let at_t =
            DsmcStudy { controller: SlidingFuzzyParams { sample_period: period, ..s.controller.clone() }, ..s.clone() };
        let (amplitude, _) = dsmc::calibrate(&at_t)?;
        let tool = ToolParams { forcing_amplitude: amplitude, ..s.tool.clone() };
        for r in &spec.readings {
            for &force_limit in &spec.force_limits {
                let base = params(&s.controller, r, period, force_limit);
                let mse = CONTROLLERS
                    .iter()
                    .map(|(_, mode)| mse_or_diverged(s, &tool, &SlidingFuzzyParams { mode: *mode, ..base.clone() }))
                    .collect();
                out.push(SweepPoint { reading: *r, period, force_limit, amplitude, mse });
            }
        }
    }
    Ok(out)
}

/// The grid as CSV: one row per point and controller.
pub fn csv(points: &[SweepPoint]) -> String {
    let mut s = String::from(
        "reading,nominal_model,computation_delay,T_s,u_max_N,A_x_N,A_y_N,controller,mse_x_um2,mse_y_um2,reduction_x_pct,reduction_y_pct\n",
    );
    for p in points {
        for (c, _) in CONTROLLERS {
            s += &format!(
                "{},{},{},{},{},{:.6},{:.6},{},{:.9e},{:.9e},{:.4},{:.4}\n",
                p.reading.label,
                model_kit::Choice::name(p.reading.nominal_model),
                p.reading.computation_delay,
                p.period,
                p.force_limit,
                p.amplitude[0],
                p.amplitude[1],
                c,
                p.mse_of(c, 0),
                p.mse_of(c, 1),
                p.reduction(c, 0),
                p.reduction(c, 1)
            );
        }
    }
    s
}

/// A reduction as printed: one decimal; "diverges" for a run that left the finite range, and
/// for a controller more than twice as bad as none the factor `×MSE/MSE(none)` instead.
fn pct(v: f64) -> String {
    if v.is_nan() {
        "diverges".into()
    } else if v < -100.0 {
        let r = 1.0 - v / 100.0;
        if r < 100.0 { format!("×{r:.1}") } else { format!("×{r:.1e}") }
    } else {
        format!("{v:.1}")
    }
}

/// The grid as a Markdown table: per point the ranking on each axis (best first) and the
/// reductions of DSMC, D-PID, T1 and T2 against no control (printed by `pct`).
pub fn markdown(points: &[SweepPoint]) -> String {
    let mut s = String::from(
        "| reading | T [s] | u_max [N] | ranking x (best first) | ranking y (best first) | reduction x [%]: DSMC / D-PID / T1 / T2 | reduction y [%]: DSMC / D-PID / T1 / T2 |\n|---|---|---|---|---|---|---|\n",
    );
    for p in points {
        let red = |a: usize| {
            ["dsmc", "dpid", "dsmc_t1", "dsmc_t2"]
                .iter()
                .map(|c| pct(p.reduction(c, a)))
                .collect::<Vec<_>>()
                .join(" / ")
        };
        s += &format!(
            "| {} | {:e} | {} | {} | {} | {} | {} |\n",
            p.reading.label,
            p.period,
            p.force_limit,
            p.ranking(0).join(" < "),
            p.ranking(1).join(" < "),
            red(0),
            red(1)
        );
    }
    s
}
