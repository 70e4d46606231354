//! # MillingPlant FMU adapter
//!
//! Translates between the plant core ([`milling_plant`]: [`PlantParams`], [`PlantInputs`],
//! [`PlantOutputs`]) and the FMI variables of `MillingPlant.fmu`, declared once in [`TABLE`].
//! The shared export layer (`fmi2-export`) does everything else; the cdylib `MillingPlant`
//! (`fmu-plant/cdylib/`) exports this model's 34 `fmi2*` functions.
//!
//! Outputs at a communication point `t` are those of the state at `t`, with the forces
//! evaluated with the inputs held over the step that ended at `t` (before the first step: the
//! input start values). They do not change when inputs are set at `t`, so no output has a
//! direct dependency on an input (`ModelStructure` declares none); a master that wants the
//! actuator force for a new command reads it after the next step.

use fmi2_export::{Environment, Fmi2Model, Header, ModelLog, Severity, StepError, Table, Values};
use milling_plant::{Mode, Plant, PlantError, PlantInputs, PlantOutputs, PlantParams};
use model_description::ModelDescription;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = include_str!("documentation.md");

/// The higher modes are FMU parameters as (frequency, damping ratio, peak receptance), the core
/// keeps (mass, stiffness, damping ratio): each setter keeps the other two FMU quantities.
fn higher<const I: usize>(p: &PlantParams) -> Mode {
    p.workpiece.higher[I]
}
fn set_higher<const I: usize>(p: &mut PlantParams, freq_hz: f64, damping_ratio: f64, peak: f64) {
    p.workpiece.higher[I] = Mode::from_peak(freq_hz, damping_ratio, peak);
}
fn mode_frequency<const I: usize>(p: &PlantParams) -> f64 {
    higher::<I>(p).frequency_hz()
}
fn mode_damping<const I: usize>(p: &PlantParams) -> f64 {
    higher::<I>(p).damping_ratio
}
fn mode_peak<const I: usize>(p: &PlantParams) -> f64 {
    higher::<I>(p).peak_receptance()
}
fn set_mode_frequency<const I: usize>(p: &mut PlantParams, f: f64) {
    set_higher::<I>(p, f, mode_damping::<I>(p), mode_peak::<I>(p));
}
fn set_mode_damping<const I: usize>(p: &mut PlantParams, z: f64) {
    set_higher::<I>(p, mode_frequency::<I>(p), z, mode_peak::<I>(p));
}
fn set_mode_peak<const I: usize>(p: &mut PlantParams, r: f64) {
    set_higher::<I>(p, mode_frequency::<I>(p), mode_damping::<I>(p), r);
}

