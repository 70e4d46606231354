//! # InertialActuator FMU adapter
//!
//! Translates between the actuator core ([`machine_structure::actuator`]) and the FMI variables
//! of `InertialActuator.fmu`, declared once in [`TABLE`]. Outputs at `t + h` are the force of
//! the state at `t + h` with the command held over the step (the feedthrough `D u` uses that
//! command); no output depends directly on an input.

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, Severity, StepError, Table, Values};
use machine_structure::actuator::{ActuatorError, ActuatorOutputs, ActuatorParams};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The actuator's one input.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ActuatorInputs {
    /// Force command [N].
    pub u: f64,
}

/// The variable table of `InertialActuator.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<ActuatorParams, ActuatorInputs, ActuatorOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "InertialActuator",
            identifier: "InertialActuator",
            description: "Inertial (proof-mass) actuator of seed 000: F/u = C (sI - A)^-1 B + D, command saturated at +-f_max",
            default_experiment: (0.0, 1.0, 1e-5),
        },
        fmi2_export::variables! {
            inputs ActuatorInputs {
                0 "u" [u] "N" [] "force command";
            }
            outputs ActuatorOutputs {
                10 "force"   [force]       "N" [] "actuator force on the structure along its direction";
                11 "force_x" [force_xy[0]] "N" [] "actuator force on the structure along +x";
                12 "force_y" [force_xy[1]] "N" [] "actuator force on the structure along +y";
                0  "saturated" [saturated] ""  [] "the command was clipped at +-f_max over the last step";
            }
            parameters ActuatorParams {
                130 "a11"             [a[0][0]]         "1/s"    []           "A[1,1] (1/s)";
                131 "a12"             [a[0][1]]         "1/s2"    []           "A[1,2] (1/s2)";
                132 "a21"             [a[1][0]]         "1"    []           "A[2,1]";
                133 "a22"             [a[1][1]]         "1/s"    []           "A[2,2]";
                134 "b1"              [b[0]]            "1"    []           "B[1]";
                135 "b2"              [b[1]]            "s"    []           "B[2]";
                136 "c1"              [c[0]]            "1/s"    []           "C[1]";
                137 "c2"              [c[1]]            "1/s2"    []           "C[2]";
                138 "d"               [d]               "1"    []           "D (F/u at high frequency)";
                139 "f_max"           [f_max]           "N"   [0.0, 1e9]   "saturation of the command";
                140 "direction_angle" [direction_angle] "rad" [-7.0, 7.0]  "direction of the force from +x towards +y";
                141 "internal_step"   [internal_step]   "s"   [1e-8, 1e-3] "largest RK4 sub-step";
            }
        },
    )
    // what a step costs, as `internal_steps` counts it: for masters, in modelDescription.xml
    .work_bound("internal_step", 1.0)
});

fmi2_export::adapter! {
    model: InertialActuator,
    table: TABLE as Table<ActuatorParams, ActuatorInputs, ActuatorOutputs>,
    parameters: |m| m.actuator.params(),
    input_errors: ActuatorError::Input,
}

/// The FMU model: the actuator core and what it has reported.
#[derive(Clone, Serialize, Deserialize)]
pub struct InertialActuator {
    actuator: machine_structure::InertialActuator,
    reported_saturation: bool,
}

impl Fmi2Model for InertialActuator {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = TABLE.read_parameters(values)?;
        let mut actuator = machine_structure::InertialActuator::new(&p).map_err(|e| e.to_string())?;
        actuator.set_command(TABLE.read_inputs(values)?.u).map_err(|e| e.to_string())?;
        Ok(InertialActuator { actuator, reported_saturation: false })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.actuator.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, t: f64, h: f64, log: &mut dyn ModelLog) -> Result<(), StepError> {
        let u = TABLE.read_inputs(v).map_err(StepError::Error)?.u;
        self.actuator.step(h, u).map_err(Self::step_error)?;
        let o = self.actuator.outputs();
        if o.saturated && !self.reported_saturation {
            self.reported_saturation = true;
            log.log(
                Severity::Info,
                &format!("actuator command {u} N clipped at t = {} s (further clips not logged)", t + h),
            );
        }
        TABLE.write_outputs(&o, v);
        Ok(())
    }

    /// `⌈h/internal_step⌉ ≤ h/internal_step + 1` RK4 sub-steps: the work bound of the table.
    /// (The core counts `⌈h/internal_step⌉ + 1`; with the layer's integer limit both refuse the
    /// same steps, and only this one is a bound a master can evaluate.)
    fn internal_steps(&self, h: f64) -> f64 {
        h / self.actuator.params().internal_step + 1.0
    }

    fn validate_state(&self) -> Result<(), String> {
        self.actuator.validate_state()
    }
}
