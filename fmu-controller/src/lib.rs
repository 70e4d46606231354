//! # ChatterController FMU adapter
//!
//! Translates between the controller core ([`chatter_control`]: [`ControllerParams`],
//! [`Controller::sample`]) and the FMI variables of `ChatterController.fmu`, declared once in
//! [`TABLE`], and adds the sample clock. The shared export layer (`fmi2-export`) does
//! everything else; the cdylib `ChatterController` (`fmu-controller/cdylib/`) exports it.
//!
//! # Timing and feedthrough
//!
//! The controller samples at `t_s = t_start + k·T` (`t_start`: the first communication point).
//! `fmi2DoStep(t, h)` takes every sample instant in `[t, t + h)`, each with the inputs `y, r`
//! set before the call (held over the step; no input interpolation), so a step `h = n·T` runs
//! exactly `n` samples; other step sizes run the samples that fall inside (possibly none).
//! The outputs at `t + h` are those of the last sample taken, i.e. the command being applied
//! at `t + h` was computed from the input held over the step. The outputs at a communication
//! point therefore do **not** depend on the inputs set at that point: no direct feedthrough,
//! declared as empty dependencies in `ModelStructure`. Stepped with `h = T`, the response from
//! `y(t_k)` to `u(t_{k+1})` is `e^{−iωT}C(e^{iωT})` ([`crate::Controller::sampled_response`]).
//! Before the first step the outputs are zero.

use chatter_control::{Controller, ControllerOutput, ControllerParams};
use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, Severity, StepError, Table, Values};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The controller's inputs, held over a communication step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControllerInputs {
    /// Measured tip displacement \[m\].
    pub y: f64,
    /// Reference displacement \[m\].
    pub r: f64,
}

/// The variable table of `ChatterController.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<ControllerParams, ControllerInputs, ControllerOutput>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "ChatterController",
            identifier: "ChatterController",
            description: "Active chatter controllers for milling: off, PID, FOPID, ADRC-FOPID (seed 000)",
            default_experiment: (0.0, 0.1, ControllerParams::default().ts),
        },
        fmi2_export::variables! {
            inputs ControllerInputs {
                0 "y" [y] "m" [] "measured tip displacement";
                1 "r" [r] "m" [] "reference displacement";
            }
            outputs ControllerOutput {
                discrete 2 "u"  [u]  "N"    [] "actuator force command, saturated at +-u_max";
                discrete 3 "e"  [e]  "m"    [] "tracking error r - y of the last sample";
                discrete 4 "z1" [z1] "m"    [] "ESO displacement estimate";
                discrete 5 "z2" [z2] "m/s"  [] "ESO velocity estimate";
                discrete 6 "z3" [z3] "m/s2" [] "ESO total-disturbance estimate (acceleration)";
                0 "saturated" [saturated] "" [] "the unsaturated command exceeded u_max at the last sample";
            }
            parameters ControllerParams {
                0  "structure"    [enum structure]    ""        []              "controller structure";
                10 "u_max"        [u_max]             "N"       [0.0, 1e9]      "actuator command limit";
                11 "Ts"           [ts]                "s"       [1e-9, 1.0]     "sample period";
                tunable 20 "pid.kp"       [pid.kp]            "N/m"     [-1e12, 1e12]   "PID proportional gain";
                tunable 21 "pid.ki"       [pid.ki]            "N/(m.s)" [0.0, 1e12]     "PID integral gain";
                tunable 22 "pid.kd"       [pid.kd]            "N.s/m"   [-1e12, 1e12]   "PID derivative gain";
                23 "pid.tf"       [pid.tf]            "s"       [0.0, 1.0]      "PID derivative filter time constant (0: none)";
                tunable 30 "fopid.kp"     [fopid.kp]          "N/m"     [-1e12, 1e12]   "proportional gain (u in N)";
                tunable 31 "fopid.ki"     [fopid.ki]          "N/(m.s^lambda)"        [0.0, 1e12]     "fractional integral gain (u in N; unit N/(m s^lambda))";
                tunable 32 "fopid.kd"     [fopid.kd]          "N.s^mu/m"        [-1e12, 1e12]   "fractional derivative gain (u in N; unit N s^mu/m)";
                33 "fopid.lambda" [fopid.lambda]      "1"        [0.0, 3.0]      "integral order lambda";
                34 "fopid.mu"     [fopid.mu]          "1"        [0.0, 3.0]      "derivative order mu";
                tunable 40 "adrc.kp"      [adrc.fopid.kp]     "1/s2"    [-1e12, 1e12]   "proportional gain (u0 in m/s2)";
                tunable 41 "adrc.ki"      [adrc.fopid.ki]     "s^(lambda-2)"        [0.0, 1e12]     "fractional integral gain (u0 in m/s2; unit s^(lambda-2))";
                tunable 42 "adrc.kd"      [adrc.fopid.kd]     "s^(mu-2)"        [-1e12, 1e12]   "fractional derivative gain (u0 in m/s2; unit s^(mu-2))";
                43 "adrc.lambda"  [adrc.fopid.lambda] "1"        [0.0, 3.0]      "integral order lambda";
                44 "adrc.mu"      [adrc.fopid.mu]     "1"        [0.0, 3.0]      "derivative order mu";
                45 "adrc.omega_o" [adrc.omega_o]      "rad/s"   [1e-3, 1e9]     "ESO bandwidth (error poles at -omega_o)";
                46 "adrc.b0"      [adrc.b0]           "1/kg"    [1e-9, 1e9]     "nominal input gain 1/Mw";
                47 "adrc.td_r"    [adrc.td_r]         "m/s2"    [1e-12, 1e12]   "TD speed factor r0";
                48 "adrc.td_h"    [adrc.td_h]         "s"       [1e-9, 1.0]     "TD filter factor h0";
                1  "fractional.method"        [enum fractional.method]   ""      []            "realisation of the fractional part";
                2  "fractional.memory_length" [fractional.memory_length] ""      [1, 1e5]      "Grunwald-Letnikov short-memory length L (samples)";
                60 "fractional.omega_b"       [fractional.omega_b]       "rad/s" [1e-6, 1e9]   "Oustaloup band, lower edge";
                61 "fractional.omega_h"       [fractional.omega_h]       "rad/s" [1e-6, 1e9]   "Oustaloup band, upper edge";
                3  "fractional.order"         [fractional.order]         ""      [1, 50]       "Oustaloup order N (2N+1 sections)";
            }
        },
    )
    // what a step costs, as `internal_steps` counts it: for masters, in modelDescription.xml
    .work_bound_scaled("Ts", SAMPLE_COST, SAMPLE_COST)
});

