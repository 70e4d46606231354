//! # ModalStructure FMU adapter
//!
//! Translates between the structure core ([`machine_structure::modal`]) and the FMI variables
//! of `ModalStructure.fmu`, declared once in [`TABLE`]. Up to four modes from parameters, or up
//! to sixteen ([`MAX_MODES`]) from a modal table from a CSV file named by the string parameter `modal_table` (absolute, or
//! relative to the FMU's `resources/` directory): one line per mode,
//! `frequency [Hz], damping_ratio, modal_mass [kg], tool_x, tool_y, actuator_x, actuator_y`
//! (`#` starts a comment; a header line of words is skipped). The file's modes replace the
//! mode parameters and set `n_modes`.

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use machine_structure::modal::{
    MAX_MODES, ModalParams, StructureError, StructureInputs, StructureMode, StructureOutputs,
};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The FMU's parameters: the core's, and the optional modal table file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StructureFmuParams {
    /// The core's parameters.
    pub structure: ModalParams,
    /// Path of a CSV modal table (empty: the mode parameters).
    pub modal_table: String,
}

/// The variable table of `ModalStructure.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<StructureFmuParams, StructureInputs, StructureOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "ModalStructure",
            identifier: "ModalStructure",
            description: "Modal machine structure: up to 4 modes as parameters (16 from a modal table) with mode shapes at a tool point and an actuator point, force inputs, displacement/velocity outputs",
            default_experiment: (0.0, 1.0, 1e-5),
        },
        fmi2_export::variables! {
            inputs StructureInputs {
                0 "tool_force_x"     [tool_force[0]]     "N" [] "force on the structure at the tool point along +x";
                1 "tool_force_y"     [tool_force[1]]     "N" [] "force on the structure at the tool point along +y";
                2 "actuator_force_x" [actuator_force[0]] "N" [] "force on the structure at the actuator point along +x";
                3 "actuator_force_y" [actuator_force[1]] "N" [] "force on the structure at the actuator point along +y";
            }
            outputs StructureOutputs {
                10 "tool_x"            [tool[0]]              "m"   [] "tool-point displacement along +x";
                11 "tool_y"            [tool[1]]              "m"   [] "tool-point displacement along +y";
                12 "tool_vx"           [tool_velocity[0]]     "m/s" [] "tool-point velocity along +x";
                13 "tool_vy"           [tool_velocity[1]]     "m/s" [] "tool-point velocity along +y";
                14 "actuator_x"        [actuator[0]]          "m"   [] "actuator-point displacement along +x";
                15 "actuator_y"        [actuator[1]]          "m"   [] "actuator-point displacement along +y";
                16 "actuator_vx"       [actuator_velocity[0]] "m/s" [] "actuator-point velocity along +x";
                17 "actuator_vy"       [actuator_velocity[1]] "m/s" [] "actuator-point velocity along +y";
                18 "disturbance_force" [disturbance_force]    "N"   [] "disturbance force (noise + sinusoid) along its direction over the last step";
            }
            parameters StructureFmuParams {
                0   "n_modes"                     [structure.n_modes]                     ""    [1, 4]        "number of modes used";
                1   "seed"                        [structure.seed]                        ""    [0, i32::MAX] "random seed of the noise";
                150 "internal_step"               [structure.internal_step]               "s"   [1e-8, 1e-3]  "grid of the noise (steps are split on it)";
                100   "mode1.frequency"     [structure.modes[0].frequency]     "Hz"  [1e-3, 1e6]  "mode 1: natural frequency";
                101 "mode1.damping_ratio" [structure.modes[0].damping_ratio] "1"    [0.0, 0.99]  "mode 1: damping ratio";
                102 "mode1.modal_mass"    [structure.modes[0].modal_mass]    "kg"  [1e-9, 1e9]  "mode 1: modal mass (1 for mass-normalised shapes)";
                103 "mode1.tool_x"        [structure.modes[0].tool[0]]       "1"    []           "mode 1: shape component along x at the tool point";
                104 "mode1.tool_y"        [structure.modes[0].tool[1]]       "1"    []           "mode 1: shape component along y at the tool point";
                105 "mode1.actuator_x"    [structure.modes[0].actuator[0]]   "1"    []           "mode 1: shape component along x at the actuator point";
                106 "mode1.actuator_y"    [structure.modes[0].actuator[1]]   "1"    []           "mode 1: shape component along y at the actuator point";
                110   "mode2.frequency"     [structure.modes[1].frequency]     "Hz"  [1e-3, 1e6]  "mode 2: natural frequency";
                111 "mode2.damping_ratio" [structure.modes[1].damping_ratio] "1"    [0.0, 0.99]  "mode 2: damping ratio";
                112 "mode2.modal_mass"    [structure.modes[1].modal_mass]    "kg"  [1e-9, 1e9]  "mode 2: modal mass (1 for mass-normalised shapes)";
                113 "mode2.tool_x"        [structure.modes[1].tool[0]]       "1"    []           "mode 2: shape component along x at the tool point";
                114 "mode2.tool_y"        [structure.modes[1].tool[1]]       "1"    []           "mode 2: shape component along y at the tool point";
                115 "mode2.actuator_x"    [structure.modes[1].actuator[0]]   "1"    []           "mode 2: shape component along x at the actuator point";
                116 "mode2.actuator_y"    [structure.modes[1].actuator[1]]   "1"    []           "mode 2: shape component along y at the actuator point";
                120   "mode3.frequency"     [structure.modes[2].frequency]     "Hz"  [1e-3, 1e6]  "mode 3: natural frequency";
                121 "mode3.damping_ratio" [structure.modes[2].damping_ratio] "1"    [0.0, 0.99]  "mode 3: damping ratio";
                122 "mode3.modal_mass"    [structure.modes[2].modal_mass]    "kg"  [1e-9, 1e9]  "mode 3: modal mass (1 for mass-normalised shapes)";
                123 "mode3.tool_x"        [structure.modes[2].tool[0]]       "1"    []           "mode 3: shape component along x at the tool point";
                124 "mode3.tool_y"        [structure.modes[2].tool[1]]       "1"    []           "mode 3: shape component along y at the tool point";
                125 "mode3.actuator_x"    [structure.modes[2].actuator[0]]   "1"    []           "mode 3: shape component along x at the actuator point";
                126 "mode3.actuator_y"    [structure.modes[2].actuator[1]]   "1"    []           "mode 3: shape component along y at the actuator point";
                130   "mode4.frequency"     [structure.modes[3].frequency]     "Hz"  [1e-3, 1e6]  "mode 4: natural frequency";
                131 "mode4.damping_ratio" [structure.modes[3].damping_ratio] "1"    [0.0, 0.99]  "mode 4: damping ratio";
                132 "mode4.modal_mass"    [structure.modes[3].modal_mass]    "kg"  [1e-9, 1e9]  "mode 4: modal mass (1 for mass-normalised shapes)";
                133 "mode4.tool_x"        [structure.modes[3].tool[0]]       "1"    []           "mode 4: shape component along x at the tool point";
                134 "mode4.tool_y"        [structure.modes[3].tool[1]]       "1"    []           "mode 4: shape component along y at the tool point";
                135 "mode4.actuator_x"    [structure.modes[3].actuator[0]]   "1"    []           "mode 4: shape component along x at the actuator point";
                136 "mode4.actuator_y"    [structure.modes[3].actuator[1]]   "1"    []           "mode 4: shape component along y at the actuator point";
                0   "disturbance.noise"           [structure.disturbance.noise]           ""    []            "band-limited Gaussian force at the tool point on/off";
                160 "disturbance.noise_rms"       [structure.disturbance.noise_rms]       "N"   [0.0, 1e9]    "noise RMS";
                161 "disturbance.noise_bandwidth" [structure.disturbance.noise_bandwidth] "Hz"  [1e-3, 1e9]   "noise cut-off (4th-order Butterworth)";
                162 "disturbance.sine_amplitude"  [structure.disturbance.sine_amplitude]  "N"   []            "sinusoidal force amplitude";
                163 "disturbance.sine_frequency"  [structure.disturbance.sine_frequency]  "Hz"  []            "sinusoidal force frequency";
                164 "disturbance.direction_angle" [structure.disturbance.direction_angle] "rad" [-7.0, 7.0]   "direction of the disturbance force from +x towards +y";
                1   "disturbance.drift"           [structure.disturbance.drift]           ""    []            "stiffness drift of mode 1 on/off";
                165 "disturbance.drift_amplitude" [structure.disturbance.drift_amplitude] "1"    [0.0, 0.99]   "relative stiffness drift A of mode 1";
                166 "disturbance.drift_frequency" [structure.disturbance.drift_frequency] "Hz"  []            "drift frequency";
                0   "modal_table"                 [modal_table]                           ""    []            "CSV modal table (absolute or relative to resources/); empty: the mode parameters";
            }
        },
    )
    // what a step costs, as `internal_steps` counts it: for masters, in modelDescription.xml
    .work_bound("internal_step", 2.0)
});

