//! The machine as FMUs: `MillingProcess` (the cut) + `ModalStructure` (the tool-point modes)
//! [+ `InertialActuator` + `ChatterController`], their parameter sets, the SSP of the user's
//! system, and the time-domain growth check through them in the Rust master.
//!
//! Connections: `structure.tool_{x,y} → process.tool_{x,y}`, `process.force_{x,y} →
//! structure.tool_force_{x,y}` (a flexible tool cutting a rigid workpiece); with an actuator on
//! axis `d`: `actuator.force_{x,y} → structure.actuator_force_{x,y}` (its point is the tool
//! point), `structure.tool_d → controller.y`, `controller.u → actuator.u`. Gauss–Seidel in the
//! order controller, actuator, structure, process. The structure's noise, sinusoid and drift
//! are off: the only forces are the cut's and the actuator's.
//!
//! Enumeration parameters are written as `ssv:Integer` values (libcosim refuses
//! `ssv:Enumeration`; our master and the FMI standard take the integer).

use crate::machine::{Axis, Law, Machine, Milling, Mode};
use crate::models::ModelError;
use chatter_control::{ControllerParams, Structure as CtrlStructure};
use fmi_master::{Override, Progress, RunConfig, SimError, Simulation, SystemFile};
use machine_structure::ActuatorParams;
use machine_structure::modal::{MAX_MODES, ModalParams, StructureMode};
use milling_process::{ForceLaw, MillingMode, ProcessInputs, ProcessParams};
use model_description::Value;
use ssp::{ComponentDesc, Connection, Connector, ConnectorKind, ConnectorType, Enumerations, SystemDescription};
use std::f64::consts::PI;
use std::path::Path;
use study_kit::fmu_params::{Resolved, apply_ssp, apply_text, overrides_of};
use study_kit::growth::Regen;

/// The parameter sets of the machine's FMUs at one operating point.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineFmus {
    /// `MillingProcess` parameters.
    pub process: ProcessParams,
    /// `MillingProcess` inputs (speed and feed).
    pub process_inputs: ProcessInputs,
    /// `ModalStructure` parameters.
    pub structure: ModalParams,
    /// `InertialActuator` and `ChatterController`, if the machine has them.
    pub control: Option<(ActuatorParams, ControllerParams)>,
    /// Communication step \[s\].
    pub step: f64,
}

impl Machine {
    /// The communication step: 10 µs, or finer so that the highest mode and the tooth passing
    /// get at least 40 steps per period and a tooth's pass through the cut (short at low
    /// immersion) at least 40 steps; always 10 µs divided by a whole number.
    pub fn fmu_step(&self, rpm: f64) -> f64 {
        let tooth_hz = rpm * self.tool.teeth as f64 / 60.0;
        let (entry, exit) = self.engagement();
        let cut_time = (exit - entry) / (2.0 * std::f64::consts::PI) * 60.0 / rpm;
        let h = (1.0 / (40.0 * self.highest_mode_hz().max(tooth_hz))).min(cut_time / 40.0);
        step_within(h)
    }

    /// The controller parameters of the file's `[controller]` (None without one, or `off`):
    /// the shipped defaults of its structure, then its SSV parameter set, then its `set`
    /// entries; the command limit is the actuator's.
    pub fn controller_params(&self) -> Result<Option<ControllerParams>, ModelError> {
        let (Some(c), Some(a)) = (&self.controller, &self.actuator) else { return Ok(None) };
        let structure = model_kit::parse_choice::<CtrlStructure>(&c.structure).map_err(ModelError::Unsupported)?;
        if structure == CtrlStructure::Off {
            return Ok(None);
        }
        let mut r: Resolved<ControllerParams, fmu_controller::ControllerInputs> = Resolved {
            params: ControllerParams { structure, u_max: a.force_limit, ..ControllerParams::tuned() },
            inputs: Default::default(),
        };
        if let Some(path) = &c.parameters {
            let text = std::fs::read_to_string(path)
                .map_err(|e| ModelError::Unsupported(format!("controller.parameters {}: {e}", path.display())))?;
            for p in ssp::parse_ssv(&text, &path.display().to_string(), "")
                .map_err(|e| ModelError::Unsupported(e.to_string()))?
            {
                apply_ssp::<fmu_controller::ChatterController>(&mut r, &p.name, &p.value)
                    .map_err(|e| ModelError::Unsupported(format!("{}: {e}", path.display())))?;
            }
        }
        for (name, text) in &c.set {
            apply_text::<fmu_controller::ChatterController>(&mut r, name, text)
                .map_err(|e| ModelError::Unsupported(format!("controller.set: {e}")))?;
        }
        r.params.structure = structure;
        r.params.validate().map_err(|e| ModelError::Unsupported(format!("controller: {e}")))?;
        Ok(Some(r.params))
    }

