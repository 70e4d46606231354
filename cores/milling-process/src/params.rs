//! Process parameters (`Default` = seed 000's cut: Table 4) and the tool geometry.
//!
//! # Conventions
//!
//! Frame: `x` along the feed, `y` normal to it; the tooth angle `φ` is measured clockwise from
//! `+y` (Altintas–Budak), so the outward radial unit vector of a tooth at `φ` is
//! `r̂ = (sin φ, cos φ)`. Up-milling engages `φ ∈ [0, φ_c]`, down-milling `φ ∈ [π − φ_c, π]`,
//! `φ_c = arccos(1 − a_e/R)`; explicit entry/exit angles override both.
//!
//! Tooth `j` sits at `φ_j = θ + ψ_j` (`ψ_0 = 0`; uniform pitch `ψ_j = 2πj/Z`, or the given
//! angles). The gap in front of tooth `j` is `g_j = ψ_j − ψ_{j−1}` (`g_0 = 2π + ψ_0 − ψ_{Z−1}`),
//! and the feed it removes is `f_z Z g_j / 2π` (`f_z` for a uniform pitch).
//!
//! # Force laws (per tooth, engaged and cutting, chip `h > 0`)
//!
//! * `linear`: `F_t = a_p (K_t h + K_te)`, `F_r = a_p (K_r h + K_re)`;
//! * `power` (seed 002, Eq. 1): `F_t = a_p K_t h^{x_F}`, `F_r = a_p K_r h^{x_F}` (`K` in
//!   N/m^{1+x_F});
//! * `cubic` (seed 003, Eq. 6's integrand): `F_t = ξ₁h³ + ξ₂h² + ξ₃h + ξ₄`,
//!   `F_r = δ₁h³ + δ₂h² + δ₃h + δ₄` (the coefficients are whole-tooth forces, as the seed
//!   gives them: `a_p` does not scale them).
//!
//! The force on the tool is `−[F_t (cos φ, −sin φ) + F_r (sin φ, cos φ)]`, the workpiece gets
//! the opposite (seed 002's `S(φ)[K_t; K_r]`).

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The most teeth with individually given angles.
pub const MAX_PITCH_TEETH: usize = 8;

model_kit::choice! {
    /// Milling direction.
    #[derive(Serialize, Deserialize)]
    pub enum MillingMode ("MillingMode", "milling direction") {
        /// Up-milling (conventional): the chip starts thin.
        Up = "up", "up-milling (conventional)";
        /// Down-milling (climb): the chip starts thick.
        Down = "down", "down-milling (climb)";
    }
}

impl MillingMode {
    /// Engagement window `[φ_st, φ_ex]` [rad] of a radial engagement `a_e` with a tool of
    /// radius `r` (angles from the feed-normal direction): `φ_c = acos(1 − a_e/r)`, up-milling
    /// `[0, φ_c]`, down-milling `[π − φ_c, π]`.
    pub fn engagement(self, radial_engagement: f64, tool_radius: f64) -> (f64, f64) {
        let phi_c = (1.0 - radial_engagement / tool_radius).clamp(-1.0, 1.0).acos();
        match self {
            MillingMode::Up => (0.0, phi_c),
            MillingMode::Down => (PI - phi_c, PI),
        }
    }
}

model_kit::choice! {
    /// Cutting-force law of one tooth.
    #[derive(Serialize, Deserialize)]
    pub enum ForceLaw ("ForceLaw", "cutting-force law of one tooth") {
        /// `F = a_p (K h + K_e)`.
        Linear = "linear", "linear in the chip, with edge coefficients";
        /// `F = a_p K h^x_F` (seed 002).
        Power = "power", "power law in the chip (seed 002)";
        /// `F = c3 h^3 + c2 h^2 + c1 h + c0` (seed 003).
        Cubic = "cubic", "cubic polynomial in the chip (seed 003)";
    }
}

/// Cutting coefficients of all three laws (only the selected law's are used).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Coefficients {
    /// Which law.
    pub law: ForceLaw,
    /// Tangential coefficient K_t [N/m² linear, N/m^(1+x_F) power].
    pub kt: f64,
    /// Radial coefficient K_r [same unit as K_t].
    pub kr: f64,
    /// Tangential edge coefficient K_te [N/m] (linear law).
    pub kte: f64,
    /// Radial edge coefficient K_re [N/m] (linear law).
    pub kre: f64,
    /// Exponent x_F of the power law [-].
    pub exponent: f64,
    /// Cubic tangential coefficients ξ₁..ξ₄ of h³, h², h, 1 [N/m³, N/m², N/m, N].
    pub xi: [f64; 4],
    /// Cubic radial coefficients δ₁..δ₄ of h³, h², h, 1.
    pub delta: [f64; 4],
}

