//! Semi-discretisation lobes ([`delay_stability`]) of the project's machines: the seed 000 plant
//! described by the `MillingPlant.fmu` parameter set ([`seed000_model`]); seed 002's two-axis
//! spindle has its presets in the `seed002` crate. Unlike the zero-order [`delay_stability::zero_order`], these keep the time-periodic
//! directional matrix of the teeth, so they show the flip (period-doubling) lobes of low
//! immersion and handle multi-DOF structures and the power law.
//!
//! **Seed 000 mapping.** Every enabled workpiece mode `(m, k, ζ)` bends along
//! `d = (cos β, sin β)`; the relative tool-minus-workpiece displacement is `−w d`, so the mode's
//! mass-normalised tool shape is `−d/√m` (the plant's chip `h = f_z sin φ − Δw (d·r̂)` and force
//! on the workpiece `−F_tool·d`, [`milling_plant::params`]). Teeth, engagement window
//! ([`PlantParams::engagement`]), `K_t`, `K_r` are the plant's, the law linear. The stiffness
//! drift, noise and the actuator (no command) do not enter the linear stability of the nominal
//! cut.

use delay_stability::milling::{Cutter, ForceLaw, MillingModel, ModeShape, Structure};
use delay_stability::{BisectionOptions, LobePoint, StabilityError};
use milling_plant::PlantParams;
use std::fmt::Write as _;
use std::path::Path;
use study_kit::StudyError;

/// A stability error as a study error.
pub fn stab(e: StabilityError) -> StudyError {
    StudyError::Invalid(e.to_string())
}

/// The seed 000 plant (module docs) as a milling model.
pub fn seed000_model(p: &PlantParams) -> Result<MillingModel, StudyError> {
    p.validate().map_err(StudyError::Invalid)?;
    let (dx, dy) = p.direction();
    let modes: Vec<ModeShape> = p
        .mode_list()
        .iter()
        .map(|m| {
            let s = 1.0 / m.mass.sqrt();
            ModeShape { omega: m.omega_n(), zeta: m.damping_ratio, tool: [-dx * s, -dy * s], actuator: [0.0, 0.0] }
        })
        .collect();
    let s = Structure::from_modes(&modes).map_err(stab)?;
    let (entry, exit) = p.engagement();
    let c = &p.cutting;
    let cutter = Cutter::new(c.teeth, entry, exit, c.kt, c.kr, ForceLaw::Linear).map_err(stab)?;
    MillingModel::new(&s, cutter, None).map_err(stab)
}

/// The lobes of `model` on `speeds` (parallel), `progress(done, total)` after each speed.
pub fn sd_lobes(
    model: &MillingModel,
    speeds: &[f64],
    o: &BisectionOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<LobePoint>, StudyError> {
    delay_stability::lobes(speeds, |rpm, a| model.at(rpm, a), o, progress).map_err(stab)
}

/// The CSV: `rpm,a_lim_mm,kind,multiplier_abs,multiplier_arg_rad` (empty depth and kind `none`
/// where stable up to the search limit).
pub fn csv(points: &[LobePoint]) -> String {
    let mut s = String::from("rpm,a_lim_mm,kind,multiplier_abs,multiplier_arg_rad\n");
    for p in points {
        let c = &p.critical;
        let depth = c.value.map_or(String::new(), |v| format!("{:.6}", v * 1e3));
        let kind = c.kind().map_or("none", |k| k.name());
        let (abs, arg) = c.multiplier.map_or((f64::NAN, f64::NAN), |m| (m.rho, m.mu.arg()));
        let _ = writeln!(s, "{:.3},{depth},{kind},{abs:.6},{arg:.6}", p.rpm);
    }
    s
}

/// Write [`csv`] atomically (a temporary file renamed into place).
pub fn write_csv(path: &Path, points: &[LobePoint]) -> Result<(), StudyError> {
    let tmp = path.with_extension("csv.partial");
    std::fs::write(&tmp, csv(points)).map_err(|e| StudyError::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| StudyError::io(path, e))
}

/// Smallest and largest critical depth over the points that have one: `(min, max)`.
pub fn extremes(points: &[LobePoint]) -> Option<(LobePoint, LobePoint)> {
    let with: Vec<_> = points.iter().filter(|p| p.critical.value.is_some()).copied().collect();
    let d = |p: &LobePoint| p.critical.value.unwrap_or(f64::NAN);
    let min = with.iter().copied().min_by(|a, b| d(a).total_cmp(&d(b)))?;
    let max = with.iter().copied().max_by(|a, b| d(a).total_cmp(&d(b)))?;
    Some((min, max))
}

#[cfg(test)]
mod tests {
    use super::*;
    use delay_stability::critical_value;
    use delay_stability::zero_order::{Cutting, GridOptions, LobeProblem};
    use milling_plant::MillingMode;

    /// The seed's half-immersion up-milling with 4 teeth is dominated by the mean directional
    /// factor: SD and the zero-order lobes (an independent solver, `delay_stability::zero_order`) agree within
    /// a few percent; the sign convention of the mode shape would flip the answer otherwise.
    #[test]
    fn seed000_sd_is_near_the_zero_order_lobes() {
        let p = PlantParams::default();
        let model = seed000_model(&p).unwrap();
        let o = BisectionOptions { m: 30, start: 0.2e-3, growth: 1.1, max: 0.05, rel_tol: 1e-5 };
        let m = p.workpiece.first;
        let k = m.stiffness;
        let c = 2.0 * m.damping_ratio * (m.mass * k).sqrt();
        let frf = move |w: f64| num_complex::Complex64::new(k - m.mass * w * w, c * w).inv();
        let cutting = Cutting { kt: p.cutting.kt, alpha0: p.directional_coefficient(), teeth: p.cutting.teeth };
        let zo = LobeProblem::new(frf, cutting, &GridOptions::new(10.0, 2000.0, 4, 1000.0)).unwrap();
        for rpm in [1500.0, 2000.0, 2600.0] {
            let sd = critical_value(|a| model.at(rpm, a), &o).unwrap().value.unwrap();
            let zero = zo.critical_depth(rpm).depth;
            println!("{rpm} rpm: SD {:.4} mm, zero-order {:.4} mm", sd * 1e3, zero * 1e3);
            assert!((sd / zero - 1.0).abs() < 0.05, "{rpm}: SD {sd} vs zero-order {zero}");
        }
        // down-milling flips the sign of the mode shape's effect, not the machinery
        let mut down = p.clone();
        down.cutting.milling = MillingMode::Down;
        assert!(seed000_model(&down).is_ok());
    }

    #[test]
    fn csv_has_one_row_per_speed() {
        let model = delay_stability::presets::seed002(1.0, None).unwrap();
        let o = BisectionOptions { m: 10, start: 0.5e-3, growth: 1.2, max: 0.02, rel_tol: 1e-3 };
        let pts = sd_lobes(&model, &[36000.0, 38000.0], &o, &|_, _| {}).unwrap();
        let text = csv(&pts);
        assert_eq!(text.lines().count(), 3);
        assert!(text.lines().nth(2).unwrap().starts_with("38000.000,1.5"), "{text}");
        let (min, max) = extremes(&pts).unwrap();
        assert!(min.critical.value <= max.critical.value);
    }
}
