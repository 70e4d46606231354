//! # MillingProcess FMU adapter
//!
//! Translates between the process core ([`milling_process`]: [`ProcessParams`],
//! [`ProcessInputs`], [`ProcessOutputs`]) and the FMI variables of `MillingProcess.fmu`,
//! declared once in [`TABLE`]. The cdylib `MillingProcess` (`fmu-milling-process/cdylib/`) exports the
//! 34 `fmi2*` functions.
//!
//! A step `[t, t + h]` takes the displacement inputs as the values at `t + h` and reports the
//! force at `t + h` (see [`milling_process::process`]): step the structure first, then the
//! process (Gauss–Seidel), and the structure holds that force over its next step.

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use milling_process::{Process, ProcessError, ProcessInputs, ProcessOutputs, ProcessParams};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The variable table of `MillingProcess.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<ProcessParams, ProcessInputs, ProcessOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "MillingProcess",
            identifier: "MillingProcess",
            description: "Regenerative milling process alone, two axes (x feed, y normal): cutting forces from tool and workpiece displacements",
            default_experiment: (0.0, 1.0, 1e-5),
        },
        fmi2_export::variables! {
            inputs ProcessInputs {
                0 "tool_x"         [tool[0]]           "m"   []          "tool displacement at the cutting point along +x (feed)";
                1 "tool_y"         [tool[1]]           "m"   []          "tool displacement at the cutting point along +y";
                2 "workpiece_x"    [workpiece[0]]      "m"   []          "workpiece displacement at the cutting point along +x";
                3 "workpiece_y"    [workpiece[1]]      "m"   []          "workpiece displacement at the cutting point along +y";
                4 "spindle_speed"  [spindle_speed_rpm] "rpm" [0.0, 1e6]  "spindle speed";
                5 "feed_per_tooth" [feed_per_tooth]    "m"   [0.0, 0.01] "feed per tooth";
            }
            outputs ProcessOutputs {
                10 "force_x"           [force[0]]           "N"   [] "cutting force on the tool along +x";
                11 "force_y"           [force[1]]           "N"   [] "cutting force on the tool along +y";
                12 "workpiece_force_x" [workpiece_force[0]] "N"   [] "cutting force on the workpiece along +x (= -force_x)";
                13 "workpiece_force_y" [workpiece_force[1]] "N"   [] "cutting force on the workpiece along +y (= -force_y)";
                14 "chip_thickness"    [chip_thickness]     "m"   [] "largest chip thickness among the cutting teeth";
                15 "delay"             [delay]              "s"   [] "regenerative delay of tooth 1 (time since the tooth before it passed its angle)";
                16 "tool_angle"        [tool_angle]         "rad" [] "tool angle theta mod 2 pi";
            }
            parameters ProcessParams {
                0   "teeth"                 [teeth]                  ""    [1, 100]      "number of teeth Z";
                1   "variable_pitch"        [variable_pitch]         ""    []            "use tooth1..tooth8.angle instead of a uniform pitch (Z <= 8)";
                100 "tooth1.angle"          [tooth_angles[0]]        "rad" [-7.0, 7.0]   "angle of tooth 1";
                101 "tooth2.angle"          [tooth_angles[1]]        "rad" [-7.0, 14.0]  "angle of tooth 2";
                102 "tooth3.angle"          [tooth_angles[2]]        "rad" [-7.0, 14.0]  "angle of tooth 3";
                103 "tooth4.angle"          [tooth_angles[3]]        "rad" [-7.0, 14.0]  "angle of tooth 4";
                104 "tooth5.angle"          [tooth_angles[4]]        "rad" [-7.0, 14.0]  "angle of tooth 5";
                105 "tooth6.angle"          [tooth_angles[5]]        "rad" [-7.0, 14.0]  "angle of tooth 6";
                106 "tooth7.angle"          [tooth_angles[6]]        "rad" [-7.0, 14.0]  "angle of tooth 7";
                107 "tooth8.angle"          [tooth_angles[7]]        "rad" [-7.0, 14.0]  "angle of tooth 8";
                110 "tool_radius"           [tool_radius]            "m"   [1e-6, 1.0]   "tool radius R";
                111 "radial_engagement"     [radial_engagement]      "m"   [1e-6, 2.0]   "radial depth a_e";
                2   "milling"               [enum milling]           ""    []            "up- or down-milling (sets the window from a_e)";
                2   "explicit_angles"       [explicit_angles]        ""    []            "use entry_angle/exit_angle instead of (a_e, milling)";
                112 "entry_angle"           [entry_angle]            "rad" [0.0, 3.2]    "entry angle phi_st (from +y, clockwise)";
                113 "exit_angle"            [exit_angle]             "rad" [0.0, 3.2]    "exit angle phi_ex";
                114 "axial_depth"           [axial_depth]            "m"   [0.0, 1.0]    "axial depth of cut a_p";
                115 "depth_ramp_time"       [depth_ramp_time]        "s"   [0.0, 1e3]    "entry ramp: the depth rises linearly from 0 to a_p over this time after the start (0: at once)";
                3   "law"                   [enum coefficients.law]  ""    []            "force law of one tooth";
                120 "kt"                    [coefficients.kt]        "N/m^(1+x_F)"    [0.0, 1e14]   "tangential coefficient K_t [N/m2 linear, N/m^(1+x_F) power]";
                121 "kr"                    [coefficients.kr]        "N/m^(1+x_F)"    [0.0, 1e14]   "radial coefficient K_r [as K_t]";
                122 "kte"                   [coefficients.kte]       "N/m" [-1e9, 1e9]   "tangential edge coefficient K_te (linear law)";
                123 "kre"                   [coefficients.kre]       "N/m" [-1e9, 1e9]   "radial edge coefficient K_re (linear law)";
                124 "exponent"              [coefficients.exponent]  "1"    [0.01, 2.0]   "power-law exponent x_F";
                130 "cubic.xi1"             [coefficients.xi[0]]     "N/m3" []           "cubic law: tangential coefficient of h^3";
                131 "cubic.xi2"             [coefficients.xi[1]]     "N/m2" []           "cubic law: tangential coefficient of h^2";
                132 "cubic.xi3"             [coefficients.xi[2]]     "N/m"  []           "cubic law: tangential coefficient of h";
                133 "cubic.xi4"             [coefficients.xi[3]]     "N"    []           "cubic law: tangential constant";
                134 "cubic.delta1"          [coefficients.delta[0]]  "N/m3" []           "cubic law: radial coefficient of h^3";
                135 "cubic.delta2"          [coefficients.delta[1]]  "N/m2" []           "cubic law: radial coefficient of h^2";
                136 "cubic.delta3"          [coefficients.delta[2]]  "N/m"  []           "cubic law: radial coefficient of h";
                137 "cubic.delta4"          [coefficients.delta[3]]  "N"    []           "cubic law: radial constant";
                3   "multiple_regeneration" [multiple_regeneration]  ""    []            "chip from the innermost of the last Z passes (a skipped tooth passes its chip on)";
            }
        },
    )
});

fmi2_export::adapter! {
    model: MillingProcess,
    table: TABLE as Table<ProcessParams, ProcessInputs, ProcessOutputs>,
    parameters: |m| m.process.params(),
    input_errors: ProcessError::Input,
}

/// The FMU model: the process core.
#[derive(Clone, Serialize, Deserialize)]
pub struct MillingProcess {
    process: Process,
}

impl MillingProcess {
    /// The process core.
    pub fn process(&self) -> &Process {
        &self.process
    }
}

impl Fmi2Model for MillingProcess {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = TABLE.read_parameters(values)?;
        let mut process = Process::new(&p).map_err(|e| e.to_string())?;
        process.set_inputs(&TABLE.read_inputs(values)?).map_err(|e| e.to_string())?;
        Ok(MillingProcess { process })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.process.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, _t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
        let inputs = TABLE.read_inputs(v).map_err(StepError::Error)?;
        self.process.step(h, &inputs).map_err(Self::step_error)?;
        TABLE.write_outputs(&self.process.outputs(), v);
        Ok(())
    }

    /// Teeth × passes history lookups per step: a fixed amount of work.
    fn internal_steps(&self, _h: f64) -> f64 {
        1.0
    }

    fn validate_state(&self) -> Result<(), String> {
        self.process.validate_state()
    }
}
