//! # SpindleStructure FMU adapter
//!
//! Translates between the spindle core ([`spindle_structure`]) and the FMI variables of
//! `SpindleStructure.fmu`, declared once in [`TABLE`]: force inputs at the tool and at the
//! bearing, displacements and velocities of both, Table I as parameters.

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use spindle_structure::{Spindle, SpindleError, SpindleInputs, SpindleOutputs, SpindleParams};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The variable table of `SpindleStructure.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<SpindleParams, SpindleInputs, SpindleOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "SpindleStructure",
            identifier: "SpindleStructure",
            description: "Seed 002's two-axis spindle with an active magnetic bearing: per axis ground-m_a-m_t, actuator force and measurement at m_a, cutting force at the tool m_t",
            default_experiment: (0.0, 0.1, 1e-6),
        },
        fmi2_export::variables! {
            inputs SpindleInputs {
                0 "tool_force_x"     [tool_force[0]]     "N" [] "force on the tool (m_t) along +x";
                1 "tool_force_y"     [tool_force[1]]     "N" [] "force on the tool (m_t) along +y";
                2 "actuator_force_x" [actuator_force[0]] "N" [] "actuator force on the bearing (m_a) along +x";
                3 "actuator_force_y" [actuator_force[1]] "N" [] "actuator force on the bearing (m_a) along +y";
            }
            outputs SpindleOutputs {
                10 "tool_x"      [tool[0]]              "m"   [] "tool displacement v_t along +x";
                11 "tool_y"      [tool[1]]              "m"   [] "tool displacement v_t along +y";
                12 "tool_vx"     [tool_velocity[0]]     "m/s" [] "tool velocity along +x";
                13 "tool_vy"     [tool_velocity[1]]     "m/s" [] "tool velocity along +y";
                14 "actuator_x"  [actuator[0]]          "m"   [] "bearing displacement v_a (the measurement) along +x";
                15 "actuator_y"  [actuator[1]]          "m"   [] "bearing displacement v_a (the measurement) along +y";
                16 "actuator_vx" [actuator_velocity[0]] "m/s" [] "bearing velocity along +x";
                17 "actuator_vy" [actuator_velocity[1]] "m/s" [] "bearing velocity along +y";
            }
            parameters SpindleParams {
                100 "tool_mass"              [tool_mass]              "kg" [1e-9, 1e9] "tool mass m_t (each axis)";
                101 "actuator_mass"          [actuator_mass]          "kg" [1e-9, 1e9] "bearing/actuator mass m_a (each axis)";
                102 "tool_frequency"         [tool_frequency]         "Hz" [1e-3, 1e6] "f_t = sqrt(c_t/m_t)/(2 pi)";
                103 "actuator_frequency"     [actuator_frequency]     "Hz" [1e-3, 1e6] "f_a = sqrt(c_a/m_a)/(2 pi)";
                104 "tool_damping_ratio"     [tool_damping_ratio]     "1"   [0.0, 10.0] "zeta_t = b_t/(2 sqrt(c_t m_t))";
                105 "actuator_damping_ratio" [actuator_damping_ratio] "1"   [0.0, 10.0] "zeta_a = b_a/(2 sqrt(c_a m_a))";
            }
        },
    )
});

fmi2_export::adapter! {
    model: SpindleStructure,
    table: TABLE as Table<SpindleParams, SpindleInputs, SpindleOutputs>,
    parameters: |m| m.spindle.params(),
    input_errors: SpindleError::Input,
}

/// The FMU model: the spindle core.
#[derive(Clone, Serialize, Deserialize)]
pub struct SpindleStructure {
    spindle: Spindle,
}

impl SpindleStructure {
    /// The spindle core.
    pub fn spindle(&self) -> &Spindle {
        &self.spindle
    }
}

impl Fmi2Model for SpindleStructure {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let params = TABLE.read_parameters(values)?;
        let spindle = Spindle::new(&params).map_err(|e| e.to_string())?;
        Ok(SpindleStructure { spindle })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.spindle.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, _t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
        let inputs = TABLE.read_inputs(v).map_err(StepError::Error)?;
        self.spindle.step(h, &inputs).map_err(Self::step_error)?;
        TABLE.write_outputs(&self.spindle.outputs(), v);
        Ok(())
    }

    fn validate_state(&self) -> Result<(), String> {
        self.spindle.validate_state()
    }
}
