//! The project's shipped systems: the SSDs of the `.ssp` archives packaging writes, seed 002's
//! controller designs, and the parameter bindings generated from the adapters' own names.

use anyhow::{Context, Result};
use fmi2_export::Fmi2Model;
use model_description::ModelDescription;

/// The project's closed-loop system (plant + controller), `packaging/scenarios/ClosedLoop.ssd`:
/// the `SystemStructure.ssd` of `ClosedLoop.ssp` (and, with the Table 2 bindings, of
/// `ClosedLoopTable2.ssp`), and the studies' scenario when no `.ssp` is at hand.
pub const CLOSED_LOOP_SSD: &str = include_str!("../scenarios/ClosedLoop.ssd");

/// Seed 000's plant decomposed into process + structure + actuator, with the controller
/// (`packaging/scenarios/DecomposedPlant.ssd`, shipped as `DecomposedPlant.ssp`).
pub const DECOMPOSED_PLANT_SSD: &str = include_str!("../scenarios/DecomposedPlant.ssd");

/// The FMUs of [`DECOMPOSED_PLANT_SSD`].
pub const DECOMPOSED_PLANT_FMUS: [&str; 4] =
    ["MillingProcess.fmu", "ModalStructure.fmu", "InertialActuator.fmu", "ChatterController.fmu"];

/// Seed 004's closed loop (MillingForcePlant + FrohMracController),
/// `packaging/scenarios/ForceControl.ssd`: the `SystemStructure.ssd` of `ForceControl.ssp`.
pub const FORCE_CONTROL_SSD: &str = include_str!("../scenarios/ForceControl.ssd");

/// Seed 002's spindle in closed loop (`packaging/scenarios/Spindle.ssd`, shipped as
/// `Spindle.ssp`): MillingProcess (power law, full immersion, 4 teeth) + SpindleStructure +
/// LinearController with the printed §6.1 gains.
pub const SPINDLE_SSD: &str = include_str!("../scenarios/Spindle.ssd");

/// The FMUs of [`SPINDLE_SSD`].
pub const SPINDLE_FMUS: [&str; 3] = ["MillingProcess.fmu", "SpindleStructure.fmu", "LinearController.fmu"];
/// Seed 002's synthesised controller designs (`chatter synth --case all`: §6.1 and Table II
/// n_c = 0, 2, 4), SSP parameter sets with the `LinearController` names, written to
/// `<fmu dir>/designs/` to bind to `controller` in `Spindle.ssp` (or `chatter spindle
/// validate --design`).
pub const SPINDLE_DESIGNS: [(&str, &str); 4] = [
    ("sec6_1.ssv", include_str!("../designs/sec6_1.ssv")),
    ("table2_nc0.ssv", include_str!("../designs/table2_nc0.ssv")),
    ("table2_nc2.ssv", include_str!("../designs/table2_nc2.ssv")),
    ("table2_nc4.ssv", include_str!("../designs/table2_nc4.ssv")),
];
/// Seed 003's closed loop (ToolXyPlant + SlidingModeFuzzyController),
/// `packaging/scenarios/SlidingModeFuzzy.ssd`: the `SystemStructure.ssd` of `SlidingModeFuzzy.ssp`.
pub const SLIDING_MODE_FUZZY_SSD: &str = include_str!("../scenarios/SlidingModeFuzzy.ssd");
/// Seed 001's closed loop (TurningProcess + AfracController), `packaging/scenarios/Afrac.ssd`:
/// the `SystemStructure.ssd` of `Afrac.ssp`.
pub const AFRAC_SSD: &str = include_str!("../scenarios/Afrac.ssd");

/// One FMU variable assignment as an SSP parameter. Enumerations are written as `ssv:Integer`
/// with the item's value, which FMI 2.0 sets through `fmi2SetInteger` anyway: libcosim (the Open
/// Simulation Platform's master) aborts on `ssv:Enumeration` values (`ssp_parser.cpp:69:
/// Internal error`, `terminate called`), and FMPy's `simulate_ssp` sets enumerations with
/// `int(value)`. Our master reads both forms.
fn ssp_parameter(md: &ModelDescription, name: String, value: model_description::Value) -> Result<ssp::Parameter> {
    ssp::fmu_parameter(md, &name, value, ssp::Enumerations::Integers).map_err(anyhow::Error::msg)
}

