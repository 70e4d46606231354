//! A MIMO linear controller of order `n_c ≤ 8` (2 inputs, 2 outputs) acting on the delayed
//! difference of its input, seed 002's Eq. 10 (IJRNC 2015):
//!
//! ```text
//! w(t) = v(t) − β v(t − τ),     ξ̇ = A_c ξ + B_c w,     F = sat(C_c ξ + D_c w),
//! ```
//!
//! with `β = 1` the Pyragas form: a τ-periodic part of `v` (the chatter-free motion) cancels,
//! so the controller acts on the perturbation only. The delay is `τ = 60/(z n)` from the
//! spindle-speed input `n` \[rpm\] and the number of teeth `z`, or a parameter.
//!
//! # Time stepping ([`LinearController::step`])
//!
//! A step `[t_k, t_k + h)` receives `v(t_k)` (held over the step, as a co-simulation master
//! delivers it). The input is appended to the delay buffer, `v(t_k − τ)` is interpolated
//! linearly between the stored samples (before the first sample: the first sample, so that `w`
//! starts at zero), and
//!
//! * **continuous** form: `F_k = sat(C_c ξ_k + D_c w_k)` and, with `w_k` held,
//!   `ξ_{k+1} = Φ(h) ξ_k + Γ(h) w_k` exactly, `exp([[A_c, B_c], [0, 0]] h) = [[Φ, Γ], [0, I]]`
//!   (computed once per step size and cached);
//! * **discrete** form (sample period `T_s`, samples at `t_0 + j T_s`): at every sample instant
//!   `t_j ∈ [t_k, t_k + h)`, `w_j = v(t_k) − β v(t_j − τ)`, `F_j = sat(C_c ξ_j + D_c w_j)`,
//!   `ξ_{j+1} = A_c ξ_j + B_c w_j`; the output holds the last sample's `F`.
//!
//! The output after the step is the force computed from the inputs at `t_k`: a master that
//! couples it back to the plant adds its usual one-step delay (negligible for `h ≪ τ`).
//! `sat` clips each output to `±F_max,i`.
//!
//! # Frequency response ([`LinearController::frequency_response`])
//!
//! From the same matrices: `F(iω) = K(iω) (1 − β e^{−iωτ}) V(iω)` with
//! `K = C_c (sI − A_c)⁻¹ B_c + D_c` (continuous) or `C_c (zI − A_c)⁻¹ B_c + D_c`,
//! `z = e^{iω T_s}` (discrete), unsaturated. A sine driven through [`LinearController::step`]
//! reproduces it (tested).

use nalgebra::DMatrix;
use num_complex::Complex64;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

mod params;
pub use params::{LinearControlParams, MAX_ORDER};

/// Why the controller refused to start or to step.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ControlError {
    /// A parameter is out of range.
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// An input or the step is out of range (the step was not taken).
    #[error("invalid input: {0}")]
    Input(String),
    /// The controller state became non-finite.
    #[error("the controller state diverged at t = {t} s")]
    Diverged {
        /// Time \[s\].
        t: f64,
    },
}

/// The inputs held over a step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ControlInputs {
    /// The measurement v (x, y) \[m\].
    pub v: [f64; 2],
    /// Spindle speed n \[rpm\] (sets τ = 60/(z n) when `delay_from_speed`).
    pub spindle_speed: f64,
}

impl Default for ControlInputs {
    /// At rest, 37000 rpm (the middle of seed 002's §6.1 range), so that a controller whose
    /// delay follows the speed can step before the speed is connected.
    fn default() -> Self {
        ControlInputs { v: [0.0; 2], spindle_speed: 37_000.0 }
    }
}

/// The outputs after a step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ControlOutputs {
    /// The force F (x, y) \[N\], saturated.
    pub force: [f64; 2],
    /// The difference w = v − β v(t − τ) it was computed from (x, y) \[m\].
    pub w: [f64; 2],
    /// The delay τ used \[s\].
    pub delay: f64,
}

