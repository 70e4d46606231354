//! # Indirect adaptive model-following control with a FROH (seed 004, Section III)
//!
//! **Model.** Behind a FROH of gain β the first-order force model `K/(τs + 1)` sampled at `T`
//! is exactly (see [`crate::froh`])
//!
//! ```text
//! y_k = a y_{k−1} + b₀ u_{k−1} + b₁ u_{k−2},   A(z) = z(z − a),  B(z) = b₀ z + b₁,
//! a = e^{−T/τ},  b₀ = Γ₀ + βΓ₁,  b₁ = −βΓ₁,
//! ```
//!
//! (order 2 with the FROH's pole at the origin; `b₁ = 0` for β = 0). The CNC lag τ_s = 0.1 ms
//! is 1.2·10⁻³ of T and is left out of the controller's model (it is in the plant).
//! RLS ([`crate::rls`]) estimates `θ = (a, b₀, b₁)` from `φ_k = (y_{k−1}, u_{k−1}, u_{k−2})`,
//! started at the FROH model of the estimated continuous model `(K̂, τ̂)`. At β = 0 the model
//! is the ZOH's first-order `y_k = a y_{k−1} + b₀ u_{k−1}` (no pole at the origin, `b₁ ≡ 0`):
//! RLS estimates the two parameters `(a, b₀)` from `(y_{k−1}, u_{k−1})` (with
//! `estimate_b1_at_zoh`, the three of the other β, as before: a `b̂₁` that is structurally zero
//! but estimated puts spurious zeros into the design).
//!
//! **Reference model.** `G_m = ω_n²/(s² + 2ζω_n s + ω_n²)` behind the same FROH:
//! `H_m = B_m/A_m` with `deg A_m = 3` (one pole at the origin) and relative degree 1.
//!
//! **RST design (Åström–Wittenmark model following).** The plant zero `−b₁/b₀` is cancelled
//! (`B = b₀B⁺`, `B⁺ = z + b₁/b₀`, `R = B⁺R₁`), with the deadbeat observer `A_o = 1`
//! (`deg A_o ≥ 2 deg A − deg A_m − deg B⁺ − 1 = −1`):
//!
//! ```text
//! A R₁ + b₀ S = A_o A_m,   T = A_o B_m / b₀,   R u_k = T r_k − S y_k,
//! ```
//!
//! so `(AR + BS) = B⁺A_m` and `y = (BT/(AR + BS)) r = (B_m/A_m) r`. With `deg R = 2`,
//! `deg S = 1`:
//! `u_k = −r₁u_{k−1} − r₂u_{k−2} + t₀r_k + t₁r_{k−1} + t₂r_{k−2} − s₀y_{k−1} − s₁y_{k−2}`.
//! The cancellation needs a stable zero: when the estimate gives `|b₁/b₀| ≥ 1` (β below the
//! non-minimum-phase boundary) or `b₀ = 0`, the previous controller is kept (counted in
//! `design_skips`; the paper leaves these cases out).
//!
//! **Hold and clock.** After sample k the command is the FROH ramp
//! `u(t) = u_k + β(u_k − u_{k−1})(t − t_k)/T`, and the reference force `F_m(t)` is the
//! continuous reference model driven by the FROH ramp of `r`, integrated exactly. [`FrohMrac::step`]
//! advances a communication step `[t, t+h)`: it takes the samples at `t_base + kT` in the step
//! (with the inputs given at `t`), and returns the command as the mean over the step plus its
//! slope, which a plant that integrates the ramp `mean + slope·(s − t − h/2)` reproduces exactly
//! when the samples fall on communication points (`h = T/M`).

use crate::rls::Rls;
use milling_force_plant::ForceError;
use milling_force_plant::froh::{DiscreteTf, RampPropagator, StateSpace};
use milling_force_plant::poly;
use nalgebra::DVector;
use serde::{Deserialize, Serialize};

/// Controller parameters (force in N, feed in mm/s).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MracParams {
    /// FROH gain β ∈ [−1, 1].
    pub beta: f64,
    /// Sample period T [s] (one spindle period at 715 rpm).
    pub sample_period: f64,
    /// Reference-model damping ratio ζ (0.75).
    pub zeta: f64,
    /// Reference-model natural frequency ω_n [rad/s] (2.5/T_r, T_r = 4T).
    pub omega_n: f64,
    /// RLS forgetting factor λ (0.98).
    pub lambda: f64,
    /// Initial covariance P₀ = p0·I (100).
    pub p0: f64,
    /// Trace limit of P (guard against wind-up).
    pub trace_max: f64,
    /// Estimated process gain K̂ [N·s/mm] of the initial model (0.5 K_p at 2 mm).
    pub gain_estimate: f64,
    /// Estimated chip time constant τ̂ [s] of the initial model (1.5 τ_c).
    pub tau_estimate: f64,
    /// Adapt (RLS on) or keep the initial model.
    pub adapt: bool,
    /// At β = 0 estimate `b₁` too (three parameters, as for β ≠ 0) instead of the ZOH model's
    /// two `(a, b₀)`.
    pub estimate_b1_at_zoh: bool,
}