fmi2_export::adapter! {
    model: ModalStructure,
    table: TABLE as Table<StructureFmuParams, StructureInputs, StructureOutputs>,
    parameters: |m| &m.params,
    input_errors: StructureError::Input,
}

/// The modes declared as parameters (`mode1.*` … `mode4.*`); more go through a modal table.
pub use machine_structure::modal::PARAMETER_MODES;

/// `p`'s modes as a modal table (module docs; full precision, read back bit for bit).
pub fn modal_table(p: &ModalParams) -> String {
    let mut s = String::from("frequency,damping_ratio,modal_mass,tool_x,tool_y,actuator_x,actuator_y\n");
    for m in p.mode_list() {
        s.push_str(&format!(
            "{:e},{:e},{:e},{:e},{:e},{:e},{:e}\n",
            m.frequency, m.damping_ratio, m.modal_mass, m.tool[0], m.tool[1], m.actuator[0], m.actuator[1]
        ));
    }
    s
}

/// Parse a modal table (module docs) into `p`'s modes and `n_modes`.
pub fn apply_modal_table(p: &mut ModalParams, text: &str) -> Result<(), String> {
    let mut modes = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let nums: Result<Vec<f64>, _> = cells.iter().map(|c| c.parse::<f64>()).collect();
        let Ok(v) = nums else {
            if modes.is_empty() && cells.iter().all(|c| c.chars().next().is_some_and(char::is_alphabetic)) {
                continue; // header
            }
            return Err(format!("modal table line {}: not 7 numbers: {line:?}", i + 1));
        };
        if v.len() != 7 {
            return Err(format!("modal table line {}: {} values, expected 7", i + 1, v.len()));
        }
        modes.push(StructureMode {
            frequency: v[0],
            damping_ratio: v[1],
            modal_mass: v[2],
            tool: [v[3], v[4]],
            actuator: [v[5], v[6]],
        });
    }
    if modes.is_empty() || modes.len() > MAX_MODES {
        return Err(format!("modal table holds {} modes, expected 1..={MAX_MODES}", modes.len()));
    }
    p.set_modes(&modes)
}

