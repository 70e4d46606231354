//! Type-1 and interval type-2 fuzzy systems on the normalised (position error, velocity error)
//! plane, with learnable constant consequents.
//!
//! # Membership functions and rules
//!
//! Each input is normalised to `[−2, 2]` (seed 003, Section 4) and clamped there. Input `a` has
//! `n_a` Gaussian sets `μ(z) = exp(−½((z − c)/s)²)` with centres evenly spaced over `[−2, 2]`
//! (`c_i = −2 + 4i/(n_a − 1)`; one set: centre 0) and width `s = 4/(n_a − 1)/2` (half the spacing;
//! one set: 2). The rules are the full grid (product t-norm): rule `(i, j)` fires
//! `f = μ_i(z_p) μ_j(z_v)`. The seed gives the rule counts only (T1: 9 rules for ĵ, 6 for ĥ; T2:
//! 6 and 4), read as grids 3×3 and 3×2 (T1), 3×2 and 2×2 (T2); the centres and widths are ours.
//!
//! **Type 1:** `y = Σ w_i φ_i`, `φ_i = f_i / Σ f`.
//!
//! **Interval type 2:** every set has an uncertain width: upper width `s`, lower width `r s`
//! (`r` = `fou_ratio` ≤ 1, default 0.8; `r = 1` is zero footprint of uncertainty). The lower
//! and upper firing strengths are `f̲`, `f̄`; the consequents are intervals `[w_l, w_r]` (two weight
//! vectors, both learned). Type reduction:
//!
//! * [`Reduction::ClosedForm`] (Eq. 25 in the physically consistent reading): `y_l = w_l·φ_l`,
//!   `y_r = w_r·φ_r` with `φ_l = f̲/Σf̲` and `φ_r = f̄/Σf̄` (Eq. 25 normalises both by
//!   `Σf̲ + Σf̄`, which with the factor ½ halves the output; we normalise each by its own sum), and
//!   `y = (y_l + y_r)/2`. With `r = 1` and `w_l = w_r` this is the type-1 output bitwise.
//! * [`Reduction::KarnikMendel`] (the paper's toolbox): `y_l = min_L` and `y_r = max_R` of the
//!   centroid over the switch points, by the KM iteration ([`km_endpoint`]); `φ_l`, `φ_r` are the
//!   normalised strengths of the final switch configuration. [`km_endpoint_reference`] searches
//!   every switch point (the slow reference).
//!
//! # Learning (Eqs. 27–29)
//!
//! With the modelling error `e_m` and the normalised strengths `φ` of the sample the prediction
//! was made from: `w ← w − Ω e_m φ / (1 + Φ)` for ĵ and `w ← w − Ω e_m u φ / (1 + Φ)` for ĥ,
//! `Φ = ‖φ_f‖² + ‖φ_g u‖²` (Eq. 29); see [`crate::controller`] for the dead zone.

use serde::{Deserialize, Serialize};

/// Type reduction of the interval type-2 system.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Reduction {
    /// Eq. 25: average of the lower- and upper-normalised outputs.
    ClosedForm,
    /// Karnik–Mendel centroid endpoints.
    KarnikMendel,
}

/// Evenly spaced Gaussian sets on `[−2, 2]`: `(centres, width)`.
pub fn grid(n: usize) -> (Vec<f64>, f64) {
    if n <= 1 {
        return (vec![0.0], 2.0);
    }
    let step = 4.0 / (n - 1) as f64;
    ((0..n).map(|i| -2.0 + step * i as f64).collect(), 0.5 * step)
}

fn gauss(z: f64, c: f64, s: f64) -> f64 {
    let d = (z - c) / s;
    (-0.5 * d * d).exp()
}

/// Firing strengths of the `np × nv` grid at `z = (z_p, z_v)` (clamped to [−2, 2]) with the
/// widths scaled by `ratio`. Rule `(i, j)` is at index `i nv + j`.
pub fn firing(np: usize, nv: usize, z: [f64; 2], ratio: f64) -> Vec<f64> {
    let (cp, sp) = grid(np);
    let (cv, sv) = grid(nv);
    let (zp, zv) = (z[0].clamp(-2.0, 2.0), z[1].clamp(-2.0, 2.0));
    let mut f = Vec::with_capacity(np * nv);
    for &a in &cp {
        let ma = gauss(zp, a, sp * ratio);
        for &b in &cv {
            f.push(ma * gauss(zv, b, sv * ratio));
        }
    }
    f
}