/// All process parameters. `Default` = seed 000 (4 teeth, 8 mm radius, half-immersion
/// up-milling, 1 mm depth, K_t = 760, K_r = 210 N/mm²).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ProcessParams {
    /// Number of teeth Z.
    pub teeth: u32,
    /// Use [`ProcessParams::tooth_angles`] instead of a uniform pitch.
    pub variable_pitch: bool,
    /// Angle ψ_j of tooth j [rad] (increasing, spanning less than 2π), first Z used.
    pub tooth_angles: [f64; MAX_PITCH_TEETH],
    /// Tool radius R [m].
    pub tool_radius: f64,
    /// Radial engagement a_e [m].
    pub radial_engagement: f64,
    /// Up- or down-milling.
    pub milling: MillingMode,
    /// Use the explicit entry/exit angles instead of (a_e, milling).
    pub explicit_angles: bool,
    /// Entry angle φ_st [rad].
    pub entry_angle: f64,
    /// Exit angle φ_ex [rad].
    pub exit_angle: f64,
    /// Axial depth of cut a_p [m].
    pub axial_depth: f64,
    /// Entry ramp [s]: the depth in the cut rises linearly from 0 to `axial_depth` over this
    /// time after the process's start (the tool feeding into the material), so the cut starts
    /// without the impulse of a full engagement at once; 0 (the default): full depth at once.
    pub depth_ramp_time: f64,
    /// Force law and coefficients.
    pub coefficients: Coefficients,
    /// Chip from the innermost of the last Z passes (a tooth that left the cut leaves the
    /// surface to the one after it); off: the previous tooth's pass only.
    pub multiple_regeneration: bool,
}

impl Default for ProcessParams {
    fn default() -> Self {
        let mut tooth_angles = [0.0; MAX_PITCH_TEETH];
        for (j, a) in tooth_angles.iter_mut().enumerate().take(4) {
            *a = j as f64 * PI / 2.0;
        }
        ProcessParams {
            teeth: 4,
            variable_pitch: false,
            tooth_angles,
            tool_radius: 8e-3,
            radial_engagement: 8e-3,
            milling: MillingMode::Up,
            explicit_angles: false,
            entry_angle: 0.0,
            exit_angle: PI / 2.0,
            axial_depth: 1e-3,
            depth_ramp_time: 0.0,
            coefficients: Coefficients {
                law: ForceLaw::Linear,
                kt: 760e6,
                kr: 210e6,
                kte: 0.0,
                kre: 0.0,
                exponent: 1.0,
                // seed 003 Table/Section 2, with the readings of the README (ξ₄ = 1700 N)
                xi: [6700e9, -4900e6, 3000e3, 1700.0],
                delta: [13000e9, -7200e6, 13.0, 25.0],
            },
            multiple_regeneration: true,
        }
    }
}

impl ProcessParams {
    /// Check ranges; the error names the parameter.
    pub fn validate(&self) -> Result<(), String> {
        let pos = |name: &str, x: f64| {
            if x.is_finite() && x > 0.0 { Ok(()) } else { Err(format!("{name} must be finite and > 0 (got {x})")) }
        };
        if self.teeth == 0 || self.teeth > 100 {
            return Err(format!("teeth must be in 1..=100 (got {})", self.teeth));
        }
        if self.variable_pitch {
            let z = self.teeth as usize;
            if z > MAX_PITCH_TEETH {
                return Err(format!("variable pitch takes at most {MAX_PITCH_TEETH} teeth (got {z})"));
            }
            let a = &self.tooth_angles[..z];
            let finite = a.iter().all(|x| x.is_finite());
            if !finite || a.windows(2).any(|w| w[1] <= w[0]) || a[z - 1] - a[0] >= 2.0 * PI {
                return Err("tooth_angles must increase and span less than 2 pi".into());
            }
        }
        pos("tool_radius", self.tool_radius)?;
        pos("radial_engagement", self.radial_engagement)?;
        if self.radial_engagement > 2.0 * self.tool_radius {
            return Err("radial_engagement must not exceed the tool diameter".into());
        }
        if self.explicit_angles
            && !(self.entry_angle >= 0.0 && self.exit_angle > self.entry_angle && self.exit_angle <= PI)
        {
            return Err("entry/exit angles must satisfy 0 <= entry < exit <= pi".into());
        }
        if !(self.axial_depth.is_finite() && self.axial_depth >= 0.0) {
            return Err("axial_depth must be finite and >= 0".into());
        }
        if !(self.depth_ramp_time.is_finite() && self.depth_ramp_time >= 0.0) {
            return Err(format!("depth_ramp_time must be finite and >= 0 (got {})", self.depth_ramp_time));
        }
        let c = &self.coefficients;
        let all = [c.kt, c.kr, c.kte, c.kre, c.exponent].into_iter().chain(c.xi).chain(c.delta);
        if !all.clone().all(f64::is_finite) {
            return Err("cutting coefficients must be finite".into());
        }
        if !(c.kt >= 0.0 && c.kr >= 0.0) {
            return Err("kt and kr must be >= 0".into());
        }
        if !(c.exponent > 0.0 && c.exponent <= 2.0) {
            return Err(format!("exponent x_F must be in (0, 2] (got {})", c.exponent));
        }
        Ok(())
    }

