//! # AfracController FMU adapter (seed 001)
//!
//! Translates between the AFrAC controller core ([`afrac_control`]: [`AfracParams`],
//! [`Afrac::sample`], [`AfracOutputs`]) and the FMI variables of `AfracController.fmu`,
//! declared once in [`TABLE`]. The cdylib `AfracController` (`fmu-afrac-controller/cdylib/`) exports it.
//!
//! # Timing
//!
//! The controller samples at `t_k = t_start + kτ` (`t_start`: the first communication point,
//! `τ` = `Ts`). `fmi2DoStep(t, h)` takes the sample instants in `[t, t + h)` (to a margin of
//! `10⁻⁶τ`) with the inputs `x`, `v` set before the call, and holds the commands of the last
//! sample until the next one (zero-order hold). The shipped system `Afrac.ssp` steps
//! Gauss–Seidel controller → plant with `h = τ`: the controller reads the plant's state at
//! `t_k` and the plant integrates `[t_k, t_{k+1})` with the commands computed from it, the loop
//! of `studies::afrac::run`. The order β(t) of the stepwise
//! schedule is a function of `t − t_start = kτ`.
//!
//! With `h = Mτ` (M > 1) the M samples of a step all see the inputs of the step start; with
//! `h < τ` a step may hold no sample and the outputs stay as they were.
//!
//! The convolution memory `Q∗ε`, the measured history, the reference model and its history,
//! every fractional integrator (one per order, Oustaloup states), the bumpless offsets and the
//! clock are all in the serialized FMU state.

use afrac_control::{Afrac, AfracError, AfracOutputs, AfracParams};
use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The controller's inputs: the measured tool displacement and velocity, held over a step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AfracInputs {
    /// Displacement x [mm].
    pub x: f64,
    /// Velocity ẋ [mm/s].
    pub v: f64,
}

/// Sample instants closer than this fraction of τ to the end of a step belong to the next.
const MARGIN: f64 = 1e-6;

/// The variable table of `AfracController.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<AfracParams, AfracInputs, AfracOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "AfracController",
            identifier: "AfracController",
            description: "Adjustable fractional-order adaptive control (AFrAC) of spindle speed and feed against single-delay regenerative chatter: reference delay model, convolution memory, Oustaloup integrators of order beta (seed 001)",
            default_experiment: (0.0, 3.0, AfracParams::default().sample_period),
        },
        fmi2_export::variables! {
            inputs AfracInputs {
                0 "x" [x] "mm"   [-1e5, 1e5] "measured tool displacement x";
                1 "v" [v] "mm/s" [-1e8, 1e8] "measured tool velocity";
            }
            outputs AfracOutputs {
                discrete 10 "spindle_speed" [spindle_speed] "rpm"    [] "spindle speed command N = 60/(T_ref + h), limited to [speed_min, speed_max] (held between samples)";
                discrete 11 "feed"          [feed]          "mm/rev" [] "feed command f0 + delta_f, limited to [feed_min, feed_max]";
                discrete 12 "beta"          [beta]          "1"       [] "order of the fractional integrators at the last sample";
                discrete 13 "eps1"          [eps1]          "mm"     [] "error x - y1 against the reference delay model";
                discrete 14 "eps2"          [eps2]          "mm/s"   [] "error v - y2";
                discrete 15 "h"             [h]             "s"      [] "delay offset h = 60/N - T_ref before the speed limits";
                discrete 16 "delta_feed"    [delta_feed]    "mm/rev" [] "feed change delta_f before the feed limits";
                discrete 17 "G"             [g]             "G"       [] "adaptation signal G = P12 z1 + P22 z2 (z = eps + Q*eps)";
            }
            parameters AfracParams {
                100 "natural_frequency" [natural_frequency] "Hz"     [1e-3, 1e5]    "natural frequency f_n of the tool mode (reference model)";
                101 "damping_ratio"     [damping_ratio]     "1"       [0.0, 10.0]    "damping ratio zeta (reference model)";
                102 "kappa"             [kappa]             "1/mm"   [1e-9, 1e3]    "lumped cutting stiffness a2/(omega_n^2 w) at the initial feed";
                103 "depth"             [depth]             "mm"     [1e-6, 1e3]    "depth of cut w (a2 of the reference model)";
                104 "force_exponent"    [force_exponent]    "1"       [1e-3, 0.999]  "force exponent Y (the feed law divides by Y - 1)";
                105 "edge_angle"        [edge_angle]        "deg"    [1e-3, 90.0]   "cutting edge angle K";
                106 "initial_speed"     [initial_speed]     "rpm"    [1.0, 1e5]     "initial spindle speed N0";
                107 "initial_feed"      [initial_feed]      "mm/rev" [1e-6, 100.0]  "initial feed f0";
                108 "reference_speed"   [reference_speed]   "rpm"    [1.0, 1e5]     "speed of the reference delay model, 60/T_ref (must be stable at depth)";
                109 "reference_y0"      [reference_y0]      "mm"     [-1e3, 1e3]    "initial displacement of the reference model (0: at rest)";
                110 "lambda_feed"       [lambda_feed]       "lambda_2"       [0.0, 1e14]    "feed adaptation gain lambda_2 (Eq. 20)";
                111 "lambda_speed"      [lambda_speed]      "lambda_3"       [0.0, 1e14]    "speed adaptation gain lambda_3 (Eq. 21)";
                112 "Ts"                [sample_period]     "s"      [1e-6, 1e-2]   "sample period tau";
                1   "beta_mode"         [enum schedule.mode] ""      []             "how the order beta of the integrators is chosen";
                113 "beta_fixed"        [schedule.beta]     "1"       [1.0, 2.0]     "order beta (beta_mode = fixed)";
                114 "beta0"             [schedule.beta0]    "1"       [1.0, 2.0]     "initial order beta0 (stepwise, Table 5: 1.9)";
                115 "beta1"             [schedule.betas[0]] "1"       [1.0, 2.0]     "order from t1 (stepwise)";
                116 "beta2"             [schedule.betas[1]] "1"       [1.0, 2.0]     "order from t2 (stepwise)";
                117 "beta3"             [schedule.betas[2]] "1"       [1.0, 2.0]     "order from t3 (stepwise)";
                118 "beta4"             [schedule.betas[3]] "1"       [1.0, 2.0]     "order from t4 (stepwise)";
                119 "t1"                [schedule.times[0]] "s"      [-1e9, 1e9]    "switch time t1 (stepwise, from the start)";
                120 "t2"                [schedule.times[1]] "s"      [-1e9, 1e9]    "switch time t2";
                121 "t3"                [schedule.times[2]] "s"      [-1e9, 1e9]    "switch time t3";
                122 "t4"                [schedule.times[3]] "s"      [-1e9, 1e9]    "switch time t4";
                123 "t_end"             [schedule.end]      "s"      [-1e9, 1e9]    "from this time beta = 1 (stepwise)";
                0   "bumpless"          [bumpless]          ""       []             "bumpless switching of the orders (the commands stay continuous)";
                124 "omega_b"           [band.omega_b]      "rad/s"  [1e-9, 1e9]    "lower edge of the Oustaloup band";
                125 "omega_h"           [band.omega_h]      "rad/s"  [1e-9, 1e9]    "upper edge of the Oustaloup band";
                2   "oustaloup_n"       [band.n]            ""       [1, 4]         "Oustaloup order N (2N + 1 zero/pole pairs)";
                126 "speed_min"         [speed_min]         "rpm"    [1.0, 1e5]     "lower limit of the speed command";
                127 "speed_max"         [speed_max]         "rpm"    [1.0, 1e5]     "upper limit of the speed command";
                128 "feed_min"          [feed_min]          "mm/rev" [1e-6, 100.0]  "lower limit of the feed command";
                129 "feed_max"          [feed_max]          "mm/rev" [1e-6, 100.0]  "upper limit of the feed command";
            }
        },
    )
    // what a step costs, as `internal_steps` counts it: for masters, in modelDescription.xml
    .work_bound("Ts", 1.0)
});

