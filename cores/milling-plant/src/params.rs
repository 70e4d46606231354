//! Plant parameters (defaults: seed 000, Tables 1 and 4, Sections 3.1–3.4) and the linear
//! frequency responses the stability tools use.
//!
//! # Direction convention
//!
//! Workpiece frame: `x` along the feed, `y` normal to it; tooth angle `φ` measured clockwise
//! from `+y` (Altintas–Budak), so a tooth at `φ` sits at `R·(sin φ, cos φ)` and its outward
//! radial unit vector is `r̂ = (sin φ, cos φ)`. Up-milling engages `φ ∈ [0, φ_c]`, down-milling
//! `φ ∈ [π − φ_c, π]`, with `φ_c = arccos(1 − a_e/R)` (half immersion: `π/2`).
//!
//! The flexible workpiece (the cantilever's bending) moves by `w` along the unit vector
//! `d = (cos β, sin β)` (`β = cutting.direction_angle`, default 0: the beam bends along the feed,
//! which is the reading that reproduces the seed's own Table 8 critical depth 1.24 mm).
//! A workpiece moving along `+d` moves the material away from the tooth, so the chip is
//!
//! `h_j = f_z sin φ_j − (w(t) − w(t − τ))·(d·r̂_j)`,
//!
//! and the tangential `K_t a_p h` and radial `K_r a_p h` tooth forces push the workpiece with
//! `F·d = a_p K_t h_j [(cos φ + k_r sin φ) d_x + (−sin φ + k_r cos φ) d_y]`, `k_r = K_r/K_t`.
//! Averaging over one revolution (zero-order term) gives
//!
//! `F_dyn = −a_p K_t α₀ (w(t) − w(t − τ))`,
//! `α₀ = Z/(2π) ∫ (d·r̂)[(cos φ + k_r sin φ) d_x + (−sin φ + k_r cos φ) d_y] dφ`,
//!
//! which for `β = 0` and half-immersion up-milling is `Z/(2π)·(1/2 + k_r π/4)` = 0.4563 with
//! the seed's `Z = 4`, `k_r = 210/760`. The characteristic equation is
//! `1 + a_p K_t α₀ (1 − e^{−iωτ}) Φ(iω) = 0`, so `a_lim = −1/(2 K_t α₀ Re Φ)`.

use num_complex::Complex64;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// One vibration mode of the workpiece tip (modal coordinates at the tip: mass, stiffness, damping ratio).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Mode {
    /// Modal mass [kg].
    pub mass: f64,
    /// Modal stiffness [N/m].
    pub stiffness: f64,
    /// Damping ratio [-].
    pub damping_ratio: f64,
}

impl Mode {
    /// Mode from natural frequency [Hz], damping ratio and peak receptance `1/(2kζ√(1−ζ²))` [m/N].
    pub fn from_peak(freq_hz: f64, damping_ratio: f64, peak_receptance: f64) -> Mode {
        let k = 1.0 / (2.0 * damping_ratio * (1.0 - damping_ratio * damping_ratio).sqrt() * peak_receptance);
        let wn = 2.0 * PI * freq_hz;
        Mode { mass: k / (wn * wn), stiffness: k, damping_ratio }
    }
    /// Natural frequency [Hz].
    pub fn frequency_hz(&self) -> f64 {
        self.omega_n() / (2.0 * PI)
    }
    /// Peak receptance `1/(2kζ√(1−ζ²))` [m/N] (the inverse of [`Mode::from_peak`]).
    pub fn peak_receptance(&self) -> f64 {
        1.0 / (2.0 * self.damping_ratio * (1.0 - self.damping_ratio * self.damping_ratio).sqrt() * self.stiffness)
    }
    /// Natural frequency [rad/s].
    pub fn omega_n(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }
    /// Viscous damping `2ζ√(mk)` [N s/m].
    pub fn damping(&self) -> f64 {
        2.0 * self.damping_ratio * (self.mass * self.stiffness).sqrt()
    }
    /// Receptance `1/(k − mω² + icω)` [m/N].
    pub fn receptance(&self, omega: f64) -> Complex64 {
        Complex64::new(self.stiffness - self.mass * omega * omega, self.damping() * omega).inv()
    }
}