impl Default for MracParams {
    fn default() -> Self {
        let t = 60.0 / 715.0;
        let tau_c = t / 4.0;
        MracParams {
            beta: -0.2,
            sample_period: t,
            zeta: 0.75,
            omega_n: 2.5 / (4.0 * t),
            lambda: 0.98,
            p0: 100.0,
            trace_max: 1e8,
            gain_estimate: 0.5 * 1200.0 * 2.0 * tau_c,
            tau_estimate: 1.5 * tau_c,
            adapt: true,
            estimate_b1_at_zoh: false,
        }
    }
}

impl MracParams {
    /// Checks every field.
    pub fn validate(&self) -> Result<(), ForceError> {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        let bad = |m: &str| Err(ForceError::Params(m.into()));
        if !(self.beta.is_finite() && (-1.0..=1.0).contains(&self.beta)) {
            return bad("beta must be in [-1, 1]");
        }
        if !(pos(self.sample_period) && pos(self.zeta) && pos(self.omega_n) && pos(self.p0) && pos(self.trace_max)) {
            return bad("sample period, zeta, omega_n, p0 and trace_max must be positive");
        }
        if !(self.lambda > 0.0 && self.lambda <= 1.0) {
            return bad("lambda must be in (0, 1]");
        }
        if !(pos(self.gain_estimate) && pos(self.tau_estimate)) {
            return bad("the initial gain and time constant estimates must be positive");
        }
        Ok(())
    }

    /// The reference model behind the FROH.
    pub fn reference_model(&self) -> Result<DiscreteTf, ForceError> {
        DiscreteTf::froh(&StateSpace::second_order(self.zeta, self.omega_n), self.sample_period, self.beta)
    }

    /// How many parameters RLS estimates: `(a, b₀)` for the ZOH (β = 0, unless
    /// `estimate_b1_at_zoh`), `(a, b₀, b₁)` otherwise.
    pub fn estimated_parameters(&self) -> usize {
        if self.beta == 0.0 && !self.estimate_b1_at_zoh { 2 } else { 3 }
    }

    /// `θ = (a, b₀, b₁)` of `K/(τs + 1)` behind the FROH.
    pub fn theta_of(&self, gain: f64, tau: f64) -> Result<[f64; 3], ForceError> {
        let tf = DiscreteTf::froh(&StateSpace::first_order(gain, tau), self.sample_period, self.beta)?;
        Ok([-tf.den[1], tf.num[1], tf.num[2]])
    }
}

/// The RST controller `R u = T r − S y` (R monic of degree 2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Rst {
    /// `R = z² + r[0] z + r[1]`.
    pub r: [f64; 2],
    /// `S = s[0] z + s[1]`.
    pub s: [f64; 2],
    /// `T = t[0] z² + t[1] z + t[2]`.
    pub t: [f64; 3],
}

/// The model-following design for `θ = (a, b₀, b₁)` and the reference `H_m = B_m/A_m`
/// (`deg A_m = 3`). Fails for `b₀ = 0` or a zero `−b₁/b₀` on or outside the unit circle.
pub fn design(theta: &[f64; 3], reference: &DiscreteTf) -> Result<Rst, ForceError> {
    let [a, b0, b1] = *theta;
    if !(theta.iter().all(|x| x.is_finite()) && b0.abs() > 1e-300) {
        return Err(ForceError::Design(format!("b0 = {b0} (theta {theta:?})")));
    }
    let zero = -b1 / b0;
    if zero.is_nan() || zero.abs() >= 1.0 {
        return Err(ForceError::Design(format!("plant zero {zero} is not stable: it cannot be cancelled")));
    }
    if reference.den.len() != 4 {
        return Err(ForceError::Design("the reference model must be of order 3".into()));
    }
    let (r1, s) = poly::diophantine(&[1.0, -a, 0.0], b0, &reference.den)?;
    let r = poly::mul(&[1.0, b1 / b0], &r1);
    let t = [reference.num[1] / b0, reference.num[2] / b0, reference.num[3] / b0];
    Ok(Rst { r: [r[1], r[2]], s: [s[0], s[1]], t })
}

