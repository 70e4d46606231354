//! The two-channel controller: `none`, `dpid`, `dsmc`, `dsmc_t1`, `dsmc_t2`.
//!
//! Each channel (x, y) measures the tool's position `p` and velocity `ṗ` at the samples
//! `t_k = kT` and holds the force `u(k)` on the damper until `t_{k+1}`; `|u| ≤ u_max`.
//!
//! # D-PID (Eq. 62)
//!
//! `u(k) = K_p e(k) + K_i T Σ_{j≤k} e(j) + (K_d/T)(e(k) − e(k−1))`, `e = −s_e p`: Eq. 62 read as
//! negative feedback (with `e = −x` as printed it is positive feedback) and the error in the
//! unit `s_e` (`s_e = 1000`: mm, the reading under which Eq. 63's gains matter; `s_e = 1`: SI).
//!
//! # DSMC (Eqs. 35–38)
//!
//! Normalised units: `p_n = p/X`, `ṗ_n = ṗ/V`, `u_n = u/U` with `U = X/b₀` (so the nominal
//! `h = 1`); `e(k) = −p_n(k)` (Eq. 35). Plant model `p_n(k+1) = j(k) + h u_n(k)` (Eq. 22) with
//! the nominal `j = (A_d[0][0] p + A_d[0][1] ṗ)/X` and `h = 1` from the exact ZOH model of the
//! nominal axis ([`crate::linear::zoh`]; the default reading of `A_dis`, which Eq. 22 calls unknown:
//! [`crate::params`] gives the Euler and identity readings and the computation delay). Sliding
//! variable, n = 2:
//! `s(k) = e(k) + k₁ e(k−1) + k₂ e(k−2)` (Eq. 37; `λ² + k₁λ + k₂` stable; default double root
//! 0.5: `k₁ = −1`, `k₂ = 0.25`). Control:
//!
//! `u_n(k) = [k₁ e(k) + k₂ e(k−1) + σ sign s(k) − ĵ(k)] / ĥ(k)`,
//!
//! so that with exact `ĵ = j`, `ĥ = h` and no saturation `s(k+1) = −σ sign s(k)`: the sliding
//! variable is in the band `|s| ≤ σ` from the first step on (Eq. 43 with G = 0). This is the
//! closed loop of Eq. 41; Eq. 36 as printed with `e = −v` gives `s(k+1) = +σ sign s(k)`, a sign
//! slip we do not copy. Plain DSMC: `ĵ = j`, `ĥ = 1`.
//!
//! # DSMC-T1 / DSMC-T2 (Eqs. 26–31)
//!
//! `ĵ = j + ĵ_f(z)` and `ĥ = max(1 + ĥ_f(z), h_min)` with the fuzzy systems of
//! [`crate::fuzzy`] on `z = (e, −ṗ_n)` (position and velocity error), starting from zero
//! consequents: the fuzzy systems learn the residual of the nominal linear model (the cutting
//! force, the forcing, the damper friction). The paper starts from unknown `A_d`, `B_d`; we
//! start from the nominal model so that the controller is defined from the first sample (with
//! zero consequents `ĥ = 0` would divide by zero). `h_min` (default 0.1) keeps `ĥ` away from 0.
//!
//! The model's prediction (Eq. 31, read without the factor `β₁ + β₂`, which only appears in
//! the analysis and would bias the model by 2.4) is `v̂(k+1) = ĵ(k) + ĥ(k) u_n(k)` with the
//! applied (limited) `u_n`. At the next sample `e_m(k+1) = v̂(k+1) − p_n(k+1)` (Eq. 30) updates the
//! consequents with the strengths of sample `k` (the causal reading of Eq. 27's indices):
//!
//! `w_f ← w_f − Ω' e_m φ_f`, `w_g ← w_g − Ω' e_m u_n(k) φ_g`, `Ω' = Ω/(1 + Φ)` (Eqs. 27, 29)
//!
//! only when `|e_m(k+1)| > |e_m(k)|/β` (the dead zone of Eq. 28; `Ω' = 0` otherwise), for the
//! right (`Ω₁`, `β₁`) and left (`Ω₂`, `β₂`) weights alike (`Ω₁ = Ω₂ = 0.9`, `β₁ = β₂ = 1.2`).
//! The consequents are part of the controller's state (serialized with it).

