//! The time-domain plant: workpiece modes, cutting force with regeneration, inertial actuator,
//! disturbances, integrated on a fixed internal grid by the exact scheme of [`crate::exact`]
//! (default) or by classical RK4 (`Integrator::Reference`, the slow reference).
//!
//! # Equations
//!
//! Each enabled mode `i` obeys `m_i q̈_i + c_i q̇_i + k_i(t) q_i = F(t)` with the tip force
//! `F = F_c + F_a + d(t)` and tip displacement `x = Σ q_i`. Drift modulates the first mode's
//! stiffness: `k_1(t) = K_w (1 + A sin 2π f_d t)` (Section 5.1's ±10 % at 0.5 Hz; Section 3.4's
//! "A_drift = 0.1 K_w" as a force would be a 2.4 MN force, dimensionally inconsistent, so we read
//! it as the relative stiffness amplitude).
//! The actuator integrates `ż = A z + B u_sat`, `F_a = C z + D u_sat`, with the command `u`
//! clipped to ±`f_max` and held over the communication step. Cutting: see [`crate::params`].
//!
//! # Grid
//!
//! The integrator advances in cells of `internal_step` anchored at the start time; the noise
//! sample of a cell is drawn when the cell is entered and held over it. A communication step
//! that ends on the grid runs whole cells, so any two masters whose steps are multiples of
//! the internal step see bitwise-identical trajectories. A step ending inside a cell runs a
//! partial step to the communication point and the next step completes the cell.
//!
//! # Integrators
//!
//! `Integrator::Reference` evaluates everything four times per cell (RK4; it is the code path
//! of the earlier releases, bit for bit). `Integrator::Exact` advances the linear modal and
//! actuator dynamics exactly (one matrix exponential per step size) and takes the cutting
//! force, the sinusoidal disturbance and the drift force as linear in time over the cell
//! (predictor–corrector, [`crate::exact`]): the cutting force is evaluated at the cell's end
//! only (its start is the previous end, or the outputs' evaluation), with the tooth angles by
//! rotation recurrences, the drift factor once per cell (at its midpoint), and the history
//! lookup in O(1). Over 1 s of the nominal scenario the two agree to about 10⁻⁶ in tip RMS
//! (`tests/integrators.rs`).

use crate::exact::MAX_DIM;
use crate::history::{History, MAX_SAMPLES, Sample};
use crate::noise::BandLimitedNoise;
use crate::params::{CuttingModel, Integrator, Mode, PlantParams};
use crate::teeth::ToothAngles;
use exact_cell::{Fast, LastCut};
use machine_structure::grid::next_sub_step;
use model_kit::rem_two_pi;

mod exact_cell;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Why the plant refused to start or to step.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlantError {
    /// A parameter is out of range.
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// An input is out of range (the step was not taken).
    #[error("invalid input: {0}")]
    Input(String),
    /// The state left any physical range (e.g. unbounded chatter growth).
    #[error("the simulation diverged at t = {t} s (|x| = {x} m)")]
    Diverged {
        /// Time [s].
        t: f64,
        /// Tip displacement [m].
        x: f64,
    },
}

/// Inputs held over a step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlantInputs {
    /// Actuator command [N] (clipped to ±f_max inside the plant).
    pub u: f64,
    /// Spindle speed [rpm] (≥ 0).
    pub spindle_speed_rpm: f64,
    /// Feed per tooth [m] (≥ 0).
    pub feed_per_tooth: f64,
}

impl Default for PlantInputs {
    fn default() -> Self {
        PlantInputs {
            u: 0.0,
            spindle_speed_rpm: crate::params::DEFAULT_SPINDLE_SPEED,
            feed_per_tooth: crate::params::DEFAULT_FEED_PER_TOOTH,
        }
    }
}

