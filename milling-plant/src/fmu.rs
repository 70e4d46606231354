//! `MillingPlant`: the FMI 2.0 co-simulation variable table and stepping of the plant (the
//! export layer in `fmi2-export` does the rest).
//!
//! Outputs at a communication point `t` are those of the state at `t`, with the forces
//! evaluated with the inputs held over the step that ended at `t` (before the first step: the
//! input start values). They do not change when inputs are set at `t`, so no output has a
//! direct dependency on an input (`ModelStructure` declares none); a master that wants the
//! actuator force for a new command reads it after the next step.

use crate::params::{CuttingModel, MillingMode, Mode, PlantParams};
use crate::plant::{Plant, PlantError, PlantInputs};
use fmi2_export::model_description::{
    Causality as C, ModelBuilder, ModelDescription, ScalarVariable as V, Variability as Va,
};
use fmi2_export::{Environment, Fmi2Model, ModelLog, Severity, StepError, Values};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Value references (Real unless noted).
pub mod vr {
    #![allow(missing_docs)]
    pub const U: u32 = 0;
    pub const SPINDLE_SPEED: u32 = 1;
    pub const FEED_PER_TOOTH: u32 = 2;
    pub const X: u32 = 10;
    pub const V: u32 = 11;
    pub const CUTTING_FORCE: u32 = 12;
    pub const ACTUATOR_FORCE: u32 = 13;
    pub const DISTURBANCE_FORCE: u32 = 14;
    pub const CHIP_THICKNESS: u32 = 15;
    pub const TOOL_ANGLE: u32 = 16;
    pub const DELAY: u32 = 17;
    pub const MASS: u32 = 100;
    pub const STIFFNESS: u32 = 101;
    pub const DAMPING_RATIO: u32 = 102;
    pub const X0: u32 = 103;
    pub const MODE2_FREQ: u32 = 104;
    pub const MODE2_ZETA: u32 = 105;
    pub const MODE2_PEAK: u32 = 106;
    pub const MODE3_FREQ: u32 = 107;
    pub const MODE3_ZETA: u32 = 108;
    pub const MODE3_PEAK: u32 = 109;
    pub const TOOL_RADIUS: u32 = 120;
    pub const RADIAL_ENGAGEMENT: u32 = 121;
    pub const AXIAL_DEPTH: u32 = 122;
    pub const KT: u32 = 123;
    pub const KR: u32 = 124;
    pub const DIRECTION_ANGLE: u32 = 125;
    pub const A11: u32 = 130;
    pub const A12: u32 = 131;
    pub const A21: u32 = 132;
    pub const A22: u32 = 133;
    pub const B1: u32 = 134;
    pub const B2: u32 = 135;
    pub const C1: u32 = 136;
    pub const C2: u32 = 137;
    pub const D: u32 = 138;
    pub const F_MAX: u32 = 139;
    pub const NOISE_RMS: u32 = 150;
    pub const NOISE_BANDWIDTH: u32 = 151;
    pub const DRIFT_AMPLITUDE: u32 = 152;
    pub const DRIFT_FREQUENCY: u32 = 153;
    pub const SINE_AMPLITUDE: u32 = 154;
    pub const SINE_FREQUENCY: u32 = 155;
    pub const INTERNAL_STEP: u32 = 160;
    /// Integer.
    pub const SEED: u32 = 0;
    /// Integer.
    pub const TEETH: u32 = 1;
    /// Integer.
    pub const MODES: u32 = 2;
    /// Integer (enumeration `CuttingModel`).
    pub const CUTTING_MODEL: u32 = 3;
    /// Integer (enumeration `MillingMode`).
    pub const MILLING: u32 = 4;
    /// Boolean output.
    pub const SATURATED: u32 = 0;
    /// Boolean.
    pub const CUTTING_ENABLED: u32 = 1;
    /// Boolean.
    pub const NOISE: u32 = 2;
    /// Boolean.
    pub const DRIFT: u32 = 3;
}

/// Long documentation of the FMU (packaged as `documentation/index.html`).
pub const DOCUMENTATION: &str = r#"# MillingPlant

Flexible cantilever workpiece in end milling with regenerative chatter (Soufi et al., seed 000,
Section 3): first bending mode (optionally the two higher modes, superposed at the tip),
mechanistic cutting force with variable regenerative delay, inertial actuator saturated at
+-27 N, stiffness drift, band-limited Gaussian force noise and an optional sinusoidal force.
SI units everywhere except `spindle_speed` [rpm].