/// The closed loop with the paper's Table 2 controller gains bound as SSP parameters
/// (`ClosedLoopTable2.ssp`): the shipped FMU defaults are the PSO-tuned gains, and this system
/// reproduces the seed's own settings with the same FMUs, in any SSP-capable tool.
pub fn table2_ssd() -> Result<String> {
    use ssp::SystemDescription;
    let mut sys = SystemDescription::from_xml(CLOSED_LOOP_SSD, "ClosedLoop.ssd", None)?;
    let md = fmu_controller::ChatterController::description();
    let mut params = Vec::new();
    for (name, value) in fmu_controller::parameter_assignments(&chatter_control::ControllerParams::paper_table2()) {
        params.push(ssp_parameter(md, name, value)?);
    }
    let ctrl = sys
        .components
        .iter_mut()
        .find(|c| c.source.ends_with("ChatterController.fmu"))
        .context("no ChatterController component in the closed-loop SSD")?;
    ctrl.parameters = params;
    sys.name = "ClosedLoopTable2".into();
    sys.description = Some(format!(
        "{} Controller gains: the paper's Table 2 preset (SI reading), not the PSO-tuned FMU defaults.",
        sys.description.unwrap_or_default()
    ));
    Ok(sys.to_xml()?)
}

/// The parameter bindings of [`SPINDLE_SSD`], by component: every value that differs from the
/// FMU's start value, from seed 002's parameter sets (Table I, §6.1): the process with the
/// power law (x_F = 1), K_t = 462, K_r = 38.6 N/mm² in SI, full immersion (0, π), 4 teeth,
/// a_p = 1 mm, 37000 rpm, f_z = 0.2 mm; the controller with `D_c = [[k₁, −k₂], [k₂, k₁]]`,
/// k₁ = 697.1599, k₂ = −1071.058 N/mm in N/m, β = 1, τ from the speed.
pub fn spindle_bindings() -> Result<Vec<(&'static str, Vec<ssp::Parameter>)>> {
    use milling_process::{ForceLaw, ProcessInputs, ProcessParams};
    use model_description::Value;
    type Pairs = Vec<(String, Value)>;
    // the assignments that differ from the start values, as SSP parameters of the FMU `md`
    let changed = |md: &ModelDescription, now: Pairs, base: Pairs| -> Result<Vec<ssp::Parameter>> {
        let mut out = Vec::new();
        for ((name, value), (_, start)) in now.into_iter().zip(base) {
            if value == start {
                continue;
            }
            out.push(ssp_parameter(md, name, value)?);
        }
        Ok(out)
    };
    let mut p = ProcessParams {
        explicit_angles: true,
        entry_angle: 0.0,
        exit_angle: std::f64::consts::PI,
        axial_depth: 1e-3,
        ..Default::default()
    };
    p.coefficients.law = ForceLaw::Power;
    p.coefficients.exponent = 1.0;
    p.coefficients.kt = 462e6;
    p.coefficients.kr = 38.6e6;
    let md = fmu_milling_process::MillingProcess::description();
    let mut process = changed(
        md,
        fmu_milling_process::parameter_assignments(&p),
        fmu_milling_process::parameter_assignments(&Default::default()),
    )?;
    let inputs = ProcessInputs { spindle_speed_rpm: 37_000.0, feed_per_tooth: 0.2e-3, ..Default::default() };
    let t = &fmu_milling_process::TABLE;
    process.extend(changed(md, t.input_assignments(&inputs), t.input_assignments(&Default::default()))?);
    let (k1, k2) = (697.1599e3, -1071.058e3);
    let c = linear_control::LinearControlParams { dc: [[k1, -k2], [k2, k1]], ..Default::default() };
    let controller = changed(
        fmu_linear_controller::LinearController::description(),
        fmu_linear_controller::parameter_assignments(&c),
        fmu_linear_controller::parameter_assignments(&Default::default()),
    )?;
    Ok(vec![("process", process), ("spindle", Vec::new()), ("controller", controller)])
}