use crate::fuzzy::{self, Reduction, T1System, T2System};
use crate::linear::{Discrete, zoh};
pub use crate::params::{AxisGains, ControlMode, NominalModel, SlidingFuzzyParams};
use crate::{SlidingFuzzyError, finite};
use serde::{Deserialize, Serialize};

/// The fuzzy compensators of one channel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Compensator {
    /// Plain DSMC, D-PID or off.
    None,
    /// Type 1: (ĵ system, ĥ system).
    T1(T1System, T1System),
    /// Interval type 2: (ĵ system, ĥ system).
    T2(T2System, T2System),
}

/// Normalised strengths of the last sample: `[φ_f,l, φ_f,r, φ_g,l, φ_g,r]` (type 1: l = r).
type Strengths = [Vec<f64>; 4];

/// One channel's state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Channel {
    model: Discrete,
    gains: AxisGains,
    scale: [f64; 2],
    u_scale: f64,
    e1: f64,
    e2: f64,
    integral: f64,
    pid_prev: f64,
    comp: Compensator,
    strengths: Option<Strengths>,
    u_prev: f64,
    v_hat: f64,
    em_prev: f64,
    /// Last outputs: `[u, s, ĵ, ĥ, e_m]`.
    last: [f64; 5],
    /// Learning updates applied (outside the dead zone).
    updates: u64,
    /// With the computation delay: the command computed at the last sample [N], which acts
    /// from the next sample instant.
    pending: f64,
}

/// Outputs of both channels after a sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ControllerOutputs {
    /// Forces `(u_x, u_y)` [N].
    pub u: [f64; 2],
    /// Sliding variables `(s_x, s_y)` (normalised).
    pub s: [f64; 2],
    /// ĵ per channel (normalised).
    pub j_hat: [f64; 2],
    /// ĥ per channel (normalised).
    pub h_hat: [f64; 2],
    /// Last modelling errors e_m (normalised).
    pub model_error: [f64; 2],
    /// Learning updates so far per channel.
    pub updates: [f64; 2],
}

fn sign(s: f64) -> f64 {
    if s > 0.0 {
        1.0
    } else if s < 0.0 {
        -1.0
    } else {
        0.0
    }
}

impl Channel {
    fn new(p: &SlidingFuzzyParams, axis: usize) -> Self {
        let (m, c, k, t) = (p.mass[axis], p.damping[axis], p.stiffness[axis], p.sample_period);
        let exact = zoh(m, c, k, t);
        // the reading's A_dis; B_dis exact in every reading (see `crate::params`)
        let a = match p.nominal_model {
            NominalModel::ExactZoh => exact.a,
            NominalModel::Euler => [[1.0, t], [-k / m * t, 1.0 - c / m * t]],
            NominalModel::Identity => [[1.0, 0.0], [0.0, 1.0]],
        };
        let model = Discrete { a, b: exact.b };
        let red = if p.karnik_mendel { Reduction::KarnikMendel } else { Reduction::ClosedForm };
        let comp = match p.mode {
            ControlMode::DsmcT1 => Compensator::T1(T1System::new(3, 3), T1System::new(3, 2)),
            ControlMode::DsmcT2 => {
                Compensator::T2(T2System::new(3, 2, p.fou_ratio, red), T2System::new(2, 2, p.fou_ratio, red))
            }
            _ => Compensator::None,
        };
        Channel {
            model,
            gains: [p.pid_x, p.pid_y][axis],
            scale: [p.position_scale[axis], p.velocity_scale[axis]],
            u_scale: p.position_scale[axis] / model.b[0],
            e1: 0.0,
            e2: 0.0,
            integral: 0.0,
            pid_prev: 0.0,
            comp,
            strengths: None,
            u_prev: 0.0,
            v_hat: 0.0,
            em_prev: 0.0,
            last: [0.0, 0.0, 0.0, 1.0, 0.0],
            updates: 0,
            pending: 0.0,
        }
    }

