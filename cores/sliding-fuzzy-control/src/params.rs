//! The controller's parameters: the mode, the sliding-mode and learning constants, the nominal
//! axes, the D-PID gains, and two readings the paper leaves open.
//!
//! # The nominal model (`nominal_model`)
//!
//! Eq. 22 writes the axis as `p(k+1) = j[z(k)] + h[z(k)] u(k)` and says that `A_dis` and
//! `B_dis` are unknown; the fuzzy systems model `j` and `h`. The controller starts from a
//! nominal `ĵ` (the fuzzy corrections start at zero) and the readings differ in how much of
//! `A_dis` it knows:
//!
//! * `exact_zoh` (default): `A_dis = e^{A T}` of the nominal axis (m, c, k), the exact
//!   zero-order-hold model ([`crate::linear::zoh`]); with Table 1's values this is the true
//!   linear part of the plant;
//! * `euler`: `A_dis = I + A T`, so `ĵ = p + T ṗ` (the first-order prediction);
//! * `identity`: `A_dis = I`, so `ĵ = p` (nothing known but the input gain).
//!
//! `B_dis` stays the exact ZOH input vector in every reading: its position entry `b₀` is the
//! input normalisation (`U = X/b₀`, nominal `ĥ = 1`) and its velocity entry is used by the
//! one-step prediction below.
//!
//! # The computation delay (`computation_delay`)
//!
//! Eq. 19 holds `u(k)`, computed from `V(k)`, over `[kT, (k+1)T)`: zero computation time (the
//! default, the paper's reading). With `computation_delay` the command computed from the
//! sample at `t_k` acts over `[t_{k+1}, t_{k+2})`, as in a digital controller that needs the
//! whole period to compute; the sliding-mode controllers then apply their law to the state
//! predicted at `t_{k+1}` by their own model (the nominal model plus the fuzzy corrections for
//! the position, the nominal model for the velocity) with the command already on its way,
//! and the D-PID simply acts one sample later.

use crate::SlidingFuzzyError;
use serde::{Deserialize, Serialize};

model_kit::choice! {
    /// Which controller runs.
    #[derive(Serialize, Deserialize)]
    pub enum ControlMode ("ControlMode", "controller of both channels") {
        /// No control: `u = 0`.
        Off = "none", "no control (u = 0)";
        /// Discrete PID (Eq. 62).
        Dpid = "dpid", "discrete-time PID (Eq. 62)";
        /// Discrete sliding mode with the nominal model.
        Dsmc = "dsmc", "discrete sliding mode control with the nominal linear model";
        /// DSMC with type-1 fuzzy compensation.
        DsmcT1 = "dsmc_t1", "DSMC with learning type-1 fuzzy compensation";
        /// DSMC with interval type-2 fuzzy compensation.
        DsmcT2 = "dsmc_t2", "DSMC with learning interval type-2 fuzzy compensation";
    }
}

model_kit::choice! {
    /// What the controller knows of `A_dis` (Eq. 22): its nominal `ĵ`.
    #[derive(Serialize, Deserialize)]
    pub enum NominalModel ("NominalModel", "nominal model of j (A_dis of Eq. 22) the sliding-mode controllers start from") {
        /// The exact ZOH model of the nominal axis.
        ExactZoh = "exact_zoh", "A_dis = exp(A T) of the nominal axis (exact zero-order hold)";
        /// The first-order (Euler) prediction.
        Euler = "euler", "A_dis = I + A T: j = p + T v (Euler prediction)";
        /// Nothing known: the position stays.
        Identity = "identity", "A_dis = I: j = p";
    }
}

/// PID gains of one axis.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct AxisGains {
    /// K_p [N per error unit].
    pub kp: f64,
    /// K_i [N per error unit per s].
    pub ki: f64,
    /// K_d [N·s per error unit].
    pub kd: f64,
}

