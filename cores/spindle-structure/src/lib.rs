//! Seed 002's spindle (IJRNC 2015, Section 6, Figure 5, Table I): per axis `k ∈ {x, y}` the
//! chain ground –(c_a, b_a)– m_a –(c_t, b_t)– m_t, the actuator (active magnetic bearing) force
//! `F_a` and the measurement `v_a` at m_a, the cutting force `F_t` and the tool displacement
//! `v_t` at m_t. The axes are decoupled and equal.
//!
//! # Equations
//!
//! With `c_i = m_i (2π f_i)²` ("ω_i = √(c_i/m_i)", so `c` is a stiffness) and
//! `b_i = 2 ζ_i √(c_i m_i)`, per axis
//!
//! ```text
//! m_a ẍ_a = −c_a x_a − b_a ẋ_a − c_t (x_a − x_t) − b_t (ẋ_a − ẋ_t) + F_a
//! m_t ẍ_t = −c_t (x_t − x_a) − b_t (ẋ_t − ẋ_a) + F_t
//! ```
//!
//! i.e. `ẋ = A x + B_t F_t + B_a F_a`, `v_t = C_t x`, `v_a = C_a x`, state
//! `(x_a, x_t, ẋ_a, ẋ_t)` of the x axis then of the y axis: exactly
//! [`delay_stability::milling::Structure::two_mass_per_axis`] (the matrices are taken from it,
//! so the analyses and this time-domain model cannot disagree). Table I gives
//! `c_t = 3.270e6 N/m`, `c_a = 1.083e7 N/m`, `b_t = 22.1 N s/m`, `b_a = 295.6 N s/m`; the
//! coupled modes are at 1302.9 and 2525.2 Hz undamped, 1296.7 and 2517.7 Hz damped
//! (imaginary parts of the eigenvalues of A; tested).
//!
//! # Discretisation
//!
//! The forces are held over a step (zero-order hold), so the step is exact:
//! `x(t + h) = Φ(h) x(t) + Γ(h) u`, `u = (F_t, F_a)`, with
//!
//! ```text
//! exp([[A, B], [0, 0]] h) = [[Φ, Γ], [0, I]],
//! ```
//!
//! (Van Loan), computed by nalgebra's Padé scaling-and-squaring exponential once per step size
//! and cached. [`Spindle::step_rk4`] is the slow reference (classical RK4 on `n` sub-steps),
//! tested against it.
//!
//! # Frequency response
//!
//! [`Spindle::frf`] is `C (iωI − A)⁻¹ B` for any output/input pair ([`Point`]); the tool FRF
//! `G_tt` is `frf(Point::Tool, Point::Tool, ω)`.

use delay_stability::milling::{Structure, TwoMassAxis};
use nalgebra::{Complex, DMatrix, SMatrix};
use num_complex::Complex64;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// State dimension (two axes × two masses × position, velocity).
pub const STATES: usize = 8;

/// Why the spindle refused to start or to step.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpindleError {
    /// A parameter is out of range.
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// An input or the step size is out of range (the step was not taken).
    #[error("invalid input: {0}")]
    Input(String),
    /// A displacement left the physical range (|x| ≥ 1 m) or became non-finite.
    #[error("the spindle diverged at t = {t} s")]
    Diverged {
        /// Time \[s\].
        t: f64,
    },
}

/// Table I of seed 002, one axis (x and y equal).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpindleParams {
    /// Tool mass m_t \[kg\].
    pub tool_mass: f64,
    /// Actuator (bearing) mass m_a \[kg\].
    pub actuator_mass: f64,
    /// f_t = √(c_t/m_t)/2π \[Hz\].
    pub tool_frequency: f64,
    /// f_a = √(c_a/m_a)/2π \[Hz\].
    pub actuator_frequency: f64,
    /// ζ_t = b_t/(2√(c_t m_t)).
    pub tool_damping_ratio: f64,
    /// ζ_a = b_a/(2√(c_a m_a)).
    pub actuator_damping_ratio: f64,
}

impl Default for SpindleParams {
    /// Table I: m_t 0.015 kg, m_a 0.14 kg, 2350 Hz, 1400 Hz, ζ_t 0.05, ζ_a 0.12.
    fn default() -> Self {
        SpindleParams::from_axis(&delay_stability::presets::SEED002_AXIS)
    }
}

