//! The modal structure: `N ≤ 4` modes seen at a tool point and an actuator point.
//!
//! # Equations
//!
//! Mode `i` (modal mass `m_i`, natural frequency `ω_i`, damping ratio `ζ_i`, mode-shape
//! components `φ_i^T = (φ_{i,x}, φ_{i,y})` at the tool point and `φ_i^A` at the actuator point)
//! obeys
//!
//! `m_i q̈_i + 2ζ_i m_i ω_i q̇_i + k_i(t) q_i = φ_i^T·(F^T + d(t) e) + φ_i^A·F^A`,
//!
//! `u^T = Σ φ_i^T q_i`, `u^A = Σ φ_i^A q_i` (and the velocities alike), with `k_i = m_i ω_i²`.
//! With `m_i = 1` the shapes are mass-normalised (1/√kg); with unit shapes `m_i` is the modal
//! mass seen along them. `F^T`, `F^A` are the force inputs on the structure at the two points,
//! `d(t)` the optional disturbance force (band-limited noise + sinusoid, along the unit vector
//! `e = (cos β_d, sin β_d)` at the tool point) and `k_1(t) = k_1 (1 + A sin 2π f_d t)` the
//! optional stiffness drift of the first mode: seed 000's disturbances, so that the monolithic
//! plant decomposes without losing them.
//!
//! # Discretisation
//!
//! Forces are held over a step (zero-order hold), so each mode advances exactly by the matrix
//! exponential of its 2×2 block: with `σ = ζω`, `ω_d = ω√(1−ζ²)`, `E = e^{−σh}`,
//! `C = cos ω_d h`, `S = sin ω_d h`,
//!
//! `Φ(h) = E [[C + σS/ω_d, S/ω_d], [−ω²S/ω_d, C − σS/ω_d]]`,
//! `Γ(h) = [(1 − E(C + σS/ω_d))/k, E S/(m ω_d)]`,
//!
//! `(q, q̇)(t+h) = Φ(h)(q, q̇)(t) + Γ(h) f` (Cayley–Hamilton form of `e^{Ah}`; computed once per
//! step size and cached). The first mode under drift is refreshed every step with the stiffness
//! at mid-step (drift is slow: second-order accurate). The grid is that of the monolithic plant:
//! cells of `internal_step` from the start time; a noise sample is drawn when a cell is entered
//! and held over it; a step ending inside a cell is split there. [`ModalStructure::step_rk4`]
//! is the slow reference (classical RK4 on the same grid, drift at the stage times).

use crate::grid::next_sub_step;
use crate::noise::BandLimitedNoise;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The most modes (a modal table's limit).
pub const MAX_MODES: usize = 16;

/// The modes held in [`ModalParams::modes`] (the FMU's `mode1.*` … `mode4.*` parameters); modes
/// beyond these are in [`ModalParams::extra_modes`].
pub const PARAMETER_MODES: usize = 4;

/// Why the structure refused to start or to step.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StructureError {
    /// A parameter is out of range.
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// An input is out of range (the step was not taken).
    #[error("invalid input: {0}")]
    Input(String),
    /// The state left any physical range.
    #[error("the structure diverged at t = {t} s")]
    Diverged {
        /// Time [s].
        t: f64,
    },
}

/// One mode.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StructureMode {
    /// Natural frequency [Hz].
    pub frequency: f64,
    /// Damping ratio [-] (< 1).
    pub damping_ratio: f64,
    /// Modal mass [kg] (1 for mass-normalised shapes).
    pub modal_mass: f64,
    /// Mode-shape components (x, y) at the tool point.
    pub tool: [f64; 2],
    /// Mode-shape components (x, y) at the actuator point.
    pub actuator: [f64; 2],
}

