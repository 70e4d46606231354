//! The two-axis tool of seed 003 with the averaged cubic cutting law and the active vibration
//! damper (AVD).
//!
//! # Equations
//!
//! Per axis `i ∈ {x, y}` (Eqs. 4, 8, 14, Table 1), with `x_d` the damper's displacement
//! relative to the tool:
//!
//! `m ẍ + c ẋ + k x = F_i + f_i(t) + u + k_d x_d + d(ẋ_d)`
//! `m_d (ẍ + ẍ_d) = −u − k_d x_d − d(ẋ_d)`,  `d(v) = Λ v + Γ m_d g tanh(Υ v)` (Eq. 13).
//!
//! `u` is the actuator force between the tool and the damper mass (`u_c` of Eq. 7: the force
//! with which the accelerated damper mass acts on the tool); the friction of Eq. 13 acts
//! between them (Eq. 14 writes `−d_c` with the tool's velocity relative to the damper, the
//! same force since `d` is odd). A centring spring `k_d` (not in the paper, default
//! `k_d = m_d (100 rad/s)²`, below both modes) keeps the damper mass from drifting under a
//! constant command; Λ = 5 N·s/m, Γ = 0.1, Υ = 100 s/m are our choices (not given). The
//! command is limited to `|u| ≤ u_max` by the controller, not here.
//!
//! Cutting (Eq. 5), `Δx = x(t) − x(t−τ)`, `Δy = y(t) − y(t−τ)`, `τ = 2π/(nΩ)`:
//!
//! `F_x = +(n/2π) P(ζ,η,γ; Δx, Δy)`, `F_y = −(n/2π) P(ζ*,η*,γ*; Δx, Δy)`,
//! `P = ζ₁Δx³ + η₁Δy³ + ζ₂Δx² + η₂Δy² + ζ₃Δx + η₃Δy + 3γ₁Δx²Δy + 3γ₂ΔxΔy² + 2γ₃ΔxΔy + γ₄`,
//!
//! with Eq. 6's coefficients from the 0..π/2 φ-integral of the tooth force
//! ([`milling_process::directional::cubic_average`]). Table 1's `ξ₄ = 1700e3 N/m` is read as
//! `ξ₄ = 1700 N` (a 1.1 kN static force; 1.7 MN is impossible) and `δ₃ = 13` as 13 N/m (kept as
//! printed, a parameter). Before the cut (t < τ) the surface is flat: `x(t−τ) = 0`.
//!
//! Forcing: `f_i(t) = A_i sin(ω_f t)`, ω_f = 650 rad/s (the paper's "650 rad/s is set as the
//! frequency of the simulation", read as a harmonic excitation; see the README).
//!
//! # Integration
//!
//! Classical RK4 with the fixed step `δ = δ_max` (`max_step`). When the delay is a whole
//! number of steps (`τ = Nδ` to 1e-9 relative, e.g. 3000 rpm at 10 µs) the delayed state is on
//! the grid at the stage times `t` and `t + δ`, and at `t + δ/2` it is the cubic Hermite
//! interpolant of the grid positions and velocities (`(x₀ + x₁)/2 + δ(v₀ − v₁)/8`, exact for
//! cubics). Otherwise (`τ = (N + f)δ`, 0 < f < 1) every delayed stage value is the cubic Hermite
//! interpolant between the two grid points around it. The input `u` is held over a
//! [`ToolPlant::step`]. A communication step must be a whole number of `δ` (to 1e-9 relative).
//! (Until issue 31 the step was `τ/⌈τ/δ_max⌉`, which put the delay on the grid but made the
//! default communication step of 0.1 ms a non-multiple at 2900, 3100 or 3333 rpm.)
//!
//! The delay line holds `⌈τ/δ⌉` states of 32 bytes; it must fit half the memory budget
//! ([`model_kit::budget`], the other half for the undo copy of a step), else [`ToolPlant::new`]
//! refuses the parameters with a message naming `spindle_speed`, `teeth` and `max_step`. A
//! stopped spindle (`spindle_rpm = 0`) does not cut: no delay line, no cutting force.

