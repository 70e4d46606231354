//! The design model: one structural mode driven by a disturbance force and an inertial
//! actuator, in normalised units, and the generalised plants of the H∞ and μ designs.
//!
//! # Normalised units
//!
//! Time `τ = ωₙ t`, displacement `x̃ = k x` (the static force that would cause it, in N),
//! forces in N. The mode `m ẍ + c ẋ + k x = d + F_a` becomes `x̃'' + 2ζ x̃' + x̃ = d + F_a`; the
//! actuator `F_a/u = C_a(sI − A_a)⁻¹B_a + D_a` keeps its matrices with `A_a, B_a` divided by
//! `ωₙ`. Every coefficient is O(1), which keeps the Riccati equations well conditioned; a
//! controller `ũ = K̃(s̃) x̃` found here is `u = k K̃(s/ωₙ) x` in SI
//! ([`DesignPlant::to_physical`]).
//!
//! # The model (`u → x̃`, states `[x̃, x̃', z_a]`)
//!
//! ```text
//! x̃'  = v
//! v'  = −x̃ − 2ζ v + d + C_a z_a + D_a u
//! z_a' = A_a z_a + B_a u
//! ```

use crate::DesignError;
use crate::ss::{Generalized, StateSpace};
use nalgebra::DMatrix;
use num_complex::Complex64;
use serde::{Deserialize, Serialize};

type Mat = DMatrix<f64>;

/// One mode and the inertial actuator (SI units), the machine the designs are made for.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignPlant {
    /// Modal mass \[kg\].
    pub mass: f64,
    /// Modal stiffness \[N/m\].
    pub stiffness: f64,
    /// Modal damping ratio \[-\].
    pub damping_ratio: f64,
    /// Actuator `A_a` \[1/s\].
    pub actuator_a: [[f64; 2]; 2],
    /// Actuator `B_a`.
    pub actuator_b: [f64; 2],
    /// Actuator `C_a`.
    pub actuator_c: [f64; 2],
    /// Actuator `D_a`.
    pub actuator_d: f64,
}

/// A first-order weight `W(s)` of MATLAB's `makeweight` kind: DC gain `dc`, gain 1 at the
/// crossover `ω_c`, high-frequency gain `hf` (`dc` and `hf` on opposite sides of 1):
/// `W(s) = (hf s + dc·p)/(s + p)`, `p = ω_c √((1 − hf²)/(dc² − 1))`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Weight {
    /// DC gain.
    pub dc: f64,
    /// Crossover frequency (|W| = 1) \[rad/s, normalised time\].
    pub crossover: f64,
    /// High-frequency gain.
    pub hf: f64,
}

impl Weight {
    /// The pole `p` (module docs), or why the weight is not valid.
    pub fn pole(&self) -> Result<f64, DesignError> {
        let r = (1.0 - self.hf * self.hf) / (self.dc * self.dc - 1.0);
        if !(self.dc > 0.0 && self.hf >= 0.0 && self.crossover > 0.0 && r > 0.0 && r.is_finite()) {
            return Err(DesignError::Invalid(format!(
                "weight: DC gain {} and HF gain {} must lie on opposite sides of 1, crossover {} > 0",
                self.dc, self.hf, self.crossover
            )));
        }
        Ok(self.crossover * r.sqrt())
    }

    /// `W(s)` as a state space (one state).
    pub fn system(&self) -> Result<StateSpace, DesignError> {
        let p = self.pole()?;
        // W = hf + p (dc − hf)/(s + p)
        StateSpace::new(
            Mat::from_element(1, 1, -p),
            Mat::from_element(1, 1, 1.0),
            Mat::from_element(1, 1, p * (self.dc - self.hf)),
            Mat::from_element(1, 1, self.hf),
        )
    }

    /// `W(s)` evaluated directly from its definition (the reference for [`Weight::system`]).
    pub fn at(&self, s: Complex64) -> Complex64 {
        let p = self.pole().unwrap_or(f64::NAN);
        (s * self.hf + self.dc * p) / (s + p)
    }
}

impl DesignPlant {
    /// ωₙ = √(k/m) \[rad/s\].
    pub fn omega_n(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }

    /// Viscous damping `c = 2ζ√(km)` \[N·s/m\].
    pub fn damping(&self) -> f64 {
        2.0 * self.damping_ratio * (self.stiffness * self.mass).sqrt()
    }

    /// Ranges and finiteness.
    pub fn validate(&self) -> Result<(), DesignError> {
        let all = [self.mass, self.stiffness, self.damping_ratio, self.actuator_d]
            .into_iter()
            .chain(self.actuator_a.iter().flatten().copied())
            .chain(self.actuator_b)
            .chain(self.actuator_c);
        if !(all.clone().all(f64::is_finite) && self.mass > 0.0 && self.stiffness > 0.0 && self.damping_ratio >= 0.0) {
            return Err(DesignError::Invalid(format!("design plant: need finite m > 0, k > 0, ζ ≥ 0 (got {self:?})")));
        }
        Ok(())
    }

