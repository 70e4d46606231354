//! The AFrAC controller: reference model, error, convolution memory, the adaptation laws for
//! the feed and the spindle speed, integrated by `I^β` (seed 001, Eqs. 18–21, 28–30).
//!
//! # Maths
//!
//! The plant's delay is the reference delay plus `h`: `T_p = T_ref + h`, so the speed is
//! `N = 60/(T_ref + h)` and `h₀ = 60/N₀ − T_ref` starts it at `N₀`. The feed is
//! `f = f₀ + δf`. With `ε = x − y` (`x = (x, ẋ)` measured, `y` the reference model's state),
//! `z = ε + Q∗ε` ([`crate::memory`]) and `G = P₁₂z₁ + P₂₂z₂` (the second row of `Pz`; the
//! error forcing `φZ` acts on the second state only):
//!
//! ```text
//! r_f = −λ₂ s₀ x(t − T_p) G / (a₂ (Y − 1) sin K)      (Eq. 20: δḟ = r_f)
//! r_h = +λ₃ ẋ(t − T_p) G / a₂                          (Eq. 21: ḣ = r_h)
//! δf = I^β[r_f],   h = h₀ + I^β[r_h]                   (Eqs. 28–29)
//! ```
//!
//! **Signs.** With the physical delay `T_ref + h`, the plant's error forcing is
//! `a₂[x(t − T − h) − x(t − T)] ≈ −a₂ h ẋ(t − T)` (the paper's Eq. 10 writes `x(t − T + h)`,
//! the opposite sign of `h`). `V = zᵀPz + (a₂²/λ₃) h² + δa₂²/λ₂` then has
//! `V̇ = −zᵀRz − 2G a₂hẋ(t−T) + 2(a₂²/λ₃) h ḣ + 2Gδa₂ x(t−T_p) + 2δa₂δȧ₂/λ₂`, which is
//! `−zᵀRz ≤ 0` for `ḣ = λ₃ẋ(t−T)G/a₂` and `δȧ₂ = −λ₂ x(t−T_p) G`; the feed enters through
//! `δa₂ = a₂(Y − 1) sin K δf/s₀` (`a₂ ∝ s₀^{Y−1}`), which gives Eq. 20 with `λ₂ > 0`. So both
//! gains are positive here; Eq. 21's minus sign belongs to the paper's `+h` convention.
//! Following Eq. 20, the feed law uses the `δB` term only (the paper's `δA = −δB` term
//! `−δa₂ x(t)` is left out, as in Eq. 20).
//!
//! **Delayed values.** `x(t − T_p)`, `ẋ(t − T_p)` come from the controller's own history of
//! the measurements, indexed by the angle of its own speed command (the angle-indexed history
//! of `milling-process`, both values linear in angle between samples): one revolution back, as
//! the plant sees it.
//!
//! **Reference model.** `ẏ = Ay + By(t − T_ref)` with `a₂` at the actual depth and nominal
//! feed, integrated by RK4 on the sample grid (delayed values linear between samples), started
//! at `y(0) = (y0, 0)` on a history at rest. With `y0 = 0` (default) it stays at rest and
//! `ε = x`.
//!
//! **Missing constants (readings).** `λ₂`, `λ₃` are not given: chosen so that β = 1 settles
//! the 5 mm case in about 2–2.5 s (the slowest curve of Figure 7), see the README. `ρ` of
//! Eq. 13 does not appear in the laws (20)–(21) and is not used. `R = I`. `T_ref = 60/524` s
//! (a speed where 5 mm is stable). The commands are limited to `[N_min, N_max]` and
//! `[f_min, f_max]` (the machine's range), the integrators are not (no anti-windup: the paper
//! has none).
//!
//! # Timing
//!
//! [`Afrac::sample`] at `t_k` reads `(x, ẋ)` at `t_k` and returns the commands to hold over
//! `[t_k, t_k + τ)`.

use crate::AfracError;
use crate::delay_model::DelayModel;
use crate::memory::Memory;
use crate::oustaloup::{Band, Integrator};
use crate::schedule::Schedule;
use milling_process::history::{History, XySample};
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;
use std::f64::consts::PI;

