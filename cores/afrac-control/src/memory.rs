//! The convolution memory `(Q∗ε)(t) = ∫₀^T Q(σ) ε(t − σ) dσ` on the controller's sample grid.
//!
//! # Maths
//!
//! `Q(σ) = e^{Sσ}Q₀` and `Q₀` has only a first column `q`, so `Q(σ)ε = g(σ) ε₁` with
//! `g(σ) = e^{Sσ}q`: only `ε₁` is stored. With the sample period `τ`, `T = Mτ + r`
//! (`0 ≤ r < τ`), the trapezoidal rule on the grid and one partial interval:
//!
//! ```text
//! (Q∗ε)(t_k) ≈ τ [½g₀ε₁(t_k) + Σ_{j=1}^{M−1} g_j ε₁(t_{k−j}) + ½g_M ε₁(t_{k−M})]
//!            + ½ r [g_M ε₁(t_{k−M}) + g(T) ε₁(t_k − T)],
//! ```
//!
//! `g_j = g(jτ)`, `ε₁(t_k − T)` linear between `t_{k−M}` and `t_{k−M−1}`. Error `O(τ²)`.
//! Before the first sample `ε₁` is the fill value (0 for a controller started at rest).

use crate::delay_model::DelayModel;
use nalgebra::Vector2;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// The convolution memory.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Memory {
    period: f64,
    m: usize,
    r: f64,
    g: Vec<[f64; 2]>,
    g_t: [f64; 2],
    eps: VecDeque<f64>,
}

impl Memory {
    /// The memory of `model` at sample period `period`, with `ε₁ = fill` before the start.
    pub fn new(model: &DelayModel, period: f64, fill: f64) -> Self {
        let m = (model.delay / period).floor() as usize;
        let r = model.delay - m as f64 * period;
        let e = (model.s() * period).exp();
        let mut g = Vec::with_capacity(m + 1);
        let mut v = Vector2::new(model.q0[0], model.q0[1]);
        for j in 0..=m {
            // re-anchor every 64 samples on the exact exponential (no drift of the powers)
            if j % 64 == 0 {
                v = model.q_column(j as f64 * period);
            }
            g.push([v[0], v[1]]);
            v = e * v;
        }
        let gt = model.q_column(model.delay);
        Memory { period, m, r, g, g_t: [gt[0], gt[1]], eps: VecDeque::from(vec![fill; m + 2]) }
    }

    /// Push `ε₁(t_k)` and return `(Q∗ε)(t_k)`.
    pub fn push(&mut self, eps1: f64) -> [f64; 2] {
        self.eps.pop_back();
        self.eps.push_front(eps1);
        self.current()
    }

    /// `(Q∗ε)` at the newest sample.
    pub fn current(&self) -> [f64; 2] {
        let (tau, m) = (self.period, self.m);
        let mut acc = [0.0; 2];
        for j in 0..=m {
            let w = if j == 0 || j == m { 0.5 } else { 1.0 };
            let e = self.eps[j] * w;
            acc[0] += self.g[j][0] * e;
            acc[1] += self.g[j][1] * e;
        }
        let (e_m, e_m1) = (self.eps[m], self.eps[m + 1]);
        let e_t = e_m + (e_m1 - e_m) * (self.r / tau);
        let out = [tau * acc[0], tau * acc[1]];
        [
            out[0] + 0.5 * self.r * (self.g[m][0] * e_m + self.g_t[0] * e_t),
            out[1] + 0.5 * self.r * (self.g[m][1] * e_m + self.g_t[1] * e_t),
        ]
    }

    /// Are the stored values finite?
    pub fn is_finite(&self) -> bool {
        self.eps.iter().all(|v| v.is_finite()) && self.g.iter().flatten().all(|v| v.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// z = ε + Q∗ε of a solution of the reference delay equation obeys ż = Sz exactly.
    #[test]
    fn z_of_a_reference_solution_follows_the_delay_free_system() {
        let wn = 2.0 * std::f64::consts::PI * 85.0;
        let model = DelayModel::new(wn, 2.0 * 0.0384 * wn, 0.01994 * 5.0 * wn * wn, 60.0 / 524.0).unwrap();
        let tau = 1e-5;
        let (a, b) = (model.a(), model.b());
        // constant initial function ε(s) = e for s ≤ 0 (continuous), RK4 with the delayed
        // value from the grid (the delay is a whole number of fine sub-steps away: linear
        // interpolation of the stored fine grid)
        let e0 = Vector2::new(1e-3, 0.0);
        let fine = 4;
        let h = tau / fine as f64;
        let mut hist: Vec<Vector2<f64>> = vec![e0];
        let delayed = |hist: &Vec<Vector2<f64>>, t: f64| -> Vector2<f64> {
            let s = (t - model.delay) / h;
            if s <= 0.0 {
                return e0;
            }
            let i = s.floor() as usize;
            let f = s - i as f64;
            hist[i] * (1.0 - f) + hist[(i + 1).min(hist.len() - 1)] * f
        };
        let mut mem = Memory::new(&model, tau, e0[0]);
        let mut zs = Vec::new();
        let n = (0.1 / tau) as usize;
        let mut y = e0;
        for k in 0..=n {
            let q = mem.push(y[0]);
            zs.push(Vector2::new(y[0] + q[0], y[1] + q[1]));
            for i in 0..fine {
                let t = (k * fine + i) as f64 * h;
                let f = |t: f64, y: Vector2<f64>| a * y + b * delayed(&hist, t);
                let k1 = f(t, y);
                let k2 = f(t + 0.5 * h, y + k1 * (0.5 * h));
                let k3 = f(t + 0.5 * h, y + k2 * (0.5 * h));
                let k4 = f(t + h, y + k3 * h);
                y += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
                hist.push(y);
            }
        }
        let (k1, k2) = (2000usize, 9000usize);
        let predicted: Vector2<f64> = (model.s() * ((k2 - k1) as f64 * tau)).exp() * zs[k1];
        let err = (predicted - zs[k2]).norm() / zs[k2].norm();
        println!("z(t2) vs e^(S(t2-t1)) z(t1): relative error {err:e}");
        assert!(err < 1e-4, "{err:e}");
    }
}