    /// The actuator `F_a/u` in normalised time.
    pub fn actuator(&self) -> StateSpace {
        let w = self.omega_n();
        StateSpace {
            a: Mat::from_fn(2, 2, |i, j| self.actuator_a[i][j] / w),
            b: Mat::from_fn(2, 1, |i, _| self.actuator_b[i] / w),
            c: Mat::from_fn(1, 2, |_, j| self.actuator_c[j]),
            d: Mat::from_element(1, 1, self.actuator_d),
        }
    }

    /// The model of the module docs with the extra stiffness `kappa` (in units of k, e.g. the
    /// nominal cutting stiffness): `A` (4 × 4), the columns `B_u` (command) and `B_d` (force on
    /// the structure), the row `C_x` (x̃) and the row `C_F` with feedthrough `D_F` (F_a).
    pub fn model(&self, kappa: f64) -> (Mat, Mat, Mat, Mat, Mat, f64) {
        let act = self.actuator();
        let mut a = Mat::zeros(4, 4);
        a[(0, 1)] = 1.0;
        a[(1, 0)] = -(1.0 + kappa);
        a[(1, 1)] = -2.0 * self.damping_ratio;
        a[(1, 2)] = act.c[(0, 0)];
        a[(1, 3)] = act.c[(0, 1)];
        a.view_mut((2, 2), (2, 2)).copy_from(&act.a);
        let bu = Mat::from_column_slice(4, 1, &[0.0, act.d[(0, 0)], act.b[(0, 0)], act.b[(1, 0)]]);
        let bd = Mat::from_column_slice(4, 1, &[0.0, 1.0, 0.0, 0.0]);
        let cx = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
        let cf = Mat::from_row_slice(1, 4, &[0.0, 0.0, act.c[(0, 0)], act.c[(0, 1)]]);
        (a, bu, bd, cx, cf, act.d[(0, 0)])
    }

    /// The physical controller `u = k K̃(s/ωₙ) x` of a normalised `K̃` (module docs), with its
    /// states scaled so that input and output couplings are alike.
    pub fn to_physical(&self, k: &StateSpace) -> StateSpace {
        k.rescaled(self.omega_n(), self.stiffness, 1.0).io_balanced()
    }

    /// The open-loop receptance `x/F` at ω \[rad/s\] (SI).
    pub fn receptance(&self, omega: f64) -> Complex64 {
        Complex64::new(self.stiffness - self.mass * omega * omega, self.damping() * omega).inv()
    }

    /// The actuator `F_a/u` at ω \[rad/s\] (SI).
    pub fn actuator_response(&self, omega: f64) -> Complex64 {
        self.actuator().at(omega / self.omega_n())
    }
}

/// What the H∞ and μ designs weigh (module docs of [`crate::designs`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MixedSensitivity {
    /// `W_S` on `S = x̃/d` (low-pass, `hf = 0`: DC gain > 1 and crossover).
    pub ws: Weight,
    /// `W_T` on `T = −F_a/d` (high-pass: DC gain < 1, crossover, HF gain > 1).
    pub wt: Weight,
    /// Sensor-noise level ε of `y = x̃ + ε n` (regularises `D₂₁`).
    pub noise: f64,
    /// Command weight ε_u added to the `T` output, `z₂ = W_T F_a + ε_u u`: without it the
    /// inertial actuator's double zero at s = 0 is a zero of `u → z` on the imaginary axis and
    /// the problem is singular.
    pub control: f64,
}

/// The channels of a generalised plant built by [`generalized`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Channels {
    /// Number of uncertainty channels in front of the performance channels (0 for H∞).
    pub uncertain: usize,
}

/// The μ design's uncertainties: the modal stiffness `k(1 + r_k δ_k)` and the regenerative
/// cutting force of depth `b` at any speed, `−κ(1 + δ_c) x̃` with `κ = (1 + r_t) b K_t α₀ / k`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Uncertainty {
    /// Relative stiffness uncertainty r_k (0.15).
    pub stiffness: f64,
    /// The cutting disk's radius κ in units of k (0: no cutting channel).
    pub cutting: f64,
}