fmi2_export::adapter! {
    model: AfracController,
    table: TABLE as Table<AfracParams, AfracInputs, AfracOutputs>,
    parameters: |m| m.ctrl.params(),
    input_errors: AfracError::Input,
}

/// The FMU model: the controller core with the time of its first sample.
#[derive(Clone, Serialize, Deserialize)]
pub struct AfracController {
    ctrl: Afrac,
    /// The first communication point (sample 0), set by the first step.
    t_start: Option<f64>,
}

impl AfracController {
    /// The controller core.
    pub fn controller(&self) -> &Afrac {
        &self.ctrl
    }

    /// The number of samples due in `[t, t + h)`.
    fn due(&self, t: f64, h: f64) -> f64 {
        let tau = self.ctrl.params().sample_period;
        let base = self.t_start.unwrap_or(t);
        let end = t + h - MARGIN * tau;
        // sample k is due while base + kτ < end: k < (end − base)/τ
        ((end - base) / tau).ceil().max(0.0) - self.ctrl.next_sample_time() / tau
    }
}

impl Fmi2Model for AfracController {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = TABLE.read_parameters(values)?;
        let ctrl = Afrac::new(&p).map_err(|e| e.to_string())?;
        Ok(AfracController { ctrl, t_start: None })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.ctrl.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
        let AfracInputs { x, v: vel } = TABLE.read_inputs(v).map_err(StepError::Error)?;
        let due = self.due(t, h);
        // more samples than the step can hold: a clock that does not belong to this run
        if !(due.is_finite() && due <= self.internal_steps(h) + 1.0) {
            return Err(StepError::Error(format!(
                "the controller's clock (next sample at {} s after {:?}) does not match the step [{t}, {} + {h})",
                self.ctrl.next_sample_time(),
                self.t_start,
                t
            )));
        }
        let saved = self.ctrl.clone();
        for _ in 0..due.round().max(0.0) as u64 {
            if let Err(e) = self.ctrl.sample(x, vel) {
                self.ctrl = saved;
                return Err(Self::step_error(e));
            }
        }
        self.t_start.get_or_insert(t);
        TABLE.write_outputs(&self.ctrl.outputs(), v);
        Ok(())
    }

    /// At most `h/τ + 1` samples in a step.
    fn internal_steps(&self, h: f64) -> f64 {
        h / self.ctrl.params().sample_period + 1.0
    }

    fn validate_state(&self) -> Result<(), String> {
        if self.t_start.is_some_and(|t| !t.is_finite()) {
            return Err("the start time is not finite".into());
        }
        self.ctrl.validate_state()
    }
}