## Inputs
`u` [N] actuator command (clipped to +-`actuator.f_max`), `spindle_speed` [rpm], `feed_per_tooth` [m].
All are held over a communication step.

## Equations
Modes: m_i q_i'' + c_i q_i' + k_i q_i = F_c + F_a + d(t), tip displacement x = sum q_i.
Drift: k_1(t) = K_w (1 + A sin(2 pi f_d t)) (Section 5.1: +-10 % at 0.5 Hz; Section 3.4's
"A_drift = 0.1 K_w" read as the relative amplitude, since a force of 0.1 K_w is dimensionally wrong).
Actuator (Table 1, signs restored): z' = A z + B u_sat, F_a = C z + D u_sat with A = [[-15.834,
-2785.6],[1, 0]], B = [1, 0], C = [-15.834, -2785.6], D = 1, i.e. a proof mass with Ca/Ma =
15.834 1/s, Ka/Ma = 2785.6 1/s2 (8.4 Hz) whose inertial force F_a = Ma xa'' reaches the beam:
F_a/u = s^2/(s^2 + 15.834 s + 2785.6), unity gain well above 8.4 Hz.

## Cutting (direction convention)
x = feed, y = normal, tooth angle phi clockwise from +y, radial unit vector r = (sin phi, cos phi).
Up-milling engages phi in [0, phi_c], down-milling [pi - phi_c, pi], phi_c = acos(1 - a_e/R).
The beam bends along d = (cos beta, sin beta) (`cutting.direction_angle` = beta, default 0 = feed
direction). Chip of tooth j: h_j = f_z sin phi_j - (x(t) - x(t - tau)) (d . r_j); no force when
h_j <= 0 (loss of contact; single-pass regeneration: the surface left by the previous tooth).
Force on the beam: F_c = sum_j a_p K_t h_j [(cos phi + k_r sin phi) d_x + (-sin phi + k_r cos phi) d_y].
`cutting.model = averaged`: F_c = a_p K_t (f_z beta0 - alpha0 (x - x(t - tau))) with the zero-order
(Altintas-Budak) factors alpha0 = Z/(2 pi) int (d.r)[...] dphi (0.4563 for the defaults) and
beta0 = Z/(2 pi) int sin phi [...] dphi. Zero-order critical depth: a_lim = -1/(2 K_t alpha0 Re Phi).

## Regenerative delay
The tool angle theta = int Omega dt is tracked; x(t - tau) is the displacement when theta was
theta(t) - 2 pi/Z, found in a history buffer and interpolated (cubic Hermite), so a changing
spindle speed changes the delay as the kinematics says. Constant speed: tau = 60/(Z N).
Before the first tooth period the surface is flat (x = 0).

## Numerics and noise
Classical RK4 on a fixed grid of `internal_step` (default 10 us) anchored at the start time.
The noise (N(0,1) from a ChaCha8 stream seeded by `seed`, 4th-order Butterworth low-pass at
`disturbance.noise_bandwidth`, scaled to `disturbance.noise_rms`) is one sample per grid cell,
held over it: the realization depends only on the seed and the grid, and communication steps
that are multiples of the grid give bitwise-identical results.

## Outputs
Values at the communication point with the inputs held over the step that ended there (no
direct feedthrough): `x`, `v`, `cutting_force`, `actuator_force`, `disturbance_force` (noise +
sine), `chip_thickness` (largest engaged chip), `saturated`, `tool_angle` (mod 2 pi), `delay`.
A diverging state (|x| > 1 m) ends the simulation with fmi2Error.
"#;

/// The FMU model.
#[derive(Clone, Serialize, Deserialize)]
pub struct MillingPlant {
    plant: Plant,
    reported_saturation: bool,
}

fn mode_from(v: &Values, f: u32) -> Mode {
    Mode::from_peak(v.real(f), v.real(f + 1), v.real(f + 2))
}