/// Parameters of [`Afrac`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AfracParams {
    /// Natural frequency f_n [Hz].
    pub natural_frequency: f64,
    /// Damping ratio ζ.
    pub damping_ratio: f64,
    /// κ = a₂/(ω_n² w) at the initial feed [1/mm].
    pub kappa: f64,
    /// Depth of cut w [mm] (a₂ at this depth).
    pub depth: f64,
    /// Force exponent Y.
    pub force_exponent: f64,
    /// Cutting edge angle K [deg].
    pub edge_angle: f64,
    /// Initial spindle speed N₀ [rpm].
    pub initial_speed: f64,
    /// Initial feed f₀ [mm/rev].
    pub initial_feed: f64,
    /// Speed of the reference model, 60/T_ref [rpm].
    pub reference_speed: f64,
    /// Initial displacement of the reference model [mm].
    pub reference_y0: f64,
    /// Feed adaptation gain λ₂.
    pub lambda_feed: f64,
    /// Speed adaptation gain λ₃.
    pub lambda_speed: f64,
    /// Sample period τ [s].
    pub sample_period: f64,
    /// The β schedule.
    pub schedule: Schedule,
    /// Bumpless switching of the orders.
    pub bumpless: bool,
    /// Oustaloup band.
    pub band: Band,
    /// Speed limits [rpm].
    pub speed_min: f64,
    /// Upper speed limit [rpm].
    pub speed_max: f64,
    /// Feed limits [mm/rev].
    pub feed_min: f64,
    /// Upper feed limit [mm/rev].
    pub feed_max: f64,
}

impl Default for AfracParams {
    fn default() -> Self {
        AfracParams {
            natural_frequency: 85.0,
            damping_ratio: 0.0384,
            kappa: 0.01994,
            depth: 5.0,
            force_exponent: 0.75,
            edge_angle: 90.0,
            initial_speed: 450.0,
            initial_feed: 0.1,
            reference_speed: 524.0,
            reference_y0: 0.0,
            lambda_feed: DEFAULT_LAMBDA_FEED,
            lambda_speed: DEFAULT_LAMBDA_SPEED,
            sample_period: 1e-4,
            schedule: Schedule::default(),
            bumpless: false,
            band: Band::default(),
            speed_min: 100.0,
            speed_max: 2000.0,
            feed_min: 0.01,
            feed_max: 0.5,
        }
    }
}

/// λ₂ (reading): the feed law's scale is `s₀ x G/a₂ ≈ 1e-13` per unit gain at the chatter
/// amplitudes of Table 2, so λ₂ = 1e9 moves the feed by a few 0.1 % to a few % of f₀ while
/// the speed moves by 5–300 % (the feed acts only through `a₂ ∝ s₀^{Y−1}`, a weak lever).
pub const DEFAULT_LAMBDA_FEED: f64 = 1e9;
/// λ₃ (reading): with β = 1 the 5 mm case falls to 10 % of its peak in about 2.7 s (Figure 7's
/// slowest curve settles in 2–2.5 s); larger λ₃ does not make β = 1 faster (the speed stops
/// near 476 rpm, just inside the stable lobe) but drives β = 1.75 into the speed limit.
pub const DEFAULT_LAMBDA_SPEED: f64 = 4e6;

impl AfracParams {
    /// ω_n.
    pub fn omega_n(&self) -> f64 {
        2.0 * PI * self.natural_frequency
    }

    /// a₂ at the depth and the initial feed.
    pub fn a2(&self) -> f64 {
        self.omega_n().powi(2) * self.kappa * self.depth
    }

