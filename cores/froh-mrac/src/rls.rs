//! # Recursive least squares with exponential forgetting
//!
//! For the linear regression `y_k = φ_kᵀθ + e_k` the estimate minimising
//! `Σ_i λ^{k−i} (y_i − φ_iᵀθ)²` (plus the prior `λ^k (θ − θ₀)ᵀP₀⁻¹(θ − θ₀)`) is updated by
//!
//! ```text
//! ε = y_k − φ_kᵀθ̂_{k−1},   K = P φ_k / (λ + φ_kᵀ P φ_k),
//! θ̂_k = θ̂_{k−1} + K ε,     P ← (P − K φ_kᵀ P)/λ,
//! ```
//!
//! (Åström–Wittenmark, *Adaptive Control*, §2.2). `P` is symmetrised after each update and,
//! as a guard against wind-up when the regressor is not exciting, scaled down when its trace
//! exceeds `trace_max` (inactive in the paper's scenario; the count is kept).

use serde::{Deserialize, Serialize};

/// The estimator state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rls {
    /// Estimate θ̂.
    pub theta: Vec<f64>,
    /// Covariance P (row-major, n × n).
    pub p: Vec<f64>,
    /// Forgetting factor λ ∈ (0, 1].
    pub lambda: f64,
    /// Trace limit of P.
    pub trace_max: f64,
    /// How often the trace limit acted.
    pub trace_clips: u64,
}

impl Rls {
    /// An estimator at `theta0` with `P = p0 I`.
    pub fn new(theta0: Vec<f64>, p0: f64, lambda: f64, trace_max: f64) -> Self {
        let n = theta0.len();
        let mut p = vec![0.0; n * n];
        for i in 0..n {
            p[i * n + i] = p0;
        }
        Rls { theta: theta0, p, lambda, trace_max, trace_clips: 0 }
    }

    /// Prediction φᵀθ̂.
    pub fn predict(&self, phi: &[f64]) -> f64 {
        phi.iter().zip(&self.theta).map(|(a, b)| a * b).sum()
    }

    /// One update with regressor `phi` and measurement `y`; returns the prior error ε.
    pub fn update(&mut self, phi: &[f64], y: f64) -> f64 {
        let n = self.theta.len();
        let eps = y - self.predict(phi);
        let pphi: Vec<f64> = (0..n).map(|i| (0..n).map(|j| self.p[i * n + j] * phi[j]).sum()).collect();
        let denom = self.lambda + phi.iter().zip(&pphi).map(|(a, b)| a * b).sum::<f64>();
        let k: Vec<f64> = pphi.iter().map(|x| x / denom).collect();
        for (t, ki) in self.theta.iter_mut().zip(&k) {
            *t += ki * eps;
        }
        // P − K φᵀP = P − K (Pφ)ᵀ (P symmetric)
        for (row, ki) in self.p.chunks_mut(n).zip(&k) {
            for (x, pj) in row.iter_mut().zip(&pphi) {
                *x = (*x - ki * pj) / self.lambda;
            }
        }
        for i in 0..n {
            for j in 0..i {
                let m = 0.5 * (self.p[i * n + j] + self.p[j * n + i]);
                self.p[i * n + j] = m;
                self.p[j * n + i] = m;
            }
        }
        let tr: f64 = (0..n).map(|i| self.p[i * n + i]).sum();
        if tr > self.trace_max {
            let s = self.trace_max / tr;
            self.p.iter_mut().for_each(|x| *x *= s);
            self.trace_clips += 1;
        }
        eps
    }

    /// Finite, λ in (0, 1], square P with a positive diagonal.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.theta.len();
        if self.p.len() != n * n {
            return Err("RLS covariance of the wrong size".into());
        }
        if !(self.lambda > 0.0 && self.lambda <= 1.0 && self.trace_max > 0.0) {
            return Err("RLS forgetting factor or trace limit out of range".into());
        }
        if self.theta.iter().chain(&self.p).any(|x| !x.is_finite()) || (0..n).any(|i| self.p[i * n + i] < 0.0) {
            return Err("RLS estimate or covariance not finite or not positive".into());
        }
        Ok(())
    }
}