/// Milling direction (one type with the process FMU's).
pub use milling_process::MillingMode;

model_kit::choice! {
    /// Which cutting-force model the plant integrates.
    #[derive(Serialize, Deserialize)]
    pub enum CuttingModel ("CuttingModel", "cutting-force model") {
        /// Mechanistic force summed over the teeth, engagement window, loss of contact.
        TimeDomain = "time_domain", "mechanistic force per tooth, engagement window, loss of contact";
        /// Linear zero-order model: mean static force plus `−a_p K_t α₀ (w − w(t−τ))`.
        Averaged = "averaged", "linear zero-order model with the Altintas-Budak directional factor";
    }
}

model_kit::choice! {
    /// How the plant advances its state over one cell of the internal grid (see [`crate::exact`]).
    #[derive(Serialize, Deserialize)]
    pub enum Integrator ("Integrator", "time integration scheme of the plant") {
        /// Linear modal + actuator dynamics exact (matrix exponential, once per step size), cutting
        /// force, sinusoidal disturbance and drift linear in time over the cell (two force evaluations).
        Exact = "exact", "exact linear dynamics, force linear over the cell (fast)";
        /// Classical RK4 on every term (four force evaluations per cell): the slow reference.
        Reference = "reference", "classical RK4, the slow reference";
    }
}

/// Workpiece (cantilever tip) parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Workpiece {
    /// First bending mode (Table 1: 30 kg, 2.40e7 N/m, ζ 0.0088).
    pub first: Mode,
    /// Higher modes superposed at the tip (Section 3.1), used when `modes == 3`.
    pub higher: [Mode; 2],
    /// Number of modes simulated: 1 or 3.
    pub modes: u32,
    /// Initial tip displacement [m] (for free-decay studies).
    pub initial_displacement: f64,
}

/// Cutting parameters (Table 4).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Cutting {
    /// Cutting on/off.
    pub enabled: bool,
    /// Force model.
    pub model: CuttingModel,
    /// Number of teeth Z.
    pub teeth: u32,
    /// Tool radius [m].
    pub tool_radius: f64,
    /// Radial engagement a_e [m].
    pub radial_engagement: f64,
    /// Up- or down-milling.
    pub milling: MillingMode,
    /// Axial depth of cut a_p [m].
    pub axial_depth: f64,
    /// Tangential cutting coefficient K_t [N/m²].
    pub kt: f64,
    /// Radial cutting coefficient K_r [N/m²].
    pub kr: f64,
    /// Angle β of the beam's bending direction from the feed axis towards +y [rad].
    pub direction_angle: f64,
}

/// Inertial actuator `ż = A z + B u`, `F_a = C z + D u` (u saturated at ±`f_max`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Actuator {
    /// State matrix, row-major.
    pub a: [[f64; 2]; 2],
    /// Input vector.
    pub b: [f64; 2],
    /// Output row.
    pub c: [f64; 2],
    /// Feedthrough.
    pub d: f64,
    /// Saturation of the command [N].
    pub f_max: f64,
}

/// Disturbance sources (Section 3.4).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Disturbance {
    /// Broadband Gaussian force on/off.
    pub noise: bool,
    /// Its RMS [N].
    pub noise_rms: f64,
    /// Its bandwidth (4th-order Butterworth cut-off) [Hz].
    pub noise_bandwidth: f64,
    /// Stiffness drift on/off.
    pub drift: bool,
    /// Relative drift amplitude A in `K(t) = K(1 + A sin 2πft)` [-].
    pub drift_amplitude: f64,
    /// Drift frequency [Hz].
    pub drift_frequency: f64,
    /// Sinusoidal force amplitude [N].
    pub sine_amplitude: f64,
    /// Sinusoidal force frequency [Hz].
    pub sine_frequency: f64,
}

/// All plant parameters. `Default` = seed 000.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlantParams {
    /// Workpiece.
    pub workpiece: Workpiece,
    /// Cutting process.
    pub cutting: Cutting,
    /// Actuator.
    pub actuator: Actuator,
    /// Disturbances.
    pub disturbance: Disturbance,
    /// Random seed of the noise.
    pub seed: u64,
    /// Internal integration step [s] (the noise grid).
    pub internal_step: f64,
    /// Integration scheme (default [`Integrator::Exact`]; [`Integrator::Reference`] is RK4).
    pub integrator: Integrator,
}