/// Read the plant parameters from the variable store.
pub fn params_from(v: &Values) -> Result<PlantParams, String> {
    let mut p = PlantParams::default();
    p.workpiece.first =
        Mode { mass: v.real(vr::MASS), stiffness: v.real(vr::STIFFNESS), damping_ratio: v.real(vr::DAMPING_RATIO) };
    p.workpiece.higher = [mode_from(v, vr::MODE2_FREQ), mode_from(v, vr::MODE3_FREQ)];
    p.workpiece.modes = u32::try_from(v.integer(vr::MODES)).map_err(|e| format!("workpiece.modes: {e}"))?;
    p.workpiece.initial_displacement = v.real(vr::X0);
    let c = &mut p.cutting;
    c.enabled = v.boolean(vr::CUTTING_ENABLED);
    c.model = match v.integer(vr::CUTTING_MODEL) {
        1 => CuttingModel::TimeDomain,
        2 => CuttingModel::Averaged,
        m => return Err(format!("cutting.model = {m} is not an item")),
    };
    c.milling = match v.integer(vr::MILLING) {
        1 => MillingMode::Up,
        2 => MillingMode::Down,
        m => return Err(format!("cutting.milling = {m} is not an item")),
    };
    c.teeth = u32::try_from(v.integer(vr::TEETH)).map_err(|e| format!("cutting.teeth: {e}"))?;
    c.tool_radius = v.real(vr::TOOL_RADIUS);
    c.radial_engagement = v.real(vr::RADIAL_ENGAGEMENT);
    c.axial_depth = v.real(vr::AXIAL_DEPTH);
    c.kt = v.real(vr::KT);
    c.kr = v.real(vr::KR);
    c.direction_angle = v.real(vr::DIRECTION_ANGLE);
    let a = &mut p.actuator;
    a.a = [[v.real(vr::A11), v.real(vr::A12)], [v.real(vr::A21), v.real(vr::A22)]];
    a.b = [v.real(vr::B1), v.real(vr::B2)];
    a.c = [v.real(vr::C1), v.real(vr::C2)];
    a.d = v.real(vr::D);
    a.f_max = v.real(vr::F_MAX);
    let d = &mut p.disturbance;
    d.noise = v.boolean(vr::NOISE);
    d.noise_rms = v.real(vr::NOISE_RMS);
    d.noise_bandwidth = v.real(vr::NOISE_BANDWIDTH);
    d.drift = v.boolean(vr::DRIFT);
    d.drift_amplitude = v.real(vr::DRIFT_AMPLITUDE);
    d.drift_frequency = v.real(vr::DRIFT_FREQUENCY);
    d.sine_amplitude = v.real(vr::SINE_AMPLITUDE);
    d.sine_frequency = v.real(vr::SINE_FREQUENCY);
    p.seed = u64::try_from(v.integer(vr::SEED)).map_err(|e| format!("seed: {e}"))?;
    p.internal_step = v.real(vr::INTERNAL_STEP);
    p.validate()?;
    Ok(p)
}

fn inputs_from(v: &Values) -> PlantInputs {
    PlantInputs {
        u: v.real(vr::U),
        spindle_speed_rpm: v.real(vr::SPINDLE_SPEED),
        feed_per_tooth: v.real(vr::FEED_PER_TOOTH),
    }
}

impl MillingPlant {
    /// The plant core.
    pub fn plant(&self) -> &Plant {
        &self.plant
    }
}

impl Fmi2Model for MillingPlant {
    fn description() -> &'static ModelDescription {
        static MD: OnceLock<ModelDescription> = OnceLock::new();
        MD.get_or_init(build_description)
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        let p = params_from(values)?;
        let mut plant = Plant::new(&p).map_err(|e| e.to_string())?;
        plant.set_inputs(&inputs_from(values)).map_err(|e| e.to_string())?;
        Ok(MillingPlant { plant, reported_saturation: false })
    }

    fn update_outputs(&self, v: &mut Values) {
        let o = self.plant.outputs();
        v.set_real(vr::X, o.x);
        v.set_real(vr::V, o.v);
        v.set_real(vr::CUTTING_FORCE, o.cutting_force);
        v.set_real(vr::ACTUATOR_FORCE, o.actuator_force);
        v.set_real(vr::DISTURBANCE_FORCE, o.disturbance_force);
        v.set_real(vr::CHIP_THICKNESS, o.chip_thickness);
        v.set_real(vr::TOOL_ANGLE, o.tool_angle);
        v.set_real(vr::DELAY, o.delay);
        v.set_boolean(vr::SATURATED, o.saturated);
    }

    fn do_step(&mut self, v: &mut Values, _t: f64, h: f64, log: &mut dyn ModelLog) -> Result<(), StepError> {
        let inputs = inputs_from(v);
        match self.plant.step(h, &inputs) {
            Ok(()) => {}
            Err(e @ PlantError::Input(_)) => return Err(StepError::Discard(e.to_string())),
            Err(e) => return Err(StepError::Error(e.to_string())),
        }
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
        self.update_outputs(v);
        Ok(())
    }
}