    /// `ModalStructure` parameters of the machine's modes ([`modal_params`]).
    pub fn structure_params(&self, step: f64) -> Result<ModalParams, ModelError> {
        self.require_modes("ModalStructure.fmu")?;
        modal_params(&self.modes, self.actuator.is_some(), step)
    }

    /// The FMUs' parameter sets at `rpm` and axial depth `depth` \[m\] (the controller: the
    /// file's, or `controller` if given).
    pub fn fmu_parameters(
        &self,
        rpm: f64,
        depth: f64,
        controller: Option<&ControllerParams>,
    ) -> Result<MachineFmus, ModelError> {
        if self.modes.len() > fmu_modal_structure::PARAMETER_MODES {
            return Err(ModelError::Unsupported(format!(
                "structure: {} modes; the machine's SSP and time-domain check bind ModalStructure's {} mode parameters (more modes go through a modal table: `chatter frf fit` writes one with its structure.ssv)",
                self.modes.len(),
                fmu_modal_structure::PARAMETER_MODES
            )));
        }
        let step = self.fmu_step(rpm);
        let mut process = ProcessParams {
            teeth: self.tool.teeth,
            tool_radius: self.tool.diameter / 2.0,
            radial_engagement: self.operation.immersion * self.tool.diameter,
            milling: match self.operation.milling {
                Milling::Up => MillingMode::Up,
                Milling::Down => MillingMode::Down,
            },
            axial_depth: depth,
            ..ProcessParams::default()
        };
        if let Some(p) = &self.tool.pitch {
            if p.len() > milling_process::params::MAX_PITCH_TEETH {
                return Err(ModelError::Unsupported(format!(
                    "tool.pitch: MillingProcess.fmu takes a variable pitch for at most {} teeth",
                    milling_process::params::MAX_PITCH_TEETH
                )));
            }
            process.variable_pitch = true;
            process.tooth_angles[..p.len()].copy_from_slice(p);
        }
        let c = &mut process.coefficients;
        (c.kt, c.kr, c.kte, c.kre) = (self.material.kt, self.material.kr, self.material.kte, self.material.kre);
        match self.material.law {
            Law::Linear => c.law = ForceLaw::Linear,
            Law::Power { x_f } => (c.law, c.exponent) = (ForceLaw::Power, x_f),
        }
        process.validate().map_err(ModelError::Unsupported)?;
        let process_inputs = ProcessInputs {
            spindle_speed_rpm: rpm,
            feed_per_tooth: self.operation.feed_per_tooth,
            ..ProcessInputs::default()
        };
        let structure = self.structure_params(step)?;
        let control =
            match (&self.actuator, controller.cloned().map(Some).map_or_else(|| self.controller_params(), Ok)?) {
                (Some(a), Some(c)) => {
                    let w = 2.0 * PI * a.frequency_hz;
                    let act = ActuatorParams {
                        a: [[-2.0 * a.damping * w, -w * w], [1.0, 0.0]],
                        b: [1.0, 0.0],
                        c: [-2.0 * a.damping * w, -w * w],
                        d: 1.0,
                        f_max: a.force_limit,
                        direction_angle: if a.axis == Axis::Y { PI / 2.0 } else { 0.0 },
                        internal_step: step,
                    };
                    Some((act, c))
                }
                _ => None,
            };
        Ok(MachineFmus { process, process_inputs, structure, control, step })
    }
}

/// The communication step: 10 µs, or 10 µs divided by the smallest whole number that brings it
/// to `h` or below.
fn step_within(h: f64) -> f64 {
    if h >= 1e-5 { 1e-5 } else { 1e-5 / (1e-5 / h).ceil() }
}