use crate::{ToolError, finite};
use milling_process::directional::cubic_average;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Standard gravity [m/s²] (Eq. 13).
pub const GRAVITY: f64 = 9.81;

/// Parameters of the tool, the cut, the damper and the forcing. `Default` = Table 1 with the
/// readings in the module doc.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToolParams {
    /// Modal masses `(m_x, m_y)` [kg].
    pub mass: [f64; 2],
    /// Damping `(c_x, c_y)` [N·s/m].
    pub damping: [f64; 2],
    /// Stiffness `(k_x, k_y)` [N/m].
    pub stiffness: [f64; 2],
    /// Number of teeth n.
    pub teeth: u32,
    /// Spindle speed Ω [rpm].
    pub spindle_rpm: f64,
    /// Tangential coefficients ξ₁..ξ₄ of h³, h², h, 1 [N/m³, N/m², N/m, N].
    pub xi: [f64; 4],
    /// Radial coefficients δ₁..δ₄.
    pub delta: [f64; 4],
    /// Cutting on (off: no cutting force at all).
    pub cutting: bool,
    /// Damper mass m_d [kg] (5 % of 20 kg).
    pub damper_mass: f64,
    /// Damper centring stiffness k_d [N/m].
    pub damper_stiffness: f64,
    /// Viscous friction Λ [N·s/m].
    pub friction_viscous: f64,
    /// Coulomb friction coefficient Γ [-].
    pub friction_coulomb: f64,
    /// Coulomb smoothing Υ [s/m].
    pub friction_smoothing: f64,
    /// Forcing amplitudes `(A_x, A_y)` [N].
    pub forcing_amplitude: [f64; 2],
    /// Forcing frequency ω_f [rad/s].
    pub forcing_frequency: f64,
    /// Largest integration step δ_max [s].
    pub max_step: f64,
}

impl Default for ToolParams {
    fn default() -> Self {
        ToolParams {
            mass: [20.0, 20.0],
            damping: [1200.0, 4300.0],
            stiffness: [7.2e6, 6.48e7],
            teeth: 4,
            spindle_rpm: 3000.0,
            xi: [6700e9, -4900e6, 3000e3, 1700.0],
            delta: [13000e9, -7200e6, 13.0, 25.0],
            cutting: true,
            damper_mass: 1.0,
            damper_stiffness: 1.0e4,
            friction_viscous: 5.0,
            friction_coulomb: 0.1,
            friction_smoothing: 100.0,
            forcing_amplitude: [0.0, 0.0],
            forcing_frequency: 650.0,
            max_step: 1e-5,
        }
    }
}

impl ToolParams {
    /// Tooth period τ = 60/(n Ω_rpm) [s] (infinite for a stopped spindle).
    pub fn delay(&self) -> f64 {
        60.0 / (f64::from(self.teeth) * self.spindle_rpm)
    }

    /// Does the tool cut? (Cutting on and the spindle turning.)
    pub fn cuts(&self) -> bool {
        self.cutting && self.spindle_rpm > 0.0
    }

    /// The delay in integration steps: `(N, f)` with `τ = (N + f)·δ`, `f = 0` when τ is a whole
    /// number of steps to 1e-9 relative; `(1, 0)` for a stopped spindle (nothing is delayed).
    pub fn delay_steps(&self) -> (usize, f64) {
        if self.spindle_rpm <= 0.0 {
            return (1, 0.0);
        }
        let r = self.delay() / self.max_step;
        if (r - r.round()).abs() <= 1e-9 * r {
            (r.round().max(1.0) as usize, 0.0)
        } else {
            (r.floor().max(1.0) as usize, r - r.floor())
        }
    }

    /// States in the delay line: `N` (`N + 1` with a fraction of a step).
    fn ring_len(&self) -> usize {
        let (n, f) = self.delay_steps();
        n + usize::from(f > 0.0)
    }