fn build_description() -> ModelDescription {
    let d = PlantParams::default();
    let [m2, m3] = d.workpiece.higher;
    let par = |name: &str, vr: u32, start: f64, unit: &str, desc: &str| {
        let v = V::real(name, vr, C::Parameter, Va::Fixed).start(start).describe(desc);
        if unit.is_empty() { v } else { v.unit_of(unit) }
    };
    let out = |name: &str, vr: u32, unit: &str, desc: &str| {
        V::real(name, vr, C::Output, Va::Continuous).unit_of(unit).describe(desc).depends_on(&[])
    };
    let peak = |m: &Mode| 1.0 / (2.0 * m.damping_ratio * (1.0 - m.damping_ratio.powi(2)).sqrt() * m.stiffness);
    let b = ModelBuilder::new("MillingPlant", "MillingPlant")
        .description(
            "Flexible workpiece in end milling: regenerative cutting, inertial actuator, disturbances (seed 000)",
        )
        .author_version("chatter-fmu", env!("CARGO_PKG_VERSION"))
        .unit("m", [0, 1, 0, 0, 0, 0, 0, 0])
        .unit("m/s", [0, 1, -1, 0, 0, 0, 0, 0])
        .unit("N", [1, 1, -2, 0, 0, 0, 0, 0])
        .unit("N/m", [1, 0, -2, 0, 0, 0, 0, 0])
        .unit("N/m2", [1, -1, -2, 0, 0, 0, 0, 0])
        .unit("m/N", [-1, 1, 2, 0, 0, 0, 0, 0])
        .unit("kg", [1, 0, 0, 0, 0, 0, 0, 0])
        .unit("s", [0, 0, 1, 0, 0, 0, 0, 0])
        .unit("Hz", [0, 0, -1, 0, 0, 0, 0, 0])
        .unit("1/s", [0, 0, -1, 0, 0, 0, 0, 0])
        .unit("1/s2", [0, 0, -2, 0, 0, 0, 0, 0])
        .unit("rad", [0, 0, 0, 0, 0, 0, 0, 1])
        .unit_scaled("rpm", [0, 0, -1, 0, 0, 0, 0, 1], 2.0 * PI / 60.0)
        .enumeration(
            "CuttingModel",
            "cutting-force model",
            &[
                ("time_domain", "mechanistic force per tooth, engagement window, loss of contact"),
                ("averaged", "linear zero-order model with the Altintas-Budak directional factor"),
            ],
        )
        .enumeration(
            "MillingMode",
            "milling direction",
            &[("up", "up-milling (conventional)"), ("down", "down-milling (climb)")],
        )
        .default_experiment(0.0, 1.0, d.internal_step)
        .var(V::real("u", vr::U, C::Input, Va::Continuous).start(0.0).unit_of("N").describe("actuator force command"))
        .var(
            V::real("spindle_speed", vr::SPINDLE_SPEED, C::Input, Va::Continuous)
                .start(crate::params::DEFAULT_SPINDLE_SPEED)
                .unit_of("rpm")
                .bounds(0.0, 1e6)
                .describe("spindle speed"),
        )
        .var(
            V::real("feed_per_tooth", vr::FEED_PER_TOOTH, C::Input, Va::Continuous)
                .start(crate::params::DEFAULT_FEED_PER_TOOTH)
                .unit_of("m")
                .bounds(0.0, 0.01)
                .describe("feed per tooth"),
        )
        .var(out("x", vr::X, "m", "tip displacement along the beam's bending direction"))
        .var(out("v", vr::V, "m/s", "tip velocity"))
        .var(out("cutting_force", vr::CUTTING_FORCE, "N", "cutting force on the beam along its bending direction"))
        .var(out("actuator_force", vr::ACTUATOR_FORCE, "N", "actuator force on the beam"))
        .var(out("disturbance_force", vr::DISTURBANCE_FORCE, "N", "noise + sinusoidal disturbance force"))
        .var(out("chip_thickness", vr::CHIP_THICKNESS, "m", "largest chip thickness among the engaged teeth"))
        .var(out("tool_angle", vr::TOOL_ANGLE, "rad", "tool angle theta mod 2 pi"))
        .var(out("delay", vr::DELAY, "s", "regenerative delay (time since the previous tooth passed this angle)"))
        .var(
            V::boolean("saturated", vr::SATURATED, C::Output, Va::Discrete)
                .describe("the command was clipped at +-f_max over the last step")
                .depends_on(&[]),
        )
        .var(
            V::integer("seed", vr::SEED, C::Parameter, Va::Fixed)
                .start(d.seed as i32)
                .bounds(0.0, f64::from(i32::MAX))
                .describe("random seed of the noise"),
        )
        .var(
            par("internal_step", vr::INTERNAL_STEP, d.internal_step, "s", "internal RK4 step / noise grid")
                .bounds(1e-8, 1e-3),
        )
        .var(
            par("workpiece.mass", vr::MASS, d.workpiece.first.mass, "kg", "first-mode modal mass Mw").bounds(1e-9, 1e9),
        )
        .var(
            par("workpiece.stiffness", vr::STIFFNESS, d.workpiece.first.stiffness, "N/m", "first-mode stiffness Kw")
                .bounds(1e-9, 1e15),
        )
        .var(
            par(
                "workpiece.damping_ratio",
                vr::DAMPING_RATIO,
                d.workpiece.first.damping_ratio,
                "",
                "first-mode damping ratio",
            )
            .bounds(0.0, 0.99),
        )
        .var(
            par("workpiece.initial_displacement", vr::X0, 0.0, "m", "initial tip displacement (free decay)")
                .bounds(-0.1, 0.1),
        )
        .var(
            V::integer("workpiece.modes", vr::MODES, C::Parameter, Va::Fixed)
                .start(d.workpiece.modes as i32)
                .bounds(1.0, 3.0)
                .describe("number of modes: 1 (first bending mode) or 3 (with the two higher modes)"),
        )
        .var(
            par("workpiece.mode2.frequency", vr::MODE2_FREQ, m2.omega_n() / (2.0 * PI), "Hz", "second mode")
                .bounds(1e-3, 1e6),
        )
        .var(
            par("workpiece.mode2.damping_ratio", vr::MODE2_ZETA, m2.damping_ratio, "", "second mode")
                .bounds(1e-6, 0.99),
        )
        .var(par("workpiece.mode2.peak_receptance", vr::MODE2_PEAK, peak(&m2), "m/N", "second mode").bounds(1e-15, 1.0))
        .var(
            par("workpiece.mode3.frequency", vr::MODE3_FREQ, m3.omega_n() / (2.0 * PI), "Hz", "third mode")
                .bounds(1e-3, 1e6),
        )
        .var(
            par("workpiece.mode3.damping_ratio", vr::MODE3_ZETA, m3.damping_ratio, "", "third mode").bounds(1e-6, 0.99),
        )
        .var(par("workpiece.mode3.peak_receptance", vr::MODE3_PEAK, peak(&m3), "m/N", "third mode").bounds(1e-15, 1.0))
        .var(
            V::boolean("cutting.enabled", vr::CUTTING_ENABLED, C::Parameter, Va::Fixed)
                .start(d.cutting.enabled)
                .describe("cutting force on/off"),
        )
        .var(
            V::enumeration("cutting.model", vr::CUTTING_MODEL, C::Parameter, Va::Fixed, "CuttingModel")
                .start(1)
                .describe("cutting-force model"),
        )
        .var(
            V::enumeration("cutting.milling", vr::MILLING, C::Parameter, Va::Fixed, "MillingMode")
                .start(1)
                .describe("up- or down-milling"),
        )
        .var(
            V::integer("cutting.teeth", vr::TEETH, C::Parameter, Va::Fixed)
                .start(d.cutting.teeth as i32)
                .bounds(1.0, 100.0)
                .describe("number of teeth Z"),
        )
        .var(par("cutting.tool_radius", vr::TOOL_RADIUS, d.cutting.tool_radius, "m", "tool radius R").bounds(1e-6, 1.0))
        .var(
            par(
                "cutting.radial_engagement",
                vr::RADIAL_ENGAGEMENT,
                d.cutting.radial_engagement,
                "m",
                "radial depth a_e",
            )
            .bounds(1e-6, 2.0),
        )
        .var(
            par("cutting.axial_depth", vr::AXIAL_DEPTH, d.cutting.axial_depth, "m", "axial depth of cut a_p")
                .bounds(0.0, 1.0),
        )
        .var(par("cutting.kt", vr::KT, d.cutting.kt, "N/m2", "tangential cutting coefficient K_t").bounds(0.0, 1e11))
        .var(par("cutting.kr", vr::KR, d.cutting.kr, "N/m2", "radial cutting coefficient K_r").bounds(0.0, 1e11))
        .var(
            par(
                "cutting.direction_angle",
                vr::DIRECTION_ANGLE,
                0.0,
                "rad",
                "beam bending direction from the feed axis towards +y",
            )
            .bounds(-7.0, 7.0),
        )
        .var(par("actuator.a11", vr::A11, d.actuator.a[0][0], "", "actuator A[1,1] (1/s)"))
        .var(par("actuator.a12", vr::A12, d.actuator.a[0][1], "", "actuator A[1,2] (1/s2)"))
        .var(par("actuator.a21", vr::A21, d.actuator.a[1][0], "", "actuator A[2,1]"))
        .var(par("actuator.a22", vr::A22, d.actuator.a[1][1], "", "actuator A[2,2]"))
        .var(par("actuator.b1", vr::B1, d.actuator.b[0], "", "actuator B[1]"))
        .var(par("actuator.b2", vr::B2, d.actuator.b[1], "", "actuator B[2]"))
        .var(par("actuator.c1", vr::C1, d.actuator.c[0], "", "actuator C[1]"))
        .var(par("actuator.c2", vr::C2, d.actuator.c[1], "", "actuator C[2]"))
        .var(par("actuator.d", vr::D, d.actuator.d, "", "actuator D (F_a/u at high frequency)"))
        .var(par("actuator.f_max", vr::F_MAX, d.actuator.f_max, "N", "saturation of the command").bounds(0.0, 1e9))
        .var(
            V::boolean("disturbance.noise", vr::NOISE, C::Parameter, Va::Fixed)
                .start(d.disturbance.noise)
                .describe("broadband Gaussian force on/off"),
        )
        .var(par("disturbance.noise_rms", vr::NOISE_RMS, d.disturbance.noise_rms, "N", "noise RMS").bounds(0.0, 1e9))
        .var(
            par(
                "disturbance.noise_bandwidth",
                vr::NOISE_BANDWIDTH,
                d.disturbance.noise_bandwidth,
                "Hz",
                "noise cut-off",
            )
            .bounds(1e-3, 1e9),
        )
        .var(
            V::boolean("disturbance.drift", vr::DRIFT, C::Parameter, Va::Fixed)
                .start(d.disturbance.drift)
                .describe("stiffness drift on/off"),
        )
        .var(
            par(
                "disturbance.drift_amplitude",
                vr::DRIFT_AMPLITUDE,
                d.disturbance.drift_amplitude,
                "",
                "relative stiffness drift A",
            )
            .bounds(0.0, 0.99),
        )
        .var(par(
            "disturbance.drift_frequency",
            vr::DRIFT_FREQUENCY,
            d.disturbance.drift_frequency,
            "Hz",
            "drift frequency",
        ))
        .var(par(
            "disturbance.sine_amplitude",
            vr::SINE_AMPLITUDE,
            d.disturbance.sine_amplitude,
            "N",
            "sinusoidal force amplitude",
        ))
        .var(par(
            "disturbance.sine_frequency",
            vr::SINE_FREQUENCY,
            d.disturbance.sine_frequency,
            "Hz",
            "sinusoidal force frequency",
        ));
    fmi2_export::with_log_categories(b).build().expect("valid MillingPlant table")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn start_values_give_the_default_parameters() {
        let v = Values::from_description(MillingPlant::description());
        let p = params_from(&v).unwrap();
        let d = PlantParams::default();
        assert_eq!(p.cutting, d.cutting);
        assert_eq!(p.actuator, d.actuator);
        assert_eq!(p.disturbance, d.disturbance);
        for (a, b) in p.workpiece.higher.iter().zip(d.workpiece.higher.iter()) {
            assert!((a.stiffness / b.stiffness - 1.0).abs() < 1e-12 && (a.mass / b.mass - 1.0).abs() < 1e-12);
        }
    }
}
