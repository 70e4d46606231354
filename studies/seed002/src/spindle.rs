//! Seed 002 end to end on the FMUs (`Spindle.ssp`: MillingProcess + SpindleStructure +
//! LinearController) and the closed-loop tool FRFs. The lobes themselves are
//! [`seed000::sd_lobes`] (presets `seed002-6.1`, `-6.1-closed`, `-6.2`) and the exact boundary
//! [`delay_stability::exact`]; this module adds what needs the new spindle and controller.
//!
//! **Time domain.** [`SpindleCheck::growth_ratio`] runs the shipped system in the Rust master
//! at a speed and depth, the controller's `D_c` set from `(k₁, k₂)` \[N/mm\] (or zero: open
//! loop), and measures the regenerative difference `d(t) = v_t(t) − v_t(t − τ)` (both axes,
//! Euclidean norm) of the recorded tool displacement: peak over the last fifth / peak over the
//! second fifth, as [`seed000::sd_validation`] does for the seed 000 plant. The forced τ-periodic
//! motion cancels in `d`; below 1 the cut is stable. With [`SpindleCheck::ramp`] the process
//! enters the cut over that time (its `depth_ramp_time`), so the growth starts from a small
//! vibration instead of the ringing of a full engagement at once (which is about the static
//! deflection and makes teeth leave the cut, README).
//!
//! **Closed-loop tool FRF** ([`tool_frf`]): `G_tt,c(iω) = C_t (iωI − A − B_a K(iω) C_a)⁻¹ B_t`
//! with `K(iω)` the controller's response including the Pyragas factor `1 − β e^{−iωτ}`, taken
//! from `LinearController.fmu`'s own code path ([`fmu_linear_controller::frequency_response`])
//! and the spindle matrices from the spindle core ([`spindle_structure`]).

use fmi_master::{Override, Progress, RunConfig, SimError, Simulation, SystemFile};
use linear_control::LinearControlParams;
use model_description::Value;
use num_complex::Complex64;
use spindle_structure::{Spindle, SpindleParams};
use std::fmt::Write as _;
use std::path::Path;
use study_kit::StudyError;
use study_kit::growth::Regen;

/// `Spindle.ssp` in `fmu_dir` if it exists, else the shipped SSD with the FMUs of `fmu_dir`.
pub fn spindle_system(fmu_dir: &Path) -> Result<SystemFile, StudyError> {
    let ssp = fmu_dir.join("Spindle.ssp");
    if ssp.exists() {
        Ok(SystemFile::open(&ssp, Some(fmu_dir))?)
    } else {
        Ok(SystemFile::from_text(packaging::SPINDLE_SSD, "Spindle.ssd", fmu_dir)?)
    }
}

/// The controller parameters of a static gain `D_c = [[k₁, −k₂], [k₂, k₁]]` (gains in N/mm,
/// β = 1, τ from the speed); `None` is the open loop (zero gain).
pub fn static_gain(gains: Option<(f64, f64)>) -> LinearControlParams {
    let mut p = LinearControlParams::default();
    if let Some((k1, k2)) = gains {
        p.dc = [[k1 * 1e3, -k2 * 1e3], [k2 * 1e3, k1 * 1e3]];
    }
    p
}

/// A controller design delivered as an SSP parameter set (`chatter synth` writes `<case>.ssv`
/// with the `LinearController` names): read through the FMU's own variable table (names, types,
/// bounds), starting from its defaults, so a design runs here exactly as bound in an SSP.
pub fn design_params(path: &Path) -> Result<LinearControlParams, StudyError> {
    let xml = std::fs::read_to_string(path).map_err(|e| StudyError::io(path, e))?;
    let file = path.display().to_string();
    let params = ssp::parse_ssv(&xml, &file, "").map_err(|e| StudyError::Invalid(format!("{file}: {e}")))?;
    let mut r = study_kit::fmu_params::Resolved::default();
    for p in &params {
        study_kit::fmu_params::apply_ssp::<fmu_linear_controller::LinearController>(&mut r, &p.name, &p.value)
            .map_err(|e| StudyError::Invalid(format!("{file}: {e}")))?;
    }
    Ok(r.params)
}

/// The design `c` as the stability model's controller (`A_c`, `B_c`, `C_c`, `D_c`, β: the
/// first `n_c` rows and columns).
pub fn sd_controller(c: &LinearControlParams) -> delay_stability::milling::Controller {
    use nalgebra::DMatrix;
    let n = c.n_c as usize;
    delay_stability::milling::Controller {
        ac: DMatrix::from_fn(n, n, |i, j| c.ac[i][j]),
        bc: DMatrix::from_fn(n, 2, |i, j| c.bc[i][j]),
        cc: DMatrix::from_fn(2, n, |i, j| c.cc[i][j]),
        dc: DMatrix::from_fn(2, 2, |i, j| c.dc[i][j]),
        beta: c.beta,
    }
}