/// The seed's first mode (Table 1).
pub const FIRST_MODE: Mode = Mode { mass: 30.0, stiffness: 2.40e7, damping_ratio: 0.0088 };

impl Default for PlantParams {
    fn default() -> Self {
        PlantParams {
            workpiece: Workpiece {
                first: FIRST_MODE,
                higher: [Mode::from_peak(895.8, 0.00936, 0.0562e-6), Mode::from_peak(2499.8, 0.00954, 0.00708e-6)],
                modes: 1,
                initial_displacement: 0.0,
            },
            cutting: Cutting {
                enabled: true,
                model: CuttingModel::TimeDomain,
                teeth: 4,
                tool_radius: 8e-3,
                radial_engagement: 8e-3,
                milling: MillingMode::Up,
                axial_depth: 1e-3,
                kt: 760e6,
                kr: 210e6,
                direction_angle: 0.0,
            },
            actuator: Actuator {
                a: [[-15.834, -2785.6], [1.0, 0.0]],
                b: [1.0, 0.0],
                c: [-15.834, -2785.6],
                d: 1.0,
                f_max: 27.0,
            },
            disturbance: Disturbance {
                noise: true,
                noise_rms: 50.0,
                noise_bandwidth: 2000.0,
                drift: true,
                drift_amplitude: 0.1,
                drift_frequency: 0.5,
                sine_amplitude: 0.0,
                sine_frequency: 50.0,
            },
            seed: 1,
            internal_step: 1e-5,
            integrator: Integrator::Exact,
        }
    }
}

/// Seed default spindle speed [rpm].
pub const DEFAULT_SPINDLE_SPEED: f64 = 2000.0;
/// Seed default feed per tooth [m].
pub const DEFAULT_FEED_PER_TOOTH: f64 = 0.05e-3;

impl PlantParams {
    /// The Ozsoy et al. benchmark plant of seed 000's Section 5.7 (Table 8): first mode
    /// 142.1 Hz, ζ = 0.88 %, k = 2.43e7 N/m; 16 mm 4-flute end mill, half-immersion
    /// down-milling; ±27 N actuator. The seed gives no cutting coefficients and no direction for
    /// it: the seed's Table 4 coefficients (K_t = 760, K_r = 210 N/mm²) and the flexible
    /// direction normal to the feed (β = 90°), for which down-milling has the same
    /// `α₀ = Z/(2π)(1/2 + k_r π/4)` as up-milling along the feed. Actuator as Table 1.
    pub fn ozsoy_benchmark() -> PlantParams {
        let mut p = PlantParams::default();
        let k = 2.43e7;
        let wn = 2.0 * PI * 142.1;
        p.workpiece.first = Mode { mass: k / (wn * wn), stiffness: k, damping_ratio: 0.0088 };
        p.workpiece.modes = 1;
        p.cutting.teeth = 4;
        p.cutting.tool_radius = 8e-3;
        p.cutting.radial_engagement = 8e-3;
        p.cutting.milling = MillingMode::Down;
        p.cutting.direction_angle = PI / 2.0;
        p.actuator.f_max = 27.0;
        p
    }

    /// The enabled modes as a list (first mode first).
    pub fn mode_list(&self) -> Vec<Mode> {
        let mut v = vec![self.workpiece.first];
        if self.workpiece.modes >= 3 {
            v.extend_from_slice(&self.workpiece.higher);
        }
        v
    }

