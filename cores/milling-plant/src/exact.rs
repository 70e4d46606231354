//! Exact discretisation of the plant's linear part, for the fast integrator
//! ([`Integrator::Exact`](crate::Integrator::Exact)).
//!
//! # Split
//!
//! With the state `y = (q_1, q̇_1, …, q_n, q̇_n, z_1, z_2)` (`n` = 1 or 3 modes, dimension
//! `2n + 2`) the plant of [`crate::plant`] is
//!
//! ```text
//! ẏ = L y + b_F F(t) + b_D D(t) + b_u u
//! ```
//!
//! * `L`: every mode with its nominal stiffness and damping, the actuator `ż = A z`, and the
//!   actuator force `C z` acting on every mode (all linear, time-invariant);
//! * `b_F = (0, 1/m_1, …, 0, 1/m_n, 0, 0)`: a force at the tip, `F` = cutting force + noise +
//!   sinusoidal disturbance (the nonlinear, time-varying part);
//! * `b_D = (0, 1/m_1, 0, …)`: the drift, a force `D = −A K_1 sin(2π f_d t) q_1` on mode 1 only
//!   (the stiffness modulation as a known, slowly varying modulation);
//! * `b_u = (0, D/m_1, …, 0, D/m_n, B_1, B_2)`: the saturated command, held over the step.
//!
//! # Scheme (exponential trapezoid, "ETD2RK")
//!
//! Over a cell of length `h` from `t_n`, with `N = (F, D)` at the cell's start:
//!
//! ```text
//! a       = E y_n + Γ1 N_n + Γ1_u u                 (predictor: N held)
//! y_{n+1} = a + Γ2 (N(t_{n+1}, a) − N_n)            (corrector: N linear over the cell)
//! E = e^{Lh},  Γ1 = ∫_0^h e^{Ls} ds B = h φ1(Lh) B,  Γ2 = (1/h) ∫_0^h e^{L(h−s)} s ds B = h φ2(Lh) B
//! ```
//!
//! It is exact for the linear dynamics at any step (no stability limit from the stiff third
//! mode or the actuator), exact when `N` is linear in time over the cell, and second order in
//! the (small) coupling of the cutting force to the state otherwise. All three matrices come
//! from one exponential of an augmented matrix (Van Loan 1978):
//!
//! ```text
//! exp([[L h, B h, 0], [0, 0, I], [0, 0, 0]]) = [[E, Γ1, Γ2], [0, I, I], [0, 0, I]]
//! ```
//!
//! computed by scaling and squaring with a Taylor series (norm ≤ 1/2, 18 terms: truncation
//! below 10⁻³⁰), once per step size ([`DiscreteCache`]).

#![allow(clippy::needless_range_loop)] // dense matrix code: index loops say which entry is which

use crate::params::PlantParams;

/// Largest state dimension (three modes and the actuator).
pub const MAX_DIM: usize = 8;
/// Input columns: tip force, drift force, command.
const INPUTS: usize = 3;
const AUG: usize = MAX_DIM + 2 * INPUTS;
type Aug = [[f64; AUG]; AUG];

/// The continuous linear part `(L, [b_F, b_D, b_u])` (module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct LinearPart {
    dim: usize,
    l: [[f64; MAX_DIM]; MAX_DIM],
    b: [[f64; MAX_DIM]; INPUTS],
}

impl LinearPart {
    /// The linear part of the plant with parameters `p`.
    pub fn new(p: &PlantParams) -> LinearPart {
        let modes = p.mode_list();
        let n = modes.len();
        let dim = 2 * n + 2;
        let a = &p.actuator;
        let mut l = [[0.0; MAX_DIM]; MAX_DIM];
        let mut b = [[0.0; MAX_DIM]; INPUTS];
        for (i, m) in modes.iter().enumerate() {
            l[2 * i][2 * i + 1] = 1.0;
            l[2 * i + 1][2 * i] = -m.stiffness / m.mass;
            l[2 * i + 1][2 * i + 1] = -m.damping() / m.mass;
            l[2 * i + 1][2 * n] = a.c[0] / m.mass;
            l[2 * i + 1][2 * n + 1] = a.c[1] / m.mass;
            b[0][2 * i + 1] = 1.0 / m.mass;
            b[2][2 * i + 1] = a.d / m.mass;
        }
        b[1][1] = 1.0 / modes[0].mass;
        for j in 0..2 {
            l[2 * n + j][2 * n] = a.a[j][0];
            l[2 * n + j][2 * n + 1] = a.a[j][1];
            b[2][2 * n + j] = a.b[j];
        }
        LinearPart { dim, l, b }
    }

    /// State dimension `2n + 2`.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// `ẏ = L y + b_F f + b_D d + b_u u` (the continuous right-hand side, for tests).
    pub fn rhs(&self, y: &[f64; MAX_DIM], f: f64, d: f64, u: f64) -> [f64; MAX_DIM] {
        let mut r = [0.0; MAX_DIM];
        for (i, ri) in r.iter_mut().enumerate().take(self.dim) {
            *ri = (0..self.dim).map(|j| self.l[i][j] * y[j]).sum::<f64>()
                + self.b[0][i] * f
                + self.b[1][i] * d
                + self.b[2][i] * u;
        }
        r
    }

