//! # FrohMracController FMU adapter (seed 004)
//!
//! Translates between the controller core ([`froh_mrac::mrac`]: [`MracParams`],
//! [`FrohMrac::step`]) and the FMI variables of `FrohMracController.fmu`, declared once in
//! [`TABLE`]. The cdylib `FrohMracController` (`fmu-froh-mrac-controller/cdylib/`) exports it.
//!
//! # Timing, the hold inside the FMU, and the communication step
//!
//! The controller samples at `t_k = t_start + kT` (`t_start`: the first communication point).
//! `fmi2DoStep(t, h)` takes the sample instants in `[t, t+h)` with the inputs `F_p`, `F_ref`
//! set before the call, and generates the fractional-order hold
//! `u(s) = u_k + β(u_k − u_{k−1})(s − t_k)/T` between samples. Its outputs after the step are
//! the hold over `[t, t+h)` as its mean `f_c` and slope `f_c_rate`: in Gauss–Seidel order
//! controller → plant, the plant integrates exactly that ramp over the same step. The master's
//! communication step must therefore put every sample instant on a communication point:
//! **h = T/M for an integer M ≥ 1** (the shipped system uses M = 20; with `f_c_rate` connected
//! the samples do not depend on M, and M only sets the output grid). A step that contains a
//! sample instant in its interior still runs (the sample uses the inputs of the step start) but
//! `f_c` and `f_c_rate` then describe a broken line by one ramp. With `f_c_rate` not connected
//! the plant holds the step mean: the staircase approximation of the ramp, second order in h.
//!
//! The RLS estimate, its covariance, the RST controller, the past signals, the hold and the
//! reference model's state are all in the serialized FMU state.

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use froh_mrac::{ForceError, FrohMrac, MracOutputs, MracParams};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The controller's inputs, held over a communication step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MracInputs {
    /// Measured cutting force [N].
    pub y: f64,
    /// Reference force [N].
    pub r: f64,
}

impl Default for MracInputs {
    /// The paper's reference force 1.2 kN (so the system runs without a reference source).
    fn default() -> Self {
        MracInputs { y: 0.0, r: 1200.0 }
    }
}

/// The variable table of `FrohMracController.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<MracParams, MracInputs, MracOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "FrohMracController",
            identifier: "FrohMracController",
            description: "Adaptive model-following force control with a fractional-order hold: RLS, RST design, FROH ramp between samples (seed 004)",
            default_experiment: (0.0, 12.0, MracParams::default().sample_period / 20.0),
        },
        fmi2_export::variables! {
            inputs MracInputs {
                0 "F_p"   [y] "N" [-1e9, 1e9] "measured cutting force";
                1 "F_ref" [r] "N" [-1e9, 1e9] "reference force";
            }
            outputs MracOutputs {
                10 "f_c"               [feed_command]      "mm/s"   [] "feed-rate command: mean of the FROH hold over the last step";
                discrete 11 "f_c_rate" [feed_command_rate] "mm/s2"  [] "slope of the FROH hold (constant between samples)";
                12 "f_hold"            [feed_hold]         "mm/s"   [] "FROH hold at the end of the last step";
                discrete 13 "u_k"      [feed_sample]       "mm/s"   [] "last sample of the control law";
                14 "F_m"               [reference_force]   "N"      [] "reference-model force (continuous model driven by the FROH of F_ref)";
                discrete 15 "a_hat"    [a_hat]             "1"       [] "RLS estimate of the pole a";
                discrete 16 "b0_hat"   [b0_hat]            "N.s/mm" [] "RLS estimate of b0";
                discrete 17 "b1_hat"   [b1_hat]            "N.s/mm" [] "RLS estimate of b1";
                discrete 18 "zero_hat" [zero_hat]          "1"       [] "estimated plant zero -b1/b0";
                discrete 19 "design_skips" [design_skips]  "1"       [] "samples at which the estimated zero was unstable and the previous controller kept";
            }
            parameters MracParams {
                100 "beta"           [beta]           "1"       [-1.0, 1.0]     "FROH gain (0: ZOH, 1: FOH)";
                101 "Ts"             [sample_period]  "s"      [1e-6, 100.0]   "sample period T (one spindle period)";
                102 "zeta"           [zeta]           "1"       [1e-3, 10.0]    "reference-model damping ratio";
                103 "omega_n"        [omega_n]        "rad/s"  [1e-6, 1e6]     "reference-model natural frequency";
                104 "lambda"         [lambda]         "1"       [1e-3, 1.0]     "RLS forgetting factor";
                105 "p0"             [p0]             "1"       [1e-12, 1e12]   "initial RLS covariance p0 I";
                106 "trace_max"      [trace_max]      "1"       [1e-12, 1e300]  "trace limit of the RLS covariance";
                107 "gain_estimate"  [gain_estimate]  "N.s/mm" [1e-12, 1e12]   "initial model: process gain";
                108 "tau_estimate"   [tau_estimate]   "s"      [1e-9, 100.0]   "initial model: chip time constant";
                0   "adapt"          [adapt]          ""       []              "RLS on (off: keep the initial model)";
                1   "estimate_b1_at_zoh" [estimate_b1_at_zoh] "" []            "at beta = 0 estimate b1 too (three parameters) instead of the ZOH model's (a, b0)";
            }
        },
    )
    // what a step costs, as `internal_steps` counts it (two per sample period): for masters, in
    // modelDescription.xml, counted in sample periods
    .work_bound_scaled("Ts", 2.0, 2.0)
});

fmi2_export::adapter! {
    model: FrohMracController,
    table: TABLE as Table<MracParams, MracInputs, MracOutputs>,
    parameters: |m| m.ctrl.params(),
    input_errors: ForceError::Input,
}

/// The FMU model: the controller core with its clock.
#[derive(Clone, Serialize, Deserialize)]
pub struct FrohMracController {
    ctrl: FrohMrac,
}

impl FrohMracController {
    /// The controller core.
    pub fn controller(&self) -> &FrohMrac {
        &self.ctrl
    }
}

impl Fmi2Model for FrohMracController {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = TABLE.read_parameters(values)?;
        let ctrl = FrohMrac::new(&p).map_err(|e| e.to_string())?;
        Ok(FrohMracController { ctrl })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.ctrl.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
        let MracInputs { y, r } = TABLE.read_inputs(v).map_err(StepError::Error)?;
        let saved = self.ctrl.clone();
        match self.ctrl.step(t, h, y, r) {
            Ok(o) => {
                TABLE.write_outputs(&o, v);
                Ok(())
            }
            Err(e) => {
                self.ctrl = saved;
                Err(Self::step_error(e))
            }
        }
    }

    /// One sample per sample period in the step, plus the pieces between them: the work bound of
    /// the table.
    fn internal_steps(&self, h: f64) -> f64 {
        2.0 * h / self.ctrl.params().sample_period + 2.0
    }

    fn validate_state(&self) -> Result<(), String> {
        self.ctrl.validate_state()
    }
}