/// The variable table of `MillingPlant.fmu`: one row per variable.
pub static TABLE: LazyLock<Table<PlantParams, PlantInputs, PlantOutputs>> = LazyLock::new(|| {
    Table::new(
        Header {
            model_name: "MillingPlant",
            identifier: "MillingPlant",
            description: "Flexible workpiece in end milling: regenerative cutting, inertial actuator, disturbances (seed 000)",
            default_experiment: (0.0, 1.0, PlantParams::default().internal_step),
        },
        fmi2_export::variables! {
            inputs PlantInputs {
                0 "u"              [u]                 "N"   []          "actuator force command";
                1 "spindle_speed"  [spindle_speed_rpm] "rpm" [0.0, 1e6]  "spindle speed";
                2 "feed_per_tooth" [feed_per_tooth]    "m"   [0.0, 0.01] "feed per tooth";
            }
            outputs PlantOutputs {
                10 "x"                 [x]                 "m"   [] "tip displacement along the beam's bending direction";
                11 "v"                 [v]                 "m/s" [] "tip velocity";
                12 "cutting_force"     [cutting_force]     "N"   [] "cutting force on the beam along its bending direction";
                13 "actuator_force"    [actuator_force]    "N"   [] "actuator force on the beam";
                14 "disturbance_force" [disturbance_force] "N"   [] "noise + sinusoidal disturbance force";
                15 "chip_thickness"    [chip_thickness]    "m"   [] "largest chip thickness among the engaged teeth";
                16 "tool_angle"        [tool_angle]        "rad" [] "tool angle theta mod 2 pi";
                17 "delay"             [delay]             "s"   [] "regenerative delay (time since the previous tooth passed this angle)";
                0  "saturated"         [saturated]         ""    [] "the command was clipped at +-f_max over the last step";
            }
            parameters PlantParams {
                0   "seed"                           [seed]                         ""     [0, i32::MAX]  "random seed of the noise";
                160 "internal_step"                  [internal_step]                "s"    [1e-8, 1e-3]   "internal RK4 step / noise grid";
                100 "workpiece.mass"                 [workpiece.first.mass]         "kg"   [1e-9, 1e9]    "first-mode modal mass Mw";
                101 "workpiece.stiffness"            [workpiece.first.stiffness]    "N/m"  [1e-9, 1e15]   "first-mode stiffness Kw";
                102 "workpiece.damping_ratio"        [workpiece.first.damping_ratio] "1"    [0.0, 0.99]    "first-mode damping ratio";
                103 "workpiece.initial_displacement" [workpiece.initial_displacement] "m"  [-0.1, 0.1]    "initial tip displacement (free decay)";
                2   "workpiece.modes"                [workpiece.modes]              ""     [1, 3]         "number of modes: 1 (first bending mode) or 3 (with the two higher modes)";
                104 "workpiece.mode2.frequency"       [get mode_frequency::<0>, set set_mode_frequency::<0>] "Hz"  [1e-3, 1e6]  "second mode";
                105 "workpiece.mode2.damping_ratio"   [get mode_damping::<0>, set set_mode_damping::<0>]     "1"    [1e-6, 0.99] "second mode";
                106 "workpiece.mode2.peak_receptance" [get mode_peak::<0>, set set_mode_peak::<0>]           "m/N" [1e-15, 1.0] "second mode";
                107 "workpiece.mode3.frequency"       [get mode_frequency::<1>, set set_mode_frequency::<1>] "Hz"  [1e-3, 1e6]  "third mode";
                108 "workpiece.mode3.damping_ratio"   [get mode_damping::<1>, set set_mode_damping::<1>]     "1"    [1e-6, 0.99] "third mode";
                109 "workpiece.mode3.peak_receptance" [get mode_peak::<1>, set set_mode_peak::<1>]           "m/N" [1e-15, 1.0] "third mode";
                1   "cutting.enabled"                [cutting.enabled]              ""     []             "cutting force on/off";
                3   "cutting.model"                  [enum cutting.model]           ""     []             "cutting-force model";
                4   "cutting.milling"                [enum cutting.milling]         ""     []             "up- or down-milling";
                5   "integrator"                     [enum integrator]              ""     []             "time integration: exact (default, fast) or reference (RK4, the slow reference)";
                1   "cutting.teeth"                  [cutting.teeth]                ""     [1, 100]       "number of teeth Z";
                120 "cutting.tool_radius"            [cutting.tool_radius]          "m"    [1e-6, 1.0]    "tool radius R";
                121 "cutting.radial_engagement"      [cutting.radial_engagement]    "m"    [1e-6, 2.0]    "radial depth a_e";
                122 "cutting.axial_depth"            [cutting.axial_depth]          "m"    [0.0, 1.0]     "axial depth of cut a_p";
                123 "cutting.kt"                     [cutting.kt]                   "N/m2" [1e6, 1e11]    "tangential cutting coefficient K_t";
                124 "cutting.kr"                     [cutting.kr]                   "N/m2" [0.0, 1e11]    "radial cutting coefficient K_r";
                125 "cutting.direction_angle"        [cutting.direction_angle]      "rad"  [-7.0, 7.0]    "beam bending direction from the feed axis towards +y";
                130 "actuator.a11"                   [actuator.a[0][0]]             "1/s"     []             "actuator A[1,1] (1/s)";
                131 "actuator.a12"                   [actuator.a[0][1]]             "1/s2"     []             "actuator A[1,2] (1/s2)";
                132 "actuator.a21"                   [actuator.a[1][0]]             "1"     []             "actuator A[2,1]";
                133 "actuator.a22"                   [actuator.a[1][1]]             "1/s"     []             "actuator A[2,2]";
                134 "actuator.b1"                    [actuator.b[0]]                "1"     []             "actuator B[1]";
                135 "actuator.b2"                    [actuator.b[1]]                "s"     []             "actuator B[2]";
                136 "actuator.c1"                    [actuator.c[0]]                "1/s"     []             "actuator C[1]";
                137 "actuator.c2"                    [actuator.c[1]]                "1/s2"     []             "actuator C[2]";
                138 "actuator.d"                     [actuator.d]                   "1"     []             "actuator D (F_a/u at high frequency)";
                139 "actuator.f_max"                 [actuator.f_max]               "N"    [0.0, 1e9]     "saturation of the command";
                2   "disturbance.noise"              [disturbance.noise]            ""     []             "broadband Gaussian force on/off";
                150 "disturbance.noise_rms"          [disturbance.noise_rms]        "N"    [0.0, 1e9]     "noise RMS";
                151 "disturbance.noise_bandwidth"    [disturbance.noise_bandwidth]  "Hz"   [1e-3, 1e9]    "noise cut-off";
                3   "disturbance.drift"              [disturbance.drift]            ""     []             "stiffness drift on/off";
                152 "disturbance.drift_amplitude"    [disturbance.drift_amplitude]  "1"     [0.0, 0.99]    "relative stiffness drift A";
                153 "disturbance.drift_frequency"    [disturbance.drift_frequency]  "Hz"   []             "drift frequency";
                154 "disturbance.sine_amplitude"     [disturbance.sine_amplitude]   "N"    []             "sinusoidal force amplitude";
                155 "disturbance.sine_frequency"     [disturbance.sine_frequency]   "Hz"   []             "sinusoidal force frequency";
            }
        },
    )
    // what a step costs, as `internal_steps` counts it: for masters, in modelDescription.xml
    .work_bound("internal_step", 2.0)
});

