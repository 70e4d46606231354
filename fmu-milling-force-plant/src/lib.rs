//! # MillingForcePlant FMU adapter (seed 004)
//!
//! Translates between the force plant core ([`milling_force_plant::plant`]: [`ForcePlantParams`],
//! [`ForcePlantInputs`], [`ForcePlantOutputs`]) and the FMI variables of
//! `MillingForcePlant.fmu`, declared once in [`TABLE`]. The cdylib `MillingForcePlant`
//! (`fmu-milling-force-plant/cdylib/`) exports its 34 `fmi2*` functions.
//!
//! `fmi2DoStep(t, h)` integrates the plant exactly over `[t, t+h)` with the command ramp
//! `f_c + f_c_rate·(s − t − h/2)` (`f_c`: the mean over the step; with `f_c_rate` unconnected,
//! 0, the command is held). The depth profile is evaluated at the master's time `t` (the plant's
//! clock is set to `t` before each step). Outputs at `t` are those of the state at `t`; no
//! output depends directly on an input.

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use milling_force_plant::{ForceError, ForcePlant, ForcePlantInputs, ForcePlantOutputs, ForcePlantParams};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The variable table of `MillingForcePlant.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<ForcePlantParams, ForcePlantInputs, ForcePlantOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "MillingForcePlant",
            identifier: "MillingForcePlant",
            description: "Milling force process: feed-rate command to cutting force through the CNC and chip lags, depth-of-cut profile (seed 004)",
            default_experiment: (0.0, 12.0, ForcePlantParams::default().spindle_period() / 20.0),
        },
        fmi2_export::variables! {
            inputs ForcePlantInputs {
                0 "f_c"      [feed_command]      "mm/s"  [-1e6, 1e6] "feed-rate command, mean over the communication step";
                1 "f_c_rate" [feed_command_rate] "mm/s2" [-1e9, 1e9] "slope of the feed-rate command within the step (0: held)";
            }
            outputs ForcePlantOutputs {
                10 "F_p" [force] "N"      [] "cutting force";
                11 "f_a" [feed]  "mm/s"   [] "actual feed rate of the table";
                12 "b"   [depth] "mm"     [] "axial depth of cut in force";
                13 "K_p" [gain]  "N.s/mm" [] "process gain K_c b S_t/(N n)";
            }
            parameters ForcePlantParams {
                100 "kc"             [kc]                "N/mm2" [1e-6, 1e6]  "specific cutting pressure K_c";
                0   "teeth"          [teeth]             ""      [1, 1000]    "number of teeth N";
                101 "spindle_speed"  [spindle_speed_rpm] "rpm"   [1e-3, 1e6]  "spindle speed";
                102 "immersion"      [immersion]         "1"      [0.0, 100.0] "immersion function S_t";
                103 "tau_s"          [tau_s]             "s"     [0.0, 10.0]  "CNC feed-drive time constant (0: ideal drive)";
                104 "tau_c"          [tau_c]             "s"     [1e-9, 100.0] "chip time constant";
                1   "depth.segments" [depth.segments]    ""      [1, 8]       "number of depth segments used";
                110 "depth.t1" [depth.t[0]] "s" [-1e9, 1e9] "start of segment 1";
                111 "depth.t2" [depth.t[1]] "s" [-1e9, 1e9] "start of segment 2";
                112 "depth.t3" [depth.t[2]] "s" [-1e9, 1e9] "start of segment 3";
                113 "depth.t4" [depth.t[3]] "s" [-1e9, 1e9] "start of segment 4";
                114 "depth.t5" [depth.t[4]] "s" [-1e9, 1e9] "start of segment 5";
                115 "depth.t6" [depth.t[5]] "s" [-1e9, 1e9] "start of segment 6";
                116 "depth.t7" [depth.t[6]] "s" [-1e9, 1e9] "start of segment 7";
                117 "depth.t8" [depth.t[7]] "s" [-1e9, 1e9] "start of segment 8";
                120 "depth.b1" [depth.b[0]] "mm" [0.0, 1e3] "axial depth of segment 1 (also before t1)";
                121 "depth.b2" [depth.b[1]] "mm" [0.0, 1e3] "axial depth of segment 2";
                122 "depth.b3" [depth.b[2]] "mm" [0.0, 1e3] "axial depth of segment 3";
                123 "depth.b4" [depth.b[3]] "mm" [0.0, 1e3] "axial depth of segment 4";
                124 "depth.b5" [depth.b[4]] "mm" [0.0, 1e3] "axial depth of segment 5";
                125 "depth.b6" [depth.b[5]] "mm" [0.0, 1e3] "axial depth of segment 6";
                126 "depth.b7" [depth.b[6]] "mm" [0.0, 1e3] "axial depth of segment 7";
                127 "depth.b8" [depth.b[7]] "mm" [0.0, 1e3] "axial depth of segment 8";
            }
        },
    )
});

fmi2_export::adapter! {
    model: MillingForcePlant,
    table: TABLE as Table<ForcePlantParams, ForcePlantInputs, ForcePlantOutputs>,
    parameters: |m| m.plant.params(),
    input_errors: ForceError::Input,
}

/// The FMU model: the plant core.
#[derive(Clone, Serialize, Deserialize)]
pub struct MillingForcePlant {
    plant: ForcePlant,
}

impl MillingForcePlant {
    /// The plant core.
    pub fn plant(&self) -> &ForcePlant {
        &self.plant
    }
}

impl Fmi2Model for MillingForcePlant {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = TABLE.read_parameters(values)?;
        let plant = ForcePlant::new(&p).map_err(|e| e.to_string())?;
        Ok(MillingForcePlant { plant })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.plant.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
        let inputs = TABLE.read_inputs(v).map_err(StepError::Error)?;
        let saved = self.plant.clone();
        self.plant.set_time(t);
        if let Err(e) = self.plant.step(h, &inputs) {
            self.plant = saved;
            return Err(Self::step_error(e));
        }
        TABLE.write_outputs(&self.plant.outputs(), v);
        Ok(())
    }

    /// One matrix exponential per piece between depth changes.
    fn internal_steps(&self, _h: f64) -> f64 {
        MAX_PIECES
    }

    fn validate_state(&self) -> Result<(), String> {
        self.plant.validate_state()
    }
}

/// A step is cut at most at every depth change: at most 9 pieces.
const MAX_PIECES: f64 = (milling_force_plant::plant::MAX_SEGMENTS + 1) as f64;