/// What the controller reports after a communication step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MracOutputs {
    /// Mean of the held feed command over the last step [mm/s].
    pub feed_command: f64,
    /// Slope of the held feed command at the end of the step [mm/s²].
    pub feed_command_rate: f64,
    /// The held command at the end of the step [mm/s].
    pub feed_hold: f64,
    /// The last sample u_k [mm/s].
    pub feed_sample: f64,
    /// Reference-model force F_m at the end of the step [N].
    pub reference_force: f64,
    /// Estimate â.
    pub a_hat: f64,
    /// Estimate b̂₀ [N·s/mm].
    pub b0_hat: f64,
    /// Estimate b̂₁ [N·s/mm].
    pub b1_hat: f64,
    /// Estimated plant zero −b̂₁/b̂₀.
    pub zero_hat: f64,
    /// Samples at which the design was refused and the previous controller kept.
    pub design_skips: f64,
}

/// The adaptive FROH controller with its sample clock.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FrohMrac {
    params: MracParams,
    reference: DiscreteTf,
    rls: Rls,
    rst: Rst,
    /// (y_{k−1}, y_{k−2}), (u_{k−1}, u_{k−2}), (r_{k−1}, r_{k−2}) before the next sample.
    y_past: [f64; 2],
    u_past: [f64; 2],
    r_past: [f64; 2],
    /// The hold segment: sample time, u_k, slope, r_k, slope of r.
    t_k: f64,
    u_k: f64,
    slope: f64,
    r_k: f64,
    r_slope: f64,
    /// Continuous reference-model state.
    xm: [f64; 2],
    t_base: Option<f64>,
    k_next: u64,
    design_skips: u64,
    last: MracOutputs,
    #[serde(skip)]
    cache: Option<(u64, RampPropagator)>,
}

impl FrohMrac {
    /// A controller at rest (all past signals zero) with the initial model and design.
    pub fn new(params: &MracParams) -> Result<Self, ForceError> {
        params.validate()?;
        let reference = params.reference_model()?;
        let theta0 = params.theta_of(params.gain_estimate, params.tau_estimate)?;
        let rst = design(&theta0, &reference)?;
        let n = params.estimated_parameters();
        let rls = Rls::new(theta0[..n].to_vec(), params.p0, params.lambda, params.trace_max);
        let mut c = FrohMrac {
            params: params.clone(),
            reference,
            rls,
            rst,
            y_past: [0.0; 2],
            u_past: [0.0; 2],
            r_past: [0.0; 2],
            t_k: 0.0,
            u_k: 0.0,
            slope: 0.0,
            r_k: 0.0,
            r_slope: 0.0,
            xm: [0.0; 2],
            t_base: None,
            k_next: 0,
            design_skips: 0,
            last: MracOutputs::default(),
            cache: None,
        };
        c.last = c.outputs_now(0.0, 0.0);
        Ok(c)
    }

    /// The parameters.
    pub fn params(&self) -> &MracParams {
        &self.params
    }

    /// The discrete reference model `B_m/A_m`.
    pub fn reference(&self) -> &DiscreteTf {
        &self.reference
    }

    /// The present estimate θ̂ = (a, b₀, b₁) (`b₁ = 0` when only `(a, b₀)` are estimated).
    pub fn theta(&self) -> [f64; 3] {
        let t = &self.rls.theta;
        [t[0], t[1], t.get(2).copied().unwrap_or(0.0)]
    }

    /// The RLS estimator.
    pub fn rls(&self) -> &Rls {
        &self.rls
    }

    /// The present controller.
    pub fn rst(&self) -> &Rst {
        &self.rst
    }

    /// Outputs after the last step.
    pub fn outputs(&self) -> MracOutputs {
        self.last
    }

    /// One sample at `t_s` with the measured force `y` and reference `r` [N]: RLS, design,
    /// control law, new hold segment. Returns u_k.
    pub fn sample(&mut self, t_s: f64, y: f64, r: f64) -> f64 {
        let [y1, y2] = self.y_past;
        let [u1, u2] = self.u_past;
        let [r1, r2] = self.r_past;
        if self.params.adapt && self.k_next > 0 {
            let phi = [y1, u1, u2];
            self.rls.update(&phi[..self.rls.theta.len()], y);
        }
        match design(&self.theta(), &self.reference) {
            Ok(rst) => self.rst = rst,
            Err(_) => self.design_skips += 1,
        }
        let c = &self.rst;
        let u = -c.r[0] * u1 - c.r[1] * u2 + c.t[0] * r + c.t[1] * r1 + c.t[2] * r2 - c.s[0] * y1 - c.s[1] * y2;
        let (beta, t) = (self.params.beta, self.params.sample_period);
        self.t_k = t_s;
        self.slope = beta * (u - u1) / t;
        self.u_k = u;
        self.r_slope = beta * (r - r1) / t;
        self.r_k = r;
        self.y_past = [y, y1];
        self.u_past = [u, u1];
        self.r_past = [r, r1];
        u
    }