    /// The exact discretisation over a step `h` (module documentation).
    pub fn discretise(&self, h: f64) -> Discrete {
        let n = self.dim;
        let size = n + 2 * INPUTS;
        let mut m: Aug = [[0.0; AUG]; AUG];
        for i in 0..n {
            for j in 0..n {
                m[i][j] = self.l[i][j] * h;
            }
            for k in 0..INPUTS {
                m[i][n + k] = self.b[k][i] * h;
            }
        }
        for k in 0..INPUTS {
            m[n + k][n + INPUTS + k] = 1.0;
        }
        let x = expm(&m, size);
        let mut d =
            Discrete { dim: n, e: [[0.0; MAX_DIM]; MAX_DIM], g1: [[0.0; MAX_DIM]; INPUTS], g2: [[0.0; MAX_DIM]; 2] };
        for i in 0..n {
            d.e[i][..n].copy_from_slice(&x[i][..n]);
            for k in 0..INPUTS {
                d.g1[k][i] = x[i][n + k];
            }
            for k in 0..2 {
                d.g2[k][i] = x[i][n + INPUTS + k];
            }
        }
        d
    }
}

/// `exp(m)` of the leading `size × size` block: scaling and squaring, Taylor series.
fn expm(m: &Aug, size: usize) -> Aug {
    let norm = (0..size).map(|j| (0..size).map(|i| m[i][j].abs()).sum::<f64>()).fold(0.0, f64::max);
    let squarings = if norm > 0.5 { (norm / 0.5).log2().ceil() as i32 } else { 0 };
    let scale = 0.5f64.powi(squarings);
    let mut a: Aug = [[0.0; AUG]; AUG];
    for i in 0..size {
        for j in 0..size {
            a[i][j] = m[i][j] * scale;
        }
    }
    let mut sum: Aug = [[0.0; AUG]; AUG];
    let mut term: Aug = [[0.0; AUG]; AUG];
    for i in 0..size {
        sum[i][i] = 1.0;
        term[i][i] = 1.0;
    }
    for k in 1..=18 {
        term = matmul(&term, &a, size);
        for i in 0..size {
            for j in 0..size {
                term[i][j] /= k as f64;
                sum[i][j] += term[i][j];
            }
        }
    }
    for _ in 0..squarings {
        sum = matmul(&sum, &sum, size);
    }
    sum
}

fn matmul(a: &Aug, b: &Aug, size: usize) -> Aug {
    let mut c: Aug = [[0.0; AUG]; AUG];
    for i in 0..size {
        for k in 0..size {
            let aik = a[i][k];
            if aik != 0.0 {
                for j in 0..size {
                    c[i][j] += aik * b[k][j];
                }
            }
        }
    }
    c
}

/// `E`, `Γ1` (tip force, drift force, command) and `Γ2` (tip force, drift force) of one step size.
#[derive(Clone, Debug, PartialEq)]
pub struct Discrete {
    dim: usize,
    e: [[f64; MAX_DIM]; MAX_DIM],
    g1: [[f64; MAX_DIM]; INPUTS],
    g2: [[f64; MAX_DIM]; 2],
}

impl Discrete {
    /// Predictor `E y + Γ1_F f + Γ1_D d + Γ1_u u`.
    #[inline]
    pub fn predict(&self, y: &[f64; MAX_DIM], f: f64, d: f64, u: f64) -> [f64; MAX_DIM] {
        match self.dim {
            4 => self.predict_n::<4>(y, f, d, u),
            _ => self.predict_n::<MAX_DIM>(y, f, d, u),
        }
    }

    #[inline]
    fn predict_n<const N: usize>(&self, y: &[f64; MAX_DIM], f: f64, d: f64, u: f64) -> [f64; MAX_DIM] {
        let mut r = [0.0; MAX_DIM];
        for i in 0..N {
            let mut acc = self.g1[0][i] * f + self.g1[1][i] * d + self.g1[2][i] * u;
            for j in 0..N {
                acc += self.e[i][j] * y[j];
            }
            r[i] = acc;
        }
        r
    }

    /// Corrector `a + Γ2_F df + Γ2_D dd`.
    #[inline]
    pub fn correct(&self, a: &mut [f64; MAX_DIM], df: f64, dd: f64) {
        for i in 0..self.dim {
            a[i] += self.g2[0][i] * df + self.g2[1][i] * dd;
        }
    }
}

/// The discretisations of the step sizes in use (the full cell, and the partial steps a
/// communication point inside a cell needs), computed on first use.
#[derive(Clone, Debug)]
pub struct DiscreteCache {
    linear: LinearPart,
    entries: Vec<(u64, Discrete)>,
}

impl DiscreteCache {
    /// Most step sizes kept (the first one, usually the full cell, is never evicted).
    const CAPACITY: usize = 4;