impl SpindleParams {
    /// From the stability crate's axis data.
    pub fn from_axis(a: &TwoMassAxis) -> Self {
        SpindleParams {
            tool_mass: a.tool_mass,
            actuator_mass: a.actuator_mass,
            tool_frequency: a.tool_hz,
            actuator_frequency: a.actuator_hz,
            tool_damping_ratio: a.tool_zeta,
            actuator_damping_ratio: a.actuator_zeta,
        }
    }

    /// As the stability crate's axis data.
    pub fn axis(&self) -> TwoMassAxis {
        TwoMassAxis {
            tool_mass: self.tool_mass,
            actuator_mass: self.actuator_mass,
            tool_hz: self.tool_frequency,
            actuator_hz: self.actuator_frequency,
            tool_zeta: self.tool_damping_ratio,
            actuator_zeta: self.actuator_damping_ratio,
        }
    }

    /// Masses in \[1e-9, 1e9\] kg, frequencies in \[1e-3, 1e6\] Hz, damping ratios in \[0, 10\].
    pub fn validate(&self) -> Result<(), String> {
        let pos = [
            ("tool_mass", self.tool_mass),
            ("actuator_mass", self.actuator_mass),
            ("tool_frequency", self.tool_frequency),
            ("actuator_frequency", self.actuator_frequency),
        ];
        for (k, (n, v)) in pos.into_iter().enumerate() {
            let (lo, hi) = if k < 2 { (1e-9, 1e9) } else { (1e-3, 1e6) };
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                return Err(format!("{n} must be in [{lo:e}, {hi:e}] (got {v})"));
            }
        }
        for (n, v) in
            [("tool_damping_ratio", self.tool_damping_ratio), ("actuator_damping_ratio", self.actuator_damping_ratio)]
        {
            if !(v.is_finite() && (0.0..=10.0).contains(&v)) {
                return Err(format!("{n} must be in [0, 10] (got {v})"));
            }
        }
        Ok(())
    }

    /// The state-space structure (module docs).
    pub fn structure(&self) -> Structure {
        Structure::two_mass_per_axis(&self.axis())
    }
}

/// Forces on the spindle, held over a step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SpindleInputs {
    /// Force on the tool (m_t), (x, y) \[N\].
    pub tool_force: [f64; 2],
    /// Actuator force on the bearing (m_a), (x, y) \[N\].
    pub actuator_force: [f64; 2],
}

/// Displacements and velocities of the two masses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SpindleOutputs {
    /// Tool displacement v_t, (x, y) \[m\].
    pub tool: [f64; 2],
    /// Tool velocity, (x, y) \[m/s\].
    pub tool_velocity: [f64; 2],
    /// Bearing displacement v_a (the measurement), (x, y) \[m\].
    pub actuator: [f64; 2],
    /// Bearing velocity, (x, y) \[m/s\].
    pub actuator_velocity: [f64; 2],
}

/// A point of the spindle: the tool (m_t) or the actuator/sensor (m_a).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Point {
    /// The tool tip, m_t.
    Tool,
    /// The bearing, m_a.
    Actuator,
}

type Mat8 = SMatrix<f64, STATES, STATES>;
type Mat84 = SMatrix<f64, STATES, 4>;

/// `Φ(h)`, `Γ(h)` for one step size.
#[derive(Clone, Debug)]
struct Discrete {
    h: f64,
    phi: Mat8,
    gamma: Mat84,
}

/// The spindle: parameters, state, time.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Spindle {
    params: SpindleParams,
    x: [f64; STATES],
    t: f64,
    #[serde(skip)]
    cache: Option<Discrete>,
}

/// Index of the state of `point` on axis `axis` (0 = x, 1 = y); `+2` is its velocity.
fn index(point: Point, axis: usize) -> usize {
    4 * axis + if point == Point::Tool { 1 } else { 0 }
}

impl Spindle {
    /// At rest at t = 0.
    pub fn new(params: &SpindleParams) -> Result<Spindle, SpindleError> {
        params.validate().map_err(SpindleError::Parameter)?;
        Ok(Spindle { params: *params, x: [0.0; STATES], t: 0.0, cache: None })
    }

    /// The parameters.
    pub fn params(&self) -> &SpindleParams {
        &self.params
    }