    /// Check ranges.
    pub fn validate(&self) -> Result<(), AfracError> {
        let e = |n: &str, v: f64| AfracError::Params(format!("{n} = {v} is out of range"));
        let pos = [
            ("natural_frequency", self.natural_frequency),
            ("kappa", self.kappa),
            ("depth", self.depth),
            ("initial_speed", self.initial_speed),
            ("initial_feed", self.initial_feed),
            ("reference_speed", self.reference_speed),
            ("sample_period", self.sample_period),
            ("speed_min", self.speed_min),
            ("feed_min", self.feed_min),
        ];
        for (n, v) in pos {
            if !(v.is_finite() && v > 0.0 && v < 1e7) {
                return Err(e(n, v));
            }
        }
        for (n, v) in [
            ("damping_ratio", self.damping_ratio),
            ("lambda_feed", self.lambda_feed),
            ("lambda_speed", self.lambda_speed),
        ] {
            if !(v.is_finite() && (0.0..1e15).contains(&v)) {
                return Err(e(n, v));
            }
        }
        if !(self.force_exponent.is_finite() && self.force_exponent > 0.0 && self.force_exponent < 1.0) {
            return Err(e("force_exponent (the feed law divides by Y − 1)", self.force_exponent));
        }
        if !(self.edge_angle.is_finite() && self.edge_angle > 0.0 && self.edge_angle <= 90.0) {
            return Err(e("edge_angle", self.edge_angle));
        }
        if !self.reference_y0.is_finite() || self.reference_y0.abs() > 1e3 {
            return Err(e("reference_y0", self.reference_y0));
        }
        if self.sample_period > 1e-2 {
            return Err(e("sample_period", self.sample_period));
        }
        if !(self.speed_max.is_finite() && self.speed_max > self.speed_min) {
            return Err(e("speed_max", self.speed_max));
        }
        if !(self.feed_max.is_finite() && self.feed_max > self.feed_min) {
            return Err(e("feed_max", self.feed_max));
        }
        let b = &self.band;
        if !(b.omega_b.is_finite()
            && b.omega_b > 0.0
            && b.omega_h.is_finite()
            && b.omega_h > b.omega_b
            && (1..=4).contains(&b.n))
        {
            return Err(AfracError::Params("the Oustaloup band needs 0 < ω_b < ω_h and 1 ≤ N ≤ 4".into()));
        }
        if 60.0 / self.reference_speed < 2.0 * self.sample_period {
            return Err(e("reference_speed (the delay must span samples)", self.reference_speed));
        }
        self.schedule.validate().map_err(AfracError::Params)
    }
}

/// What the controller reports at a sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AfracOutputs {
    /// Spindle speed command N [rpm].
    pub spindle_speed: f64,
    /// Feed command f [mm/rev].
    pub feed: f64,
    /// Current order β.
    pub beta: f64,
    /// Error ε₁ = x − y₁ [mm].
    pub eps1: f64,
    /// Error ε₂ = ẋ − y₂ [mm/s].
    pub eps2: f64,
    /// Delay offset h = T_p − T_ref [s].
    pub h: f64,
    /// Feed change δf [mm/rev].
    pub delta_feed: f64,
    /// G = P₁₂z₁ + P₂₂z₂.
    pub g: f64,
}

/// One bank of integrators (one per order), fed with the same law.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Bank {
    integrators: Vec<Integrator>,
    active: usize,
    offset: f64,
}

impl Bank {
    fn new(orders: &[f64], band: &Band, period: f64) -> Self {
        Bank { integrators: orders.iter().map(|b| Integrator::new(*b, band, period)).collect(), active: 0, offset: 0.0 }
    }

    /// Output at this sample with order `beta`, input `u` held over the next period.
    fn sample(&mut self, beta: f64, u: f64, bumpless: bool) -> f64 {
        let want = self.integrators.iter().position(|i| i.beta().to_bits() == beta.to_bits()).unwrap_or(self.active);
        if want != self.active {
            if bumpless {
                self.offset += self.integrators[self.active].peek(u) - self.integrators[want].peek(u);
            }
            self.active = want;
        }
        let mut y = 0.0;
        for (i, integ) in self.integrators.iter_mut().enumerate() {
            let yi = integ.sample(u);
            if i == self.active {
                y = yi;
            }
        }
        y + self.offset
    }

    fn is_finite(&self) -> bool {
        self.offset.is_finite() && self.integrators.iter().all(Integrator::is_finite)
    }
}

/// The AFrAC controller.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Afrac {
    params: AfracParams,
    model: DelayModel,
    memory: Memory,
    k: u64,
    theta: f64,
    measured: History<XySample>,
    y: [f64; 2],
    y_hist: VecDeque<[f64; 2]>,
    speed_bank: Bank,
    feed_bank: Bank,
    h0: f64,
    out: AfracOutputs,
}