    /// Check ranges.
    pub fn validate(&self) -> Result<(), ToolError> {
        let bad = |what: &str| Err(ToolError::Params(what.to_string()));
        let pos = |v: f64| v.is_finite() && v > 0.0;
        let nonneg = |v: f64| v.is_finite() && v >= 0.0;
        if !self.mass.iter().chain(&self.stiffness).all(|&v| pos(v)) || !self.damping.iter().all(|&v| nonneg(v)) {
            return bad("modal mass and stiffness must be > 0 and damping >= 0, all finite");
        }
        if self.teeth == 0 || !nonneg(self.spindle_rpm) {
            return bad("teeth >= 1 and spindle speed >= 0 required (0: stopped, no cutting)");
        }
        if !self.xi.iter().chain(&self.delta).chain(&self.forcing_amplitude).all(|v| v.is_finite()) {
            return bad("cutting coefficients and forcing amplitudes must be finite");
        }
        if !pos(self.damper_mass) || !nonneg(self.damper_stiffness) {
            return bad("damper mass must be > 0 and its stiffness >= 0");
        }
        if ![self.friction_viscous, self.friction_coulomb, self.friction_smoothing, self.forcing_frequency]
            .iter()
            .all(|&v| nonneg(v))
        {
            return bad("friction parameters and forcing frequency must be finite and >= 0");
        }
        if !pos(self.max_step) || self.max_step > self.delay() {
            return bad(&format!(
                "max_step must be in (0, tau]: tau = 60/(teeth · spindle_speed) = {:e} s, max_step = {:e} s",
                self.delay(),
                self.max_step
            ));
        }
        let r = if self.spindle_rpm > 0.0 { self.delay() / self.max_step } else { 1.0 };
        model_kit::budget::check_state_bytes(2.0 * 32.0 * (r.ceil() + 1.0), || {
            format!(
                "the delay line of tau = 60/(teeth · spindle_speed) = 60/({} · {} rpm) = {:e} s in RK4 steps of \
                 max_step = {:e} s ({:.3e} states, with its undo copy)",
                self.teeth,
                self.spindle_rpm,
                self.delay(),
                self.max_step,
                r.ceil()
            )
        })
        .map_err(|m| {
            ToolError::Params(format!(
                "{m}: raise spindle_speed or max_step (or set spindle_speed = 0: a stopped spindle does not cut)"
            ))
        })
    }

    /// Eq. 5 coefficients including `±n/2π`: `(x row, y row)` in the layout of
    /// [`milling_process::directional::CubicAverage`].
    pub fn force_coefficients(&self) -> ([f64; 10], [f64; 10]) {
        let avg = cubic_average(&self.xi, &self.delta, 0.0, PI / 2.0);
        let f = f64::from(self.teeth) / (2.0 * PI);
        (avg.x.map(|c| f * c), avg.y.map(|c| -f * c))
    }
}

/// Eq. 5's polynomial with the `(3, 2)` multiplicities already folded into the layout
/// `[ζ₁, η₁, ζ₂, η₂, ζ₃, η₃, γ₁, γ₂, γ₃, γ₄]`.
pub fn eq5_polynomial(c: &[f64; 10], dx: f64, dy: f64) -> f64 {
    c[0] * dx * dx * dx
        + c[1] * dy * dy * dy
        + c[2] * dx * dx
        + c[3] * dy * dy
        + c[4] * dx
        + c[5] * dy
        + 3.0 * c[6] * dx * dx * dy
        + 3.0 * c[7] * dx * dy * dy
        + 2.0 * c[8] * dx * dy
        + c[9]
}

/// Held inputs: the actuator forces on the tool [N].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ToolInputs {
    /// Actuator force along x [N].
    pub ux: f64,
    /// Actuator force along y [N].
    pub uy: f64,
}