    fn hold_at(&self, s: f64) -> f64 {
        self.u_k + self.slope * (s - self.t_k)
    }

    fn propagate_reference(&mut self, s0: f64, s1: f64) -> Result<(), ForceError> {
        let len = s1 - s0;
        if self.cache.as_ref().is_none_or(|c| c.0 != len.to_bits()) {
            let sys = StateSpace::second_order(self.params.zeta, self.params.omega_n);
            self.cache = Some((len.to_bits(), RampPropagator::new(&sys, len)?));
        }
        let p = &self.cache.as_ref().expect("just set").1;
        let r0 = self.r_k + self.r_slope * (s0 - self.t_k);
        let x = p.propagate(&DVector::from_column_slice(&self.xm), r0, self.r_slope);
        self.xm = [x[0], x[1]];
        Ok(())
    }

    fn outputs_now(&self, mean: f64, end: f64) -> MracOutputs {
        let th = self.theta();
        MracOutputs {
            feed_command: mean,
            feed_command_rate: self.slope,
            feed_hold: self.hold_at(end),
            feed_sample: self.u_k,
            reference_force: self.xm[0],
            a_hat: th[0],
            b0_hat: th[1],
            b1_hat: th[2],
            zero_hat: -th[2] / th[1],
            design_skips: self.design_skips as f64,
        }
    }

    /// One communication step `[t, t+h)` with the inputs `y` (measured force) and `r`
    /// (reference force) held over it.
    pub fn step(&mut self, t: f64, h: f64, y: f64, r: f64) -> Result<MracOutputs, ForceError> {
        if !(y.is_finite() && r.is_finite()) {
            return Err(ForceError::Input(format!("force {y} N, reference {r} N")));
        }
        if !(t.is_finite() && h.is_finite() && h > 0.0) {
            return Err(ForceError::Input(format!("step [{t}, {t} + {h})")));
        }
        let ts = self.params.sample_period;
        let base = *self.t_base.get_or_insert(t);
        // A clock that jumped ahead (restored state, restarted master) continues from the
        // first sample at or after t instead of catching up one by one.
        let first_due = ((t - base) / ts - 1e-6).ceil().max(0.0);
        if first_due > (self.k_next + 1) as f64 {
            self.k_next = first_due as u64;
        }
        let end = t + h;
        let margin = 1e-6 * ts;
        let mut s = t;
        let mut integral = 0.0;
        while s < end {
            let t_next = base + self.k_next as f64 * ts;
            if t_next <= s + margin && t_next < end - margin {
                self.sample(t_next, y, r);
                self.k_next += 1;
                continue;
            }
            let s1 = if t_next < end - margin { t_next } else { end };
            integral += (s1 - s) * self.hold_at(0.5 * (s + s1));
            self.propagate_reference(s, s1)?;
            s = s1;
        }
        let out = self.outputs_now(integral / h, end);
        if ![out.feed_command, out.feed_hold, out.reference_force, out.feed_command_rate].iter().all(|x| x.is_finite())
        {
            return Err(ForceError::Input("the command left the finite range".into()));
        }
        self.last = out;
        Ok(out)
    }

    /// Parameters, estimator and signals valid (for restored FMU states).
    pub fn validate_state(&self) -> Result<(), String> {
        self.params.validate().map_err(|e| e.to_string())?;
        self.rls.validate()?;
        if self.rls.theta.len() != self.params.estimated_parameters()
            || self.reference.den.len() != 4
            || self.reference.num.len() != 4
        {
            return Err("controller model of the wrong order".into());
        }
        let sig = [self.y_past, self.u_past, self.r_past, self.xm].concat();
        let more = [self.t_k, self.u_k, self.slope, self.r_k, self.r_slope];
        let rst = [self.rst.r.as_slice(), &self.rst.s, &self.rst.t].concat();
        if sig
            .iter()
            .chain(&more)
            .chain(&rst)
            .chain(&self.reference.num)
            .chain(&self.reference.den)
            .any(|x| !x.is_finite())
        {
            return Err("controller signals not finite".into());
        }
        let reference = self.params.reference_model().map_err(|e| e.to_string())?;
        if reference != self.reference {
            return Err("the reference model does not match the parameters".into());
        }
        let o = &self.last;
        if ![o.feed_command, o.feed_command_rate, o.feed_hold, o.feed_sample, o.reference_force]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err("the last outputs are not finite".into());
        }
        if self.t_base.is_some_and(|t| !t.is_finite()) || self.k_next > u64::MAX / 2 {
            return Err("the sample clock is invalid".into());
        }
        Ok(())
    }
}