/// Plant outputs at the current time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PlantOutputs {
    /// Tip displacement [m].
    pub x: f64,
    /// Tip velocity [m/s].
    pub v: f64,
    /// Cutting force along the beam [N].
    pub cutting_force: f64,
    /// Actuator force on the beam [N].
    pub actuator_force: f64,
    /// Disturbance force (noise + sinusoid) [N].
    pub disturbance_force: f64,
    /// Largest chip thickness among the engaged teeth [m] (0 if none cuts).
    pub chip_thickness: f64,
    /// Was the command clipped?
    pub saturated: bool,
    /// Tool angle θ mod 2π [rad].
    pub tool_angle: f64,
    /// Regenerative delay t − t* [s] (0 before the first full tooth period).
    pub delay: f64,
}

const MAX_MODES: usize = 3;

/// Mechanical state: modal coordinates, velocities, actuator states.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
struct State {
    q: [f64; MAX_MODES],
    qd: [f64; MAX_MODES],
    z: [f64; 2],
}

impl State {
    fn axpy(&self, h: f64, d: &State) -> State {
        let mut s = *self;
        for i in 0..MAX_MODES {
            s.q[i] += h * d.q[i];
            s.qd[i] += h * d.qd[i];
        }
        s.z[0] += h * d.z[0];
        s.z[1] += h * d.z[1];
        s
    }

    /// `(q_1, q̇_1, …, q_n, q̇_n, z_1, z_2)`, the state vector of [`crate::exact`].
    fn flat(&self, n: usize) -> [f64; MAX_DIM] {
        let mut y = [0.0; MAX_DIM];
        for i in 0..n {
            y[2 * i] = self.q[i];
            y[2 * i + 1] = self.qd[i];
        }
        y[2 * n] = self.z[0];
        y[2 * n + 1] = self.z[1];
        y
    }

    fn from_flat(y: &[f64; MAX_DIM], n: usize) -> State {
        let mut s = State::default();
        for i in 0..n {
            s.q[i] = y[2 * i];
            s.qd[i] = y[2 * i + 1];
        }
        s.z = [y[2 * n], y[2 * n + 1]];
        s
    }
}

/// Cutting force and the largest chip.
#[derive(Clone, Copy, Debug, Default)]
struct Cut {
    force: f64,
    chip: f64,
}

/// The plant.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Plant {
    p: PlantParams,
    modes: Vec<Mode>,
    dir: (f64, f64),
    alpha0: f64,
    static_coef: f64,
    engagement: (f64, f64),
    state: State,
    /// Start time and grid position: t = t0 + cell·T + offset.
    t0: f64,
    cell: u64,
    offset: f64,
    theta: f64,
    history: History,
    noise: Option<BandLimitedNoise>,
    noise_now: f64,
    out: PlantOutputs,
    /// Tooth angles of the exact scheme (state: the recurrence continues after a restore).
    angles: ToothAngles,
    /// Valid until the next history sample.
    #[serde(skip)]
    last_cut: Option<LastCut>,
    /// The last history lookup of the exact scheme: (angle bits, result); see `push_history`.
    #[serde(skip)]
    lookup: Option<(u64, Option<(f64, f64)>)>,
    #[serde(skip)]
    fast: Option<Box<Fast>>,
}

impl Plant {
    /// A plant at rest (tip at `workpiece.initial_displacement`) at time 0.
    pub fn new(p: &PlantParams) -> Result<Plant, PlantError> {
        Plant::new_at(p, 0.0)
    }

