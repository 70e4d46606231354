//! # ToolXyPlant FMU adapter (seed 003)
//!
//! Translates between the tool core ([`tool_xy::tool`]: [`ToolParams`],
//! [`ToolPlant::step`]) and the FMI variables of `ToolXyPlant.fmu`, declared once in [`TABLE`].
//! The cdylib `ToolXyPlant` (`fmu-tool-xy-plant/cdylib/`) exports it.
//!
//! The plant starts in the static equilibrium of the cut and integrates with RK4 at the fixed
//! step `δ = max_step` (a delay that is not a whole number of steps is interpolated); a
//! communication step must be a whole number of `δ` (else fmi2Discard with a message). The
//! delay line must fit the memory budget (`model_kit::budget`), else initialization is an
//! fmi2Error naming `spindle_speed`, `teeth` and `max_step`; `spindle_speed = 0` is a stopped
//! spindle, which does not cut. The damper forces `u_x`, `u_y` are held over
//! the step. Outputs `x`, `y` are the vibration about the static deflection (what the controller
//! sees); `deflection_x`, `deflection_y` the total displacement.

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, StepError, Table, Values};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;
use tool_xy::{ToolError, ToolInputs, ToolParams, ToolPlant};

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The outputs of the FMU.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToolXyOutputs {
    /// Vibration `(x, y)` about the static deflection [m].
    pub vib: [f64; 2],
    /// Velocities [m/s].
    pub vel: [f64; 2],
    /// Total displacements [m].
    pub deflection: [f64; 2],
    /// Cutting forces `(F_x, F_y)` [N].
    pub force: [f64; 2],
    /// Damper strokes relative to the tool [m].
    pub damper: [f64; 2],
}

/// The variable table of `ToolXyPlant.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<ToolParams, ToolInputs, ToolXyOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "ToolXyPlant",
            identifier: "ToolXyPlant",
            description: "Two-axis milling tool of seed 003: decoupled x/y modes, averaged cubic regenerative cutting force (Eqs. 5-6), active vibration damper with friction, harmonic forcing",
            default_experiment: (0.0, 0.6, 1e-4),
        },
        fmi2_export::variables! {
            inputs ToolInputs {
                0 "u_x" [ux] "N" [-1e9, 1e9] "damper force on the tool along x";
                1 "u_y" [uy] "N" [-1e9, 1e9] "damper force on the tool along y";
            }
            outputs ToolXyOutputs {
                10 "x"            [vib[0]]        "m"   [] "tool vibration along x (about the static deflection)";
                11 "y"            [vib[1]]        "m"   [] "tool vibration along y";
                12 "vx"           [vel[0]]        "m/s" [] "tool velocity along x";
                13 "vy"           [vel[1]]        "m/s" [] "tool velocity along y";
                14 "deflection_x" [deflection[0]] "m"   [] "total tool displacement along x";
                15 "deflection_y" [deflection[1]] "m"   [] "total tool displacement along y";
                16 "F_x"          [force[0]]      "N"   [] "cutting force on the tool along x (Eq. 5)";
                17 "F_y"          [force[1]]      "N"   [] "cutting force on the tool along y (Eq. 5)";
                18 "damper_x"     [damper[0]]     "m"   [] "damper mass displacement relative to the tool, x";
                19 "damper_y"     [damper[1]]     "m"   [] "damper mass displacement relative to the tool, y";
            }
            parameters ToolParams {
                100 "m_x"        [mass[0]]              "kg"    [1e-9, 1e9]     "modal mass, x";
                101 "m_y"        [mass[1]]              "kg"    [1e-9, 1e9]     "modal mass, y";
                102 "c_x"        [damping[0]]           "N.s/m" [0.0, 1e12]     "modal damping, x";
                103 "c_y"        [damping[1]]           "N.s/m" [0.0, 1e12]     "modal damping, y";
                104 "k_x"        [stiffness[0]]         "N/m"   [1e-9, 1e15]    "modal stiffness, x";
                105 "k_y"        [stiffness[1]]         "N/m"   [1e-9, 1e15]    "modal stiffness, y";
                0   "teeth"      [teeth]                ""      [1, 100]        "number of teeth n";
                106 "spindle_speed" [spindle_rpm]       "rpm"   [0.0, 1e6]      "spindle speed (delay tau = 60/(n rpm)); 0: stopped, no cutting";
                110 "xi1"        [xi[0]]                "N/m3"  [-1e20, 1e20]   "tangential coefficient of h^3";
                111 "xi2"        [xi[1]]                "N/m2"  [-1e20, 1e20]   "tangential coefficient of h^2";
                112 "xi3"        [xi[2]]                "N/m"   [-1e20, 1e20]   "tangential coefficient of h";
                113 "xi4"        [xi[3]]                "N"     [-1e20, 1e20]   "tangential constant (Table 1's 1700e3 read as 1700 N)";
                114 "delta1"     [delta[0]]             "N/m3"  [-1e20, 1e20]   "radial coefficient of h^3";
                115 "delta2"     [delta[1]]             "N/m2"  [-1e20, 1e20]   "radial coefficient of h^2";
                116 "delta3"     [delta[2]]             "N/m"   [-1e20, 1e20]   "radial coefficient of h (printed 13)";
                117 "delta4"     [delta[3]]             "N"     [-1e20, 1e20]   "radial constant";
                0   "cutting"    [cutting]              ""      []              "cutting force on";
                120 "m_d"        [damper_mass]          "kg"    [1e-9, 1e9]     "damper mass (5 % of 20 kg)";
                121 "k_d"        [damper_stiffness]     "N/m"   [0.0, 1e15]     "damper centring stiffness (not in the paper)";
                122 "Lambda"     [friction_viscous]     "N.s/m" [0.0, 1e12]     "damper viscous friction (Eq. 13)";
                123 "Gamma"      [friction_coulomb]     "1"      [0.0, 1e6]      "damper Coulomb friction coefficient (Eq. 13)";
                124 "Upsilon"    [friction_smoothing]   "s/m"      [0.0, 1e12]     "tanh smoothing of the Coulomb friction (Eq. 13) [s/m]";
                125 "A_x"        [forcing_amplitude[0]] "N"     [-1e9, 1e9]     "harmonic forcing amplitude, x";
                126 "A_y"        [forcing_amplitude[1]] "N"     [-1e9, 1e9]     "harmonic forcing amplitude, y";
                127 "omega_f"    [forcing_frequency]    "rad/s" [0.0, 1e9]      "forcing frequency (650 rad/s)";
                128 "max_step"   [max_step]             "s"     [1e-9, 1.0]     "RK4 step (communication steps are whole multiples of it)";
            }
        },
    )
    .work_bound("max_step", 1.0)
});