/// The semi-discretisation boundary \[m\] of seed 002's spindle with controller `c` (`None`:
/// open loop) at `rpm`, force exponent `x_f` (the seed's cutter), `m` intervals per period.
pub fn sd_boundary(c: Option<&LinearControlParams>, x_f: f64, rpm: f64, m: usize) -> Result<f64, StudyError> {
    let inv = |e: delay_stability::StabilityError| StudyError::Invalid(e.to_string());
    let cutter = delay_stability::presets::seed002_cutter(x_f).map_err(inv)?;
    let ctrl = c.map(sd_controller);
    let model = delay_stability::milling::MillingModel::new(
        &delay_stability::presets::seed002_structure(),
        cutter,
        ctrl.as_ref(),
    )
    .map_err(inv)?;
    let o = delay_stability::BisectionOptions { m, start: 0.3e-3, growth: 1.1, max: 0.02, rel_tol: 1e-5 };
    delay_stability::critical_value(|d| model.at(rpm, d), &o)
        .map_err(inv)?
        .value
        .ok_or_else(|| StudyError::Invalid(format!("no stability boundary below 20 mm at {rpm} rpm")))
}

/// The shipped spindle system set up for growth/decay runs.
pub struct SpindleCheck<'a> {
    sys: &'a SystemFile,
    /// Communication step \[s\] (default 1 µs).
    pub step: f64,
    /// The process's entry ramp `depth_ramp_time` \[s\] (default 0: full depth at once). With
    /// a ramp the growth ratio compares windows after it: it must end within the first fifth of
    /// the run ([`SpindleCheck::growth_ratio`] refuses a longer one).
    pub ramp: f64,
    /// The process's force exponent x_F (1: §6.1, 0.744: §6.2 and Table II), with the seed's
    /// coefficients for it (`delay_stability::presets::seed002_cutter`). Default 1.
    pub x_f: f64,
}

impl<'a> SpindleCheck<'a> {
    /// The check on `sys` (the shipped `Spindle.ssp`/`.ssd`: components `process`, `spindle`,
    /// `controller`).
    pub fn new(sys: &'a SystemFile) -> Self {
        SpindleCheck { sys, step: 1e-6, ramp: 0.0, x_f: 1.0 }
    }

    /// The typed overrides of one run: depth and speed of the process, the speed and the
    /// parameters `c` of the controller.
    pub fn overrides(&self, rpm: f64, depth: f64, c: &LinearControlParams) -> Vec<Override> {
        let mut o = vec![
            Override::typed("process.axial_depth", Value::Real(depth)),
            Override::typed("process.spindle_speed", Value::Real(rpm)),
            Override::typed("controller.spindle_speed", Value::Real(rpm)),
            Override::typed("process.depth_ramp_time", Value::Real(self.ramp)),
        ];
        if (self.x_f - 1.0).abs() > 1e-12 {
            // the seed's coefficients for x_F (N/m^(1+x_F)), the law the SD model linearises
            let scale = 1000f64.powf(1.0 + self.x_f);
            o.extend([
                Override::typed("process.exponent", Value::Real(self.x_f)),
                Override::typed("process.kt", Value::Real(462.0 * scale)),
                Override::typed("process.kr", Value::Real(38.6 * scale)),
            ]);
        }
        o.extend(study_kit::fmu_params::overrides_of("controller", fmu_linear_controller::parameter_assignments(c)));
        o
    }