    /// A plant at rest at time `t0`.
    pub fn new_at(p: &PlantParams, t0: f64) -> Result<Plant, PlantError> {
        p.validate().map_err(PlantError::Parameter)?;
        let modes = p.mode_list();
        let mut state = State::default();
        // put the initial displacement in static equilibrium shape: each mode's share of a static tip load
        let flex: f64 = modes.iter().map(|m| 1.0 / m.stiffness).sum();
        for (i, m) in modes.iter().enumerate() {
            state.q[i] = p.workpiece.initial_displacement / (m.stiffness * flex);
        }
        let d = &p.disturbance;
        let mut noise = (d.noise && d.noise_rms > 0.0)
            .then(|| BandLimitedNoise::new(p.seed, d.noise_rms, d.noise_bandwidth, p.internal_step));
        let noise_now = noise.as_mut().map_or(0.0, BandLimitedNoise::next_sample);
        let mut plant = Plant {
            p: p.clone(),
            modes,
            dir: p.direction(),
            alpha0: p.directional_coefficient(),
            static_coef: p.static_force_coefficient(),
            engagement: p.engagement(),
            state,
            t0,
            cell: 0,
            offset: 0.0,
            theta: 0.0,
            history: History::default(),
            noise,
            noise_now,
            out: PlantOutputs::default(),
            angles: ToothAngles::new(0.0),
            last_cut: None,
            lookup: None,
            fast: (p.integrator == Integrator::Exact).then(|| Fast::new(p)),
        };
        plant.push_history();
        plant.refresh_outputs(&PlantInputs::default(), 0.0);
        Ok(plant)
    }