impl StructureMode {
    /// A mode from mass [kg], stiffness [N/m] and damping ratio, with shapes.
    pub fn from_mass_stiffness(m: f64, k: f64, zeta: f64, tool: [f64; 2], actuator: [f64; 2]) -> StructureMode {
        StructureMode { frequency: (k / m).sqrt() / (2.0 * PI), damping_ratio: zeta, modal_mass: m, tool, actuator }
    }
    /// Natural frequency [rad/s].
    pub fn omega(&self) -> f64 {
        2.0 * PI * self.frequency
    }
    /// Viscous modal damping `2ζmω` [N s/m] (does not drift with the stiffness).
    pub fn damping(&self) -> f64 {
        2.0 * self.damping_ratio * self.modal_mass * self.omega()
    }
    /// Modal stiffness `m ω²` [N/m].
    pub fn stiffness(&self) -> f64 {
        self.modal_mass * self.omega() * self.omega()
    }
}

/// Disturbance forces at the tool point and stiffness drift of mode 1 (seed 000, Section 3.4).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Disturbance {
    /// Band-limited Gaussian force on/off.
    pub noise: bool,
    /// Its RMS [N].
    pub noise_rms: f64,
    /// Its bandwidth (4th-order Butterworth) [Hz].
    pub noise_bandwidth: f64,
    /// Sinusoidal force amplitude [N].
    pub sine_amplitude: f64,
    /// Sinusoidal force frequency [Hz].
    pub sine_frequency: f64,
    /// Direction β_d of the disturbance force from +x towards +y [rad].
    pub direction_angle: f64,
    /// Stiffness drift of mode 1 on/off.
    pub drift: bool,
    /// Relative drift amplitude A [-].
    pub drift_amplitude: f64,
    /// Drift frequency [Hz].
    pub drift_frequency: f64,
}

/// All structure parameters. `Default` = seed 000's workpiece (first bending mode along x,
/// actuator at the same point, 50 N RMS noise and ±10 % drift at 0.5 Hz).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModalParams {
    /// Number of modes used (1..=[`MAX_MODES`]).
    pub n_modes: u32,
    /// The first modes (the first `n_modes` of `modes` then `extra_modes` are used).
    pub modes: [StructureMode; PARAMETER_MODES],
    /// Modes beyond [`PARAMETER_MODES`] (from a modal table; empty by default).
    #[serde(default)]
    pub extra_modes: Vec<StructureMode>,
    /// Disturbances.
    pub disturbance: Disturbance,
    /// Random seed of the noise.
    pub seed: u64,
    /// Grid of the noise and of the split steps [s].
    pub internal_step: f64,
}

/// Mode from frequency [Hz], damping ratio and peak receptance [m/N] (seed 000's higher modes).
fn from_peak(f: f64, z: f64, peak: f64) -> (f64, f64) {
    let k = 1.0 / (2.0 * z * (1.0 - z * z).sqrt() * peak);
    let w = 2.0 * PI * f;
    (k / (w * w), k)
}

impl Default for ModalParams {
    fn default() -> Self {
        let x = [1.0, 0.0];
        let (m2, k2) = from_peak(895.8, 0.00936, 0.0562e-6);
        let (m3, k3) = from_peak(2499.8, 0.00954, 0.00708e-6);
        ModalParams {
            n_modes: 1,
            modes: [
                StructureMode::from_mass_stiffness(30.0, 2.40e7, 0.0088, x, x),
                StructureMode::from_mass_stiffness(m2, k2, 0.00936, x, x),
                StructureMode::from_mass_stiffness(m3, k3, 0.00954, x, x),
                StructureMode::from_mass_stiffness(30.0, 2.40e7, 0.0088, [0.0, 1.0], [0.0, 1.0]),
            ],
            extra_modes: Vec::new(),
            disturbance: Disturbance {
                noise: true,
                noise_rms: 50.0,
                noise_bandwidth: 2000.0,
                sine_amplitude: 0.0,
                sine_frequency: 50.0,
                direction_angle: 0.0,
                drift: true,
                drift_amplitude: 0.1,
                drift_frequency: 0.5,
            },
            seed: 1,
            internal_step: 1e-5,
        }
    }
}