impl Afrac {
    /// Design (Q₀, P) and start at rest with the initial speed and feed.
    pub fn new(params: &AfracParams) -> Result<Self, AfracError> {
        params.validate()?;
        let p = params;
        let wn = p.omega_n();
        let t_ref = 60.0 / p.reference_speed;
        let model = DelayModel::new(wn, 2.0 * p.damping_ratio * wn, p.a2(), t_ref)?;
        let tau = p.sample_period;
        let memory = Memory::new(&model, tau, 0.0);
        let orders = p.schedule.orders();
        let m = (t_ref / tau).ceil() as usize + 2;
        let h0 = 60.0 / p.initial_speed - t_ref;
        let mut measured = History::default();
        measured.push(XySample { t: 0.0, theta: 0.0, r: [0.0, 0.0] });
        Ok(Afrac {
            params: p.clone(),
            model,
            memory,
            k: 0,
            theta: 0.0,
            measured,
            y: [p.reference_y0, 0.0],
            y_hist: VecDeque::from(vec![[0.0, 0.0]; m]),
            speed_bank: Bank::new(&orders, &p.band, tau),
            feed_bank: Bank::new(&orders, &p.band, tau),
            h0,
            out: AfracOutputs {
                spindle_speed: p.initial_speed,
                feed: p.initial_feed,
                beta: p.schedule.beta_at(0.0),
                h: h0,
                ..Default::default()
            },
        })
    }

    /// The parameters.
    pub fn params(&self) -> &AfracParams {
        &self.params
    }

    /// The reference model with Q₀ and P.
    pub fn model(&self) -> &DelayModel {
        &self.model
    }

    /// The latest outputs.
    pub fn outputs(&self) -> AfracOutputs {
        self.out
    }

    /// Time of the next sample [s].
    pub fn next_sample_time(&self) -> f64 {
        self.k as f64 * self.params.sample_period
    }

