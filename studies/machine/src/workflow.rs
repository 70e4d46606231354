//! The machine workflow as plain functions, what the `chatter` command and the Python package
//! both call: the file's summary, the controller to draw, the time-domain validation of a
//! boundary through the FMUs.

use crate::fmus::{FmuCheck, Growth};
use crate::machine::Machine;
use crate::models::ModelError;
use chatter_control::{ControllerParams, Structure};
use delay_stability::{Bifurcation, LobeOptions, Method, critical};
use std::fmt::Write as _;
use std::path::PathBuf;

/// Where the FMUs are (`$FMU_DIR`, else the workspace's `target/fmu`).
pub fn fmu_dir() -> PathBuf {
    packaging::fmu_dir()
}

/// `n` speeds evenly spaced over `[lo, hi]` \[rpm\].
pub fn speeds(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    delay_stability::zero_order::speed_grid(lo, hi, n)
}

/// The name of a controller structure.
pub fn structure_name(s: Structure) -> &'static str {
    model_kit::Choice::name(s)
}

/// A controller structure by name (`off`, `pid`, `fopid`, `adrc_fopid`).
pub fn structure(name: &str) -> Result<Structure, ModelError> {
    model_kit::parse_choice(name).map_err(|e| ModelError::Unsupported(format!("unknown controller: {e}")))
}

/// What the machine file describes, as a reader would check it.
pub fn summary(m: &Machine) -> String {
    let mut s = format!("{}: {} teeth, D = {} mm", m.name, m.tool.teeth, m.tool.diameter * 1e3);
    if let Some(p) = &m.tool.pitch {
        let deg: Vec<String> = p.iter().map(|a| format!("{:.1}", a.to_degrees())).collect();
        let _ = write!(s, ", variable pitch [{}] deg", deg.join(", "));
    }
    if let Some(f) = &m.frf {
        let (lo, hi) = f.range_hz();
        let pairs: Vec<&str> = f.h.keys().map(|p| p.name()).collect();
        let _ = write!(
            s,
            "\n\nMeasured FRFs: {} ({}, {} frequencies over {lo}–{hi} Hz, peak at {:.1} Hz)",
            f.source,
            pairs.join(", "),
            f.freq_hz.len(),
            f.peak_hz()
        );
        for n in &f.notes {
            let _ = write!(s, "\n  note: {n}");
        }
    }
    if m.modes.is_empty() {
        let _ = write!(
            s,
            "\n\nNo modes: zero-order lobes from the measured FRFs only (fit modes with `chatter frf fit` for the rest)."
        );
        return s;
    }
    let _ = writeln!(s, "\n\n| mode | f (Hz) | ζ | k (N/m) | m (kg) | shape (x, y) |\n|---|---|---|---|---|---|");
    for md in &m.modes {
        let _ = writeln!(
            s,
            "| {} | {:.1} | {:.4} | {:.3e} | {:.4} | ({:.3}, {:.3}) |",
            md.label,
            md.frequency_hz,
            md.damping,
            md.stiffness,
            md.mass(),
            md.shape[0],
            md.shape[1]
        );
    }
    let c = m.static_compliance();
    let _ = writeln!(s, "\nstatic stiffness: x {:.3e} N/m, y {:.3e} N/m", 1.0 / c[0][0], 1.0 / c[1][1]);
    let (e, x) = m.engagement();
    let law = match m.material.law {
        crate::machine::Law::Linear => "linear".to_string(),
        crate::machine::Law::Power { x_f } => format!("power, x_F = {x_f}"),
    };
    let _ = writeln!(
        s,
        "cut: a_e/D = {}, {:?}-milling (engaged {:.1}°–{:.1}°), f_z = {} mm, K_t = {} N/mm², K_r = {} N/mm² ({law})",
        m.operation.immersion,
        m.operation.milling,
        e.to_degrees(),
        x.to_degrees(),
        m.operation.feed_per_tooth * 1e3,
        m.material.kt * 1e-6,
        m.material.kr * 1e-6
    );
    let _ = writeln!(s, "lobes over {:.0}–{:.0} rpm", m.operation.speed_range_rpm.0, m.operation.speed_range_rpm.1);
    if let Some(a) = &m.actuator {
        let _ = writeln!(
            s,
            "actuator on {}: {:.2} Hz, ζ = {:.3}, ±{} N",
            a.axis.name(),
            a.frequency_hz,
            a.damping,
            a.force_limit
        );
    }
    if let Some(c) = &m.controller {
        let _ = writeln!(s, "controller: {}", c.structure);
    }
    for w in &m.warnings {
        let _ = writeln!(s, "warning: {w}");
    }
    s
}