impl ModalParams {
    /// Check ranges; the error names the parameter.
    pub fn validate(&self) -> Result<(), String> {
        if !(1..=MAX_MODES as u32).contains(&self.n_modes) {
            return Err(format!("n_modes must be in 1..={MAX_MODES} (got {})", self.n_modes));
        }
        let held = PARAMETER_MODES + self.extra_modes.len();
        if self.n_modes as usize > held {
            return Err(format!(
                "n_modes = {} but {held} modes are given (more than {PARAMETER_MODES} come from a modal table)",
                self.n_modes
            ));
        }
        for (i, m) in self.mode_list().iter().enumerate() {
            let n = i + 1;
            if !(m.frequency.is_finite() && m.frequency > 0.0) {
                return Err(format!("mode{n}.frequency must be finite and > 0"));
            }
            if !(m.damping_ratio >= 0.0 && m.damping_ratio < 1.0) {
                return Err(format!("mode{n}.damping_ratio must be in [0, 1)"));
            }
            if !(m.modal_mass.is_finite() && m.modal_mass > 0.0) {
                return Err(format!("mode{n}.modal_mass must be finite and > 0"));
            }
            if !m.tool.iter().chain(&m.actuator).all(|x| x.is_finite()) {
                return Err(format!("mode{n} shape components must be finite"));
            }
        }
        if !(self.internal_step.is_finite() && self.internal_step > 0.0) {
            return Err("internal_step must be finite and > 0".into());
        }
        let d = &self.disturbance;
        if !(d.noise_rms.is_finite() && d.noise_rms >= 0.0) {
            return Err("disturbance.noise_rms must be finite and >= 0".into());
        }
        if d.noise && !(d.noise_bandwidth > 0.0 && d.noise_bandwidth < 0.45 / self.internal_step) {
            return Err(format!("disturbance.noise_bandwidth must be in (0, {} Hz)", 0.45 / self.internal_step));
        }
        if !(d.drift_amplitude >= 0.0 && d.drift_amplitude < 1.0) {
            return Err("disturbance.drift_amplitude must be in [0, 1)".into());
        }
        let z1 = self.modes[0].damping_ratio;
        if d.drift && z1 * z1 >= 1.0 - d.drift_amplitude {
            return Err("mode1 must stay underdamped under drift (damping_ratio² < 1 − drift_amplitude)".into());
        }
        let rest = [d.sine_amplitude, d.sine_frequency, d.direction_angle, d.drift_frequency];
        if !rest.iter().all(|x| x.is_finite()) {
            return Err("disturbance parameters must be finite".into());
        }
        Ok(())
    }

    /// The used modes.
    pub fn mode_list(&self) -> Vec<StructureMode> {
        self.modes.iter().chain(&self.extra_modes).take(self.n_modes as usize).copied().collect()
    }

    /// Set the modes (1..=[`MAX_MODES`]): the first [`PARAMETER_MODES`] into `modes`, the rest
    /// into `extra_modes`, and `n_modes`.
    pub fn set_modes(&mut self, modes: &[StructureMode]) -> Result<(), String> {
        if modes.is_empty() || modes.len() > MAX_MODES {
            return Err(format!("{} modes, expected 1..={MAX_MODES}", modes.len()));
        }
        let k = modes.len().min(PARAMETER_MODES);
        self.modes[..k].copy_from_slice(&modes[..k]);
        self.extra_modes = modes[k..].to_vec();
        self.n_modes = modes.len() as u32;
        Ok(())
    }
}

/// Force inputs held over a step [N] (on the structure, along +x/+y).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StructureInputs {
    /// Force at the tool point.
    pub tool_force: [f64; 2],
    /// Force at the actuator point.
    pub actuator_force: [f64; 2],
}

/// Outputs at the current time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StructureOutputs {
    /// Tool-point displacement (x, y) [m].
    pub tool: [f64; 2],
    /// Tool-point velocity [m/s].
    pub tool_velocity: [f64; 2],
    /// Actuator-point displacement [m].
    pub actuator: [f64; 2],
    /// Actuator-point velocity [m/s].
    pub actuator_velocity: [f64; 2],
    /// Disturbance force along its direction over the last step [N].
    pub disturbance_force: f64,
}