    /// The fuzzy compensators (their consequents are the learned weights).
    pub fn compensator(&self) -> &Compensator {
        &self.comp
    }

    fn learn(&mut self, p: &SlidingFuzzyParams, pn: f64) {
        let Some(phi) = &self.strengths else { return };
        let em = self.v_hat - pn;
        let outside = em.abs() > self.em_prev.abs() / p.dead_zone;
        self.em_prev = em;
        self.last[4] = em;
        if !outside {
            return;
        }
        let u = self.u_prev;
        let ug: [Vec<f64>; 2] = [phi[2].iter().map(|x| x * u).collect(), phi[3].iter().map(|x| x * u).collect()];
        let gain = |f: &[f64], g: &[f64]| p.learning_rate * em / (1.0 + fuzzy::norm2(f) + fuzzy::norm2(g));
        match &mut self.comp {
            Compensator::None => return,
            Compensator::T1(fj, fh) => {
                let g = gain(&phi[0], &ug[0]);
                fuzzy::learn(&mut fj.w, &phi[0], g);
                fuzzy::learn(&mut fh.w, &phi[2], g * u);
            }
            Compensator::T2(fj, fh) => {
                let g2 = gain(&phi[0], &ug[0]); // left: Ω₂, Φ₂
                let g1 = gain(&phi[1], &ug[1]); // right: Ω₁, Φ₁
                fuzzy::learn(&mut fj.wl, &phi[0], g2);
                fuzzy::learn(&mut fj.wr, &phi[1], g1);
                fuzzy::learn(&mut fh.wl, &phi[2], g2 * u);
                fuzzy::learn(&mut fh.wr, &phi[3], g1 * u);
            }
        }
        self.updates += 1;
    }

    /// One sample: returns the force that acts over `[t_k, t_{k+1})` (the command of this
    /// sample, or with the computation delay the one computed at the previous sample).
    fn sample(&mut self, p: &SlidingFuzzyParams, pos: f64, vel: f64) -> f64 {
        let u = match p.mode {
            ControlMode::Off => 0.0,
            ControlMode::Dpid => {
                let e = -p.pid_error_scale * pos;
                self.integral += e;
                let g = self.gains;
                let u =
                    g.kp * e + g.ki * p.sample_period * self.integral + g.kd / p.sample_period * (e - self.pid_prev);
                self.pid_prev = e;
                u.clamp(-p.force_limit, p.force_limit)
            }
            _ => self.sliding(p, pos, vel),
        };
        let acting = if p.computation_delay { std::mem::replace(&mut self.pending, u) } else { u };
        self.last[0] = acting;
        acting
    }

    /// The controller's model at `z` with the nominal term `j_nom`: `(ĵ, ĥ, strengths)`.
    fn model_at(&self, p: &SlidingFuzzyParams, j_nom: f64, z: [f64; 2]) -> (f64, f64, Option<Strengths>) {
        let (jf, hf, strengths) = match &self.comp {
            Compensator::None => (0.0, 0.0, None),
            Compensator::T1(fj, fh) => {
                let (a, b) = (fj.phi(z), fh.phi(z));
                (fj.output(&a), fh.output(&b), Some([a.clone(), a, b.clone(), b]))
            }
            Compensator::T2(fj, fh) => {
                let ((al, ar), (bl, br)) = (fj.phi(z), fh.phi(z));
                (fj.output(&al, &ar), fh.output(&bl, &br), Some([al, ar, bl, br]))
            }
        };
        (j_nom + jf, (1.0 + hf).max(p.h_min), strengths)
    }