fn normalise(f: &[f64]) -> Vec<f64> {
    let s: f64 = f.iter().sum();
    f.iter().map(|x| x / s).collect()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `w ← w − g φ` (one learning step with the gain `g = Ω e_m (u) / (1 + Φ)` already formed).
pub fn learn(w: &mut [f64], phi: &[f64], g: f64) {
    for (wi, p) in w.iter_mut().zip(phi) {
        *wi -= g * p;
    }
}

/// Squared norm.
pub fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum()
}

/// A type-1 fuzzy system with constant consequents.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct T1System {
    /// Sets on the position error.
    pub np: usize,
    /// Sets on the velocity error.
    pub nv: usize,
    /// Consequents, one per rule.
    pub w: Vec<f64>,
}

impl T1System {
    /// All consequents zero.
    pub fn new(np: usize, nv: usize) -> Self {
        T1System { np, nv, w: vec![0.0; np * nv] }
    }

    /// Normalised strengths at `z`.
    pub fn phi(&self, z: [f64; 2]) -> Vec<f64> {
        normalise(&firing(self.np, self.nv, z, 1.0))
    }

    /// Output for the strengths `phi`.
    pub fn output(&self, phi: &[f64]) -> f64 {
        dot(&self.w, phi)
    }
}

/// An interval type-2 fuzzy system with interval constant consequents `[w_l, w_r]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct T2System {
    /// Sets on the position error.
    pub np: usize,
    /// Sets on the velocity error.
    pub nv: usize,
    /// Lower-width ratio r (1: zero footprint of uncertainty).
    pub ratio: f64,
    /// Type reduction.
    pub reduction: Reduction,
    /// Left consequents.
    pub wl: Vec<f64>,
    /// Right consequents.
    pub wr: Vec<f64>,
}

impl T2System {
    /// All consequents zero.
    pub fn new(np: usize, nv: usize, ratio: f64, reduction: Reduction) -> Self {
        T2System { np, nv, ratio, reduction, wl: vec![0.0; np * nv], wr: vec![0.0; np * nv] }
    }

    /// Lower and upper firing strengths at `z`.
    pub fn firing(&self, z: [f64; 2]) -> (Vec<f64>, Vec<f64>) {
        (firing(self.np, self.nv, z, self.ratio), firing(self.np, self.nv, z, 1.0))
    }

    /// The normalised strengths `(φ_l, φ_r)` that multiply `w_l` and `w_r`.
    pub fn phi(&self, z: [f64; 2]) -> (Vec<f64>, Vec<f64>) {
        let (lo, up) = self.firing(z);
        match self.reduction {
            Reduction::ClosedForm => (normalise(&lo), normalise(&up)),
            Reduction::KarnikMendel => {
                (km_endpoint(&self.wl, &lo, &up, false).phi, km_endpoint(&self.wr, &lo, &up, true).phi)
            }
        }
    }

    /// Output `(w_l·φ_l + w_r·φ_r)/2`.
    pub fn output(&self, phi_l: &[f64], phi_r: &[f64]) -> f64 {
        0.5 * (dot(&self.wl, phi_l) + dot(&self.wr, phi_r))
    }
}

/// A Karnik–Mendel endpoint.
#[derive(Clone, Debug, PartialEq)]
pub struct KmEndpoint {
    /// The endpoint `y_l` or `y_r`.
    pub y: f64,
    /// Normalised strengths of the final switch configuration, in rule order.
    pub phi: Vec<f64>,
    /// Iterations used.
    pub iterations: usize,
}

fn config(order: &[usize], lo: &[f64], up: &[f64], k: usize, right: bool) -> Vec<f64> {
    // positions 0..=k in sorted order take the upper strength for y_l (lower for y_r)
    let mut f = vec![0.0; lo.len()];
    for (pos, &i) in order.iter().enumerate() {
        let first = pos <= k;
        f[i] = if first != right { up[i] } else { lo[i] };
    }
    f
}