/// Exact one-step map of one mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
struct Disc {
    phi: [[f64; 2]; 2],
    gamma: [f64; 2],
}

/// The exact map of `m q̈ + c q̇ + k q = f` over `h` (underdamped: `c² < 4mk`).
fn discretise(m: f64, c: f64, k: f64, h: f64) -> Disc {
    let w2 = k / m;
    let sigma = c / (2.0 * m);
    let wd = (w2 - sigma * sigma).sqrt();
    let w = w2.sqrt();
    let e = (-sigma * h).exp();
    let (s, c) = (wd * h).sin_cos();
    Disc {
        phi: [[e * (c + sigma * s / wd), e * s / wd], [-e * w * w * s / wd, e * (c - sigma * s / wd)]],
        gamma: [(1.0 - e * (c + sigma * s / wd)) / k, e * s / (m * wd)],
    }
}

/// The structure.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ModalStructure {
    p: ModalParams,
    /// The used modes, resolved once from `p` (no allocation per step).
    modes: Vec<StructureMode>,
    q: [f64; MAX_MODES],
    qd: [f64; MAX_MODES],
    t0: f64,
    cell: u64,
    offset: f64,
    noise: Option<BandLimitedNoise>,
    noise_now: f64,
    /// (step size bits, maps) of the last step sizes used.
    cache: Vec<(u64, [Disc; MAX_MODES])>,
    out: StructureOutputs,
}

impl ModalStructure {
    /// A structure at rest at time `t0`.
    pub fn new_at(p: &ModalParams, t0: f64) -> Result<ModalStructure, StructureError> {
        p.validate().map_err(StructureError::Parameter)?;
        let d = &p.disturbance;
        let mut noise = (d.noise && d.noise_rms > 0.0)
            .then(|| BandLimitedNoise::new(p.seed, d.noise_rms, d.noise_bandwidth, p.internal_step));
        let noise_now = noise.as_mut().map_or(0.0, BandLimitedNoise::next_sample);
        let mut s = ModalStructure {
            p: p.clone(),
            modes: p.mode_list(),
            q: [0.0; MAX_MODES],
            qd: [0.0; MAX_MODES],
            t0,
            cell: 0,
            offset: 0.0,
            noise,
            noise_now,
            cache: Vec::new(),
            out: StructureOutputs::default(),
        };
        s.refresh(s.disturbance(t0));
        Ok(s)
    }

    /// A structure at rest at time 0.
    pub fn new(p: &ModalParams) -> Result<ModalStructure, StructureError> {
        ModalStructure::new_at(p, 0.0)
    }