    /// Time since the start \[s\].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The state `(x_a, x_t, ẋ_a, ẋ_t)` of x then y.
    pub fn state(&self) -> &[f64; STATES] {
        &self.x
    }

    /// `A` and `B = [B_t, B_a]` (8 × 4).
    pub fn matrices(&self) -> (Mat8, Mat84) {
        let s = self.params.structure();
        let a = Mat8::from_fn(|i, j| s.a[(i, j)]);
        let b = Mat84::from_fn(|i, j| if j < 2 { s.bt[(i, j)] } else { s.ba[(i, j - 2)] });
        (a, b)
    }

    /// `Φ(h)`, `Γ(h)` by the exponential of the augmented matrix (module docs); refused when
    /// `‖[A, B] h‖₁` exceeds 1e12 (or is not finite), where scaling and squaring would not end.
    pub fn discretise(&self, h: f64) -> Result<(Mat8, Mat84), SpindleError> {
        let (a, b) = self.matrices();
        let mut m = DMatrix::<f64>::zeros(STATES + 4, STATES + 4);
        m.view_mut((0, 0), (STATES, STATES)).copy_from(&(a * h));
        m.view_mut((0, STATES), (STATES, 4)).copy_from(&(b * h));
        let norm = m.column_iter().map(|c| c.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max);
        if !(norm.is_finite() && norm <= 1e12) {
            return Err(SpindleError::Input(format!(
                "the step {h} s is too large for the exponential (‖A h‖ = {norm:e})"
            )));
        }
        let e = m.exp();
        Ok((Mat8::from_fn(|i, j| e[(i, j)]), Mat84::from_fn(|i, j| e[(i, STATES + j)])))
    }