/// Outputs after a step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ToolOutputs {
    /// Tool displacement x [m].
    pub x: f64,
    /// Tool displacement y [m].
    pub y: f64,
    /// Tool velocity ẋ [m/s].
    pub vx: f64,
    /// Tool velocity ẏ [m/s].
    pub vy: f64,
    /// Cutting force F_x [N].
    pub fx: f64,
    /// Cutting force F_y [N].
    pub fy: f64,
    /// Damper displacement relative to the tool, x axis [m].
    pub damper_x: f64,
    /// Damper displacement relative to the tool, y axis [m].
    pub damper_y: f64,
}

/// State order: `[x, ẋ, x_d, ẋ_d]` for x then y.
type State = [f64; 8];

/// The tool with its delay line.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ToolPlant {
    p: ToolParams,
    cx: [f64; 10],
    cy: [f64; 10],
    dt: f64,
    n_delay: usize,
    /// The fraction of a step in the delay (`τ = (N + frac)·δ`, see [`ToolParams::delay_steps`]).
    frac: f64,
    /// `(x, y, ẋ, ẏ)` at the last `n_delay` grid points, oldest at `head`.
    ring: Vec<[f64; 4]>,
    head: usize,
    steps: u64,
    state: State,
    out: ToolOutputs,
}

impl ToolPlant {
    /// The tool at rest in the static equilibrium of the cut ([`ToolPlant::static_deflection`]),
    /// with the surface of the previous tooth at the same deflection (Δ = 0).
    pub fn new(p: &ToolParams) -> Result<Self, ToolError> {
        p.validate()?;
        let n_delay = p.ring_len();
        let (cx, cy) = p.force_coefficients();
        let mut t = ToolPlant {
            p: p.clone(),
            cx,
            cy,
            dt: p.max_step,
            n_delay,
            frac: p.delay_steps().1,
            ring: Vec::new(),
            head: 0,
            steps: 0,
            state: [0.0; 8],
            out: ToolOutputs::default(),
        };
        let xs = t.static_deflection();
        t.state[0] = xs[0];
        t.state[4] = xs[1];
        t.ring = vec![[xs[0], xs[1], 0.0, 0.0]; n_delay];
        t.out = t.outputs_of(&t.state.clone(), t.ring[0]);
        Ok(t)
    }

    /// The static deflection `(γ₄ n/2π / k_x, −γ₄* n/2π / k_y)` under the constant cutting force
    /// (Δ = 0) [m]; zero with the cut off.
    pub fn static_deflection(&self) -> [f64; 2] {
        if !self.p.cuts() {
            return [0.0; 2];
        }
        [self.cx[9] / self.p.stiffness[0], self.cy[9] / self.p.stiffness[1]]
    }

    /// The parameters.
    pub fn params(&self) -> &ToolParams {
        &self.p
    }

    /// Integration step δ [s].
    pub fn integration_step(&self) -> f64 {
        self.dt
    }