    /// Check ranges; the error says which parameter is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let pos = |name: &str, x: f64| {
            if x.is_finite() && x > 0.0 { Ok(()) } else { Err(format!("{name} must be finite and > 0 (got {x})")) }
        };
        for (i, m) in self.mode_list().iter().enumerate() {
            pos(&format!("mode {} mass", i + 1), m.mass)?;
            pos(&format!("mode {} stiffness", i + 1), m.stiffness)?;
            if !(m.damping_ratio >= 0.0 && m.damping_ratio < 1.0) {
                return Err(format!("mode {} damping ratio must be in [0, 1)", i + 1));
            }
        }
        if self.workpiece.modes != 1 && self.workpiece.modes != 3 {
            return Err(format!("workpiece.modes must be 1 or 3 (got {})", self.workpiece.modes));
        }
        let c = &self.cutting;
        if c.teeth == 0 {
            return Err("cutting.teeth must be >= 1".into());
        }
        pos("cutting.tool_radius", c.tool_radius)?;
        pos("cutting.radial_engagement", c.radial_engagement)?;
        if c.radial_engagement > 2.0 * c.tool_radius {
            return Err("cutting.radial_engagement must not exceed the tool diameter".into());
        }
        if !(c.axial_depth >= 0.0 && c.kt >= 0.0 && c.kr >= 0.0) {
            return Err("cutting.axial_depth, kt, kr must be >= 0".into());
        }
        pos("internal_step", self.internal_step)?;
        let d = &self.disturbance;
        if d.noise_rms.is_nan() || d.noise_rms < 0.0 {
            return Err("disturbance.noise_rms must be >= 0".into());
        }
        if d.noise && !(d.noise_bandwidth > 0.0 && d.noise_bandwidth < 0.45 / self.internal_step) {
            return Err(format!(
                "disturbance.noise_bandwidth must be in (0, 0.45/internal_step = {} Hz)",
                0.45 / self.internal_step
            ));
        }
        if self.actuator.f_max.is_nan() || self.actuator.f_max < 0.0 {
            return Err("actuator.f_max must be >= 0".into());
        }
        Ok(())
    }

    /// Engagement window `[φ_st, φ_ex]` [rad].
    pub fn engagement(&self) -> (f64, f64) {
        let c = &self.cutting;
        c.milling.engagement(c.radial_engagement, c.tool_radius)
    }

    /// Tip receptance x/F [m/N] of the enabled workpiece modes at `omega` [rad/s].
    pub fn receptance(&self, omega: f64) -> Complex64 {
        self.mode_list().iter().map(|m| m.receptance(omega)).sum()
    }

    /// Actuator transfer F_a/u [-] at `omega` (linear, unsaturated): `C (iωI − A)⁻¹ B + D`.
    pub fn actuator_response(&self, omega: f64) -> Complex64 {
        let a = &self.actuator;
        let s = Complex64::new(0.0, omega);
        // (sI − A)⁻¹ = adj / det
        let m00 = s - a.a[0][0];
        let m01 = Complex64::from(-a.a[0][1]);
        let m10 = Complex64::from(-a.a[1][0]);
        let m11 = s - a.a[1][1];
        let det = m00 * m11 - m01 * m10;
        let x0 = (m11 * a.b[0] - m01 * a.b[1]) / det;
        let x1 = (-m10 * a.b[0] + m00 * a.b[1]) / det;
        x0 * a.c[0] + x1 * a.c[1] + a.d
    }

    /// Averaged (zero-order) directional coefficient α₀ [-] (module docs), such that
    /// `F_dyn = −a_p K_t α₀ (x(t) − x(t − τ))`. Includes `Z/(2π)`.
    pub fn directional_coefficient(&self) -> f64 {
        let (dx, dy) = self.direction();
        let kr = self.cutting.kr / self.cutting.kt.max(f64::MIN_POSITIVE);
        let (s, e) = self.engagement();
        let i = |f: fn(f64) -> f64| f(e) - f(s);
        // antiderivatives of sin·cos, sin², cos²
        let sc = i(|p| 0.5 * p.sin().powi(2));
        let ss = i(|p| 0.5 * p - 0.25 * (2.0 * p).sin());
        let cc = i(|p| 0.5 * p + 0.25 * (2.0 * p).sin());
        // (dx sin + dy cos)·[(cos + kr sin) dx + (−sin + kr cos) dy]
        let integral =
            dx * dx * (sc + kr * ss) + dx * dy * (-ss + kr * sc) + dy * dx * (cc + kr * sc) + dy * dy * (-sc + kr * cc);
        self.cutting.teeth as f64 / (2.0 * PI) * integral
    }

    /// Mean static cutting force along the beam per unit of `a_p K_t f_z` [-]:
    /// `Z/(2π) ∫ sin φ [(cos φ + k_r sin φ) d_x + (−sin φ + k_r cos φ) d_y] dφ`.
    pub fn static_force_coefficient(&self) -> f64 {
        let (dx, dy) = self.direction();
        let kr = self.cutting.kr / self.cutting.kt.max(f64::MIN_POSITIVE);
        let (s, e) = self.engagement();
        let i = |f: fn(f64) -> f64| f(e) - f(s);
        let sc = i(|p| 0.5 * p.sin().powi(2));
        let ss = i(|p| 0.5 * p - 0.25 * (2.0 * p).sin());
        let integral = dx * (sc + kr * ss) + dy * (-ss + kr * sc);
        self.cutting.teeth as f64 / (2.0 * PI) * integral
    }

    /// Unit vector of the beam's bending direction in the (feed, normal) frame.
    pub fn direction(&self) -> (f64, f64) {
        (self.cutting.direction_angle.cos(), self.cutting.direction_angle.sin())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn half_immersion_up_milling_factor_has_closed_form() {
        let p = PlantParams::default();
        let kr: f64 = 210.0 / 760.0;
        assert_relative_eq!(
            p.directional_coefficient(),
            4.0 / (2.0 * PI) * (0.5 + kr * PI / 4.0),
            max_relative = 1e-12
        );
        // full-immersion normal direction: Z/2π ∫_0^π cos φ (−sin φ + kr cos φ) dφ = Z/2π · kr π/2
        let mut q = p.clone();
        q.cutting.radial_engagement = 16e-3;
        q.cutting.direction_angle = PI / 2.0;
        assert_relative_eq!(q.directional_coefficient(), 4.0 / (2.0 * PI) * kr * PI / 2.0, max_relative = 1e-9);
    }

    #[test]
    fn directional_coefficient_matches_quadrature() {
        for (beta, milling, ae) in [(0.3, MillingMode::Down, 5e-3), (-1.1, MillingMode::Up, 12e-3)] {
            let mut p = PlantParams::default();
            p.cutting.direction_angle = beta;
            p.cutting.milling = milling;
            p.cutting.radial_engagement = ae;
            let (dx, dy) = p.direction();
            let kr = 210.0 / 760.0;
            let (s, e) = p.engagement();
            let n = 20000;
            let mut acc = 0.0;
            for i in 0..n {
                let f = s + (e - s) * (i as f64 + 0.5) / n as f64;
                let proj = dx * f.sin() + dy * f.cos();
                acc += proj * ((f.cos() + kr * f.sin()) * dx + (-f.sin() + kr * f.cos()) * dy);
            }
            let q = 4.0 / (2.0 * PI) * acc * (e - s) / n as f64;
            assert_relative_eq!(p.directional_coefficient(), q, max_relative = 1e-6);
        }
    }

    #[test]
    fn higher_modes_have_the_published_peaks() {
        let p = PlantParams::default();
        for (m, f, peak) in [(p.workpiece.higher[0], 895.8, 0.0562e-6), (p.workpiece.higher[1], 2499.8, 0.00708e-6)] {
            assert_relative_eq!(m.omega_n() / (2.0 * PI), f, max_relative = 1e-12);
            // peak of |Φ| is at ω_n√(1−2ζ²)
            let z = m.damping_ratio;
            let w = m.omega_n() * (1.0 - 2.0 * z * z).sqrt();
            assert_relative_eq!(m.receptance(w).norm(), peak, max_relative = 1e-9);
        }
    }

    #[test]
    fn actuator_is_a_high_pass_with_unit_gain() {
        let p = PlantParams::default();
        // F_a/u = s²/(s² + 15.834 s + 2785.6)
        for w in [1.0, 52.78, 900.0, 1e4] {
            let s = Complex64::new(0.0, w);
            let expect = s * s / (s * s + 15.834 * s + 2785.6);
            assert_relative_eq!((p.actuator_response(w) - expect).norm(), 0.0, epsilon = 1e-12);
        }
        assert!((p.actuator_response(2.0 * PI * 143.0).norm() - 1.0).abs() < 0.01);
    }
}