    /// The nominal `j` of the state `(pos, vel)` [m, m/s] (normalised).
    fn j_nominal(&self, pos: f64, vel: f64) -> f64 {
        (self.model.a[0][0] * pos + self.model.a[0][1] * vel) / self.scale[0]
    }

    /// The sliding-mode law; returns the (limited) command computed at this sample [N].
    fn sliding(&mut self, p: &SlidingFuzzyParams, pos: f64, vel: f64) -> f64 {
        let (pn, vn) = (pos / self.scale[0], vel / self.scale[1]);
        self.learn(p, pn);
        let e = -pn;
        let (j_hat, h_hat, strengths) = self.model_at(p, self.j_nominal(pos, vel), [e, -vn]);
        let (u, s, j_hat, h_hat) = if p.computation_delay {
            // the command on its way acts over [t_k, t_{k+1}): the one-step model predicts
            // p(k+1) with it (and learns from it at the next sample); the law then acts on the
            // predicted state, for the step from t_{k+1}
            let (m, acting) = (self.model, self.pending);
            let un_acting = acting / self.u_scale;
            let p1 = j_hat + h_hat * un_acting;
            let v1 = (m.a[1][0] * pos + m.a[1][1] * vel + m.b[1] * acting) / self.scale[1];
            self.v_hat = p1;
            self.u_prev = un_acting;
            self.strengths = strengths;
            let e1 = -p1;
            let s = e1 + p.k1 * e + p.k2 * self.e1;
            let (j1, h1, _) = self.model_at(p, self.j_nominal(p1 * self.scale[0], v1 * self.scale[1]), [e1, -v1]);
            let un = (p.k1 * e1 + p.k2 * e + p.sigma * sign(s) - j1) / h1;
            ((un * self.u_scale).clamp(-p.force_limit, p.force_limit), s, j1, h1)
        } else {
            let s = e + p.k1 * self.e1 + p.k2 * self.e2;
            let un = (p.k1 * e + p.k2 * self.e1 + p.sigma * sign(s) - j_hat) / h_hat;
            let u = (un * self.u_scale).clamp(-p.force_limit, p.force_limit);
            let un = u / self.u_scale;
            self.v_hat = j_hat + h_hat * un;
            self.u_prev = un;
            self.strengths = strengths;
            (u, s, j_hat, h_hat)
        };
        self.e2 = self.e1;
        self.e1 = e;
        self.last[1..4].copy_from_slice(&[s, j_hat, h_hat]);
        u
    }

    fn finite(&self) -> bool {
        let w: Vec<f64> = match &self.comp {
            Compensator::None => vec![],
            Compensator::T1(a, b) => a.w.iter().chain(&b.w).copied().collect(),
            Compensator::T2(a, b) => a.wl.iter().chain(&a.wr).chain(&b.wl).chain(&b.wr).copied().collect(),
        };
        [self.e1, self.e2, self.integral, self.pid_prev, self.u_prev, self.v_hat, self.em_prev, self.pending]
            .iter()
            .chain(&self.last)
            .chain(&w)
            .all(|v| v.is_finite())
    }
}

/// The two-channel controller with its sample clock.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlidingFuzzy {
    p: SlidingFuzzyParams,
    ch: [Channel; 2],
    samples: u64,
    /// Time of sample 0 (the first communication point), once known.
    t0: Option<f64>,
}

impl SlidingFuzzy {
    /// A controller at rest.
    pub fn new(p: &SlidingFuzzyParams) -> Result<Self, SlidingFuzzyError> {
        p.validate()?;
        Ok(SlidingFuzzy { p: p.clone(), ch: [Channel::new(p, 0), Channel::new(p, 1)], samples: 0, t0: None })
    }

    /// The parameters.
    pub fn params(&self) -> &SlidingFuzzyParams {
        &self.p
    }