fmi2_export::adapter! {
    model: MillingPlant,
    table: TABLE as Table<PlantParams, PlantInputs, PlantOutputs>,
    parameters: |m| m.plant.params(),
    input_errors: PlantError::Input,
}

/// The FMU model: the plant core and what it has reported.
#[derive(Clone, Serialize, Deserialize)]
pub struct MillingPlant {
    plant: Plant,
    reported_saturation: bool,
}

impl MillingPlant {
    /// The plant core.
    pub fn plant(&self) -> &Plant {
        &self.plant
    }
}

impl Fmi2Model for MillingPlant {
    fn description() -> &'static ModelDescription {
        TABLE.description()
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = TABLE.read_parameters(values)?;
        p.validate()?;
        let mut plant = Plant::new(&p).map_err(|e| e.to_string())?;
        plant.set_inputs(&TABLE.read_inputs(values)?).map_err(|e| e.to_string())?;
        Ok(MillingPlant { plant, reported_saturation: false })
    }

    fn update_outputs(&self, v: &mut Values) {
        TABLE.write_outputs(&self.plant.outputs(), v);
    }

    fn do_step(&mut self, v: &mut Values, _t: f64, h: f64, log: &mut dyn ModelLog) -> Result<(), StepError> {
        let inputs = TABLE.read_inputs(v).map_err(StepError::Error)?;
        self.plant.step(h, &inputs).map_err(Self::step_error)?;
        let o = self.plant.outputs();
        if o.saturated && !self.reported_saturation {
            self.reported_saturation = true;
            log.log(
                Severity::Info,
                &format!(
                    "actuator command {} N clipped at t = {} s (further clips not logged)",
                    inputs.u,
                    self.plant.time()
                ),
            );
        }
        TABLE.write_outputs(&o, v);
        Ok(())
    }

    /// One integrator step per cell of `internal_step`, plus one partial step at either end.
    fn internal_steps(&self, h: f64) -> f64 {
        h / self.plant.params().internal_step + 2.0
    }

    /// The core's parameter validation and state invariants.
    fn validate_state(&self) -> Result<(), String> {
        self.plant.validate_state()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The higher modes, computed rows, come back from their start values as the same modes
    /// (the shared `start_values_are_the_defaults` compares the rows).
    #[test]
    fn start_values_give_the_default_parameters() {
        let v = Values::from_description(MillingPlant::description());
        let p = TABLE.read_parameters(&v).unwrap();
        let d = PlantParams::default();
        assert_eq!(p.cutting, d.cutting);
        assert_eq!(p.actuator, d.actuator);
        assert_eq!(p.disturbance, d.disturbance);
        assert_eq!(p.workpiece.first, d.workpiece.first);
        for (a, b) in p.workpiece.higher.iter().zip(d.workpiece.higher.iter()) {
            assert!((a.stiffness / b.stiffness - 1.0).abs() < 1e-12 && (a.mass / b.mass - 1.0).abs() < 1e-12);
        }
    }
}