#[cfg(test)]
mod tests {
    use ssp::{ConnectorKind, SystemDescription};

    /// Spindle.ssd is canonical, names only shipped FMUs, and binds exactly
    /// [`super::spindle_bindings`] (the seed's values, from the adapters' own names).
    #[test]
    fn the_embedded_spindle_system_is_canonical_and_binds_the_seed() {
        let d = SystemDescription::from_xml(super::SPINDLE_SSD, "Spindle.ssd", None).unwrap();
        let mut want = d.clone();
        for (name, params) in super::spindle_bindings().unwrap() {
            let c = want.component_mut(name).unwrap();
            c.parameters = params;
        }
        if std::env::var_os("WRITE_SPINDLE_SSD").is_some() {
            std::fs::write(crate::workspace_root().join("packaging/scenarios/Spindle.ssd"), want.to_xml().unwrap())
                .unwrap();
        }
        assert_eq!(d, want, "Spindle.ssd does not bind the seed's values");
        assert_eq!(d.to_xml().unwrap(), super::SPINDLE_SSD, "Spindle.ssd is not canonical");
        for c in &d.components {
            let file = c.source.strip_prefix("resources/").unwrap();
            assert!(super::SPINDLE_FMUS.contains(&file), "{file}");
        }
        assert_eq!(d.connections.len(), 8);
        connections_end_on_declared_connectors(&d);
    }

    /// The parameters an FMU runs with when nothing is set (its start values, read through its
    /// own table).
    fn start_parameters<M: fmi2_export::table::TableModel>() -> M::Params {
        let values = fmi2_export::Values::from_description(M::description());
        M::table().read_parameters(&values).expect("the start values are valid parameters")
    }

    /// Every connection starts at a declared output connector and ends at a declared input.
    fn connections_end_on_declared_connectors(d: &SystemDescription) {
        for c in &d.connections {
            let s = d.component(c.start_element.as_deref().unwrap()).unwrap();
            let e = d.component(c.end_element.as_deref().unwrap()).unwrap();
            assert!(s.connectors.iter().any(|x| x.name == c.start_connector && x.kind == ConnectorKind::Output));
            assert!(e.connectors.iter().any(|x| x.name == c.end_connector && x.kind == ConnectorKind::Input));
        }
    }

    /// The decomposed plant's SSD is canonical, names only shipped FMUs, and connects every
    /// connection end to a declared connector of the right kind.
    #[test]
    fn the_embedded_decomposed_plant_is_canonical_and_complete() {
        let d = SystemDescription::from_xml(super::DECOMPOSED_PLANT_SSD, "DecomposedPlant.ssd", None).unwrap();
        assert_eq!(d.to_xml().unwrap(), super::DECOMPOSED_PLANT_SSD, "DecomposedPlant.ssd is not canonical");
        assert_eq!(d.components.len(), 4);
        for c in &d.components {
            let file = c.source.strip_prefix("resources/").unwrap();
            assert!(super::DECOMPOSED_PLANT_FMUS.contains(&file), "{file}");
        }
        assert_eq!(d.connections.len(), 8);
        connections_end_on_declared_connectors(&d);
    }