/// `ModalStructure` parameters of `modes` (internal step `step` \[s\]; noise, drift and
/// sinusoid off; the actuator point is the tool point if `at_actuator`).
pub fn modal_params(modes: &[Mode], at_actuator: bool, step: f64) -> Result<ModalParams, ModelError> {
    if modes.is_empty() || modes.len() > MAX_MODES {
        return Err(ModelError::Unsupported(format!(
            "structure: {} modes, ModalStructure.fmu takes 1 to {MAX_MODES}",
            modes.len()
        )));
    }
    let mut structure = ModalParams::default();
    let list: Vec<StructureMode> = modes
        .iter()
        .map(|m| StructureMode {
            frequency: m.frequency_hz,
            damping_ratio: m.damping,
            modal_mass: m.mass(),
            tool: m.shape,
            actuator: if at_actuator { m.shape } else { [0.0, 0.0] },
        })
        .collect();
    structure.set_modes(&list).map_err(ModelError::Unsupported)?;
    let d = &mut structure.disturbance;
    (d.noise, d.drift, d.sine_amplitude) = (false, false, 0.0);
    structure.internal_step = step;
    structure.validate().map_err(ModelError::Unsupported)?;
    Ok(structure)
}

/// `modes` as a `ModalStructure` parameter set (SSV: the parameters that differ from the
/// FMU's start values), internal step 10 µs or finer (40 steps per period of the highest mode).
/// Up to four modes are parameters; with more, the SSV names the modal table `table` (an
/// absolute path) and the table's text is returned beside it, for the caller to write there.
pub fn structure_ssv(
    modes: &[Mode],
    at_actuator: bool,
    name: &str,
    table: &Path,
) -> Result<(String, Option<String>), ModelError> {
    use fmi2_export::Fmi2Model;
    let f = modes.iter().map(|m| m.frequency_hz).fold(0.0, f64::max);
    let h = 1.0 / (40.0 * f);
    let step = step_within(h);
    let structure = modal_params(modes, at_actuator, step)?;
    let (sp, text) = if modes.len() <= fmu_modal_structure::PARAMETER_MODES {
        (fmu_modal_structure::StructureFmuParams { structure, modal_table: String::new() }, None)
    } else {
        let text = fmu_modal_structure::modal_table(&structure);
        let only_settings =
            ModalParams { n_modes: 1, modes: ModalParams::default().modes, extra_modes: Vec::new(), ..structure };
        (
            fmu_modal_structure::StructureFmuParams {
                structure: only_settings,
                modal_table: table.display().to_string(),
            },
            Some(text),
        )
    };
    let params = changed(
        fmu_modal_structure::ModalStructure::description(),
        fmu_modal_structure::parameter_assignments(&sp),
        &fmu_modal_structure::parameter_assignments(&Default::default()),
    )?;
    Ok((ssp::ssv_xml(name, &params).map_err(|e| ModelError::Unsupported(e.to_string()))?, text))
}

/// Every variable of `now` whose value differs from the FMU's start value (`base`), as SSP
/// parameters.
fn changed(
    md: &model_description::ModelDescription,
    now: Vec<(String, Value)>,
    base: &[(String, Value)],
) -> Result<Vec<ssp::Parameter>, ModelError> {
    now.into_iter()
        .filter(|(n, v)| base.iter().find(|(b, _)| b == n).is_none_or(|(_, bv)| bv != v))
        .map(|(n, v)| ssp::fmu_parameter(md, &n, v, Enumerations::Integers).map_err(ModelError::Unsupported))
        .collect()
}

fn real(name: &str, kind: ConnectorKind, unit: &str) -> Connector {
    Connector { name: name.into(), kind, ty: Some(ConnectorType::Real(Some(unit.into()))) }
}

fn component(name: &str, id: &str, connectors: Vec<Connector>, parameters: Vec<ssp::Parameter>) -> ComponentDesc {
    ComponentDesc {
        name: name.into(),
        source: format!("resources/{id}.fmu"),
        implementation: Some("CoSimulation".into()),
        description: None,
        connectors,
        parameters,
    }
}

fn connect(from: (&str, &str), to: (&str, &str)) -> Connection {
    Connection {
        start_element: Some(from.0.into()),
        start_connector: from.1.into(),
        end_element: Some(to.0.into()),
        end_connector: to.1.into(),
        linear: None,
    }
}

