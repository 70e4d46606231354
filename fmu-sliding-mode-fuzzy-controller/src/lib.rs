//! # SlidingModeFuzzyController FMU adapter (seed 003)
//!
//! Translates between the controller core ([`sliding_fuzzy_control::controller`]:
//! [`SlidingFuzzyParams`], [`SlidingFuzzy::step`]) and the FMI variables of
//! `SlidingModeFuzzyController.fmu`, declared once in [`TABLE`]. The cdylib
//! `SlidingModeFuzzyController` (`fmu-sliding-mode-fuzzy-controller/cdylib/`) exports it.
//!
//! # Timing
//!
//! The controller samples at `t_k = t_start + kT` (`t_start`: the first communication point).
//! `fmi2DoStep(t, h)` takes the sample instants in `[t, t+h)` with the inputs set before the
//! call and holds the forces `u_x`, `u_y` until the next sample. The shipped system steps
//! Gauss–Seidel controller → plant with `h = T`, so the plant integrates `[t_k, t_{k+1})` with
//! `u(t_k)` computed from its state at `t_k`: the loop of [`sliding_fuzzy_control::simulate`].
//! The outputs after a step are the force that acts over that step; a Jacobi master hands the
//! plant the previous step's instead, which at `h = T` is one more sample of delay (the
//! `computation_delay` parameter models a controller that needs it; no FMU output can serve
//! both orders, since the two give the plant the controller's output of two different steps).
//!
//! The fuzzy consequents (the learned weights), the error history, the PID integrator, the
//! model prediction and the clock are all in the serialized FMU state.

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use sliding_fuzzy_control::{ControllerOutputs, SlidingFuzzy, SlidingFuzzyError, SlidingFuzzyParams};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The controller's inputs: the tool's vibration (position about the static deflection) and
/// velocity, held over a communication step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FuzzyInputs {
    /// Positions `(x, y)` [m].
    pub pos: [f64; 2],
    /// Velocities `(ẋ, ẏ)` [m/s].
    pub vel: [f64; 2],
}