    /// The embedded SSD is in the writer's canonical form; also writes
    /// `target/ssd-test/ClosedLoop.ssd` for `tests/python/test_ssd_schema.py`.
    #[test]
    fn the_embedded_closed_loop_is_canonical_and_complete() {
        let d = SystemDescription::from_xml(super::CLOSED_LOOP_SSD, "ClosedLoop.ssd", None).unwrap();
        assert_eq!(
            d.to_xml().unwrap(),
            super::CLOSED_LOOP_SSD,
            "packaging/scenarios/ClosedLoop.ssd is not in the writer's canonical form"
        );
        assert_eq!(d.components.len(), 2);
        assert!(d.components.iter().all(|c| c.source.starts_with("resources/") && c.source.ends_with(".fmu")));
        assert_eq!(d.connections.len(), 2, "the closed loop has one feedback and one command connection");
        // Every connection's end points are declared connectors of matching kinds.
        for c in &d.connections {
            let s = d.component(c.start_element.as_deref().unwrap()).unwrap();
            let e = d.component(c.end_element.as_deref().unwrap()).unwrap();
            let has = |k: &ssp::ComponentDesc, name: &str, kind| {
                k.connectors.iter().any(|x| x.name == name && x.kind == kind)
            };
            assert!(has(s, &c.start_connector, ConnectorKind::Output), "{}", c.label());
            assert!(has(e, &c.end_connector, ConnectorKind::Input), "{}", c.label());
        }
        assert!(d.master.step_size.is_some() && d.stop_time.is_some());
        let target = std::env::var_os("CARGO_TARGET_DIR")
            .map(std::path::PathBuf::from)
            .unwrap_or_else(|| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target"));
        let dir = target.join("ssd-test");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("ClosedLoop.ssd"), super::CLOSED_LOOP_SSD).unwrap();
    }

    /// `SlidingModeFuzzy.ssd` (seed 003) is canonical, binds the forcing, and steps the
    /// controller's sample period.
    #[test]
    fn the_sliding_mode_fuzzy_system_is_canonical_and_steps_the_sample_period() {
        let d = SystemDescription::from_xml(super::SLIDING_MODE_FUZZY_SSD, "SlidingModeFuzzy.ssd", None).unwrap();
        let canonical = d.to_xml().unwrap();
        if canonical != super::SLIDING_MODE_FUZZY_SSD {
            let out = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/SlidingModeFuzzy.canonical.ssd");
            std::fs::write(&out, &canonical).unwrap();
            panic!("SlidingModeFuzzy.ssd is not canonical (canonical form written to {})", out.display());
        }
        assert_eq!(d.components.len(), 2);
        assert_eq!(d.connections.len(), 6, "x, y, vx, vy to the controller; u_x, u_y to the plant");
        let plant = d.components.iter().find(|c| c.name == "plant").unwrap();
        assert_eq!(plant.parameters.len(), 2, "the calibrated forcing amplitudes");
        let ts = start_parameters::<fmu_sliding_mode_fuzzy_controller::SlidingModeFuzzyController>().sample_period;
        assert!((ts / d.master.step_size.unwrap() - 1.0).abs() < 1e-12);
    }

    /// `Afrac.ssd` (seed 001) is canonical, connects x, v and the two commands, and steps the
    /// controller's sample period (the loop of `seed001::afrac`).
    #[test]
    fn the_afrac_system_is_canonical_and_steps_the_sample_period() {
        let d = SystemDescription::from_xml(super::AFRAC_SSD, "Afrac.ssd", None).unwrap();
        assert_eq!(d.to_xml().unwrap(), super::AFRAC_SSD, "Afrac.ssd is not canonical");
        assert_eq!(d.components.len(), 2);
        assert_eq!(d.connections.len(), 4, "x, v to the controller; spindle_speed, feed to the plant");
        let ts = start_parameters::<fmu_afrac_controller::AfracController>().sample_period;
        assert!((ts / d.master.step_size.unwrap() - 1.0).abs() < 1e-12);
    }

    /// `ForceControl.ssd` (seed 004) is canonical, and its step is an integer fraction of the
    /// controller's sample period, as FrohMracController requires.
    #[test]
    fn the_force_control_system_is_canonical_and_steps_a_fraction_of_the_sample_period() {
        let d = SystemDescription::from_xml(super::FORCE_CONTROL_SSD, "ForceControl.ssd", None).unwrap();
        assert_eq!(d.to_xml().unwrap(), super::FORCE_CONTROL_SSD, "ForceControl.ssd is not canonical");
        assert_eq!(d.components.len(), 2);
        assert_eq!(d.connections.len(), 3, "force feedback, command mean and command slope");
        let ts = start_parameters::<fmu_froh_mrac_controller::FrohMracController>().sample_period;
        let m = ts / d.master.step_size.unwrap();
        assert!((m - m.round()).abs() < 1e-9 && m.round() >= 1.0, "Ts/h = {m}");
    }
}