    /// Time since the start [s].
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.dt
    }

    /// The outputs at the current time.
    pub fn outputs(&self) -> ToolOutputs {
        self.out
    }

    fn outputs_of(&self, s: &State, delayed: [f64; 4]) -> ToolOutputs {
        let (fx, fy) = self.cutting(s, delayed);
        ToolOutputs { x: s[0], y: s[4], vx: s[1], vy: s[5], fx, fy, damper_x: s[2], damper_y: s[6] }
    }

    fn cutting(&self, s: &State, d: [f64; 4]) -> (f64, f64) {
        if !self.p.cuts() {
            return (0.0, 0.0);
        }
        let (dx, dy) = (s[0] - d[0], s[4] - d[1]);
        (eq5_polynomial(&self.cx, dx, dy), eq5_polynomial(&self.cy, dx, dy))
    }

    fn friction(&self, v: f64) -> f64 {
        let p = &self.p;
        p.friction_viscous * v + p.friction_coulomb * p.damper_mass * GRAVITY * (p.friction_smoothing * v).tanh()
    }

    fn rhs(&self, s: &State, delayed: [f64; 4], t: f64, u: [f64; 2]) -> State {
        let (fx, fy) = self.cutting(s, delayed);
        let p = &self.p;
        let mut d = [0.0; 8];
        for (a, f) in [(0usize, fx), (1, fy)] {
            let o = 4 * a;
            let (x, v, xd, vd) = (s[o], s[o + 1], s[o + 2], s[o + 3]);
            let coupling = p.damper_stiffness * xd + self.friction(vd);
            let forcing = p.forcing_amplitude[a] * (p.forcing_frequency * t).sin();
            let acc = (f + forcing + u[a] + coupling - p.damping[a] * v - p.stiffness[a] * x) / p.mass[a];
            d[o] = v;
            d[o + 1] = acc;
            d[o + 2] = vd;
            d[o + 3] = (-u[a] - coupling) / p.damper_mass - acc;
        }
        d
    }

    /// The state `(x, y, ẋ, ẏ)` `k` grid steps ago (`k = 0`: now; `1 ≤ k ≤ n_delay`: the line).
    fn ago(&self, k: usize) -> [f64; 4] {
        if k == 0 {
            [self.state[0], self.state[4], self.state[1], self.state[5]]
        } else {
            self.ring[(self.head + self.n_delay - k) % self.n_delay]
        }
    }

    /// The cubic Hermite interpolant of the grid states `a` (older) and `b` (one step later) at
    /// the fraction `θ` of the step from `a`: positions and velocities.
    fn hermite(&self, a: [f64; 4], b: [f64; 4], th: f64) -> [f64; 4] {
        let h = self.dt;
        let (t2, t3) = (th * th, th * th * th);
        let (h00, h10, h01, h11) = (2.0 * t3 - 3.0 * t2 + 1.0, t3 - 2.0 * t2 + th, -2.0 * t3 + 3.0 * t2, t3 - t2);
        let (d00, d10, d01, d11) =
            (6.0 * t2 - 6.0 * th, 3.0 * t2 - 4.0 * th + 1.0, -6.0 * t2 + 6.0 * th, 3.0 * t2 - 2.0 * th);
        let pos = |i: usize| h00 * a[i] + h10 * h * a[i + 2] + h01 * b[i] + h11 * h * b[i + 2];
        let vel = |i: usize| (d00 * a[i] + h * d10 * a[i + 2] + d01 * b[i] + h * d11 * b[i + 2]) / h;
        [pos(0), pos(1), vel(0), vel(1)]
    }

    /// The delayed `(x, y, ẋ, ẏ)` at the RK4 stage times `t − τ`, `t + δ − τ` and the midpoint
    /// `t + δ/2 − τ`.
    fn delayed(&self) -> ([f64; 4], [f64; 4], [f64; 4]) {
        if self.frac > 0.0 {
            // τ = (N + f)δ: t − τ lies between N + 1 and N steps ago, θ = 1 − f past the older
            let n = self.n_delay - 1;
            let (a, b, c) = (self.ago(n + 1), self.ago(n), self.ago(n - 1));
            let th = 1.0 - self.frac;
            let mid = if th < 0.5 { self.hermite(a, b, th + 0.5) } else { self.hermite(b, c, th - 0.5) };
            return (self.hermite(a, b, th), self.hermite(b, c, th), mid);
        }
        let d0 = self.ring[self.head];
        let d1 = if self.n_delay == 1 {
            [self.state[0], self.state[4], self.state[1], self.state[5]]
        } else {
            self.ring[(self.head + 1) % self.n_delay]
        };
        let h = self.dt;
        let mid = [
            0.5 * (d0[0] + d1[0]) + h * (d0[2] - d1[2]) / 8.0,
            0.5 * (d0[1] + d1[1]) + h * (d0[3] - d1[3]) / 8.0,
            1.5 * (d1[0] - d0[0]) / h - 0.25 * (d0[2] + d1[2]),
            1.5 * (d1[1] - d0[1]) / h - 0.25 * (d0[3] + d1[3]),
        ];
        (d0, d1, mid)
    }

    fn rk4(&mut self, u: [f64; 2]) {
        let (d0, d1, dm) = self.delayed();
        let (t, h) = (self.time(), self.dt);
        let s = self.state;
        let add = |a: &State, k: &State, c: f64| -> State { std::array::from_fn(|i| a[i] + c * k[i]) };
        let k1 = self.rhs(&s, d0, t, u);
        let k2 = self.rhs(&add(&s, &k1, 0.5 * h), dm, t + 0.5 * h, u);
        let k3 = self.rhs(&add(&s, &k2, 0.5 * h), dm, t + 0.5 * h, u);
        let k4 = self.rhs(&add(&s, &k3, h), d1, t + h, u);
        // the current state enters the delay line; the oldest leaves
        self.ring[self.head] = [s[0], s[4], s[1], s[5]];
        self.head = (self.head + 1) % self.n_delay;
        self.state = std::array::from_fn(|i| s[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
        self.steps += 1;
    }

    /// Advance by `h` (a whole number of integration steps) with the forces `inputs` held.
    pub fn step(&mut self, h: f64, inputs: &ToolInputs) -> Result<ToolOutputs, ToolError> {
        let u = [finite("ux", inputs.ux)?, finite("uy", inputs.uy)?];
        if !(h.is_finite() && h > 0.0) {
            return Err(ToolError::Input(format!("step size {h} must be finite and > 0")));
        }
        let n = (h / self.dt).round();
        if n < 1.0 || (n * self.dt - h).abs() > 1e-9 * h {
            return Err(ToolError::Input(format!(
                "step size {h} s is not a whole number of integration steps {} s",
                self.dt
            )));
        }
        // what the step overwrites, to undo it (not a copy of the whole line every step)
        let saved = (self.state, self.head, self.steps);
        let undo: Vec<[f64; 4]> =
            (0..(n as usize).min(self.n_delay)).map(|k| self.ring[(self.head + k) % self.n_delay]).collect();
        for _ in 0..n as u64 {
            self.rk4(u);
        }
        if !self.state.iter().all(|v| v.is_finite()) {
            (self.state, self.head, self.steps) = saved;
            for (k, r) in undo.into_iter().enumerate() {
                self.ring[(self.head + k) % self.n_delay] = r;
            }
            return Err(ToolError::State("the tool state is no longer finite".into()));
        }
        let d0 = self.ring[self.head];
        self.out = self.outputs_of(&self.state.clone(), d0);
        Ok(self.out)
    }

    /// Every stored number finite and the delay line consistent with the parameters.
    pub fn validate_state(&self) -> Result<(), String> {
        let expect = self.p.ring_len();
        if self.n_delay != expect
            || self.p.max_step.to_bits() != self.dt.to_bits()
            || self.p.delay_steps().1.to_bits() != self.frac.to_bits()
        {
            return Err("integration grid inconsistent with the parameters".into());
        }
        let (cx, cy) = self.p.force_coefficients();
        if cx.iter().chain(&cy).zip(self.cx.iter().chain(&self.cy)).any(|(a, b)| a.to_bits() != b.to_bits()) {
            return Err("cutting coefficients inconsistent with the parameters".into());
        }
        if self.ring.len() != self.n_delay || self.head >= self.n_delay {
            return Err("delay line inconsistent with the parameters".into());
        }
        if !self.state.iter().chain(self.ring.iter().flatten()).all(|v| v.is_finite()) {
            return Err("non-finite number in the tool state".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn force_coefficients_are_eq_6_times_n_over_2pi() {
        // the φ-integral itself is tested against Eq. 6 to 1e-12 in milling-process
        // (directional::tests::cubic_average_is_seed_003_eq_6); here: the static force γ₄
        let p = ToolParams::default();
        let (cx, cy) = p.force_coefficients();
        let f = 4.0 / (2.0 * PI);
        assert!((cx[9] - f * (1700.0 + 25.0)).abs() < 1e-12 * cx[9].abs());
        assert!((cy[9] + f * (1700.0 - 25.0)).abs() < 1e-12 * cy[9].abs());
        assert!((cx[4] - f * 0.5 * (3000e3 + 0.5 * PI * 13.0)).abs() < 1e-12 * cx[4]);
    }

    #[test]
    fn rk4_converges_without_the_cut() {
        // cutting off, forcing and held commands on: halving the step changes little
        let p = ToolParams {
            cutting: false,
            damper_stiffness: 0.0,
            friction_viscous: 0.0,
            friction_coulomb: 0.0,
            forcing_amplitude: [100.0, 0.0],
            ..Default::default()
        };
        let mut tool = ToolPlant::new(&p).unwrap();
        let mut tool2 = ToolPlant::new(&ToolParams { max_step: 0.5e-5, ..p.clone() }).unwrap();
        for _ in 0..100 {
            tool.step(1e-4, &ToolInputs { ux: 50.0, uy: -20.0 }).unwrap();
            tool2.step(1e-4, &ToolInputs { ux: 50.0, uy: -20.0 }).unwrap();
        }
        let (a, b) = (tool.outputs(), tool2.outputs());
        // RK4: halving the step changes the result by ~1/16 of its error
        assert!((a.x - b.x).abs() < 1e-7 * a.x.abs().max(1e-6), "{} vs {}", a.x, b.x);
        assert!((a.y - b.y).abs() < 1e-7 * a.y.abs().max(1e-7), "{} vs {}", a.y, b.y);
        // y is driven by the constant −20 N only: bounded by the step response's 2·20/k_y
        assert!(a.y.abs() <= 2.0 * 20.0 / 6.48e7 * 1.01);
    }

    #[test]
    fn the_static_deflection_is_an_equilibrium() {
        // F_x = (n/2π)(ξ₄ + δ₄) = 1098 N → 0.1525 mm; no forcing, no command: nothing moves
        let mut tool = ToolPlant::new(&ToolParams::default()).unwrap();
        let xs = tool.static_deflection();
        let f = 4.0 / (2.0 * PI) * 1725.0;
        assert!((xs[0] - f / 7.2e6).abs() < 1e-12 * xs[0]);
        for _ in 0..1000 {
            tool.step(1e-4, &ToolInputs::default()).unwrap();
        }
        let o = tool.outputs();
        assert!((o.x - xs[0]).abs() < 1e-15 && (o.y - xs[1]).abs() < 1e-15, "{o:?}");
    }

    #[test]
    fn a_step_into_the_cut_is_nonlinearly_unstable() {
        // the cubic law of Table 1 is subcritical: starting from the undeflected tool (a 0.15 mm
        // step into the static force) the vibration grows without bound within 0.1 s, while a
        // 10 N forcing about the equilibrium stays small (the reason for the μm reading of
        // Table 2, README)
        let mut tool = ToolPlant::new(&ToolParams::default()).unwrap();
        tool.state = [0.0; 8];
        tool.ring = vec![[0.0; 4]; tool.n_delay];
        let blew_up = (0..1000).any(|_| tool.step(1e-4, &ToolInputs::default()).is_err());
        assert!(blew_up);
        let p = ToolParams { forcing_amplitude: [10.0, 10.0], ..Default::default() };
        let mut tool = ToolPlant::new(&p).unwrap();
        let xs = tool.static_deflection();
        for _ in 0..5000 {
            let o = tool.step(1e-4, &ToolInputs::default()).unwrap();
            assert!((o.x - xs[0]).abs() < 1e-5);
        }
    }

    #[test]
    fn bad_inputs_are_errors_and_leave_the_state() {
        let mut tool = ToolPlant::new(&ToolParams::default()).unwrap();
        tool.step(1e-4, &ToolInputs { ux: 10.0, uy: 0.0 }).unwrap();
        let before = tool.outputs();
        assert!(tool.step(1e-4, &ToolInputs { ux: f64::NAN, uy: 0.0 }).is_err());
        assert!(tool.step(1.5e-5, &ToolInputs::default()).is_err());
        assert!(tool.step(-1.0, &ToolInputs::default()).is_err());
        assert_eq!(tool.outputs(), before);
    }
}