/// `Φ(h)`, `Γ(h)` of the continuous form for one step size.
#[derive(Clone, Debug)]
struct Discrete {
    h: f64,
    phi: DMatrix<f64>,
    gamma: DMatrix<f64>,
}

/// The controller: parameters, state ξ, the input history, the last outputs.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LinearController {
    p: LinearControlParams,
    xi: [f64; MAX_ORDER],
    /// `(t_i, v(t_i))`, times ascending, back to `t − max_delay`.
    history: VecDeque<(f64, [f64; 2])>,
    /// Index of the next sample instant of the discrete form (`t_0 + j T_s`).
    next_sample: u64,
    /// Start time t_0.
    t0: Option<f64>,
    out: ControlOutputs,
    #[serde(skip)]
    cache: Option<Discrete>,
}

impl LinearController {
    /// A controller at rest (ξ = 0, empty history).
    pub fn new(p: &LinearControlParams) -> Result<LinearController, ControlError> {
        p.validate().map_err(ControlError::Parameter)?;
        let delay = if p.delay_from_speed { 0.0 } else { p.delay };
        Ok(LinearController {
            p: p.clone(),
            xi: [0.0; MAX_ORDER],
            history: VecDeque::new(),
            next_sample: 0,
            t0: None,
            out: ControlOutputs { delay, ..ControlOutputs::default() },
            cache: None,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &LinearControlParams {
        &self.p
    }

    /// Change the feedthrough gains `D_c` while running (the state ξ and the history kept): what
    /// the FMU does with its tunable `Dc[i,j]` set between steps. `p` must equal the current
    /// parameters but for `dc`.
    pub fn retune(&mut self, p: &LinearControlParams) -> Result<(), ControlError> {
        let mut only_dc = self.p.clone();
        only_dc.dc = p.dc;
        if only_dc != *p {
            return Err(ControlError::Parameter("only D_c can change while the controller runs".into()));
        }
        p.validate().map_err(ControlError::Parameter)?;
        self.p.dc = p.dc;
        Ok(())
    }

    /// The outputs of the last step.
    pub fn outputs(&self) -> ControlOutputs {
        self.out
    }

    /// The controller state ξ (first `n_c` entries).
    pub fn state(&self) -> &[f64] {
        &self.xi[..self.p.order()]
    }

    /// The delay at spindle speed `rpm` (or the parameter).
    pub fn delay(&self, rpm: f64) -> Result<f64, ControlError> {
        let p = &self.p;
        if !p.delay_from_speed {
            return Ok(p.delay);
        }
        let tau = 60.0 / (p.teeth as f64 * rpm);
        if !(rpm.is_finite() && rpm > 0.0 && tau <= p.max_delay) {
            return Err(ControlError::Input(format!(
                "spindle_speed {rpm} rpm gives the delay 60/(z n) = {tau} s, outside (0, max_delay = {} s]",
                p.max_delay
            )));
        }
        Ok(tau)
    }

    /// `v(s)` from the history (module docs).
    fn delayed(&self, s: f64) -> [f64; 2] {
        let Some(&(t_first, v_first)) = self.history.front() else { return [0.0; 2] };
        if s <= t_first {
            return v_first;
        }
        // first sample after s
        let i = self.history.partition_point(|&(t, _)| t <= s);
        if i >= self.history.len() {
            return self.history.back().map_or([0.0; 2], |&(_, v)| v);
        }
        let (ta, va) = self.history[i - 1];
        let (tb, vb) = self.history[i];
        let f = (s - ta) / (tb - ta);
        [va[0] + f * (vb[0] - va[0]), va[1] + f * (vb[1] - va[1])]
    }

    /// `C_c ξ + D_c w`, clipped.
    fn output(&self, w: [f64; 2]) -> [f64; 2] {
        let p = &self.p;
        let n = p.order();
        let mut f = [0.0; 2];
        for (i, fi) in f.iter_mut().enumerate() {
            let mut s = p.dc[i][0] * w[0] + p.dc[i][1] * w[1];
            for j in 0..n {
                s += p.cc[i][j] * self.xi[j];
            }
            *fi = s.clamp(-p.saturation[i], p.saturation[i]);
        }
        f
    }

    /// `Φ(h)`, `Γ(h)` of the continuous form (module docs); refused when `‖[A_c, B_c] h‖₁`
    /// exceeds 1e12 (or is not finite), where scaling and squaring would not end.
    pub fn discretise(&self, h: f64) -> Result<(DMatrix<f64>, DMatrix<f64>), ControlError> {
        let n = self.p.order();
        let mut m = DMatrix::<f64>::zeros(n + 2, n + 2);
        for i in 0..n {
            for j in 0..n {
                m[(i, j)] = self.p.ac[i][j] * h;
            }
            m[(i, n)] = self.p.bc[i][0] * h;
            m[(i, n + 1)] = self.p.bc[i][1] * h;
        }
        let norm = m.column_iter().map(|c| c.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max);
        if !(norm.is_finite() && norm <= 1e12) {
            return Err(ControlError::Input(format!(
                "the step {h} s is too large for the exponential of the controller (‖A_c h‖ = {norm:e})"
            )));
        }
        let e = m.exp();
        Ok((e.view((0, 0), (n, n)).into_owned(), e.view((0, n), (n, 2)).into_owned()))
    }

    /// How many samples (internal steps) a step of `h` costs: `h/T_s + 1` (an upper bound for
    /// both forms; the continuous form does one).
    pub fn internal_steps(&self, h: f64) -> f64 {
        h / self.p.sample_period + 1.0
    }

    /// Advance from `t` by `h` with the inputs `u` held (module docs).
    pub fn step(&mut self, t: f64, h: f64, u: &ControlInputs) -> Result<(), ControlError> {
        if !(t.is_finite() && h.is_finite() && h > 0.0) {
            return Err(ControlError::Input(format!("need a finite time and a step > 0 (got {t}, {h})")));
        }
        if !u.v.iter().all(|v| v.is_finite()) || !u.spindle_speed.is_finite() {
            return Err(ControlError::Input(format!("inputs must be finite (got {u:?})")));
        }
        if self.history.back().is_some_and(|&(tl, _)| t <= tl) {
            return Err(ControlError::Input(format!("time {t} does not advance past the last sample")));
        }
        let tau = self.delay(u.spindle_speed)?;
        let beta = self.p.beta;
        self.history.push_back((t, u.v));
        let keep = t - self.p.max_delay - h;
        while self.history.len() > 2 && self.history[1].0 <= keep {
            self.history.pop_front();
        }
        let t0 = *self.t0.get_or_insert(t);
        let n = self.p.order();
        let mut xi = self.xi;
        let (force, w) = if self.p.discrete {
            let ts = self.p.sample_period;
            let (mut force, mut w_last) = (self.out.force, self.out.w);
            // a clock behind the step (a restored state) jumps to the first sample due
            let first_due = ((t - t0) / ts - 1e-6).ceil().max(0.0);
            if first_due >= 9e15 {
                return Err(ControlError::Input(format!("the sample clock (start {t0} s) is invalid at t = {t} s")));
            }
            if first_due as u64 > self.next_sample + 1 {
                self.next_sample = first_due as u64;
            }
            loop {
                let tj = t0 + self.next_sample as f64 * ts;
                if tj >= t + h * (1.0 - 1e-9) {
                    break;
                }
                self.next_sample += 1;
                if tj < t - 1e-9 * h {
                    continue; // a sample instant before this step (restored or irregular steps)
                }
                let d = self.delayed(tj - tau);
                let w = [u.v[0] - beta * d[0], u.v[1] - beta * d[1]];
                self.xi = xi;
                force = self.output(w);
                w_last = w;
                let mut nx = [0.0; MAX_ORDER];
                for (i, x) in nx.iter_mut().enumerate().take(n) {
                    *x = self.p.bc[i][0] * w[0] + self.p.bc[i][1] * w[1];
                    for (j, xj) in xi.iter().enumerate().take(n) {
                        *x += self.p.ac[i][j] * xj;
                    }
                }
                xi = nx;
            }
            (force, w_last)
        } else {
            let d = self.delayed(t - tau);
            let w = [u.v[0] - beta * d[0], u.v[1] - beta * d[1]];
            let force = self.output(w);
            if n > 0 {
                if self.cache.as_ref().is_none_or(|c| c.h.to_bits() != h.to_bits()) {
                    let (phi, gamma) = self.discretise(h)?;
                    self.cache = Some(Discrete { h, phi, gamma });
                }
                let Some(c) = &self.cache else { unreachable!("filled above") };
                let mut nx = [0.0; MAX_ORDER];
                for (i, x) in nx.iter_mut().enumerate().take(n) {
                    *x = c.gamma[(i, 0)] * w[0] + c.gamma[(i, 1)] * w[1];
                    for (j, xj) in xi.iter().enumerate().take(n) {
                        *x += c.phi[(i, j)] * xj;
                    }
                }
                xi = nx;
            }
            (force, w)
        };
        if !xi.iter().chain(&force).all(|x| x.is_finite()) {
            return Err(ControlError::Diverged { t: t + h });
        }
        self.xi = xi;
        self.out = ControlOutputs { force, w, delay: tau };
        Ok(())
    }

    /// `K(iω)` (2 × 2) of the module docs, without the delay factor.
    pub fn gain(&self, omega: f64) -> [[Complex64; 2]; 2] {
        let p = &self.p;
        let n = p.order();
        let s =
            if p.discrete { Complex64::from_polar(1.0, omega * p.sample_period) } else { Complex64::new(0.0, omega) };
        let mut k = [[Complex64::new(0.0, 0.0); 2]; 2];
        for (i, row) in k.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = Complex64::from(p.dc[i][j]);
            }
        }
        if n == 0 {
            return k;
        }
        let m = DMatrix::from_fn(n, n, |i, j| {
            let d = if i == j { s } else { Complex64::new(0.0, 0.0) };
            d - p.ac[i][j]
        });
        let b = DMatrix::from_fn(n, 2, |i, j| Complex64::from(p.bc[i][j]));
        if let Some(x) = m.lu().solve(&b) {
            for (i, row) in k.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v += (0..n).map(|l| p.cc[i][l] * x[(l, j)]).sum::<Complex64>();
                }
            }
        }
        k
    }

    /// The response `F/V` at `omega` \[rad/s\] with delay `tau`: `K(iω)(1 − β e^{−iωτ})`.
    pub fn frequency_response(&self, omega: f64, tau: f64) -> [[Complex64; 2]; 2] {
        let f = Complex64::new(1.0, 0.0) - self.p.beta * Complex64::from_polar(1.0, -omega * tau);
        self.gain(omega).map(|row| row.map(|v| v * f))
    }

    /// The invariants of a restored state (parameters, finite state, ordered history no longer
    /// than needed).
    pub fn validate_state(&self) -> Result<(), String> {
        self.p.validate()?;
        if !self.xi.iter().all(|x| x.is_finite()) {
            return Err("the controller state is not finite".into());
        }
        let o = &self.out;
        if !(o.force.iter().chain(&o.w).all(|x| x.is_finite()) && o.delay.is_finite() && o.delay >= 0.0) {
            return Err("the outputs are not finite".into());
        }
        if !self.history.iter().all(|(t, v)| t.is_finite() && v.iter().all(|x| x.is_finite())) {
            return Err("the input history is not finite".into());
        }
        if self.history.iter().zip(self.history.iter().skip(1)).any(|(a, b)| b.0 <= a.0) {
            return Err("the input history is not in time order".into());
        }
        if self.t0.is_some_and(|t| !t.is_finite()) || self.next_sample > 1 << 53 {
            return Err("the start time or the sample counter is invalid".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