/// The FMU model: the structure core and the parameters it was built from.
#[derive(Clone, Serialize, Deserialize)]
pub struct ModalStructure {
    params: StructureFmuParams,
    structure: machine_structure::ModalStructure,
}

impl ModalStructure {
    /// The structure core.
    pub fn structure(&self) -> &machine_structure::ModalStructure {
        &self.structure
    }
}

impl Fmi2Model for ModalStructure {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, env: &Environment) -> Result<Self, String> {
        let params = TABLE.read_parameters(values)?;
        let mut core = params.structure.clone();
        if !params.modal_table.is_empty() {
            let mut path = std::path::PathBuf::from(&params.modal_table);
            if let (true, Some(r)) = (path.is_relative(), &env.resources) {
                path = r.join(path);
            }
            let text = std::fs::read_to_string(&path).map_err(|e| format!("modal_table {}: {e}", path.display()))?;
            apply_modal_table(&mut core, &text).map_err(|e| format!("{}: {e}", path.display()))?;
        }
        let structure = machine_structure::ModalStructure::new(&core).map_err(|e| e.to_string())?;
        Ok(ModalStructure { params, structure })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.structure.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, _t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
        let inputs = TABLE.read_inputs(v).map_err(StepError::Error)?;
        self.structure.step(h, &inputs).map_err(Self::step_error)?;
        TABLE.write_outputs(&self.structure.outputs(), v);
        Ok(())
    }

    /// One sub-step per cell of the noise grid `internal_step`, plus a partial one at either end
    /// (`h / internal_step + 2`, the work bound of the table).
    fn internal_steps(&self, h: f64) -> f64 {
        self.structure.internal_steps(h)
    }

    fn validate_state(&self) -> Result<(), String> {
        self.structure.validate_state()
    }
}