    /// Engagement window `[φ_st, φ_ex]` [rad].
    pub fn engagement(&self) -> (f64, f64) {
        if self.explicit_angles {
            return (self.entry_angle, self.exit_angle);
        }
        self.milling.engagement(self.radial_engagement, self.tool_radius)
    }

    /// Tooth angles ψ_j [rad] (uniform or given).
    pub fn tooth_offsets(&self) -> Vec<f64> {
        let z = self.teeth as usize;
        if self.variable_pitch {
            self.tooth_angles[..z].to_vec()
        } else {
            (0..z).map(|j| j as f64 * 2.0 * PI / z as f64).collect()
        }
    }

    /// Gap g_j in front of each tooth [rad] (sums to 2π).
    pub fn gaps(&self) -> Vec<f64> {
        let psi = self.tooth_offsets();
        let z = psi.len();
        if !self.variable_pitch {
            return vec![2.0 * PI / z as f64; z];
        }
        (0..z).map(|j| if j == 0 { 2.0 * PI + psi[0] - psi[z - 1] } else { psi[j] - psi[j - 1] }).collect()
    }

    /// Tangential and radial force of one tooth [N] at chip `h` > 0.
    pub fn tooth_force(&self, h: f64) -> (f64, f64) {
        let c = &self.coefficients;
        let ap = self.axial_depth;
        match c.law {
            ForceLaw::Linear => (ap * (c.kt * h + c.kte), ap * (c.kr * h + c.kre)),
            ForceLaw::Power => {
                let hx = h.powf(c.exponent);
                (ap * c.kt * hx, ap * c.kr * hx)
            }
            ForceLaw::Cubic => (cubic(&c.xi, h), cubic(&c.delta, h)),
        }
    }

    /// Slope (dF_t/dh, dF_r/dh) of one tooth's force at chip `h` > 0 (the linearisation).
    pub fn tooth_force_slope(&self, h: f64) -> (f64, f64) {
        let c = &self.coefficients;
        let ap = self.axial_depth;
        match c.law {
            ForceLaw::Linear => (ap * c.kt, ap * c.kr),
            ForceLaw::Power => {
                let s = c.exponent * h.powf(c.exponent - 1.0);
                (ap * c.kt * s, ap * c.kr * s)
            }
            ForceLaw::Cubic => {
                let d = |k: &[f64; 4]| 3.0 * k[0] * h * h + 2.0 * k[1] * h + k[2];
                (d(&c.xi), d(&c.delta))
            }
        }
    }
}

/// `k₁h³ + k₂h² + k₃h + k₄` (Horner).
fn cubic(k: &[f64; 4], h: f64) -> f64 {
    ((k[0] * h + k[1]) * h + k[2]) * h + k[3]
}

/// Force on the tool [N] of one tooth at angle `phi` with tangential and radial forces.
pub fn tool_force(phi: f64, ft: f64, fr: f64) -> [f64; 2] {
    let (s, c) = phi.sin_cos();
    [-(ft * c + fr * s), -(-ft * s + fr * c)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_half_immersion_up_milling() {
        let p = ProcessParams::default();
        p.validate().unwrap();
        let (s, e) = p.engagement();
        assert!(s == 0.0 && (e - PI / 2.0).abs() < 1e-15);
        assert_eq!(p.gaps(), vec![PI / 2.0; 4]);
        let mut q = p.clone();
        q.variable_pitch = true;
        q.tooth_angles[..4].copy_from_slice(&[0.0, 1.4, 3.2, 4.6]);
        let g = q.gaps();
        assert!((g.iter().sum::<f64>() - 2.0 * PI).abs() < 1e-12 && (g[0] - (2.0 * PI - 4.6)).abs() < 1e-12);
        q.tooth_angles[2] = 1.0;
        assert!(q.validate().unwrap_err().contains("tooth_angles"));
    }

    #[test]
    fn the_force_on_the_tool_points_back_against_the_tooth_motion_and_outward_radial_force() {
        // tooth at phi = pi/2 sits at +x and moves along -y: tangential force on the tool along +y, radial along -x
        let f = tool_force(PI / 2.0, 1.0, 0.0);
        assert!(f[0].abs() < 1e-15 && (f[1] - 1.0).abs() < 1e-15);
        let f = tool_force(PI / 2.0, 0.0, 1.0);
        assert!((f[0] + 1.0).abs() < 1e-15 && f[1].abs() < 1e-15);
    }

    #[test]
    fn slopes_are_the_derivatives_of_the_laws() {
        let mut p = ProcessParams::default();
        for law in [ForceLaw::Linear, ForceLaw::Power, ForceLaw::Cubic] {
            p.coefficients.law = law;
            p.coefficients.exponent = 0.744;
            let h = 3e-5;
            let d = 1e-9;
            let (a, b) = (p.tooth_force(h + d), p.tooth_force(h - d));
            let (st, sr) = p.tooth_force_slope(h);
            assert!(((a.0 - b.0) / (2.0 * d) - st).abs() <= 1e-5 * st.abs(), "{law:?}");
            assert!(((a.1 - b.1) / (2.0 * d) - sr).abs() <= 1e-5 * sr.abs(), "{law:?}");
        }
    }
}