    /// Channel `axis` (0: x, 1: y).
    pub fn channel(&self, axis: usize) -> &Channel {
        &self.ch[axis]
    }

    /// Samples taken.
    pub fn samples(&self) -> u64 {
        self.samples
    }

    /// One sample: positions `[x, y]` [m] and velocities `[ẋ, ẏ]` [m/s] in, forces out.
    pub fn sample(&mut self, pos: [f64; 2], vel: [f64; 2]) -> Result<ControllerOutputs, SlidingFuzzyError> {
        for (n, v) in [("x", pos[0]), ("y", pos[1]), ("vx", vel[0]), ("vy", vel[1])] {
            finite(n, v)?;
        }
        let saved = self.ch.clone();
        let p = &self.p;
        for (c, (x, v)) in self.ch.iter_mut().zip(pos.into_iter().zip(vel)) {
            c.sample(p, x, v);
        }
        if !self.ch.iter().all(Channel::finite) {
            self.ch = saved;
            return Err(SlidingFuzzyError::State("controller state is no longer finite".into()));
        }
        self.samples += 1;
        Ok(self.outputs())
    }

    /// Advance the sample clock over the communication step `[t, t + h)`: every sample instant
    /// `t_k = t₀ + kT` in it (`t₀`: the first `t` seen) samples `pos`, `vel` (the inputs at the
    /// step start). With `h = T` each step takes exactly one sample at its start.
    pub fn step(
        &mut self,
        t: f64,
        h: f64,
        pos: [f64; 2],
        vel: [f64; 2],
    ) -> Result<ControllerOutputs, SlidingFuzzyError> {
        if !(t.is_finite() && h.is_finite() && h > 0.0) {
            return Err(SlidingFuzzyError::Input(format!("communication step [{t}, {t} + {h})")));
        }
        let ts = self.p.sample_period;
        let t0 = *self.t0.get_or_insert(t);
        // the sample instants due in [t, t + h): at most h/T + 1 for a consistent clock
        let due = ((t + h - 1e-9 * ts - t0) / ts).ceil() - self.samples as f64;
        if due.is_nan() || due > h / ts + 2.0 {
            return Err(SlidingFuzzyError::State(format!(
                "sample clock inconsistent: {due} samples due in a step of {h} s (T = {ts} s)"
            )));
        }
        let saved = self.clone();
        while t0 + self.samples as f64 * ts < t + h - 1e-9 * ts {
            if let Err(e) = self.sample(pos, vel) {
                *self = saved;
                return Err(e);
            }
        }
        Ok(self.outputs())
    }

    /// The outputs of the last sample.
    pub fn outputs(&self) -> ControllerOutputs {
        let f = |i: usize| [self.ch[0].last[i], self.ch[1].last[i]];
        ControllerOutputs {
            u: f(0),
            s: f(1),
            j_hat: f(2),
            h_hat: f(3),
            model_error: f(4),
            updates: [self.ch[0].updates as f64, self.ch[1].updates as f64],
        }
    }

