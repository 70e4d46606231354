//! # TurningProcess FMU adapter (seed 001)
//!
//! Translates between the turning process core ([`turning_process`]: [`TurningParams`],
//! [`TurningInputs`], [`TurningOutputs`]) and the FMI variables of `TurningProcess.fmu`,
//! declared once in [`TABLE`]. The cdylib `TurningProcess` (`fmu-turning-process/cdylib/`) exports its
//! 34 `fmi2*` functions.
//!
//! `fmi2DoStep(t, h)` sets the core's clock to the master's `t` (the disturbance pulse is timed
//! on it) and takes `n = ⌈h/max_step⌉` RK4 steps of `h/n` with the spindle speed and the feed
//! held. Outputs at `t` are those of the state at `t`; no output depends directly on an input
//! (the chip and force outputs are evaluated with the inputs of the last step).

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;
use turning_process::{TurningError, TurningInputs, TurningOutputs, TurningParams, TurningProcess};

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The variable table of `TurningProcess.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<TurningParams, TurningInputs, TurningOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "TurningProcess",
            identifier: "TurningProcess",
            description: "Orthogonal turning with regenerative chatter: one-mode tool, nonlinear chip force, delay by workpiece angle (seed 001)",
            default_experiment: (0.0, 1.0, 1e-4),
        },
        fmi2_export::variables! {
            inputs TurningInputs {
                0 "spindle_speed" [spindle_speed] "rpm"    [0.0, 1e6]   "spindle speed N, held over the step";
                1 "feed"          [feed]          "mm/rev" [0.0, 100.0] "feed f, held over the step";
            }
            outputs TurningOutputs {
                10 "x"     [x]     "mm"   [] "tool displacement from the static equilibrium";
                11 "v"     [v]     "mm/s" [] "tool velocity";
                12 "q"     [force] "mm"   [] "dynamic cutting force as the static deflection it causes, dF cos(alpha)/k";
                13 "chip"  [chip]  "mm"   [] "chip thickness s";
                14 "delay" [delay] "s"    [] "regenerative delay: time since the surface now cut was left (0 in the first revolution)";
                15 "angle" [angle] "rad"  [] "workpiece angle mod 2 pi";
            }
            parameters TurningParams {
                100 "natural_frequency" [natural_frequency] "Hz"     [1e-6, 1e5]   "natural frequency f_n of the tool mode";
                101 "damping_ratio"     [damping_ratio]     "1"       [0.0, 10.0]   "damping ratio zeta";
                102 "kappa"             [kappa]             "1/mm"   [0.0, 1e3]    "lumped cutting stiffness a2/(omega_n^2 w) at the reference feed";
                103 "reference_feed"    [reference_feed]    "mm/rev" [1e-9, 100.0] "feed at which kappa is given";
                104 "force_exponent"    [force_exponent]    "1"       [1e-6, 2.0]   "force exponent Y";
                105 "edge_angle"        [edge_angle]        "deg"    [1e-6, 90.0]  "cutting edge angle K";
                106 "process_damping"   [process_damping]   "rpm.s"  [0.0, 1e6]    "process damping constant C (0: none)";
                107 "depth"             [depth]             "mm"     [0.0, 1e3]    "depth of cut w";
                108 "pulse_time"        [pulse_time]        "s"      [-1e9, 1e9]   "start of the disturbance force pulse";
                109 "pulse_duration"    [pulse_duration]    "s"      [0.0, 1e3]    "duration of the pulse";
                110 "pulse_fraction"    [pulse_fraction]    "1"       [-1e3, 1e3]   "pulse size as a fraction of the static force P w s0^Y";
                111 "max_step"          [max_step]          "s"      [1e-7, 1e-2]  "largest internal RK4 step";
            }
        },
    )
    // what a step costs, as `internal_steps` counts it: for masters, in modelDescription.xml
    .work_bound("max_step", 1.0)
});

fmi2_export::adapter! {
    model: TurningProcessFmu,
    table: TABLE as Table<TurningParams, TurningInputs, TurningOutputs>,
    parameters: |m| m.process.params(),
    input_errors: TurningError::Input,
}

/// The FMU model: the turning process core.
#[derive(Clone, Serialize, Deserialize)]
pub struct TurningProcessFmu {
    process: TurningProcess,
}

impl TurningProcessFmu {
    /// The process core.
    pub fn process(&self) -> &TurningProcess {
        &self.process
    }
}

impl Fmi2Model for TurningProcessFmu {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = TABLE.read_parameters(values)?;
        let process = TurningProcess::new(&p).map_err(|e| e.to_string())?;
        Ok(TurningProcessFmu { process })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.process.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
        let inputs = TABLE.read_inputs(v).map_err(StepError::Error)?;
        let saved = self.process.clone();
        self.process.set_time(t);
        if let Err(e) = self.process.step(h, &inputs) {
            self.process = saved;
            return Err(Self::step_error(e));
        }
        TABLE.write_outputs(&self.process.outputs(), v);
        Ok(())
    }

    /// `⌈h/max_step⌉ ≤ h/max_step + 1` RK4 steps.
    fn internal_steps(&self, h: f64) -> f64 {
        h / self.process.params().max_step + 1.0
    }

    fn validate_state(&self) -> Result<(), String> {
        self.process.validate_state()
    }
}