/// The generalised plant of the mixed-sensitivity problem (`w = [d, n]`, `z = [W_S x̃, W_T F_a + ε_u u]`,
/// `y = x̃ + ε n`), with the uncertainty channels of `unc` in front (`w = [w_k, w_c, d, n]`,
/// `z = [r_k x̃, κ x̃, W_S x̃, W_T F_a]`; the nominal plant then carries the cutting stiffness κ).
/// States: the model (4), `W_S` (1), `W_T` (1).
pub fn generalized(
    plant: &DesignPlant,
    w: &MixedSensitivity,
    unc: Option<&Uncertainty>,
) -> Result<(Generalized, Channels), DesignError> {
    let ws = w.ws.system()?;
    let wt = w.wt.system()?;
    let kappa = unc.map_or(0.0, |u| u.cutting);
    let (a0, bu, bd, cx, cf, df) = plant.model(kappa);
    let nu = if unc.is_some() { 2 } else { 0 };
    let n = 6;
    let mut a = Mat::zeros(n, n);
    a.view_mut((0, 0), (4, 4)).copy_from(&a0);
    // W_S driven by x̃, W_T driven by F_a = C_F x + D_F u
    a.view_mut((4, 0), (1, 4)).copy_from(&(&ws.b * &cx));
    a[(4, 4)] = ws.a[(0, 0)];
    a.view_mut((5, 0), (1, 4)).copy_from(&(&wt.b * &cf));
    a[(5, 5)] = wt.a[(0, 0)];
    let mut b2 = Mat::zeros(n, 1);
    b2.view_mut((0, 0), (4, 1)).copy_from(&bu);
    b2[(5, 0)] = wt.b[(0, 0)] * df;
    let mut b1 = Mat::zeros(n, nu + 2);
    for j in 0..nu {
        b1.view_mut((0, j), (4, 1)).copy_from(&bd); // uncertain forces on the structure
    }
    b1.view_mut((0, nu), (4, 1)).copy_from(&bd);
    let mut c1 = Mat::zeros(nu + 2, n);
    if let Some(u) = unc {
        c1[(0, 0)] = u.stiffness;
        c1[(1, 0)] = u.cutting;
    }
    c1[(nu, 0)] = ws.d[(0, 0)];
    c1[(nu, 4)] = ws.c[(0, 0)];
    c1.view_mut((nu + 1, 0), (1, 4)).copy_from(&(&wt.d * &cf));
    c1[(nu + 1, 5)] = wt.c[(0, 0)];
    let mut d12 = Mat::zeros(nu + 2, 1);
    d12[(nu + 1, 0)] = wt.d[(0, 0)] * df + w.control;
    let mut c2 = Mat::zeros(1, n);
    c2[(0, 0)] = 1.0;
    let mut d21 = Mat::zeros(1, nu + 2);
    d21[(0, nu + 1)] = w.noise;
    let p = Generalized { a, b1, b2, c1, c2, d11: Mat::zeros(nu + 2, nu + 2), d12, d21 };
    Ok((p, Channels { uncertain: nu }))
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn ozsoy() -> DesignPlant {
        let k = 2.43e7;
        let wn = 2.0 * std::f64::consts::PI * 142.1;
        DesignPlant {
            mass: k / (wn * wn),
            stiffness: k,
            damping_ratio: 0.0088,
            actuator_a: [[-15.834, -2785.6], [1.0, 0.0]],
            actuator_b: [1.0, 0.0],
            actuator_c: [-15.834, -2785.6],
            actuator_d: 1.0,
        }
    }

    #[test]
    fn a_weight_has_its_dc_crossover_and_hf_gains() {
        for w in [Weight { dc: 10.0, crossover: 2.0, hf: 0.0 }, Weight { dc: 0.1, crossover: 0.5, hf: 10.0 }] {
            let s = w.system().unwrap();
            assert!((s.at(0.0).norm() - w.dc).abs() < 1e-12);
            assert!((s.at(w.crossover).norm() - 1.0).abs() < 1e-12);
            assert!((s.at(1e9).norm() - w.hf).abs() < 1e-6);
            for x in [0.1, 3.0] {
                assert!((s.at(x) - w.at(Complex64::new(0.0, x))).norm() < 1e-12);
            }
        }
        assert!(Weight { dc: 0.5, crossover: 1.0, hf: 0.0 }.pole().is_err());
    }

    /// The normalised model is the receptance times k, in normalised frequency; the actuator
    /// is Table 1's.
    #[test]
    fn the_normalised_model_is_the_scaled_receptance() {
        let p = ozsoy();
        let (a, bu, bd, cx, _, _) = p.model(0.0);
        let wn = p.omega_n();
        let d = StateSpace { a: a.clone(), b: bd, c: cx.clone(), d: Mat::zeros(1, 1) };
        let u = StateSpace { a, b: bu, c: cx, d: Mat::zeros(1, 1) };
        for w in [50.0, 800.0, 892.85, 3000.0] {
            let want = p.receptance(w) * p.stiffness;
            assert!((d.at(w / wn) - want).norm() < 1e-9 * want.norm());
            let s = Complex64::new(0.0, w);
            let ga = s * s / (s * s + 15.834 * s + 2785.6);
            assert!((u.at(w / wn) - want * ga).norm() < 1e-9 * want.norm());
        }
    }
}