/// What one controller sample counts in [`Fmi2Model::internal_steps`]: its worst case, with the
/// longest Grünwald–Letnikov memory. The partitioned tail costs about `L/B` complex
/// multiply–adds per sample and operator, linear in `L`: the audit measured 2.2 s per step of
/// 10⁴ samples at `L = 10⁶` (220 µs a sample), 61 h per simulated second within the declared
/// bounds. `L` is bounded to 10⁵ now (22 µs a sample) and a sample counts 100 internal steps, so
/// that a call of at most `MAX_INTERNAL_STEPS_PER_CALL` = 10⁷ (10⁵ samples) takes seconds, not
/// hours, at any legal parameter values.
pub const SAMPLE_COST: f64 = 100.0;

fmi2_export::adapter! {
    model: ChatterController,
    table: TABLE as Table<ControllerParams, ControllerInputs, ControllerOutput>,
    parameters: |m| m.ctrl.params(),
}

/// The FMU model: a [`Controller`] plus its sample clock.
#[derive(Clone, Serialize, Deserialize)]
pub struct ChatterController {
    ctrl: Controller,
    ts: f64,
    t_base: Option<f64>,
    k_next: u64,
    last: ControllerOutput,
    reported_saturation: bool,
}

impl ChatterController {
    /// The parameters of the running controller.
    pub fn params(&self) -> &ControllerParams {
        self.ctrl.params()
    }
}

impl Fmi2Model for ChatterController {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = TABLE.read_parameters(values)?;
        let ctrl = Controller::new(&p)?;
        Ok(ChatterController {
            ctrl,
            ts: p.ts,
            t_base: None,
            k_next: 0,
            last: ControllerOutput::default(),
            reported_saturation: false,
        })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.last, v);
    }

    fn do_step(&mut self, v: &mut Values, t: f64, h: f64, log: &mut dyn ModelLog) -> Result<(), StepError> {
        let ControllerInputs { y, r } = TABLE.read_inputs(v).map_err(StepError::Error)?;
        let base = *self.t_base.get_or_insert(t);
        // Samples due before `t` are not caught up one by one: in a run the previous step took
        // them all; a clock that jumped ahead of the sample index (a restored or restarted
        // instance) continues from the first sample at or after `t`. The margin of one sample
        // leaves every ordinary step untouched by rounding.
        // (`⌈q⌉ > k + 1` exactly when `q > k + 1`: the ceiling, a library call on baseline
        // x86-64, is taken only when the clock did jump)
        let due = (t - base) / self.ts - 1e-6;
        if due > (self.k_next + 1) as f64 {
            self.k_next = due.ceil() as u64;
        }
        let end = t + h - 1e-6 * self.ts;
        while base + self.k_next as f64 * self.ts < end {
            self.last = self.ctrl.sample(y, r);
            self.k_next += 1;
            if self.last.saturated && !self.reported_saturation {
                self.reported_saturation = true;
                let ts = base + (self.k_next - 1) as f64 * self.ts;
                log.log(Severity::Info, &format!("command saturated at t = {ts} (further saturations not logged)"));
            }
        }
        self.update_outputs(v);
        Ok(())
    }

    /// The gains (`pid.*`, `fopid.*`, `adrc.*` kp, ki, kd) are tunable: a change between steps
    /// applies from the next sample on, with every state kept ([`Controller::retune`]).
    fn retune(&mut self, values: &Values) -> Result<(), String> {
        let p = TABLE.read_parameters(values)?;
        self.ctrl.retune(&p)
    }

    /// One controller sample per sample period `ts` in the step (and one more at most), each
    /// counted [`SAMPLE_COST`].
    fn internal_steps(&self, h: f64) -> f64 {
        SAMPLE_COST * (h / self.ts + 1.0)
    }

    /// The core's validation and invariants, and a sample clock that matches them.
    fn validate_state(&self) -> Result<(), String> {
        self.ctrl.validate_state()?;
        if self.ts.to_bits() != self.ctrl.params().ts.to_bits() {
            return Err("the sample period does not match the parameters".into());
        }
        if self.t_base.is_some_and(|t| !t.is_finite()) || self.k_next > u64::MAX / 2 {
            return Err("the sample clock is invalid".into());
        }
        let o = &self.last;
        if ![o.u, o.e, o.z1, o.z2, o.z3].iter().all(|x| x.is_finite()) {
            return Err("the last outputs are not finite".into());
        }
        Ok(())
    }
}