impl MachineFmus {
    /// The SSD of the machine's system with these parameter sets bound, stopping at `stop` \[s\].
    pub fn system(&self, name: &str, description: &str, stop: f64) -> Result<SystemDescription, ModelError> {
        use ConnectorKind::{Input, Output};
        use fmi2_export::Fmi2Model;
        let pmd = fmu_milling_process::MillingProcess::description();
        let smd = fmu_modal_structure::ModalStructure::description();
        let mut params = changed(
            pmd,
            fmu_milling_process::parameter_assignments(&self.process),
            &fmu_milling_process::parameter_assignments(&ProcessParams::default()),
        )?;
        params.extend(changed(
            pmd,
            fmu_milling_process::TABLE.input_assignments(&self.process_inputs),
            &fmu_milling_process::TABLE.input_assignments(&ProcessInputs::default()),
        )?);
        let sp =
            fmu_modal_structure::StructureFmuParams { structure: self.structure.clone(), modal_table: String::new() };
        let structure_params = changed(
            smd,
            fmu_modal_structure::parameter_assignments(&sp),
            &fmu_modal_structure::parameter_assignments(&Default::default()),
        )?;
        let mut sys = SystemDescription::new(name);
        sys.description = Some(description.into());
        sys.components.push(component(
            "process",
            "MillingProcess",
            vec![
                real("tool_x", Input, "m"),
                real("tool_y", Input, "m"),
                real("force_x", Output, "N"),
                real("force_y", Output, "N"),
            ],
            params,
        ));
        let mut sc = vec![
            real("tool_force_x", Input, "N"),
            real("tool_force_y", Input, "N"),
            real("tool_x", Output, "m"),
            real("tool_y", Output, "m"),
        ];
        if self.control.is_some() {
            sc.extend([real("actuator_force_x", Input, "N"), real("actuator_force_y", Input, "N")]);
        }
        sys.components.push(component("structure", "ModalStructure", sc, structure_params));
        for axis in ["x", "y"] {
            sys.connections.push(connect(("structure", &format!("tool_{axis}")), ("process", &format!("tool_{axis}"))));
            sys.connections
                .push(connect(("process", &format!("force_{axis}")), ("structure", &format!("tool_force_{axis}"))));
        }
        let mut sequence = vec!["structure".to_string(), "process".to_string()];
        if let Some((act, ctrl)) = &self.control {
            let amd = fmu_inertial_actuator::InertialActuator::description();
            let cmd = fmu_controller::ChatterController::description();
            let ap = changed(
                amd,
                fmu_inertial_actuator::parameter_assignments(act),
                &fmu_inertial_actuator::parameter_assignments(&ActuatorParams::default()),
            )?;
            let cp = changed(
                cmd,
                fmu_controller::parameter_assignments(ctrl),
                &fmu_controller::parameter_assignments(&ControllerParams::tuned()),
            )?;
            sys.components.push(component(
                "actuator",
                "InertialActuator",
                vec![real("u", Input, "N"), real("force_x", Output, "N"), real("force_y", Output, "N")],
                ap,
            ));
            sys.components.push(component(
                "controller",
                "ChatterController",
                vec![real("y", Input, "m"), real("u", Output, "N")],
                cp,
            ));
            let axis = if act.direction_angle == 0.0 { "x" } else { "y" };
            sys.connections.push(connect(("actuator", "force_x"), ("structure", "actuator_force_x")));
            sys.connections.push(connect(("actuator", "force_y"), ("structure", "actuator_force_y")));
            sys.connections.push(connect(("structure", &format!("tool_{axis}")), ("controller", "y")));
            sys.connections.push(connect(("controller", "u"), ("actuator", "u")));
            sequence = ["controller", "actuator", "structure", "process"].map(String::from).to_vec();
        }
        sys.start_time = Some(0.0);
        sys.stop_time = Some(stop);
        sys.master.step_size = Some(self.step);
        sys.master.order = Some(ssp::Order::GaussSeidel);
        sys.master.sequence = sequence;
        Ok(sys)
    }
}