    /// Late / mid peak of `|v_t(t) − v_t(t − τ)|` over `duration` (module docs).
    pub fn growth_ratio(
        &self,
        rpm: f64,
        depth: f64,
        c: &LinearControlParams,
        duration: f64,
    ) -> Result<f64, StudyError> {
        if !(rpm > 0.0 && depth >= 0.0 && duration > 0.0 && self.step > 0.0) {
            return Err(StudyError::Invalid(format!(
                "need rpm > 0, depth >= 0, duration > 0 (got {rpm}, {depth}, {duration})"
            )));
        }
        if !(self.ramp >= 0.0 && self.ramp <= 0.2 * duration) {
            return Err(StudyError::Invalid(format!(
                "the entry ramp ({} s) must end within the first fifth of the run ({duration} s): the growth is \
                 measured from the second fifth",
                self.ramp
            )));
        }
        let cfg = RunConfig {
            start: Some(0.0),
            stop: Some(duration),
            step: Some(self.step),
            overrides: self.overrides(rpm, depth, c),
            record: Some(vec!["spindle.tool_x".into(), "spindle.tool_y".into()]),
            ..RunConfig::default()
        };
        let mut sim = Simulation::new(self.sys, &cfg)?;
        let n = usize::try_from(sim.n_steps() + 1).unwrap_or(usize::MAX);
        let tau = 60.0 / (c.teeth as f64 * rpm);
        // |v_t(t) − v_t(t − τ)| of the tool displacement (x, y)
        let mut obs = Regen::<2>::new(n, tau / self.step);
        match sim.run(&mut obs, Progress::Off) {
            // the spindle stops with an error when a displacement passes 1 m: grown without bound
            Err(SimError::Fmu(_)) if obs.windows.max > 1e-3 => Ok(f64::INFINITY),
            Err(e) => Err(e.into()),
            Ok(_) => Ok(obs.windows.ratio()),
        }
    }
}

/// One row of [`tool_frf`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrfRow {
    /// Frequency \[Hz\].
    pub hz: f64,
    /// Open-loop `G_tt` (x→x, y→y) \[m/N\].
    pub open: [Complex64; 2],
    /// Closed-loop `G_tt,c` (x→x, y→y) \[m/N\].
    pub closed: [Complex64; 2],
}

/// Open- and closed-loop tool FRFs of Table I's spindle with controller `c` at spindle speed
/// `rpm` (module docs) on the frequencies `hz`.
pub fn tool_frf(c: &LinearControlParams, rpm: f64, hz: &[f64]) -> Result<Vec<FrfRow>, StudyError> {
    let s = Spindle::new(&SpindleParams::default()).map_err(|e| StudyError::Invalid(e.to_string()))?;
    let (a, b) = s.matrices();
    let st = SpindleParams::default().structure();
    let tau = 60.0 / (c.teeth as f64 * rpm);
    let n = a.nrows();
    let mut rows = Vec::with_capacity(hz.len());
    for &f in hz {
        let w = 2.0 * std::f64::consts::PI * f;
        let k = fmu_linear_controller::frequency_response(c, w, tau).map_err(StudyError::Invalid)?;
        let kc = nalgebra::DMatrix::from_fn(2, 2, |i, j| k[i][j]);
        let ba = st.ba.map(Complex64::from);
        let ca = st.ca.map(Complex64::from);
        let loop_ = &ba * &kc * &ca;
        let m = |with: bool| {
            nalgebra::DMatrix::from_fn(n, n, |i, j| {
                let d = if i == j { Complex64::new(0.0, w) } else { Complex64::new(0.0, 0.0) };
                d - a[(i, j)] - if with { loop_[(i, j)] } else { Complex64::new(0.0, 0.0) }
            })
        };
        let bt = nalgebra::DMatrix::from_fn(n, 2, |i, j| Complex64::from(b[(i, j)]));
        let ct = st.ct.map(Complex64::from);
        let solve = |with: bool| -> Result<[Complex64; 2], StudyError> {
            let x = m(with).lu().solve(&bt).ok_or_else(|| StudyError::Invalid(format!("singular at {f} Hz")))?;
            let g = &ct * x;
            Ok([g[(0, 0)], g[(1, 1)]])
        };
        rows.push(FrfRow { hz: f, open: solve(false)?, closed: solve(true)? });
    }
    Ok(rows)
}

/// The CSV of [`tool_frf`]: `hz, |G_xx| open, |G_xx| closed, |G_yy| open, |G_yy| closed` \[m/N\]
/// and the phases \[rad\].
pub fn frf_csv(rows: &[FrfRow]) -> String {
    let mut s = String::from(
        "hz,open_xx_abs,closed_xx_abs,open_yy_abs,closed_yy_abs,open_xx_arg,closed_xx_arg,open_yy_arg,closed_yy_arg\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{:.3},{:.6e},{:.6e},{:.6e},{:.6e},{:.6},{:.6},{:.6},{:.6}",
            r.hz,
            r.open[0].norm(),
            r.closed[0].norm(),
            r.open[1].norm(),
            r.closed[1].norm(),
            r.open[0].arg(),
            r.closed[0].arg(),
            r.open[1].arg(),
            r.closed[1].arg()
        );
    }
    s
}

/// The frequency of the largest closed-loop `|G_xx|` among `rows` \[Hz\].
pub fn closed_peak(rows: &[FrfRow]) -> Option<f64> {
    rows.iter().max_by(|a, b| a.closed[0].norm().total_cmp(&b.closed[0].norm())).map(|r| r.hz)
}