    /// The parameters.
    pub fn params(&self) -> &ModalParams {
        &self.p
    }

    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.t0 + self.cell as f64 * self.p.internal_step + self.offset
    }

    /// Time since the last internal cell boundary \[s\]: 0 while the communication points lie
    /// on the internal grid (steps that are multiples of `internal_step`), at any run length.
    pub fn cell_offset(&self) -> f64 {
        self.offset
    }

    /// Outputs at the current time.
    pub fn outputs(&self) -> StructureOutputs {
        self.out
    }

    /// Internal sub-steps a communication step of `h` takes (cells plus partial ends).
    pub fn internal_steps(&self, h: f64) -> f64 {
        h / self.p.internal_step + 2.0
    }

    fn disturbance(&self, t: f64) -> f64 {
        let d = &self.p.disturbance;
        let sine =
            if d.sine_amplitude == 0.0 { 0.0 } else { d.sine_amplitude * (2.0 * PI * d.sine_frequency * t).sin() };
        self.noise_now + sine
    }

    fn stiffness(&self, i: usize, t: f64) -> f64 {
        let k = self.modes[i].stiffness();
        let d = &self.p.disturbance;
        if i == 0 && d.drift { k * (1.0 + d.drift_amplitude * (2.0 * PI * d.drift_frequency * t).sin()) } else { k }
    }

    /// Modal forces for the inputs and the disturbance force `dist`.
    fn modal_forces(&self, inputs: &StructureInputs, dist: f64) -> [f64; MAX_MODES] {
        let dir = self.p.disturbance.direction_angle;
        let ft = [inputs.tool_force[0] + dist * dir.cos(), inputs.tool_force[1] + dist * dir.sin()];
        let mut f = [0.0; MAX_MODES];
        for (i, m) in self.modes.iter().enumerate() {
            f[i] = m.tool[0] * ft[0]
                + m.tool[1] * ft[1]
                + m.actuator[0] * inputs.actuator_force[0]
                + m.actuator[1] * inputs.actuator_force[1];
        }
        f
    }

    fn maps(&mut self, dt: f64) -> [Disc; MAX_MODES] {
        let key = dt.to_bits();
        if let Some((_, d)) = self.cache.iter().find(|(k, _)| *k == key) {
            return *d;
        }
        let mut d = [Disc::default(); MAX_MODES];
        for (i, m) in self.modes.iter().enumerate() {
            d[i] = discretise(m.modal_mass, m.damping(), m.stiffness(), dt);
        }
        if self.cache.len() >= 4 {
            self.cache.remove(0);
        }
        self.cache.push((key, d));
        d
    }

    fn check(&self, h: f64, inputs: &StructureInputs) -> Result<(), StructureError> {
        let all = inputs.tool_force.iter().chain(&inputs.actuator_force);
        if !all.clone().all(|f| f.is_finite()) {
            return Err(StructureError::Input(format!("force inputs must be finite (got {inputs:?})")));
        }
        if !(h.is_finite() && h >= 0.0) {
            return Err(StructureError::Input(format!("step size {h} must be finite and >= 0")));
        }
        Ok(())
    }

    /// Advance by `h` with the forces held: exact per mode (module docs).
    pub fn step(&mut self, h: f64, inputs: &StructureInputs) -> Result<(), StructureError> {
        self.advance(h, inputs, 0)
    }

    /// The slow reference: the same grid and held forces, `substeps` classical RK4 steps per
    /// grid sub-step (drift at the stage times).
    pub fn step_rk4(&mut self, h: f64, inputs: &StructureInputs, substeps: u32) -> Result<(), StructureError> {
        self.advance(h, inputs, substeps.max(1))
    }

    /// `rk4` = 0: exact maps; else that many RK4 steps per sub-step.
    fn advance(&mut self, h: f64, inputs: &StructureInputs, rk4: u32) -> Result<(), StructureError> {
        self.check(h, inputs)?;
        let hi = self.p.internal_step;
        // what is left of the step, counted down by `next_sub_step` (see `machine_structure::grid`)
        let mut remaining = h;
        let mut dist = self.out.disturbance_force;
        while let Some((dt, completes)) = next_sub_step(&mut remaining, self.offset, hi) {
            let t = self.time();
            dist = self.disturbance(t + 0.5 * dt);
            let f = self.modal_forces(inputs, dist);
            if rk4 == 0 {
                self.exact(t, dt, &f);
            } else {
                let d = dt / f64::from(rk4);
                for j in 0..rk4 {
                    self.rk4(t + f64::from(j) * d, d, &f);
                }
            }
            if completes {
                self.cell += 1;
                self.offset = 0.0;
                self.noise_now = self.noise.as_mut().map_or(0.0, BandLimitedNoise::next_sample);
            } else {
                self.offset += dt;
            }
        }
        self.refresh(dist);
        let u = self.out.tool;
        if !(u.iter().chain(&self.out.actuator).all(|x| x.is_finite() && x.abs() < 1.0)) {
            return Err(StructureError::Diverged { t: self.time() });
        }
        Ok(())
    }

    fn exact(&mut self, t: f64, dt: f64, f: &[f64; MAX_MODES]) {
        let mut maps = self.maps(dt);
        if self.p.disturbance.drift {
            let m = &self.modes[0];
            maps[0] = discretise(m.modal_mass, m.damping(), self.stiffness(0, t + 0.5 * dt), dt);
        }
        for (i, d) in maps.iter().enumerate().take(self.p.n_modes as usize) {
            let (q, v) = (self.q[i], self.qd[i]);
            self.q[i] = d.phi[0][0] * q + d.phi[0][1] * v + d.gamma[0] * f[i];
            self.qd[i] = d.phi[1][0] * q + d.phi[1][1] * v + d.gamma[1] * f[i];
        }
    }

    fn rk4(&mut self, t: f64, dt: f64, f: &[f64; MAX_MODES]) {
        #[allow(clippy::needless_range_loop)] // i indexes the modes, their forces and states alike
        for i in 0..self.p.n_modes as usize {
            let m = self.modes[i];
            let c = m.damping();
            let acc = |tt: f64, q: f64, v: f64| (f[i] - c * v - self.stiffness(i, tt) * q) / m.modal_mass;
            let (q0, v0) = (self.q[i], self.qd[i]);
            let (k1q, k1v) = (v0, acc(t, q0, v0));
            let (k2q, k2v) = (v0 + 0.5 * dt * k1v, acc(t + 0.5 * dt, q0 + 0.5 * dt * k1q, v0 + 0.5 * dt * k1v));
            let (k3q, k3v) = (v0 + 0.5 * dt * k2v, acc(t + 0.5 * dt, q0 + 0.5 * dt * k2q, v0 + 0.5 * dt * k2v));
            let (k4q, k4v) = (v0 + dt * k3v, acc(t + dt, q0 + dt * k3q, v0 + dt * k3v));
            self.q[i] = q0 + dt / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q);
            self.qd[i] = v0 + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
    }

    fn refresh(&mut self, dist: f64) {
        let mut o = StructureOutputs { disturbance_force: dist, ..Default::default() };
        for (i, m) in self.modes.iter().enumerate() {
            for a in 0..2 {
                o.tool[a] += m.tool[a] * self.q[i];
                o.tool_velocity[a] += m.tool[a] * self.qd[i];
                o.actuator[a] += m.actuator[a] * self.q[i];
                o.actuator_velocity[a] += m.actuator[a] * self.qd[i];
            }
        }
        self.out = o;
    }

    /// Is this a state the structure can continue from? (Run on every restored FMU state.)
    pub fn validate_state(&self) -> Result<(), String> {
        self.p.validate()?;
        if !self.q.iter().chain(&self.qd).all(|x| x.is_finite()) {
            return Err("the modal state is not finite".into());
        }
        let o = &self.out;
        let outs = o.tool.iter().chain(&o.tool_velocity).chain(&o.actuator).chain(&o.actuator_velocity);
        if !(outs.clone().all(|x| x.is_finite()) && o.tool.iter().chain(&o.actuator).all(|x| x.abs() < 1.0)) {
            return Err("the outputs are not finite or out of range".into());
        }
        if !(o.disturbance_force.is_finite() && self.noise_now.is_finite()) {
            return Err("the disturbance is not finite".into());
        }
        if !(self.t0.is_finite() && self.offset >= 0.0 && self.offset < self.p.internal_step && self.time().is_finite())
        {
            return Err("the time or the grid position is invalid".into());
        }
        for (k, maps) in &self.cache {
            let h = f64::from_bits(*k);
            for (i, m) in self.modes.iter().enumerate() {
                if maps[i] != discretise(m.modal_mass, m.damping(), m.stiffness(), h) {
                    return Err("the cached discretisation does not match the parameters".into());
                }
            }
        }
        let d = &self.p.disturbance;
        match (&self.noise, d.noise && d.noise_rms > 0.0) {
            (None, false) => Ok(()),
            (Some(n), true) => {
                n.matches(&BandLimitedNoise::new(self.p.seed, d.noise_rms, d.noise_bandwidth, self.p.internal_step))
            }
            _ => Err("the noise generator does not match the parameters".into()),
        }
    }
}

#[cfg(test)]
mod tests;