/// Controller parameters. `Default`: the readings of [`crate::controller`] and of this module's
/// doc (exact ZOH model, no computation delay), Table 1's nominal axes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlidingFuzzyParams {
    /// Controller.
    pub mode: ControlMode,
    /// Sample period T [s].
    pub sample_period: f64,
    /// Force limit u_max [N].
    pub force_limit: f64,
    /// Sliding gain σ (normalised units).
    pub sigma: f64,
    /// k₁ of `s = e(k) + k₁e(k−1) + k₂e(k−2)`.
    pub k1: f64,
    /// k₂.
    pub k2: f64,
    /// Learning rate Ω.
    pub learning_rate: f64,
    /// Dead-zone parameter β (> 1).
    pub dead_zone: f64,
    /// Lower/upper width ratio r of the type-2 sets (1: no footprint of uncertainty).
    pub fou_ratio: f64,
    /// Karnik–Mendel type reduction instead of Eq. 25's closed form.
    pub karnik_mendel: bool,
    /// Floor h_min of ĥ (normalised).
    pub h_min: f64,
    /// Position normalisation X per axis [m].
    pub position_scale: [f64; 2],
    /// Velocity normalisation V per axis [m/s].
    pub velocity_scale: [f64; 2],
    /// Nominal masses [kg].
    pub mass: [f64; 2],
    /// Nominal damping [N·s/m].
    pub damping: [f64; 2],
    /// Nominal stiffness [N/m].
    pub stiffness: [f64; 2],
    /// D-PID gains, x axis.
    pub pid_x: AxisGains,
    /// D-PID gains, y axis.
    pub pid_y: AxisGains,
    /// D-PID error unit factor s_e (1000: error in mm).
    pub pid_error_scale: f64,
    /// The nominal model of `ĵ` (what is known of `A_dis`).
    pub nominal_model: NominalModel,
    /// One sample of computation delay: the command of sample k acts from `t_{k+1}`.
    pub computation_delay: bool,
}

impl Default for SlidingFuzzyParams {
    fn default() -> Self {
        SlidingFuzzyParams {
            mode: ControlMode::DsmcT2,
            sample_period: 1e-4,
            force_limit: 2000.0,
            sigma: 0.17,
            k1: -1.0,
            k2: 0.25,
            learning_rate: 0.9,
            dead_zone: 1.2,
            fou_ratio: 0.8,
            karnik_mendel: false,
            h_min: 0.1,
            position_scale: [0.5e-6, 0.5e-6],
            velocity_scale: [3e-4, 9e-4],
            mass: [20.0, 20.0],
            damping: [1200.0, 4300.0],
            stiffness: [7.2e6, 6.48e7],
            pid_x: AxisGains { kp: 200.0, ki: 1500.0, kd: 84.0 },
            pid_y: AxisGains { kp: 190.0, ki: 1400.0, kd: 76.0 },
            pid_error_scale: 1000.0,
            nominal_model: NominalModel::ExactZoh,
            computation_delay: false,
        }
    }
}

impl SlidingFuzzyParams {
    /// Check ranges.
    pub fn validate(&self) -> Result<(), SlidingFuzzyError> {
        let bad = |w: &str| Err(SlidingFuzzyError::Params(w.to_string()));
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !pos(self.sample_period) || !pos(self.force_limit) {
            return bad("sample period and force limit must be > 0");
        }
        if !self.sigma.is_finite() || self.sigma < 0.0 {
            return bad("sigma must be finite and >= 0");
        }
        // λ² + k₁λ + k₂ stable (Jury): |k₂| < 1, |k₁| < 1 + k₂
        if !(self.k1.is_finite() && self.k2.is_finite() && self.k2.abs() < 1.0 && self.k1.abs() < 1.0 + self.k2) {
            return bad("lambda^2 + k1 lambda + k2 must have its roots inside the unit circle");
        }
        if !(self.learning_rate > 0.0 && self.learning_rate <= 1.0) {
            return bad("learning rate must be in (0, 1]");
        }
        if !(self.dead_zone.is_finite() && self.dead_zone > 1.0) {
            return bad("dead-zone parameter beta must be > 1");
        }
        if !(self.fou_ratio > 0.0 && self.fou_ratio <= 1.0) {
            return bad("fou_ratio must be in (0, 1]");
        }
        if !pos(self.h_min) {
            return bad("h_min must be > 0");
        }
        let all = self.position_scale.iter().chain(&self.velocity_scale).chain(&self.mass).chain(&self.stiffness);
        if !all.copied().all(pos) || !self.damping.iter().all(|&c| c.is_finite() && c >= 0.0) {
            return bad("scales, masses and stiffnesses must be > 0, damping >= 0");
        }
        let g = [self.pid_x, self.pid_y];
        if !g.iter().flat_map(|g| [g.kp, g.ki, g.kd]).chain([self.pid_error_scale]).all(f64::is_finite) {
            return bad("PID gains must be finite");
        }
        Ok(())
    }
}
