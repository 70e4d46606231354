//! # LinearController FMU adapter
//!
//! Translates between the controller core ([`linear_control`]) and the FMI variables of
//! `LinearController.fmu`, declared once in [`TABLE`]: the measurement and the spindle speed in,
//! the force out, the matrices as structured scalar parameters `Ac[i,j]`, `Bc[i,j]`, `Cc[i,j]`,
//! `Dc[i,j]` (1-based). [`frequency_response`] evaluates the response of the FMU's own model
//! (the core built from the same parameters).

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use linear_control::{ControlError, ControlInputs, ControlOutputs, LinearControlParams};
use model_description::ModelDescription;
use num_complex::Complex64;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The variable table of `LinearController.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<LinearControlParams, ControlInputs, ControlOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "LinearController",
            identifier: "LinearController",
            description: "MIMO linear state-space controller (order 0-8) on the delayed difference w = v - beta v(t - tau), tau = 60/(z n) or a parameter; continuous (exactly discretised) or discrete, per-output saturation",
            default_experiment: (0.0, 0.1, 1e-6),
        },
        fmi2_export::variables! {
            inputs ControlInputs {
                0 "v_x"           [v[0]]          "m"   []         "measurement v along +x";
                1 "v_y"           [v[1]]          "m"   []         "measurement v along +y";
                2 "spindle_speed" [spindle_speed] "rpm" [0.0, 1e6] "spindle speed n (tau = 60/(teeth n) when delay_from_speed)";
            }
            outputs ControlOutputs {
                10 "F_x"   [force[0]] "N" [] "controller force along +x (saturated)";
                11 "F_y"   [force[1]] "N" [] "controller force along +y (saturated)";
                12 "w_x"   [w[0]]     "m" [] "w = v - beta v(t - tau) along +x";
                13 "w_y"   [w[1]]     "m" [] "w = v - beta v(t - tau) along +y";
                14 "tau"   [delay]    "s" [] "delay tau used in the last step";
            }
            parameters LinearControlParams {
                0   "n_c"              [n_c]              ""  [0, 8]       "controller order";
                1   "teeth"            [teeth]            ""  [1, 100]     "number of teeth z (tau = 60/(z n))";
                0   "delay_from_speed" [delay_from_speed] ""  []           "tau from the spindle_speed input (else the delay parameter)";
                1   "discrete"         [discrete]         ""  []           "discrete form: xi(k+1) = A_c xi(k) + B_c w(k) every sample_period";
                100 "beta"             [beta]             "1"  [-10.0, 10.0] "beta of w = v - beta v(t - tau) (1: Pyragas)";
                101 "delay"            [delay]            "s" [0.0, 1.0]   "tau when not from the speed";
                102 "max_delay"        [max_delay]        "s" [1e-9, 1.0]  "longest delay the input buffer keeps";
                103 "sample_period"    [sample_period]    "s" [1e-9, 1.0]  "sample period of the discrete form";
                104 "saturation_x"     [saturation[0]]    "N" [0.0, 1e12]  "limit |F_x| <= saturation_x";
                105 "saturation_y"     [saturation[1]]    "N" [0.0, 1e12]  "limit |F_y| <= saturation_y";
                1011 "Ac[1,1]" [ac[0][0]] "1/s|1" [] "A_c row 1, column 1";
                1012 "Ac[1,2]" [ac[0][1]] "1/s|1" [] "A_c row 1, column 2";
                1013 "Ac[1,3]" [ac[0][2]] "1/s|1" [] "A_c row 1, column 3";
                1014 "Ac[1,4]" [ac[0][3]] "1/s|1" [] "A_c row 1, column 4";
                1015 "Ac[1,5]" [ac[0][4]] "1/s|1" [] "A_c row 1, column 5";
                1016 "Ac[1,6]" [ac[0][5]] "1/s|1" [] "A_c row 1, column 6";
                1017 "Ac[1,7]" [ac[0][6]] "1/s|1" [] "A_c row 1, column 7";
                1018 "Ac[1,8]" [ac[0][7]] "1/s|1" [] "A_c row 1, column 8";
                1021 "Ac[2,1]" [ac[1][0]] "1/s|1" [] "A_c row 2, column 1";
                1022 "Ac[2,2]" [ac[1][1]] "1/s|1" [] "A_c row 2, column 2";
                1023 "Ac[2,3]" [ac[1][2]] "1/s|1" [] "A_c row 2, column 3";
                1024 "Ac[2,4]" [ac[1][3]] "1/s|1" [] "A_c row 2, column 4";
                1025 "Ac[2,5]" [ac[1][4]] "1/s|1" [] "A_c row 2, column 5";
                1026 "Ac[2,6]" [ac[1][5]] "1/s|1" [] "A_c row 2, column 6";
                1027 "Ac[2,7]" [ac[1][6]] "1/s|1" [] "A_c row 2, column 7";
                1028 "Ac[2,8]" [ac[1][7]] "1/s|1" [] "A_c row 2, column 8";
                1031 "Ac[3,1]" [ac[2][0]] "1/s|1" [] "A_c row 3, column 1";
                1032 "Ac[3,2]" [ac[2][1]] "1/s|1" [] "A_c row 3, column 2";
                1033 "Ac[3,3]" [ac[2][2]] "1/s|1" [] "A_c row 3, column 3";
                1034 "Ac[3,4]" [ac[2][3]] "1/s|1" [] "A_c row 3, column 4";
                1035 "Ac[3,5]" [ac[2][4]] "1/s|1" [] "A_c row 3, column 5";
                1036 "Ac[3,6]" [ac[2][5]] "1/s|1" [] "A_c row 3, column 6";
                1037 "Ac[3,7]" [ac[2][6]] "1/s|1" [] "A_c row 3, column 7";
                1038 "Ac[3,8]" [ac[2][7]] "1/s|1" [] "A_c row 3, column 8";
                1041 "Ac[4,1]" [ac[3][0]] "1/s|1" [] "A_c row 4, column 1";
                1042 "Ac[4,2]" [ac[3][1]] "1/s|1" [] "A_c row 4, column 2";
                1043 "Ac[4,3]" [ac[3][2]] "1/s|1" [] "A_c row 4, column 3";
                1044 "Ac[4,4]" [ac[3][3]] "1/s|1" [] "A_c row 4, column 4";
                1045 "Ac[4,5]" [ac[3][4]] "1/s|1" [] "A_c row 4, column 5";
                1046 "Ac[4,6]" [ac[3][5]] "1/s|1" [] "A_c row 4, column 6";
                1047 "Ac[4,7]" [ac[3][6]] "1/s|1" [] "A_c row 4, column 7";
                1048 "Ac[4,8]" [ac[3][7]] "1/s|1" [] "A_c row 4, column 8";
                1051 "Ac[5,1]" [ac[4][0]] "1/s|1" [] "A_c row 5, column 1";
                1052 "Ac[5,2]" [ac[4][1]] "1/s|1" [] "A_c row 5, column 2";
                1053 "Ac[5,3]" [ac[4][2]] "1/s|1" [] "A_c row 5, column 3";
                1054 "Ac[5,4]" [ac[4][3]] "1/s|1" [] "A_c row 5, column 4";
                1055 "Ac[5,5]" [ac[4][4]] "1/s|1" [] "A_c row 5, column 5";
                1056 "Ac[5,6]" [ac[4][5]] "1/s|1" [] "A_c row 5, column 6";
                1057 "Ac[5,7]" [ac[4][6]] "1/s|1" [] "A_c row 5, column 7";
                1058 "Ac[5,8]" [ac[4][7]] "1/s|1" [] "A_c row 5, column 8";
                1061 "Ac[6,1]" [ac[5][0]] "1/s|1" [] "A_c row 6, column 1";
                1062 "Ac[6,2]" [ac[5][1]] "1/s|1" [] "A_c row 6, column 2";
                1063 "Ac[6,3]" [ac[5][2]] "1/s|1" [] "A_c row 6, column 3";
                1064 "Ac[6,4]" [ac[5][3]] "1/s|1" [] "A_c row 6, column 4";
                1065 "Ac[6,5]" [ac[5][4]] "1/s|1" [] "A_c row 6, column 5";
                1066 "Ac[6,6]" [ac[5][5]] "1/s|1" [] "A_c row 6, column 6";
                1067 "Ac[6,7]" [ac[5][6]] "1/s|1" [] "A_c row 6, column 7";
                1068 "Ac[6,8]" [ac[5][7]] "1/s|1" [] "A_c row 6, column 8";
                1071 "Ac[7,1]" [ac[6][0]] "1/s|1" [] "A_c row 7, column 1";
                1072 "Ac[7,2]" [ac[6][1]] "1/s|1" [] "A_c row 7, column 2";
                1073 "Ac[7,3]" [ac[6][2]] "1/s|1" [] "A_c row 7, column 3";
                1074 "Ac[7,4]" [ac[6][3]] "1/s|1" [] "A_c row 7, column 4";
                1075 "Ac[7,5]" [ac[6][4]] "1/s|1" [] "A_c row 7, column 5";
                1076 "Ac[7,6]" [ac[6][5]] "1/s|1" [] "A_c row 7, column 6";
                1077 "Ac[7,7]" [ac[6][6]] "1/s|1" [] "A_c row 7, column 7";
                1078 "Ac[7,8]" [ac[6][7]] "1/s|1" [] "A_c row 7, column 8";
                1081 "Ac[8,1]" [ac[7][0]] "1/s|1" [] "A_c row 8, column 1";
                1082 "Ac[8,2]" [ac[7][1]] "1/s|1" [] "A_c row 8, column 2";
                1083 "Ac[8,3]" [ac[7][2]] "1/s|1" [] "A_c row 8, column 3";
                1084 "Ac[8,4]" [ac[7][3]] "1/s|1" [] "A_c row 8, column 4";
                1085 "Ac[8,5]" [ac[7][4]] "1/s|1" [] "A_c row 8, column 5";
                1086 "Ac[8,6]" [ac[7][5]] "1/s|1" [] "A_c row 8, column 6";
                1087 "Ac[8,7]" [ac[7][6]] "1/s|1" [] "A_c row 8, column 7";
                1088 "Ac[8,8]" [ac[7][7]] "1/s|1" [] "A_c row 8, column 8";
                2011 "Bc[1,1]" [bc[0][0]] "1/s|1" [] "B_c row 1, column 1";
                2012 "Bc[1,2]" [bc[0][1]] "1/s|1" [] "B_c row 1, column 2";
                2021 "Bc[2,1]" [bc[1][0]] "1/s|1" [] "B_c row 2, column 1";
                2022 "Bc[2,2]" [bc[1][1]] "1/s|1" [] "B_c row 2, column 2";
                2031 "Bc[3,1]" [bc[2][0]] "1/s|1" [] "B_c row 3, column 1";
                2032 "Bc[3,2]" [bc[2][1]] "1/s|1" [] "B_c row 3, column 2";
                2041 "Bc[4,1]" [bc[3][0]] "1/s|1" [] "B_c row 4, column 1";
                2042 "Bc[4,2]" [bc[3][1]] "1/s|1" [] "B_c row 4, column 2";
                2051 "Bc[5,1]" [bc[4][0]] "1/s|1" [] "B_c row 5, column 1";
                2052 "Bc[5,2]" [bc[4][1]] "1/s|1" [] "B_c row 5, column 2";
                2061 "Bc[6,1]" [bc[5][0]] "1/s|1" [] "B_c row 6, column 1";
                2062 "Bc[6,2]" [bc[5][1]] "1/s|1" [] "B_c row 6, column 2";
                2071 "Bc[7,1]" [bc[6][0]] "1/s|1" [] "B_c row 7, column 1";
                2072 "Bc[7,2]" [bc[6][1]] "1/s|1" [] "B_c row 7, column 2";
                2081 "Bc[8,1]" [bc[7][0]] "1/s|1" [] "B_c row 8, column 1";
                2082 "Bc[8,2]" [bc[7][1]] "1/s|1" [] "B_c row 8, column 2";
                3011 "Cc[1,1]" [cc[0][0]] "N/m" [] "C_c row 1, column 1";
                3012 "Cc[1,2]" [cc[0][1]] "N/m" [] "C_c row 1, column 2";
                3013 "Cc[1,3]" [cc[0][2]] "N/m" [] "C_c row 1, column 3";
                3014 "Cc[1,4]" [cc[0][3]] "N/m" [] "C_c row 1, column 4";
                3015 "Cc[1,5]" [cc[0][4]] "N/m" [] "C_c row 1, column 5";
                3016 "Cc[1,6]" [cc[0][5]] "N/m" [] "C_c row 1, column 6";
                3017 "Cc[1,7]" [cc[0][6]] "N/m" [] "C_c row 1, column 7";
                3018 "Cc[1,8]" [cc[0][7]] "N/m" [] "C_c row 1, column 8";
                3021 "Cc[2,1]" [cc[1][0]] "N/m" [] "C_c row 2, column 1";
                3022 "Cc[2,2]" [cc[1][1]] "N/m" [] "C_c row 2, column 2";
                3023 "Cc[2,3]" [cc[1][2]] "N/m" [] "C_c row 2, column 3";
                3024 "Cc[2,4]" [cc[1][3]] "N/m" [] "C_c row 2, column 4";
                3025 "Cc[2,5]" [cc[1][4]] "N/m" [] "C_c row 2, column 5";
                3026 "Cc[2,6]" [cc[1][5]] "N/m" [] "C_c row 2, column 6";
                3027 "Cc[2,7]" [cc[1][6]] "N/m" [] "C_c row 2, column 7";
                3028 "Cc[2,8]" [cc[1][7]] "N/m" [] "C_c row 2, column 8";
                tunable 4011 "Dc[1,1]" [dc[0][0]] "N/m" [] "D_c row 1, column 1 (force per metre of w)";
                tunable 4012 "Dc[1,2]" [dc[0][1]] "N/m" [] "D_c row 1, column 2 (force per metre of w)";
                tunable 4021 "Dc[2,1]" [dc[1][0]] "N/m" [] "D_c row 2, column 1 (force per metre of w)";
                tunable 4022 "Dc[2,2]" [dc[1][1]] "N/m" [] "D_c row 2, column 2 (force per metre of w)";
            }
        },
    )
    // what a step costs, as `internal_steps` counts it: for masters, in modelDescription.xml
    .work_bound("sample_period", 1.0)
});

fmi2_export::adapter! {
    model: LinearController,
    table: TABLE as Table<LinearControlParams, ControlInputs, ControlOutputs>,
    parameters: |m| m.ctrl.params(),
    input_errors: ControlError::Input,
}

/// The response `F/V` (2 × 2) at `omega` [rad/s] with delay `tau` of the controller the FMU
/// builds from `p` (the same core and code path as its steps).
pub fn frequency_response(p: &LinearControlParams, omega: f64, tau: f64) -> Result<[[Complex64; 2]; 2], String> {
    let c = linear_control::LinearController::new(p).map_err(|e| e.to_string())?;
    Ok(c.frequency_response(omega, tau))
}

/// The FMU model: the controller core.
#[derive(Clone, Serialize, Deserialize)]
pub struct LinearController {
    ctrl: linear_control::LinearController,
}

impl LinearController {
    /// The controller core.
    pub fn controller(&self) -> &linear_control::LinearController {
        &self.ctrl
    }
}

impl Fmi2Model for LinearController {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let params = TABLE.read_parameters(values)?;
        let ctrl = linear_control::LinearController::new(&params).map_err(|e| e.to_string())?;
        Ok(LinearController { ctrl })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.ctrl.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
        let inputs = TABLE.read_inputs(v).map_err(StepError::Error)?;
        self.ctrl.step(t, h, &inputs).map_err(Self::step_error)?;
        TABLE.write_outputs(&self.ctrl.outputs(), v);
        Ok(())
    }

    fn internal_steps(&self, h: f64) -> f64 {
        self.ctrl.internal_steps(h)
    }

    /// `Dc[i,j]` are tunable: a change between steps applies from the next step on.
    fn retune(&mut self, values: &Values) -> Result<(), String> {
        let p = TABLE.read_parameters(values)?;
        self.ctrl.retune(&p).map_err(|e| e.to_string())
    }

    fn validate_state(&self) -> Result<(), String> {
        self.ctrl.validate_state()
    }
}