/// Karnik–Mendel: `y_l` (`right = false`) or `y_r` of the consequents `w` with firing intervals
/// `[lo, up]`.
pub fn km_endpoint(w: &[f64], lo: &[f64], up: &[f64], right: bool) -> KmEndpoint {
    let n = w.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| w[a].total_cmp(&w[b]));
    let mid: Vec<f64> = lo.iter().zip(up).map(|(a, b)| 0.5 * (a + b)).collect();
    let mut y = dot(w, &mid) / mid.iter().sum::<f64>();
    let mut last = usize::MAX;
    for it in 1..=n + 1 {
        // switch point: last sorted position with w ≤ y
        let k = order.iter().rposition(|&i| w[i] <= y).unwrap_or(0);
        let f = config(&order, lo, up, k, right);
        let phi = normalise(&f);
        let y_new = dot(w, &phi);
        if k == last {
            return KmEndpoint { y: y_new, phi, iterations: it };
        }
        last = k;
        y = y_new;
    }
    let f = config(&order, lo, up, last, right);
    let phi = normalise(&f);
    KmEndpoint { y: dot(w, &phi), phi, iterations: n + 1 }
}

/// Slow reference: the extreme centroid over every switch point.
pub fn km_endpoint_reference(w: &[f64], lo: &[f64], up: &[f64], right: bool) -> f64 {
    let n = w.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| w[a].total_cmp(&w[b]));
    let vals = (0..n).map(|k| {
        let f = config(&order, lo, up, k, right);
        dot(w, &normalise(&f))
    });
    if right { vals.fold(f64::NEG_INFINITY, f64::max) } else { vals.fold(f64::INFINITY, f64::min) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fixed pseudo-random sequence in [−1, 1) (no dependency).
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    #[test]
    fn zero_footprint_type_2_equals_type_1_bitwise_through_learning() {
        let mut s = 7u64;
        let mut t1 = T1System::new(3, 2);
        let mut t2 = T2System::new(3, 2, 1.0, Reduction::ClosedForm);
        let w0: Vec<f64> = (0..6).map(|_| lcg(&mut s)).collect();
        t1.w.clone_from(&w0);
        t2.wl.clone_from(&w0);
        t2.wr = w0;
        for _ in 0..1000 {
            let z = [3.0 * lcg(&mut s), 3.0 * lcg(&mut s)];
            let p1 = t1.phi(z);
            let (pl, pr) = t2.phi(z);
            let (y1, y2) = (t1.output(&p1), t2.output(&pl, &pr));
            assert_eq!(y1.to_bits(), y2.to_bits(), "z = {z:?}");
            let e = lcg(&mut s);
            let g1 = 0.9 * e / (1.0 + norm2(&p1));
            learn(&mut t1.w, &p1, g1);
            learn(&mut t2.wl, &pl, 0.9 * e / (1.0 + norm2(&pl)));
            learn(&mut t2.wr, &pr, 0.9 * e / (1.0 + norm2(&pr)));
        }
        // and with a footprint the outputs differ
        let t2b = T2System { ratio: 0.8, ..t2.clone() };
        let (pl, pr) = t2b.phi([0.7, -1.1]);
        let p1 = t1.phi([0.7, -1.1]);
        assert!((t2b.output(&pl, &pr) - t1.output(&p1)).abs() > 1e-6);
    }

    #[test]
    fn karnik_mendel_matches_exhaustive_search_within_range_and_rule_count() {
        let mut s = 11u64;
        for _ in 0..500 {
            let n = 6;
            let w: Vec<f64> = (0..n).map(|_| lcg(&mut s)).collect();
            let z = [2.5 * lcg(&mut s), 2.5 * lcg(&mut s)];
            let lo = firing(3, 2, z, 0.8);
            let up = firing(3, 2, z, 1.0);
            assert!(lo.iter().zip(&up).all(|(a, b)| a <= b));
            for right in [false, true] {
                let km = km_endpoint(&w, &lo, &up, right);
                let r = km_endpoint_reference(&w, &lo, &up, right);
                assert!((km.y - r).abs() < 1e-14, "KM {} vs exhaustive {r}", km.y);
                assert!(km.iterations <= n, "{} iterations", km.iterations);
                let (mn, mx) = w.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
                assert!(km.y >= mn - 1e-15 && km.y <= mx + 1e-15);
            }
            let l = km_endpoint(&w, &lo, &up, false).y;
            let r = km_endpoint(&w, &lo, &up, true).y;
            assert!(l <= r + 1e-15);
        }
    }

    #[test]
    fn grids_have_the_documented_centres() {
        assert_eq!(grid(3), (vec![-2.0, 0.0, 2.0], 1.0));
        assert_eq!(grid(2), (vec![-2.0, 2.0], 2.0));
        let f = firing(3, 2, [0.0, 2.0], 1.0);
        assert_eq!(f[3].to_bits(), 1.0f64.to_bits(), "rule (1, 1) at its centres");
    }
}