    /// Every stored number finite.
    pub fn validate_state(&self) -> Result<(), String> {
        self.p.validate().map_err(|e| e.to_string())?;
        if !self.ch.iter().all(Channel::finite) || self.t0.is_some_and(|t| !t.is_finite()) {
            return Err("non-finite controller state".into());
        }
        let want = |m: ControlMode| self.p.mode == m;
        for c in &self.ch {
            let ok = match &c.comp {
                Compensator::None => !want(ControlMode::DsmcT1) && !want(ControlMode::DsmcT2),
                Compensator::T1(a, b) => want(ControlMode::DsmcT1) && a.w.len() == 9 && b.w.len() == 6,
                Compensator::T2(a, b) => {
                    want(ControlMode::DsmcT2)
                        && a.wl.len() == 6
                        && a.wr.len() == 6
                        && b.wl.len() == 4
                        && b.wr.len() == 4
                        && a.ratio.to_bits() == self.p.fou_ratio.to_bits()
                        && b.ratio.to_bits() == self.p.fou_ratio.to_bits()
                }
            };
            if !ok {
                return Err("fuzzy rule base inconsistent with the mode".into());
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The nominal linear axis, exactly discretised, driven by the controller: with exact model
    /// terms the DSMC reaches the band |s| ≤ σ at the first step and stays in it.
    #[test]
    fn dsmc_reaches_its_band_with_exact_model_terms_on_a_linear_plant() {
        let p = SlidingFuzzyParams { mode: ControlMode::Dsmc, force_limit: 1e12, ..Default::default() };
        let mut c = SlidingFuzzy::new(&p).unwrap();
        let d = [zoh(20.0, 1200.0, 7.2e6, 1e-4), zoh(20.0, 4300.0, 6.48e7, 1e-4)];
        let mut v = [[0.4e-3, -20e-3], [-0.3e-3, 50e-3]];
        let mut max_s: f64 = 0.0;
        for k in 0..400 {
            let o = c.sample([v[0][0], v[1][0]], [v[0][1], v[1][1]]).unwrap();
            if k >= 1 {
                for s in o.s {
                    max_s = max_s.max((s.abs() - p.sigma).max(0.0));
                }
            }
            for ((va, m), u) in v.iter_mut().zip(&d).zip(o.u) {
                let x = m.a[0][0] * va[0] + m.a[0][1] * va[1] + m.b[0] * u;
                let y = m.a[1][0] * va[0] + m.a[1][1] * va[1] + m.b[1] * u;
                *va = [x, y];
            }
        }
        assert!(max_s < 1e-9, "|s| exceeded sigma by {max_s}");
        // and the position ends in the chattering band: e oscillates with amplitude σ/(1−k₁+k₂)
        let band = p.sigma / (1.0 - p.k1 + p.k2) * p.position_scale[0];
        assert!(v[0][0].abs() <= band * 1.01 && v[1][0].abs() <= band * 1.01, "{v:?}, band {band}");
    }

    /// With one sample of computation delay the command of sample k acts from t_(k+1): the
    /// law on the predicted state keeps the true s(k+1) in the band |s| <= σ (exact model
    /// terms, linear plant driven by the force the controller says acts now).
    #[test]
    fn dsmc_with_a_computation_delay_reaches_its_band_through_its_prediction() {
        let p = SlidingFuzzyParams {
            mode: ControlMode::Dsmc,
            force_limit: 1e12,
            computation_delay: true,
            ..Default::default()
        };
        let mut c = SlidingFuzzy::new(&p).unwrap();
        let d = [zoh(20.0, 1200.0, 7.2e6, 1e-4), zoh(20.0, 4300.0, 6.48e7, 1e-4)];
        let mut v = [[0.4e-3, -20e-3], [-0.3e-3, 50e-3]];
        let (mut e, mut max_s) = (Vec::new(), 0.0f64);
        for k in 0..400 {
            let o = c.sample([v[0][0], v[1][0]], [v[0][1], v[1][1]]).unwrap();
            e.push(-v[0][0] / p.position_scale[0]);
            // the true sliding variable of the x channel from the measured errors
            if k >= 4 {
                let n = e.len();
                let s = e[n - 1] + p.k1 * e[n - 2] + p.k2 * e[n - 3];
                max_s = max_s.max((s.abs() - p.sigma).max(0.0));
            }
            if k == 0 {
                assert!(o.u.iter().all(|u| *u == 0.0), "nothing acts before the first command arrives");
            }
            for ((va, m), u) in v.iter_mut().zip(&d).zip(o.u) {
                let x = m.a[0][0] * va[0] + m.a[0][1] * va[1] + m.b[0] * u;
                let y = m.a[1][0] * va[0] + m.a[1][1] * va[1] + m.b[1] * u;
                *va = [x, y];
            }
        }
        assert!(max_s < 1e-9, "|s| exceeded sigma by {max_s}");
        let band = p.sigma / (1.0 - p.k1 + p.k2) * p.position_scale[0];
        assert!(v[0][0].abs() <= band * 1.01 && v[1][0].abs() <= band * 1.01, "{v:?}, band {band}");
    }

    #[test]
    fn the_nominal_models_are_the_documented_matrices() {
        let (m, c, k, t) = (20.0, 1200.0, 7.2e6, 3e-4);
        let exact = zoh(m, c, k, t);
        let of = |nominal_model| {
            let p = SlidingFuzzyParams { nominal_model, sample_period: t, ..Default::default() };
            SlidingFuzzy::new(&p).unwrap().ch[0].model
        };
        assert_eq!(of(NominalModel::ExactZoh), exact);
        let euler = of(NominalModel::Euler);
        assert_eq!(euler.a, [[1.0, t], [-k / m * t, 1.0 - c / m * t]]);
        assert_eq!(of(NominalModel::Identity).a, [[1.0, 0.0], [0.0, 1.0]]);
        // B_dis (the input normalisation) is the exact one in every reading
        for n in [NominalModel::Euler, NominalModel::Identity] {
            assert_eq!(of(n).b.map(f64::to_bits), exact.b.map(f64::to_bits));
        }
    }

    #[test]
    fn the_delayed_dpid_is_the_immediate_one_a_sample_later() {
        let p = SlidingFuzzyParams { mode: ControlMode::Dpid, force_limit: 1e9, ..Default::default() };
        let mut now = SlidingFuzzy::new(&p).unwrap();
        let mut late = SlidingFuzzy::new(&SlidingFuzzyParams { computation_delay: true, ..p }).unwrap();
        let mut previous = [0.0; 2];
        for k in 0..50 {
            let x = [1e-6 * (k as f64 * 0.3).sin(), -2e-6 * (k as f64 * 0.2).cos()];
            let a = now.sample(x, [0.0; 2]).unwrap().u;
            assert_eq!(late.sample(x, [0.0; 2]).unwrap().u.map(f64::to_bits), previous.map(f64::to_bits), "sample {k}");
            previous = a;
        }
    }

    #[test]
    fn bad_parameters_and_inputs_are_rejected() {
        for p in [
            SlidingFuzzyParams { k2: 1.5, ..Default::default() },
            SlidingFuzzyParams { dead_zone: 1.0, ..Default::default() },
            SlidingFuzzyParams { fou_ratio: 0.0, ..Default::default() },
            SlidingFuzzyParams { sample_period: f64::NAN, ..Default::default() },
        ] {
            assert!(SlidingFuzzy::new(&p).is_err());
        }
        let mut c = SlidingFuzzy::new(&SlidingFuzzyParams::default()).unwrap();
        c.sample([1e-4, 0.0], [0.0, 0.0]).unwrap();
        let before = c.clone();
        assert!(c.sample([f64::NAN, 0.0], [0.0, 0.0]).is_err());
        assert!(c.sample([0.0, 0.0], [f64::INFINITY, 0.0]).is_err());
        assert_eq!(c, before);
    }

    #[test]
    fn dpid_is_eq_62_with_negative_feedback() {
        let p = SlidingFuzzyParams { mode: ControlMode::Dpid, force_limit: 1e9, ..Default::default() };
        let mut c = SlidingFuzzy::new(&p).unwrap();
        let o1 = c.sample([1e-3, 0.0], [0.0, 0.0]).unwrap();
        // e = −1 mm: u = −200 − 1500·1e-4 − 84/1e-4 (e − 0)
        assert!((o1.u[0] - (-200.0 - 0.15 - 840_000.0)).abs() < 1e-6);
        let o2 = c.sample([1e-3, 0.0], [0.0, 0.0]).unwrap();
        assert!((o2.u[0] - (-200.0 - 0.3)).abs() < 1e-9);
    }
}