impl Machine {
    /// The machine's system (module docs) at `rpm` and `depth`, the file's controller.
    pub fn system(&self, rpm: f64, depth: f64, stop: f64) -> Result<SystemDescription, ModelError> {
        let fmus = self.fmu_parameters(rpm, depth, None)?;
        let name: String = self.name.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
        fmus.system(
            &name,
            &format!("{}: MillingProcess + ModalStructure{} at {rpm} rpm, a_p = {} mm (written by chatter from a machine file)", self.name, if fmus.control.is_some() { " + InertialActuator + ChatterController" } else { "" }, depth * 1e3),
            stop,
        )
    }

    /// Write the machine's `.ssp` (with the FMUs of `fmu_dir`) to `out`.
    pub fn write_ssp(&self, out: &Path, fmu_dir: &Path, rpm: f64, depth: f64, stop: f64) -> Result<(), ModelError> {
        let sys = self.system(rpm, depth, stop)?;
        let ids: Vec<String> =
            sys.components.iter().map(|c| c.source.trim_start_matches("resources/").to_string()).collect();
        let paths: Vec<std::path::PathBuf> = ids.iter().map(|id| fmu_dir.join(id)).collect();
        if let Some(p) = paths.iter().find(|p| !p.is_file()) {
            return Err(ModelError::Unsupported(format!(
                "{} is missing: build the FMUs with `cargo run --release -p packaging`",
                p.display()
            )));
        }
        let fmus: Vec<(&str, &Path)> = ids.iter().map(String::as_str).zip(paths.iter().map(|p| p.as_path())).collect();
        ssp::write_ssp(out, &sys, &fmus).map_err(|e| ModelError::Unsupported(e.to_string()))
    }
}

impl Machine {
    /// The machine's system at `rpm` and `depth` \[m\] for `duration` seconds (a whole number of
    /// its steps) with the FMUs of `fmu_dir`, ready for the Rust master; and its step.
    pub fn system_file(
        &self,
        fmu_dir: &Path,
        rpm: f64,
        depth: f64,
        duration: f64,
        controller: Option<&ControllerParams>,
    ) -> Result<(SystemFile, MachineFmus, f64), ModelError> {
        let fmus = self.fmu_parameters(rpm, depth, controller)?;
        let duration = (duration / fmus.step).round().max(1.0) * fmus.step;
        let desc = fmus.system("machine", "time-domain run", duration)?;
        let xml = desc.to_xml().map_err(|e| ModelError::Unsupported(e.to_string()))?;
        let sys = SystemFile::from_text(&xml, &format!("{} (machine)", self.name), fmu_dir)
            .map_err(|e| ModelError::Unsupported(e.to_string()))?;
        Ok((sys, fmus, duration))
    }

    /// Run the machine's system (the file's controller) at `rpm` and `depth` \[m\] for `stop`
    /// seconds in the Rust master, recording `record` (default: every output).
    pub fn simulate(
        &self,
        fmu_dir: &Path,
        rpm: f64,
        depth: f64,
        stop: f64,
        record: Option<Vec<String>>,
    ) -> Result<fmi_master::Recorder, ModelError> {
        let (sys, fmus, stop) = self.system_file(fmu_dir, rpm, depth, stop, None)?;
        let cfg =
            RunConfig { start: Some(0.0), stop: Some(stop), step: Some(fmus.step), record, ..RunConfig::default() };
        let mut sim = Simulation::new(&sys, &cfg).map_err(|e| ModelError::Unsupported(e.to_string()))?;
        let mut rec = fmi_master::Recorder::default();
        sim.run(&mut rec, Progress::Off).map_err(|e| ModelError::Unsupported(e.to_string()))?;
        Ok(rec)
    }
}

/// The time-domain check of a machine through its FMUs in the Rust master.
pub struct FmuCheck<'a> {
    machine: &'a Machine,
    fmu_dir: std::path::PathBuf,
    controller: Option<ControllerParams>,
}

/// The outcome of one run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Growth {
    /// Late/mid peak of `|v(t) − v(t − τ)|` (> 1: the cut chatters).
    pub ratio: f64,
    /// Largest |v| \[m\].
    pub peak: f64,
    /// Did the controller's unsaturated command pass the actuator's limit (with a controller)?
    pub saturated: bool,
    /// Largest |u| of the controller over the last half of the run \[N\] (0 without one).
    pub peak_u: f64,
}