    /// Reference delayed state at `t − T_ref` (linear between stored samples; y_hist[0] is t_k).
    fn y_delayed(&self, back: f64) -> [f64; 2] {
        let tau = self.params.sample_period;
        let s = (self.model.delay - back) / tau;
        let i = s.floor().max(0.0) as usize;
        let f = s - i as f64;
        let (a, b) = (self.y_hist[i.min(self.y_hist.len() - 1)], self.y_hist[(i + 1).min(self.y_hist.len() - 1)]);
        [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])]
    }

    fn advance_reference(&mut self) {
        let tau = self.params.sample_period;
        let (a, b) = (self.model.a(), self.model.b());
        let f = |y: [f64; 2], yd: [f64; 2]| {
            [
                a[(0, 0)] * y[0] + a[(0, 1)] * y[1] + b[(0, 0)] * yd[0] + b[(0, 1)] * yd[1],
                a[(1, 0)] * y[0] + a[(1, 1)] * y[1] + b[(1, 0)] * yd[0] + b[(1, 1)] * yd[1],
            ]
        };
        let y = self.y;
        let (d0, dh, d1) = (self.y_delayed(0.0), self.y_delayed(0.5 * tau), self.y_delayed(tau));
        let add = |y: [f64; 2], k: [f64; 2], c: f64| [y[0] + c * k[0], y[1] + c * k[1]];
        let k1 = f(y, d0);
        let k2 = f(add(y, k1, 0.5 * tau), dh);
        let k3 = f(add(y, k2, 0.5 * tau), dh);
        let k4 = f(add(y, k3, tau), d1);
        self.y = [
            y[0] + tau / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
            y[1] + tau / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
        ];
        self.y_hist.pop_back();
        self.y_hist.push_front(self.y);
    }

    /// One sample at `t_k = k τ`: measurements `(x, ẋ)` in, commands for `[t_k, t_k + τ)` out.
    pub fn sample(&mut self, x: f64, v: f64) -> Result<AfracOutputs, AfracError> {
        if !(x.is_finite() && v.is_finite() && x.abs() < 1e6 && v.abs() < 1e9) {
            return Err(AfracError::Input(format!(
                "measurement x = {x} mm, v = {v} mm/s is not finite or out of range"
            )));
        }
        let p = &self.params;
        let tau = p.sample_period;
        let t = self.k as f64 * tau;
        if self.k == 0 {
            self.y_hist[0] = self.y;
        }
        self.measured.set_newest(XySample { t, theta: self.theta, r: [x, v] });
        let eps = [x - self.y[0], v - self.y[1]];
        let q = self.memory.push(eps[0]);
        let z = [eps[0] + q[0], eps[1] + q[1]];
        let g = self.model.p[1] * z[0] + self.model.p[2] * z[1];
        let [xd, vd] = self.measured.at_angle(self.theta - 2.0 * PI).map_or([0.0, 0.0], |(_, r)| r);
        let y_exp = p.force_exponent;
        let sin_k = p.edge_angle.to_radians().sin();
        let s0 = p.initial_feed * sin_k;
        let a2 = self.model.a2;
        let r_f = -p.lambda_feed * s0 * xd * g / (a2 * (y_exp - 1.0) * sin_k);
        let r_h = p.lambda_speed * vd * g / a2;
        let beta = p.schedule.beta_at(t);
        let df = self.feed_bank.sample(beta, r_f, p.bumpless);
        let h = self.h0 + self.speed_bank.sample(beta, r_h, p.bumpless);
        let t_ref = self.model.delay;
        let n_raw = if t_ref + h > 0.0 { 60.0 / (t_ref + h) } else { p.speed_max };
        let speed = n_raw.clamp(p.speed_min, p.speed_max);
        let feed = (p.initial_feed + df).clamp(p.feed_min, p.feed_max);
        if !(self.feed_bank.is_finite() && self.speed_bank.is_finite() && speed.is_finite() && feed.is_finite()) {
            return Err(AfracError::Input("the adaptation diverged (non-finite integrator state)".into()));
        }
        self.out = AfracOutputs { spindle_speed: speed, feed, beta, eps1: eps[0], eps2: eps[1], h, delta_feed: df, g };
        // advance to t_{k+1}
        self.theta += 2.0 * PI * speed / 60.0 * tau;
        self.k += 1;
        self.measured.push(XySample { t: self.k as f64 * tau, theta: self.theta, r: [x, v] });
        self.measured.prune(self.theta - 2.0 * PI - 2.0 * PI * p.speed_max / 60.0 * 4.0 * tau);
        self.advance_reference();
        Ok(self.out)
    }

    /// Is a restored state usable?
    pub fn validate_state(&self) -> Result<(), String> {
        self.params.validate().map_err(|e| e.to_string())?;
        if !(self.theta.is_finite() && self.y.iter().all(|v| v.is_finite()) && self.h0.is_finite()) {
            return Err("controller state is not finite".into());
        }
        if !(self.memory.is_finite() && self.speed_bank.is_finite() && self.feed_bank.is_finite()) {
            return Err("controller memory is not finite".into());
        }
        self.measured.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_rest_the_commands_stay_at_the_initial_point_bitwise() {
        let mut c = Afrac::new(&AfracParams::default()).unwrap();
        for _ in 0..3000 {
            let o = c.sample(0.0, 0.0).unwrap();
            assert_eq!(o.spindle_speed.to_bits(), 450f64.to_bits());
            assert_eq!(o.feed.to_bits(), 0.1f64.to_bits());
        }
        assert!(matches!(c.sample(f64::NAN, 0.0), Err(AfracError::Input(_))));
        assert!(matches!(c.sample(0.0, f64::INFINITY), Err(AfracError::Input(_))));
        assert!(c.validate_state().is_ok());
    }

    #[test]
    fn bumpless_switching_keeps_the_integrated_output_continuous() {
        let jump = |bumpless: bool| {
            let mut bank = Bank::new(&[1.9, 1.75, 1.0], &Band::default(), 1e-4);
            let mut y = 0.0;
            for _ in 0..5000 {
                y = bank.sample(1.9, 1.0, bumpless);
            }
            let step = bank.sample(1.9, 1.0, bumpless) - y;
            let after = bank.sample(1.75, 1.0, bumpless);
            let after2 = bank.sample(1.75, 1.0, bumpless);
            (after - (y + 2.0 * step), after2 - after)
        };
        let (plain, smooth) = (jump(false), jump(true));
        // switched: the output jumps to the other filter's value; bumpless: it moves on by about
        // one sample's increment
        assert!(plain.0.abs() > 100.0 * plain.1.abs(), "{plain:?}");
        assert!(smooth.0.abs() < 2.0 * smooth.1.abs(), "{smooth:?}");
    }

    #[test]
    fn an_unstable_reference_speed_is_refused() {
        let p = AfracParams { reference_speed: 450.0, ..Default::default() };
        assert!(matches!(Afrac::new(&p), Err(AfracError::Design(_))));
    }
}