fmi2_export::adapter! {
    model: ToolXyPlant,
    table: TABLE as Table<ToolParams, ToolInputs, ToolXyOutputs>,
    parameters: |m| m.tool.params(),
    input_errors: ToolError::Input,
}

/// The FMU model: the tool core.
#[derive(Clone, Serialize, Deserialize)]
pub struct ToolXyPlant {
    tool: ToolPlant,
}

impl ToolXyPlant {
    /// The tool core.
    pub fn tool(&self) -> &ToolPlant {
        &self.tool
    }

    fn outputs(&self) -> ToolXyOutputs {
        let o = self.tool.outputs();
        let xs = self.tool.static_deflection();
        ToolXyOutputs {
            vib: [o.x - xs[0], o.y - xs[1]],
            vel: [o.vx, o.vy],
            deflection: [o.x, o.y],
            force: [o.fx, o.fy],
            damper: [o.damper_x, o.damper_y],
        }
    }
}

impl Fmi2Model for ToolXyPlant {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = TABLE.read_parameters(values)?;
        let tool = ToolPlant::new(&p).map_err(|e| e.to_string())?;
        Ok(ToolXyPlant { tool })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, _t: f64, h: f64, _log: &mut dyn ModelLog) -> Result<(), StepError> {
        let inputs = TABLE.read_inputs(v).map_err(StepError::Error)?;
        self.tool.step(h, &inputs).map_err(Self::step_error)?;
        TABLE.write_outputs(&self.outputs(), v);
        Ok(())
    }

    /// RK4 steps per communication step.
    fn internal_steps(&self, h: f64) -> f64 {
        h / self.tool.integration_step() + 1.0
    }

    fn validate_state(&self) -> Result<(), String> {
        self.tool.params().validate().map_err(|e| e.to_string())?;
        self.tool.validate_state()
    }
}