impl<'a> FmuCheck<'a> {
    /// The check with the FMUs of `fmu_dir` and the controller `controller` (None: the open loop).
    pub fn new(machine: &'a Machine, fmu_dir: &Path, controller: Option<ControllerParams>) -> FmuCheck<'a> {
        FmuCheck { machine, fmu_dir: fmu_dir.to_path_buf(), controller }
    }

    /// Run `duration` seconds at `rpm` and `depth` \[m\]: the growth ratio of the regenerative
    /// difference of the tool displacement (x and y), as `chatter sd-lobes --validate-rpm` does
    /// for the seed plant: the forced τ-periodic motion cancels in `v(t) − v(t − τ)`, the
    /// start-up transient of the cutting force is the perturbation. A difference larger than the
    /// feed per tooth after the start-up (the teeth leave the cut: the motion grew out of the
    /// linear regime into a limit cycle, whose late/mid ratio is about 1) counts as growth.
    pub fn growth(&self, rpm: f64, depth: f64, duration: f64) -> Result<Growth, ModelError> {
        let (sys, fmus, duration) =
            self.machine.system_file(&self.fmu_dir, rpm, depth, duration, self.controller.as_ref())?;
        let mut record = vec!["structure.tool_x".to_string(), "structure.tool_y".to_string()];
        if fmus.control.is_some() {
            record.push("controller.saturated".into());
            record.push("controller.u".into());
        }
        let cfg = RunConfig {
            start: Some(0.0),
            stop: Some(duration),
            step: Some(fmus.step),
            record: Some(record),
            ..RunConfig::default()
        };
        let mut sim = Simulation::new(&sys, &cfg).map_err(|e| ModelError::Unsupported(e.to_string()))?;
        let n = usize::try_from(sim.n_steps() + 1).unwrap_or(usize::MAX);
        let tau = 60.0 / (f64::from(self.machine.tool.teeth) * rpm);
        let mut obs = Saturation {
            regen: Regen::<2>::new(n, tau / fmus.step),
            saturated: false,
            peak_u: 0.0,
            from: 0.5 * duration,
        };
        match sim.run(&mut obs, Progress::Off) {
            Ok(_) => {
                let w = &obs.regen.windows;
                let left_the_cut = w.after_startup() > self.machine.operation.feed_per_tooth;
                let ratio = if left_the_cut { f64::INFINITY } else { w.ratio() };
                Ok(Growth { ratio, peak: w.max, saturated: obs.saturated, peak_u: obs.peak_u })
            }
            // the structure refuses to go on when the motion has grown beyond any cut
            Err(SimError::Fmu(_)) if obs.regen.windows.max > 1e-4 => Ok(Growth {
                ratio: f64::INFINITY,
                peak: obs.regen.windows.max,
                saturated: obs.saturated,
                peak_u: obs.peak_u,
            }),
            Err(e) => Err(ModelError::Unsupported(e.to_string())),
        }
    }

    /// Overrides of one run (for callers that run the system themselves).
    pub fn overrides(&self, rpm: f64, depth: f64) -> Result<Vec<Override>, ModelError> {
        let f = self.machine.fmu_parameters(rpm, depth, self.controller.as_ref())?;
        let mut o = overrides_of("process", fmu_milling_process::parameter_assignments(&f.process));
        o.extend(overrides_of("process", fmu_milling_process::TABLE.input_assignments(&f.process_inputs)));
        Ok(o)
    }
}

/// [`Regen`] over the two tool channels, the actuator's saturation flag and the command's peak
/// over `t ≥ from`.
struct Saturation {
    regen: Regen<2>,
    saturated: bool,
    peak_u: f64,
    from: f64,
}

impl fmi_master::Observer for Saturation {
    fn start(&mut self, names: &[String]) -> Result<(), SimError> {
        self.regen.start(names)
    }
    fn sample(&mut self, t: f64, values: &[f64]) -> Result<(), SimError> {
        if values.get(2).is_some_and(|s| *s != 0.0) {
            self.saturated = true;
        }
        if t >= self.from
            && let Some(u) = values.get(3)
        {
            self.peak_u = self.peak_u.max(u.abs());
        }
        self.regen.sample(t, values)
    }
    fn finish(&mut self) -> Result<(), SimError> {
        self.regen.finish()
    }
}