/// The variable table of `SlidingModeFuzzyController.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<SlidingFuzzyParams, FuzzyInputs, ControllerOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "SlidingModeFuzzyController",
            identifier: "SlidingModeFuzzyController",
            description: "Two-axis active damper controller of seed 003: D-PID, discrete sliding mode, and DSMC with learning type-1 / interval type-2 fuzzy compensation",
            default_experiment: (0.0, 0.6, SlidingFuzzyParams::default().sample_period),
        },
        fmi2_export::variables! {
            inputs FuzzyInputs {
                0 "x"  [pos[0]] "m"   [-1.0, 1.0]     "tool vibration along x (about the static deflection)";
                1 "y"  [pos[1]] "m"   [-1.0, 1.0]     "tool vibration along y";
                2 "vx" [vel[0]] "m/s" [-1e3, 1e3]     "tool velocity along x";
                3 "vy" [vel[1]] "m/s" [-1e3, 1e3]     "tool velocity along y";
            }
            outputs ControllerOutputs {
                discrete 10 "u_x"     [u[0]]           "N" [] "damper force command along x (held between samples)";
                discrete 11 "u_y"     [u[1]]           "N" [] "damper force command along y";
                discrete 12 "s_x"     [s[0]]           "1"  [] "sliding variable of the x channel (normalised)";
                discrete 13 "s_y"     [s[1]]           "1"  [] "sliding variable of the y channel";
                discrete 14 "j_hat_x" [j_hat[0]]       "1"  [] "model term j-hat of the x channel (normalised)";
                discrete 15 "j_hat_y" [j_hat[1]]       "1"  [] "model term j-hat of the y channel";
                discrete 16 "h_hat_x" [h_hat[0]]       "1"  [] "input gain h-hat of the x channel (normalised, nominal 1)";
                discrete 17 "h_hat_y" [h_hat[1]]       "1"  [] "input gain h-hat of the y channel";
                discrete 18 "e_m_x"   [model_error[0]] "1"  [] "last modelling error of the x channel (normalised)";
                discrete 19 "e_m_y"   [model_error[1]] "1"  [] "last modelling error of the y channel";
                discrete 20 "updates_x" [updates[0]]   "1"  [] "learning updates outside the dead zone, x channel";
                discrete 21 "updates_y" [updates[1]]   "1"  [] "learning updates outside the dead zone, y channel";
            }
            parameters SlidingFuzzyParams {
                1   "mode"             [enum mode]          ""      []              "controller of both channels";
                100 "Ts"               [sample_period]      "s"     [1e-7, 1.0]     "sample period T";
                101 "u_max"            [force_limit]        "N"     [1e-6, 1e9]     "force limit of the damper";
                102 "sigma"            [sigma]              "1"      [0.0, 100.0]    "sliding gain sigma (normalised units)";
                103 "k1"               [k1]                 "1"      [-2.0, 2.0]     "s(k) = e(k) + k1 e(k-1) + k2 e(k-2)";
                104 "k2"               [k2]                 "1"      [-1.0, 1.0]     "second coefficient of the sliding surface";
                105 "Omega"            [learning_rate]      "1"      [1e-9, 1.0]     "learning rate Omega_1 = Omega_2";
                106 "beta"             [dead_zone]          "1"      [1.0, 1e6]      "dead-zone parameter beta_1 = beta_2 (> 1)";
                107 "fou_ratio"        [fou_ratio]          "1"      [1e-6, 1.0]     "lower/upper width of the type-2 sets (1: no footprint of uncertainty)";
                108 "h_min"            [h_min]              "1"      [1e-9, 1e9]     "floor of h-hat (normalised)";
                109 "X_x"              [position_scale[0]]  "m"     [1e-12, 1.0]    "position normalisation, x (error in [-2, 2] X)";
                110 "X_y"              [position_scale[1]]  "m"     [1e-12, 1.0]    "position normalisation, y";
                111 "V_x"              [velocity_scale[0]]  "m/s"   [1e-12, 1e3]    "velocity normalisation, x";
                112 "V_y"              [velocity_scale[1]]  "m/s"   [1e-12, 1e3]    "velocity normalisation, y";
                113 "m_x"              [mass[0]]            "kg"    [1e-9, 1e9]     "nominal mass, x";
                114 "m_y"              [mass[1]]            "kg"    [1e-9, 1e9]     "nominal mass, y";
                115 "c_x"              [damping[0]]         "N.s/m" [0.0, 1e12]     "nominal damping, x";
                116 "c_y"              [damping[1]]         "N.s/m" [0.0, 1e12]     "nominal damping, y";
                117 "k_x"              [stiffness[0]]       "N/m"   [1e-9, 1e15]    "nominal stiffness, x";
                118 "k_y"              [stiffness[1]]       "N/m"   [1e-9, 1e15]    "nominal stiffness, y";
                120 "Kp_x"             [pid_x.kp]           "N/e"      [-1e12, 1e12]   "D-PID proportional gain, x [N per error unit]";
                121 "Ki_x"             [pid_x.ki]           "N/(e.s)"      [-1e12, 1e12]   "D-PID integral gain, x [N per error unit per s]";
                122 "Kd_x"             [pid_x.kd]           "N.s/e"      [-1e12, 1e12]   "D-PID derivative gain, x [N.s per error unit]";
                123 "Kp_y"             [pid_y.kp]           "N/e"      [-1e12, 1e12]   "D-PID proportional gain, y";
                124 "Ki_y"             [pid_y.ki]           "N/(e.s)"      [-1e12, 1e12]   "D-PID integral gain, y";
                125 "Kd_y"             [pid_y.kd]           "N.s/e"      [-1e12, 1e12]   "D-PID derivative gain, y";
                126 "pid_error_scale"  [pid_error_scale]    "e/m"      [1e-12, 1e12]   "D-PID error unit: e = -scale * position (1000: mm)";
                0   "karnik_mendel"    [karnik_mendel]      ""      []              "Karnik-Mendel type reduction instead of the closed form (Eq. 25)";
                2   "nominal_model"    [enum nominal_model] ""      []              "what the sliding-mode controllers know of A_dis (Eq. 22): exact_zoh, euler (j = p + T v) or identity (j = p)";
                1   "computation_delay" [computation_delay] ""      []              "one sample of computation delay: the command of sample k acts from t_(k+1) (with one-step prediction)";
            }
        },
    )
    // what a step costs, as `internal_steps` counts it: for masters, in modelDescription.xml
    .work_bound("Ts", 1.0)
});

fmi2_export::adapter! {
    model: SlidingModeFuzzyController,
    table: TABLE as Table<SlidingFuzzyParams, FuzzyInputs, ControllerOutputs>,
    parameters: |m| m.ctrl.params(),
    input_errors: SlidingFuzzyError::Input,
}

/// The FMU model: the controller core with its clock.
#[derive(Clone, Serialize, Deserialize)]
pub struct SlidingModeFuzzyController {
    ctrl: SlidingFuzzy,
}

impl SlidingModeFuzzyController {
    /// The controller core (its channels hold the learned fuzzy weights).
    pub fn controller(&self) -> &SlidingFuzzy {
        &self.ctrl
    }
}

impl Fmi2Model for SlidingModeFuzzyController {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = TABLE.read_parameters(values)?;
        let ctrl = SlidingFuzzy::new(&p).map_err(|e| e.to_string())?;
        Ok(SlidingModeFuzzyController { ctrl })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.ctrl.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
        let FuzzyInputs { pos, vel } = TABLE.read_inputs(v).map_err(StepError::Error)?;
        match self.ctrl.step(t, h, pos, vel) {
            Ok(o) => {
                TABLE.write_outputs(&o, v);
                Ok(())
            }
            Err(e) => Err(Self::step_error(e)),
        }
    }

    /// One sample per sample period in the step.
    fn internal_steps(&self, h: f64) -> f64 {
        h / self.ctrl.params().sample_period + 1.0
    }

    fn validate_state(&self) -> Result<(), String> {
        self.ctrl.validate_state()
    }
}
