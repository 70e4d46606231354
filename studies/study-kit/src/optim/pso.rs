//! Particle swarm optimisation (seed 000, Section 4.4), minimising a cost over a box.
//!
//! ```text
//! v_i ← w_k v_i + c1 r1 ⊙ (p_i − x_i) + c2 r2 ⊙ (g − x_i),   |v_i,d| ≤ v_max,d = 0.3 (hi_d − lo_d)
//! x_i ← clamp(x_i + v_i, lo, hi)
//! w_k = w_start − (w_start − w_end)·k/(K − 1),   k = 0..K−1
//! ```
//!
//! `r1`, `r2` are fresh U(0,1) per particle and dimension. Defaults: 40 particles, K = 60
//! iterations, inertia 0.9 → 0.4, c1 = c2 = 2, clamp 30 % of each range. The initial swarm is
//! uniform in the box with velocities uniform in ±v_max and is evaluated before the first
//! iteration, so one run makes `particles × (K + 1)` evaluations. A particle that hits a bound
//! stays on it (position clamped, velocity kept).
//!
//! Reproducible: all random numbers come from one `ChaCha8Rng` seeded by [`PsoConfig::seed`]
//! and are drawn sequentially, before the parallel (rayon) evaluation of the particles, so the
//! result does not depend on the number of threads.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// PSO settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PsoConfig {
    /// Swarm size.
    pub particles: usize,
    /// Iterations after the initial evaluation.
    pub iterations: usize,
    /// Inertia at the first iteration.
    pub w_start: f64,
    /// Inertia at the last iteration.
    pub w_end: f64,
    /// Cognitive coefficient.
    pub c1: f64,
    /// Social coefficient.
    pub c2: f64,
    /// Velocity clamp as a fraction of each range.
    pub v_clamp: f64,
    /// Random seed.
    pub seed: u64,
}

impl Default for PsoConfig {
    fn default() -> Self {
        PsoConfig { particles: 40, iterations: 60, w_start: 0.9, w_end: 0.4, c1: 2.0, c2: 2.0, v_clamp: 0.3, seed: 1 }
    }
}

/// Result of one run.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PsoResult {
    /// Best position.
    pub best_x: Vec<f64>,
    /// Its cost.
    pub best_cost: f64,
    /// Global best cost after the initial evaluation and after every iteration.
    pub history: Vec<f64>,
    /// Number of cost evaluations.
    pub evaluations: usize,
}

/// Minimise `cost` over the box `[lo, hi]`. `on_iteration` is called after every iteration
/// (for a progress bar).
pub fn minimize<F, P>(cost: F, lo: &[f64], hi: &[f64], cfg: &PsoConfig, on_iteration: P) -> PsoResult
where
    F: Fn(&[f64]) -> f64 + Sync,
    P: Fn(usize, f64),
{
    assert_eq!(lo.len(), hi.len(), "bounds of different lengths");
    let d = lo.len();
    let n = cfg.particles.max(1);
    let vmax: Vec<f64> = (0..d).map(|j| cfg.v_clamp * (hi[j] - lo[j])).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    let mut x: Vec<Vec<f64>> =
        (0..n).map(|_| (0..d).map(|j| lo[j] + rng.random::<f64>() * (hi[j] - lo[j])).collect()).collect();
    let mut v: Vec<Vec<f64>> =
        (0..n).map(|_| (0..d).map(|j| (2.0 * rng.random::<f64>() - 1.0) * vmax[j]).collect()).collect();
    let eval = |x: &Vec<Vec<f64>>| -> Vec<f64> {
        x.par_iter()
            .map(|p| {
                let c = cost(p);
                if c.is_nan() { f64::INFINITY } else { c }
            })
            .collect()
    };
    let mut f = eval(&x);
    let mut pbest = x.clone();
    let mut pcost = f.clone();
    let mut gi = argmin(&pcost);
    let mut gbest = pbest[gi].clone();
    let mut gcost = pcost[gi];
    let mut history = vec![gcost];
    let mut evaluations = n;
    let k_den = (cfg.iterations.max(2) - 1) as f64;
    for k in 0..cfg.iterations {
        let w = cfg.w_start - (cfg.w_start - cfg.w_end) * k as f64 / k_den;
        for i in 0..n {
            for j in 0..d {
                let (r1, r2): (f64, f64) = (rng.random(), rng.random());
                let vn = w * v[i][j] + cfg.c1 * r1 * (pbest[i][j] - x[i][j]) + cfg.c2 * r2 * (gbest[j] - x[i][j]);
                v[i][j] = vn.clamp(-vmax[j], vmax[j]);
                x[i][j] = (x[i][j] + v[i][j]).clamp(lo[j], hi[j]);
            }
        }
        f = eval(&x);
        evaluations += n;
        for i in 0..n {
            if f[i] < pcost[i] {
                pcost[i] = f[i];
                pbest[i] = x[i].clone();
            }
        }
        gi = argmin(&pcost);
        if pcost[gi] < gcost {
            gcost = pcost[gi];
            gbest = pbest[gi].clone();
        }
        history.push(gcost);
        on_iteration(k + 1, gcost);
    }
    PsoResult { best_x: gbest, best_cost: gcost, history, evaluations }
}

fn argmin(v: &[f64]) -> usize {
    (0..v.len()).min_by(|&a, &b| v[a].total_cmp(&v[b])).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_minimum_of_a_shifted_sphere() {
        let cfg = PsoConfig { seed: 3, ..Default::default() };
        let r = minimize(
            |x| (x[0] - 1.0).powi(2) + (x[1] + 2.0).powi(2) + (x[2] - 0.5).powi(2),
            &[-5.0; 3],
            &[5.0; 3],
            &cfg,
            |_, _| {},
        );
        assert!(r.best_cost < 1e-6, "cost {}", r.best_cost);
        assert_eq!(r.evaluations, 40 * 61);
        assert!(r.history.windows(2).all(|w| w[1] <= w[0]));
    }

    #[test]
    fn is_reproducible_and_seed_dependent() {
        let f = |x: &[f64]| (x[0] * 3.0).sin() + x[1] * x[1];
        let cfg = PsoConfig { iterations: 5, ..Default::default() };
        let a = minimize(f, &[-2.0, -2.0], &[2.0, 2.0], &cfg, |_, _| {});
        let b = minimize(f, &[-2.0, -2.0], &[2.0, 2.0], &cfg, |_, _| {});
        assert_eq!(a.best_x, b.best_x);
        let c = minimize(f, &[-2.0, -2.0], &[2.0, 2.0], &PsoConfig { seed: 2, ..cfg }, |_, _| {});
        assert_ne!(a.best_x, c.best_x);
    }

    #[test]
    fn respects_bounds() {
        let r = minimize(|x| x[0], &[0.5], &[2.0], &PsoConfig { iterations: 10, ..Default::default() }, |_, _| {});
        assert!((r.best_x[0] - 0.5).abs() < 1e-15);
    }
}