    /// An empty cache for the plant with parameters `p`.
    pub fn new(p: &PlantParams) -> DiscreteCache {
        DiscreteCache { linear: LinearPart::new(p), entries: Vec::with_capacity(Self::CAPACITY) }
    }

    /// The discretisation over `h`.
    #[inline]
    pub fn get(&mut self, h: f64) -> &Discrete {
        let key = h.to_bits();
        let at = match self.entries.iter().position(|(k, _)| *k == key) {
            Some(i) => i,
            None => {
                if self.entries.len() == Self::CAPACITY {
                    self.entries.truncate(1);
                }
                self.entries.push((key, self.linear.discretise(h)));
                self.entries.len() - 1
            }
        };
        &self.entries[at].1
    }

    /// Number of step sizes held (bounded by a constant, whatever the run length).
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Is the cache empty?
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Mode;

    /// One mode, no actuator coupling: the free response and the response to a constant and
    /// to a ramp force have closed forms (underdamped oscillator).
    #[test]
    fn single_mode_steps_match_the_closed_form() {
        let mut p = PlantParams::default();
        p.actuator.c = [0.0; 2];
        p.actuator.d = 0.0;
        let lin = LinearPart::new(&p);
        let m: Mode = p.workpiece.first;
        let (wn, z) = (m.omega_n(), m.damping_ratio);
        let wd = wn * (1.0 - z * z).sqrt();
        let h = 3e-4; // large: ω_n h = 0.27
        let d = lin.discretise(h);
        // free response from (x0, v0)
        let (x0, v0) = (1e-5, 2e-3);
        let e = (-z * wn * h).exp();
        let x_exact = e * (x0 * (wd * h).cos() + (v0 + z * wn * x0) / wd * (wd * h).sin());
        let y = d.predict(&[x0, v0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], 0.0, 0.0, 0.0);
        assert!((y[0] - x_exact).abs() < 1e-13 * x0, "{} vs {x_exact}", y[0]);
        // constant force F from rest: x = F/k (1 − e(cos + ζωn/ωd sin))
        let f = 100.0;
        let xs = f / m.stiffness * (1.0 - e * ((wd * h).cos() + z * wn / wd * (wd * h).sin()));
        let y = d.predict(&[0.0; MAX_DIM], f, 0.0, 0.0);
        assert!((y[0] - xs).abs() < 1e-12 * xs.abs(), "{} vs {xs}", y[0]);
        // the drift column acts on mode 1 like the tip force when there is one mode
        let yd = d.predict(&[0.0; MAX_DIM], 0.0, f, 0.0);
        assert!((yd[0] - y[0]).abs() < 1e-15 * y[0].abs());
    }

    /// The corrector makes a force linear in time exact: compare with RK4 at a tiny step on
    /// the full system (three modes, actuator coupled, command held).
    #[test]
    fn ramp_force_and_command_match_a_fine_rk4() {
        let mut p = PlantParams::default();
        p.workpiece.modes = 3;
        let lin = LinearPart::new(&p);
        let h = 1e-4;
        let d = lin.discretise(h);
        let y0 = [1e-6, -1e-4, 2e-7, 3e-4, -1e-8, 1e-3, 0.01, 1e-5];
        let (f0, f1, d0, d1, u) = (10.0, -30.0, 5.0, 7.0, 2.0);
        let mut a = d.predict(&y0, f0, d0, u);
        d.correct(&mut a, f1 - f0, d1 - d0);
        let n = 20_000;
        let dt = h / n as f64;
        let mut y = y0;
        let force = |s: f64| (f0 + (f1 - f0) * s / h, d0 + (d1 - d0) * s / h);
        for k in 0..n {
            let s = k as f64 * dt;
            let stage = |y: &[f64; MAX_DIM], s: f64| {
                let (f, dd) = force(s);
                lin.rhs(y, f, dd, u)
            };
            let add = |y: &[f64; MAX_DIM], k: &[f64; MAX_DIM], c: f64| {
                let mut r = *y;
                for i in 0..MAX_DIM {
                    r[i] += c * k[i];
                }
                r
            };
            let k1 = stage(&y, s);
            let k2 = stage(&add(&y, &k1, dt / 2.0), s + dt / 2.0);
            let k3 = stage(&add(&y, &k2, dt / 2.0), s + dt / 2.0);
            let k4 = stage(&add(&y, &k3, dt), s + dt);
            for i in 0..MAX_DIM {
                y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        for i in 0..lin.dim() {
            let scale = y0[i].abs().max(y[i].abs());
            assert!((a[i] - y[i]).abs() < 1e-9 * scale, "component {i}: {} vs {}", a[i], y[i]);
        }
    }

    #[test]
    fn the_cache_is_bounded_and_keeps_the_first_step() {
        let mut c = DiscreteCache::new(&PlantParams::default());
        let full = c.get(1e-5).clone();
        for k in 1..20 {
            c.get(k as f64 * 1e-7);
            assert!(c.len() <= DiscreteCache::CAPACITY);
        }
        assert_eq!(*c.get(1e-5), full);
        assert_eq!(c.entries[0].0, 1e-5f64.to_bits());
    }
}