    /// The parameters.
    pub fn params(&self) -> &PlantParams {
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

    /// Outputs at the current time (forces evaluated with the inputs of the last step).
    pub fn outputs(&self) -> PlantOutputs {
        self.out
    }

    /// Recompute the outputs for new inputs at the current time (e.g. during initialization).
    pub fn set_inputs(&mut self, inputs: &PlantInputs) -> Result<(), PlantError> {
        check_inputs(inputs)?;
        let delay_dummy = self.out.delay;
        self.refresh_outputs(inputs, delay_dummy);
        Ok(())
    }

    /// Number of samples in the regenerative history (bounded by [`MAX_SAMPLES`]).
    pub fn history_len(&self) -> usize {
        self.history.len()
    }

    /// The lowest spindle speed [rpm] at which the plant cuts: one tooth period must fit in half
    /// the history (`MAX_SAMPLES / 2` internal steps; 11.4 rpm for 4 teeth at 10 µs). A step
    /// cutting more slowly (but above 0 rpm) is refused as an invalid input.
    pub fn min_cutting_speed_rpm(&self) -> f64 {
        60.0 / (self.p.cutting.teeth as f64 * (MAX_SAMPLES / 2) as f64 * self.p.internal_step)
    }

    /// Is this a state the plant can continue from? The parameters pass [`PlantParams::validate`]
    /// (as at construction), the derived quantities are those the parameters give, the state,
    /// time and outputs are finite, the grid position lies in its cell, and the history is
    /// ordered, bounded and ends at the current instant. Run on every restored FMU state.
    pub fn validate_state(&self) -> Result<(), String> {
        let p = &self.p;
        p.validate()?;
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
        let (dir, eng) = (p.direction(), p.engagement());
        if self.modes != p.mode_list()
            || !same(self.dir.0, dir.0)
            || !same(self.dir.1, dir.1)
            || !same(self.alpha0, p.directional_coefficient())
            || !same(self.static_coef, p.static_force_coefficient())
            || !same(self.engagement.0, eng.0)
            || !same(self.engagement.1, eng.1)
        {
            return Err("derived plant quantities do not match the parameters".into());
        }
        let s = &self.state;
        if !(s.q.iter().chain(&s.qd).chain(&s.z).all(|x| x.is_finite()) && self.tip().abs() < 1.0) {
            return Err("the mechanical state is not finite or out of range".into());
        }
        if !(self.t0.is_finite() && self.offset >= 0.0 && self.offset < p.internal_step && self.time().is_finite()) {
            return Err("the time or the grid position is invalid".into());
        }
        if !(self.theta.is_finite() && self.theta >= 0.0 && self.noise_now.is_finite()) {
            return Err("the tool angle or the noise sample is not finite".into());
        }
        if !self.angles.is_valid() {
            return Err("the tooth-angle recurrence is not on the unit circle".into());
        }
        let o = &self.out;
        let outs = [o.x, o.v, o.cutting_force, o.actuator_force, o.disturbance_force, o.chip_thickness, o.tool_angle];
        if !(outs.iter().all(|x| x.is_finite()) && o.delay.is_finite() && o.delay >= 0.0) {
            return Err("the outputs are not finite".into());
        }
        self.history.validate()?;
        if self.history.newest().is_none_or(|n| !same(n.t, self.time()) || !same(n.theta, self.theta)) {
            return Err("the history does not end at the current instant".into());
        }
        let d = &p.disturbance;
        match (&self.noise, d.noise && d.noise_rms > 0.0) {
            (None, false) => Ok(()),
            (Some(n), true) => {
                n.matches(&BandLimitedNoise::new(p.seed, d.noise_rms, d.noise_bandwidth, p.internal_step))
            }
            _ => Err("the noise generator does not match the parameters".into()),
        }
    }

    /// Advance by `h` [s] with the inputs held.
    pub fn step(&mut self, h: f64, inputs: &PlantInputs) -> Result<(), PlantError> {
        check_inputs(inputs)?;
        let c = &self.p.cutting;
        let n = inputs.spindle_speed_rpm;
        if c.enabled && c.axial_depth > 0.0 && n > 0.0 && n < self.min_cutting_speed_rpm() {
            return Err(PlantError::Input(format!(
                "spindle_speed = {n} rpm is below the lowest cutting speed {} rpm (one tooth period must fit \
                 in the regenerative history); use 0 rpm to stop",
                self.min_cutting_speed_rpm()
            )));
        }
        if !(h.is_finite() && h >= 0.0) {
            return Err(PlantError::Input(format!("step size {h} must be finite and >= 0")));
        }
        let hi = self.p.internal_step;
        // what is left of the step, counted down by `next_sub_step` (see `machine_structure::grid`)
        let mut remaining = h;
        let omega = inputs.spindle_speed_rpm * 2.0 * PI / 60.0;
        let mut delay = self.out.delay;
        while let Some((dt, completes)) = next_sub_step(&mut remaining, self.offset, hi) {
            match self.p.integrator {
                Integrator::Reference => delay = self.rk4(dt, omega, inputs),
                Integrator::Exact => {
                    self.exact_cell(dt, omega, inputs);
                    delay = f64::NAN; // looked up once, after the last cell
                }
            }
            if completes {
                self.cell += 1;
                self.offset = 0.0;
                self.noise_now = self.noise.as_mut().map_or(0.0, BandLimitedNoise::next_sample);
            } else {
                self.offset += dt;
            }
            self.push_history();
            let x = self.tip();
            if !(x.is_finite() && x.abs() < 1.0) {
                return Err(PlantError::Diverged { t: self.time(), x });
            }
        }
        if delay.is_nan() {
            let pitch = 2.0 * PI / self.p.cutting.teeth as f64;
            let t = self.time();
            delay = self.delayed(self.theta - pitch).map_or(0.0, |(ts, _)| t - ts);
        }
        self.refresh_outputs(inputs, delay);
        Ok(())
    }

    fn tip(&self) -> f64 {
        self.state.q[..self.modes.len()].iter().sum()
    }

    fn tip_velocity(&self) -> f64 {
        self.state.qd[..self.modes.len()].iter().sum()
    }

    fn push_history(&mut self) {
        let s = Sample { t: self.time(), theta: self.theta, x: self.tip(), v: self.tip_velocity() };
        let newest = self.history.newest().map_or(f64::NEG_INFINITY, |n| n.theta);
        self.history.push(s);
        self.last_cut = None;
        let pitch = 2.0 * PI / self.p.cutting.teeth as f64;
        let theta_min = self.theta - pitch;
        self.history.prune(theta_min);
        // the remembered lookup stays valid if the new sample was appended past it (not
        // coalesced), pruning kept its bracket and nothing was dropped for the size bound
        let keep = self.lookup.is_some_and(|l| {
            let q = f64::from_bits(l.0);
            s.theta > newest && q >= theta_min && q < newest && self.history.len() < MAX_SAMPLES
        });
        if !keep {
            self.lookup = None;
        }
    }

    /// One RK4 step of length `dt`; returns the delay at the end of the step.
    fn rk4(&mut self, dt: f64, omega: f64, inputs: &PlantInputs) -> f64 {
        let t = self.time();
        let s0 = self.state;
        let th = self.theta;
        let k1 = self.deriv(t, th, &s0, omega, inputs);
        let s1 = s0.axpy(0.5 * dt, &k1);
        let k2 = self.deriv(t + 0.5 * dt, th + 0.5 * dt * omega, &s1, omega, inputs);
        let s2 = s0.axpy(0.5 * dt, &k2);
        let k3 = self.deriv(t + 0.5 * dt, th + 0.5 * dt * omega, &s2, omega, inputs);
        let s3 = s0.axpy(dt, &k3);
        let k4 = self.deriv(t + dt, th + dt * omega, &s3, omega, inputs);
        let mut s = s0;
        for i in 0..MAX_MODES {
            s.q[i] += dt / 6.0 * (k1.q[i] + 2.0 * k2.q[i] + 2.0 * k3.q[i] + k4.q[i]);
            s.qd[i] += dt / 6.0 * (k1.qd[i] + 2.0 * k2.qd[i] + 2.0 * k3.qd[i] + k4.qd[i]);
        }
        for j in 0..2 {
            s.z[j] += dt / 6.0 * (k1.z[j] + 2.0 * k2.z[j] + 2.0 * k3.z[j] + k4.z[j]);
        }
        self.state = s;
        self.theta = th + dt * omega;
        let pitch = 2.0 * PI / self.p.cutting.teeth as f64;
        self.history.at_angle(self.theta - pitch).map_or(0.0, |(ts, _)| t + dt - ts)
    }

    fn u_sat(&self, u: f64) -> (f64, bool) {
        let f = self.p.actuator.f_max;
        (u.clamp(-f, f), u.abs() > f)
    }

    fn actuator_force(&self, z: &[f64; 2], u_sat: f64) -> f64 {
        let a = &self.p.actuator;
        a.c[0] * z[0] + a.c[1] * z[1] + a.d * u_sat
    }

    fn disturbance(&self, t: f64) -> f64 {
        let d = &self.p.disturbance;
        let sine =
            if d.sine_amplitude == 0.0 { 0.0 } else { d.sine_amplitude * (2.0 * PI * d.sine_frequency * t).sin() };
        self.noise_now + sine
    }

    fn first_stiffness(&self, t: f64) -> f64 {
        let d = &self.p.disturbance;
        let k = self.modes[0].stiffness;
        if d.drift { k * (1.0 + d.drift_amplitude * (2.0 * PI * d.drift_frequency * t).sin()) } else { k }
    }

    /// Cutting force along the beam at tool angle `theta`, tip displacement `x`.
    fn cutting(&self, theta: f64, x: f64, omega: f64, inputs: &PlantInputs) -> Cut {
        let c = &self.p.cutting;
        if !c.enabled || omega <= 0.0 || c.axial_depth == 0.0 {
            return Cut::default();
        }
        let pitch = 2.0 * PI / c.teeth as f64;
        let x_prev = self.history.at_angle(theta - pitch).map_or(0.0, |(_, xp)| xp);
        let dx = x - x_prev;
        let fz = inputs.feed_per_tooth;
        match c.model {
            CuttingModel::Averaged => {
                Cut { force: c.axial_depth * c.kt * (fz * self.static_coef - self.alpha0 * dx), chip: fz }
            }
            CuttingModel::TimeDomain => {
                let (st, ex) = self.engagement;
                let (ux, uy) = self.dir;
                let kr = c.kr / c.kt.max(f64::MIN_POSITIVE);
                let base = theta.rem_euclid(2.0 * PI);
                let mut cut = Cut::default();
                for j in 0..c.teeth {
                    let phi = (base + j as f64 * pitch).rem_euclid(2.0 * PI);
                    if phi < st || phi > ex {
                        continue;
                    }
                    let (s, co) = phi.sin_cos();
                    let h = fz * s - dx * (ux * s + uy * co);
                    if h <= 0.0 {
                        continue; // loss of contact
                    }
                    cut.chip = cut.chip.max(h);
                    cut.force += c.axial_depth * c.kt * h * ((co + kr * s) * ux + (-s + kr * co) * uy);
                }
                cut
            }
        }
    }

    fn deriv(&self, t: f64, theta: f64, s: &State, omega: f64, inputs: &PlantInputs) -> State {
        let n = self.modes.len();
        let x: f64 = s.q[..n].iter().sum();
        let (u, _) = self.u_sat(inputs.u);
        let fa = self.actuator_force(&s.z, u);
        let f = self.cutting(theta, x, omega, inputs).force + fa + self.disturbance(t);
        let mut d = State::default();
        for (i, m) in self.modes.iter().enumerate() {
            let k = if i == 0 { self.first_stiffness(t) } else { m.stiffness };
            d.q[i] = s.qd[i];
            d.qd[i] = (f - m.damping() * s.qd[i] - k * s.q[i]) / m.mass;
        }
        let a = &self.p.actuator;
        d.z[0] = a.a[0][0] * s.z[0] + a.a[0][1] * s.z[1] + a.b[0] * u;
        d.z[1] = a.a[1][0] * s.z[0] + a.a[1][1] * s.z[1] + a.b[1] * u;
        d
    }

    fn refresh_outputs(&mut self, inputs: &PlantInputs, delay: f64) {
        let t = self.time();
        let omega = inputs.spindle_speed_rpm * 2.0 * PI / 60.0;
        let x = self.tip();
        let cut = match self.p.integrator {
            Integrator::Reference => self.cutting(self.theta, x, omega, inputs),
            Integrator::Exact => {
                let fast = self.fast.take().unwrap_or_else(|| Fast::new(&self.p));
                let cut = self.fast_cut(&fast.geo, self.theta, None, x, omega, inputs);
                let key = [self.theta.to_bits(), x.to_bits(), inputs.feed_per_tooth.to_bits(), omega.to_bits()];
                self.last_cut = Some(LastCut { key, cut });
                self.fast = Some(fast);
                cut
            }
        };
        let (u, saturated) = self.u_sat(inputs.u);
        self.out = PlantOutputs {
            x,
            v: self.tip_velocity(),
            cutting_force: cut.force,
            actuator_force: self.actuator_force(&self.state.z, u),
            disturbance_force: self.disturbance(t),
            chip_thickness: cut.chip,
            saturated,
            tool_angle: rem_two_pi(self.theta),
            delay,
        };
    }
}

fn check_inputs(i: &PlantInputs) -> Result<(), PlantError> {
    if !i.u.is_finite() {
        return Err(PlantError::Input(format!("u = {} is not finite", i.u)));
    }
    if !(i.spindle_speed_rpm.is_finite() && i.spindle_speed_rpm >= 0.0) {
        return Err(PlantError::Input(format!("spindle_speed = {} rpm must be finite and >= 0", i.spindle_speed_rpm)));
    }
    if !(i.feed_per_tooth.is_finite() && i.feed_per_tooth >= 0.0) {
        return Err(PlantError::Input(format!("feed_per_tooth = {} m must be finite and >= 0", i.feed_per_tooth)));
    }
    Ok(())
}