    fn check(&self, h: f64, u: &SpindleInputs) -> Result<(), SpindleError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(SpindleError::Input(format!("step size must be finite and > 0 (got {h})")));
        }
        if !u.tool_force.iter().chain(&u.actuator_force).all(|f| f.is_finite()) {
            return Err(SpindleError::Input(format!("forces must be finite (got {u:?})")));
        }
        Ok(())
    }

    fn accept(&mut self, x: [f64; STATES], h: f64) -> Result<(), SpindleError> {
        let t = self.t + h;
        if !x.iter().all(|v| v.is_finite()) || [0, 1, 4, 5].iter().any(|&i| x[i].abs() >= 1.0) {
            return Err(SpindleError::Diverged { t });
        }
        self.x = x;
        self.t = t;
        Ok(())
    }

    /// Advance by `h` with the forces `u` held (exact, module docs).
    pub fn step(&mut self, h: f64, u: &SpindleInputs) -> Result<(), SpindleError> {
        self.check(h, u)?;
        if self.cache.as_ref().is_none_or(|c| c.h.to_bits() != h.to_bits()) {
            let (phi, gamma) = self.discretise(h)?;
            self.cache = Some(Discrete { h, phi, gamma });
        }
        let Some(c) = &self.cache else { unreachable!("filled above") };
        let uu = SMatrix::<f64, 4, 1>::new(u.tool_force[0], u.tool_force[1], u.actuator_force[0], u.actuator_force[1]);
        let x = c.phi * SMatrix::<f64, STATES, 1>::from_column_slice(&self.x) + c.gamma * uu;
        let mut out = [0.0; STATES];
        out.copy_from_slice(x.as_slice());
        self.accept(out, h)
    }

    /// The slow reference: classical RK4 on `n` equal sub-steps of `h`.
    pub fn step_rk4(&mut self, h: f64, u: &SpindleInputs, n: usize) -> Result<(), SpindleError> {
        self.check(h, u)?;
        let (a, b) = self.matrices();
        let uu = SMatrix::<f64, 4, 1>::new(u.tool_force[0], u.tool_force[1], u.actuator_force[0], u.actuator_force[1]);
        let bu = b * uu;
        let f = |x: &SMatrix<f64, STATES, 1>| a * x + bu;
        let dt = h / n.max(1) as f64;
        let mut x = SMatrix::<f64, STATES, 1>::from_column_slice(&self.x);
        for _ in 0..n.max(1) {
            let k1 = f(&x);
            let k2 = f(&(x + k1 * (0.5 * dt)));
            let k3 = f(&(x + k2 * (0.5 * dt)));
            let k4 = f(&(x + k3 * dt));
            x += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (dt / 6.0);
        }
        let mut out = [0.0; STATES];
        out.copy_from_slice(x.as_slice());
        self.accept(out, h)
    }

    /// Displacements and velocities now.
    pub fn outputs(&self) -> SpindleOutputs {
        let g = |p: Point, ax: usize, vel: bool| self.x[index(p, ax) + if vel { 2 } else { 0 }];
        SpindleOutputs {
            tool: [g(Point::Tool, 0, false), g(Point::Tool, 1, false)],
            tool_velocity: [g(Point::Tool, 0, true), g(Point::Tool, 1, true)],
            actuator: [g(Point::Actuator, 0, false), g(Point::Actuator, 1, false)],
            actuator_velocity: [g(Point::Actuator, 0, true), g(Point::Actuator, 1, true)],
        }
    }

    /// Eigenvalues of `A` \[rad/s\], sorted by imaginary part (each once per axis).
    pub fn eigenvalues(&self) -> Vec<Complex64> {
        let (a, _) = self.matrices();
        let mut e: Vec<Complex64> = a.complex_eigenvalues().iter().map(|c| Complex64::new(c.re, c.im)).collect();
        e.sort_by(|p, q| p.im.total_cmp(&q.im));
        e
    }

    /// Damped natural frequencies `Im λ / 2π` \[Hz\] of the modes of one axis, ascending.
    pub fn damped_frequencies(&self) -> [f64; 2] {
        let pos: Vec<f64> = self.eigenvalues().iter().filter(|e| e.im > 0.0).map(|e| e.im / (2.0 * PI)).collect();
        // x and y give each frequency twice
        [pos[0], pos[2]]
    }

    /// Undamped natural frequencies \[Hz\]: `√eig(M⁻¹K)/2π` of one axis, ascending.
    pub fn undamped_frequencies(&self) -> [f64; 2] {
        let p = &self.params;
        let w = |f: f64| (2.0 * PI * f).powi(2);
        let (kt, ka) = (p.tool_mass * w(p.tool_frequency), p.actuator_mass * w(p.actuator_frequency));
        // M⁻¹K = [[(k_a + k_t)/m_a, −k_t/m_a], [−k_t/m_t, k_t/m_t]]
        let (a11, a12, a21, a22) =
            ((ka + kt) / p.actuator_mass, -kt / p.actuator_mass, -kt / p.tool_mass, kt / p.tool_mass);
        let tr = a11 + a22;
        let det = a11 * a22 - a12 * a21;
        let d = (0.25 * tr * tr - det).sqrt();
        [(0.5 * tr - d).sqrt() / (2.0 * PI), (0.5 * tr + d).sqrt() / (2.0 * PI)]
    }

    /// The frequency response `C_out (iωI − A)⁻¹ B_in` (2 × 2, \[m/N\]) at `omega` \[rad/s\].
    pub fn frf(&self, output: Point, input: Point, omega: f64) -> [[Complex64; 2]; 2] {
        let (a, b) = self.matrices();
        let m = SMatrix::<Complex<f64>, STATES, STATES>::from_fn(|i, j| {
            let d = if i == j { Complex64::new(0.0, omega) } else { Complex64::new(0.0, 0.0) };
            d - a[(i, j)]
        });
        let off = if input == Point::Tool { 0 } else { 2 };
        let rhs = SMatrix::<Complex<f64>, STATES, 2>::from_fn(|i, j| Complex64::from(b[(i, off + j)]));
        let mut out = [[Complex64::new(0.0, 0.0); 2]; 2];
        // (iωI − A) is regular for ω real when A is stable
        if let Some(x) = m.lu().solve(&rhs) {
            for (k, row) in out.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = x[(index(output, k), j)];
                }
            }
        }
        out
    }

    /// The invariants of a restored state: valid parameters, finite state and time,
    /// displacements within ±1 m.
    pub fn validate_state(&self) -> Result<(), String> {
        self.params.validate()?;
        if !(self.x.iter().all(|v| v.is_finite()) && [0, 1, 4, 5].iter().all(|&i| self.x[i].abs() < 1.0)) {
            return Err("the spindle state is not finite or out of range".into());
        }
        if !(self.t.is_finite() && self.t >= 0.0) {
            return Err(format!("the time {} is invalid", self.t));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