/// The controller parameters to draw for a structure name on machine `m`: the file's controller
/// if it has this structure, else the shipped defaults; the command limit is the actuator's.
pub fn controller_for(m: &Machine, name: &str) -> Result<Option<(String, ControllerParams)>, ModelError> {
    let s = structure(name)?;
    if s == Structure::Off {
        return Ok(None);
    }
    let a = m
        .actuator
        .as_ref()
        .ok_or_else(|| ModelError::Unsupported(format!("controller {name}: the machine file has no [actuator]")))?;
    if let Some(c) = m.controller_params()?
        && c.structure == s
    {
        return Ok(Some((format!("{name} (machine file)"), c)));
    }
    Ok(Some((
        format!("{name} (shipped defaults)"),
        ControllerParams { structure: s, u_max: a.force_limit, ..ControllerParams::tuned() },
    )))
}

/// A time-periodic boundary checked through the FMUs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Validation {
    /// Speed \[rpm\].
    pub rpm: f64,
    /// The boundary \[m\].
    pub boundary: f64,
    /// The discretisation that gave it.
    pub method: Method,
    /// Its kind (Hopf, flip).
    pub kind: Option<Bifurcation>,
    /// The run at 0.97 of it.
    pub below: Growth,
    /// The run at 1.03 of it.
    pub above: Growth,
}

impl Validation {
    /// Decays below and grows above.
    pub fn confirmed(&self) -> bool {
        self.below.ratio < 1.0 && self.above.ratio > 1.0
    }

    /// One line for a report.
    pub fn line(&self) -> String {
        format!(
            "validate {:.0} rpm through the FMUs: boundary {:.3} mm ({}; {}); at 0.97× growth ratio {:.3} ({}), at 1.03× {:.3} ({}): {}",
            self.rpm,
            self.boundary * 1e3,
            self.kind.map_or("?", |k| k.name()),
            self.method,
            self.below.ratio,
            if self.below.ratio < 1.0 { "decays" } else { "grows" },
            self.above.ratio,
            if self.above.ratio > 1.0 { "grows" } else { "decays" },
            if self.confirmed() { "confirmed" } else { "NOT CONFIRMED" }
        )
    }
}

/// The time-periodic boundary at `rpm` by `method` ([`Method::default`]: converged), run through
/// the FMUs at 0.97 and 1.03 of it for 200 tooth periods (0.3–1 s); None if stable up to 100 mm.
pub fn validate(m: &Machine, rpm: f64, method: Method) -> Result<Option<Validation>, ModelError> {
    let model = m.sd_model()?;
    let o = LobeOptions { method, start: 1e-5, growth: 1.1, max: 0.1, rel_tol: 1e-4 };
    let c = critical(|a| model.at(rpm, a), &o)?;
    let Some(b) = c.value else { return Ok(None) };
    let check = FmuCheck::new(m, &fmu_dir(), None);
    let duration = (200.0 * 60.0 / (rpm * m.tool.teeth as f64)).clamp(0.3, 1.0);
    let below = check.growth(rpm, 0.97 * b, duration)?;
    let above = check.growth(rpm, 1.03 * b, duration)?;
    Ok(Some(Validation { rpm, boundary: b, method, kind: c.kind(), below, above }))
}
