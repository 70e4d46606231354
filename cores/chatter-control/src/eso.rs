//! Linear extended state observer (ESO), discretised exactly as a current observer.
//!
//! Plant in canonical ADRC form (seed 000, Section 4.2): `ẍ = f + b0·u`, extended state
//! `x = [x, ẋ, f]`, `ḟ = h` unknown. The continuous linear ESO
//!
//! ```text
//! ż = A z + B u + β (y − z1),  A = \[[0,1,0\],\[0,0,1\],\[0,0,0\]],  B = \[0, b0, 0\]ᵀ,
//! β = \[3ωo, 3ωo², ωo³\]ᵀ   (error dynamics (s + ωo)³: bandwidth parameterisation)
//! ```
//!
//! is not stepped with Euler. The extended model is discretised exactly (zero-order hold on
//! `u`, `f` piecewise constant), `Φ = e^{AT}`, `Γ = ∫₀ᵀ e^{Aτ}B dτ`:
//!
//! ```text
//! Φ = \[[1, T, T²/2\], \[0, 1, T\], \[0, 0, 1\]],   Γ = b0·\[T²/2, T, 0\]ᵀ
//! ```
//!
//! and a *current* observer (predict with the applied command of the previous sample, correct
//! with the measurement of this sample) is designed on it:
//!
//! ```text
//! z⁻_k = Φ z_{k−1} + Γ u_{k−1}           (u_{k−1}: the SATURATED command actually applied)
//! z_k  = z⁻_k + K (y_k − z⁻_{k,1})
//! error: e_k = (I − K C) Φ e_{k−1}
//! ```
//!
//! The gain `K` puts the three eigenvalues of `(I − KC)Φ` at `q = e^{−ωo T}`, the exact image
//! of the continuous triple pole `−ωo` (matrix determinant lemma on the nilpotent part of Φ;
//! Miklosovic, Radke & Gao 2006):
//!
//! ```text
//! K = \[1 − q³,  3 (1 − q)² (1 + q) / (2T),  (1 − q)³ / T²\]
//! ```
//!
//! As `T → 0`, `K/T → β`; unlike forward Euler (`z_{k+1} = z_k + T·ż`, stable only for
//! `ωo T ≲ 1.6` and with poles `1 − ωo T` only to first order), this is stable and exact in pole
//! location for any `ωo T`. The estimate `z_k` uses `y_k` (direct feedthrough, no extra delay)
//! but only `u_{k−1}`, so the control law `u_k = (u0 − z3)/b0` has no algebraic loop.
//!
//! Accuracy note (deviation from the paper's Eq. 26a): the transfer from the disturbance to
//! its estimate is `z3/f = ωo³/(s + ωo)³`, so the estimation error `f − z3` of a sinusoid at ω
//! is `|1 − (1 + jω/ωo)^(−3)| ≈ 3ω/ωo`, not `(ω/ωo)³`. With ωo = 2699 rad/s and ω = 900 rad/s
//! (143 Hz) that is 87 % (amplitude 85 % of f, 55° lag). A 5 % error at 143 Hz needs
//! `ωo ≳ 60 ω ≈ 5.4·10⁴ rad/s`; the tests check both statements.

use num_complex::Complex64;
use serde::{Deserialize, Serialize};

/// Discrete current-form linear ESO (see the module documentation).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Eso {
    ts: f64,
    b0: f64,
    omega_o: f64,
    k: [f64; 3],
    z: [f64; 3],
    u_prev: f64,
}

impl Eso {
    /// A restored ESO: the gains `fresh` has, a finite state.
    pub(crate) fn check(&self, fresh: &Self) -> Result<(), String> {
        let cfg = |e: &Eso| [e.ts, e.b0, e.omega_o, e.k[0], e.k[1], e.k[2]];
        crate::restored::same("ESO gains", &cfg(self), &cfg(fresh))?;
        crate::restored::finite("ESO state", &[self.z[0], self.z[1], self.z[2], self.u_prev])
    }

    /// Observer of bandwidth `omega_o` \[rad/s\] for input gain `b0` \[1/kg\] at sample period `ts`.
    pub fn new(omega_o: f64, b0: f64, ts: f64) -> Self {
        // `libm`, not the platform's: the same bits on every platform (see `grunwald`)
        let q = libm::exp(-omega_o * ts);
        let d = -libm::expm1(-omega_o * ts); // 1 − q without cancellation
        let k = [1.0 - q * q * q, 3.0 * d * d * (1.0 + q) / (2.0 * ts), d * d * d / (ts * ts)];
        Eso { ts, b0, omega_o, k, z: [0.0; 3], u_prev: 0.0 }
    }

    /// Observer bandwidth ωo.
    pub fn omega_o(&self) -> f64 {
        self.omega_o
    }

    /// Gain K.
    pub fn gain(&self) -> [f64; 3] {
        self.k
    }

    /// `Φ` and `Γ` of the exact discretisation.
    fn phi_gamma(&self) -> ([[f64; 3]; 3], [f64; 3]) {
        let t = self.ts;
        ([[1.0, t, t * t / 2.0], [0.0, 1.0, t], [0.0, 0.0, 1.0]], [self.b0 * t * t / 2.0, self.b0 * t, 0.0])
    }

    /// Error dynamics `M = (I − KC)Φ` and input matrix `G = (I − KC)Γ` (`z_k = M z_{k−1} + G u_{k−1} + K y_k`).
    pub fn matrices(&self) -> ([[f64; 3]; 3], [f64; 3]) {
        let (phi, gam) = self.phi_gamma();
        let mut m = phi;
        let mut g = gam;
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] -= self.k[i] * phi[0][j];
            }
            g[i] -= self.k[i] * gam[0];
        }
        (m, g)
    }

    /// Measurement update with `y_k`; returns `z_k`. Uses the command stored by
    /// [`set_applied`](Self::set_applied) at the previous sample.
    #[inline]
    pub fn update(&mut self, y: f64) -> [f64; 3] {
        let t = self.ts;
        let [z1, z2, z3] = self.z;
        let bu = self.b0 * self.u_prev;
        let p1 = z1 + t * z2 + 0.5 * t * t * (z3 + bu);
        let p2 = z2 + t * (z3 + bu);
        let p3 = z3;
        let innov = y - p1;
        self.z = [p1 + self.k[0] * innov, p2 + self.k[1] * innov, p3 + self.k[2] * innov];
        self.z
    }

    /// Store the command actually applied over the coming sample interval.
    #[inline]
    pub fn set_applied(&mut self, u: f64) {
        self.u_prev = u;
    }

    /// Current estimates.
    pub fn state(&self) -> [f64; 3] {
        self.z
    }

    /// Linear response at `z`: `Ẑ = a·U + b·Y` with `a = (zI − M)⁻¹ G`, `b = z (zI − M)⁻¹ K`.
    pub fn response(&self, z: Complex64) -> ([Complex64; 3], [Complex64; 3]) {
        let (m, g) = self.matrices();
        let mut a = [[Complex64::new(0.0, 0.0); 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                a[i][j] = Complex64::new(-m[i][j], 0.0);
            }
            a[i][i] += z;
        }
        let gu = solve3(a, [g[0].into(), g[1].into(), g[2].into()]);
        let ky = solve3(a, [z * self.k[0], z * self.k[1], z * self.k[2]]);
        (gu, ky)
    }
}

/// Solve a complex 3×3 system by Cramer's rule.
fn solve3(a: [[Complex64; 3]; 3], b: [Complex64; 3]) -> [Complex64; 3] {
    let det = |m: &[[Complex64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(&a);
    let mut x = [Complex64::new(0.0, 0.0); 3];
    for (c, xc) in x.iter_mut().enumerate() {
        let mut m = a;
        for r in 0..3 {
            m[r][c] = b[r];
        }
        *xc = det(&m) / d;
    }
    x
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
pub(crate) mod tests {
    use super::*;
    use std::f64::consts::PI;

    const TS: f64 = 1e-5;
    const B0: f64 = 1.0 / 30.0;
    const WO: f64 = 2699.3;

    /// Characteristic polynomial coefficients `[c2, c1, c0]` of `λ³ + c2 λ² + c1 λ + c0`.
    fn charpoly(m: [[f64; 3]; 3]) -> [f64; 3] {
        let tr = m[0][0] + m[1][1] + m[2][2];
        let minors = m[0][0] * m[1][1] - m[0][1] * m[1][0] + m[0][0] * m[2][2] - m[0][2] * m[2][0] + m[1][1] * m[2][2]
            - m[1][2] * m[2][1];
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        [-tr, minors, -det]
    }

    /// The eigenvalues of the discrete error dynamics are the triple `q = e^{−ωo T}`:
    /// the characteristic polynomial equals `(λ − q)³` and `(M − qI)³ = 0`.
    #[test]
    fn error_poles_at_mapped_bandwidth() {
        for &wo in &[WO, 5.4e4, 2e5] {
            let eso = Eso::new(wo, B0, TS);
            let (m, _) = eso.matrices();
            let q = (-wo * TS).exp();
            let c = charpoly(m);
            let want = [-3.0 * q, 3.0 * q * q, -q * q * q];
            for i in 0..3 {
                assert!((c[i] - want[i]).abs() < 1e-12, "wo {wo}: coeff {i}: {} vs {}", c[i], want[i]);
            }
            // (M − qI)^3 = 0, scaled by the entry sizes of M^3
            let mut n = m;
            for (i, row) in n.iter_mut().enumerate() {
                row[i] -= q;
            }
            let mul = |a: [[f64; 3]; 3], b: [[f64; 3]; 3]| {
                let mut c = [[0.0; 3]; 3];
                for i in 0..3 {
                    for j in 0..3 {
                        c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
                    }
                }
                c
            };
            let n3 = mul(mul(n, n), n);
            let scale = [1.0, 1.0 / TS, 1.0 / (TS * TS)]; // row scaling of the state units
            for i in 0..3 {
                for j in 0..3 {
                    let s = scale[i] / scale[j];
                    assert!(n3[i][j].abs() < 1e-9 * s.max(1.0), "wo {wo}: (M-qI)^3[{i}][{j}] = {}", n3[i][j]);
                }
            }
            // continuous limit: K/T ≈ β for small ωo T
            if wo * TS < 0.05 {
                let k = eso.gain();
                assert!((k[0] / TS / (3.0 * wo) - 1.0).abs() < 0.05);
                assert!((k[1] / TS / (3.0 * wo * wo) - 1.0).abs() < 0.05);
                assert!((k[2] / TS / (wo * wo * wo) - 1.0).abs() < 0.05);
            }
        }
    }

    /// Double integrator `ẍ = f(t) + b0 u`, integrated exactly between samples for a ZOH
    /// `u` and `f` given as constant + sine (closed form), sampled every `TS`.
    pub(crate) struct DoubleIntegrator {
        pub x: f64,
        pub v: f64,
        pub t: f64,
    }

    impl DoubleIntegrator {
        /// Advance by `TS` with force-free acceleration `b0 u` held and `f = f0 + a sin(ω t)`.
        pub fn step(&mut self, acc_u: f64, f0: f64, a: f64, w: f64, ts: f64) {
            let (t0, t1) = (self.t, self.t + ts);
            // ∫∫ a sin(w s): velocity gain a/w (cos w t0 − cos w t1); position via exact integral
            let dv = (acc_u + f0) * ts + a / w * ((w * t0).cos() - (w * t1).cos());
            let dx = self.v * ts
                + 0.5 * (acc_u + f0) * ts * ts
                + a / w * ((w * t0).cos() * ts - ((w * t1).sin() - (w * t0).sin()) / w);
            self.x += dx;
            self.v += dv;
            self.t = t1;
        }
    }

    fn run(wo: f64, f0: f64, amp: f64, freq: f64, with_control: bool) -> (Vec<f64>, Vec<f64>) {
        let w = 2.0 * PI * freq;
        let mut eso = Eso::new(wo, B0, TS);
        let mut p = DoubleIntegrator { x: 0.0, v: 0.0, t: 0.0 };
        let (mut est, mut truth) = (Vec::new(), Vec::new());
        for _ in 0..40_000 {
            let f = f0 + amp * (w * p.t).sin();
            let z = eso.update(p.x);
            est.push(z[2]);
            truth.push(f);
            // an arbitrary stabilising command (PD on the estimate) so the test exercises the u path
            let u = if with_control { (-1e4 * z[0] - 200.0 * z[1] - z[2]) / B0 } else { 0.0 };
            eso.set_applied(u);
            p.step(B0 * u, f0, amp, w, TS);
        }
        (est, truth)
    }

    #[test]
    fn constant_disturbance_is_estimated() {
        for ctl in [false, true] {
            let (est, truth) = run(WO, 3.0, 0.0, 1.0, ctl);
            // after 10 ms (27 time constants) the estimate has converged
            let worst = est[1000..].iter().zip(&truth[1000..]).map(|(e, t)| (e - t).abs()).fold(0.0, f64::max);
            assert!(worst < 0.05 * 3.0 * 1e-3, "control {ctl}: worst error {worst}");
        }
    }

    /// 143 Hz sinusoidal disturbance: with ωo = 100·ω (> 60 ω, the corrected rule) the RMS
    /// estimation error after the transient is below 5 % of the disturbance RMS; with the
    /// paper's ωo = 2699 rad/s it is the 87 % the analysis predicts (and fails the 5 %).
    #[test]
    fn sinusoidal_disturbance_at_143_hz() {
        let w = 2.0 * PI * 143.0;
        let rms_err = |wo: f64| {
            let (est, truth) = run(wo, 0.0, 5.0, 143.0, true);
            let e: f64 = est[20_000..].iter().zip(&truth[20_000..]).map(|(e, t)| (e - t).powi(2)).sum();
            let s: f64 = truth[20_000..].iter().map(|t| t * t).sum();
            (e / s).sqrt()
        };
        let fast = rms_err(100.0 * w);
        assert!(fast < 0.05, "ωo = 100 ω: RMS error {fast}");
        let paper = rms_err(WO);
        let predicted = (1.0 - Complex64::new(1.0, w / WO).powi(-3)).norm();
        assert!((paper - predicted).abs() < 0.02, "paper ωo: RMS error {paper} vs predicted {predicted}");
        assert!(paper > 0.05);
    }

    #[test]
    fn response_matches_stepping() {
        let eso = Eso::new(WO, B0, TS);
        let z = Complex64::from_polar(1.0, 2.0 * PI * 150.0 * TS);
        let (a, b) = eso.response(z);
        // z-domain identity: (zI − M) Ẑ = G U + z K Y with Ẑ = aU + bY
        let (m, g) = eso.matrices();
        for i in 0..3 {
            let lhs_a = z * a[i] - (0..3).map(|j| m[i][j] * a[j]).sum::<Complex64>();
            let lhs_b = z * b[i] - (0..3).map(|j| m[i][j] * b[j]).sum::<Complex64>();
            assert!((lhs_a - g[i]).norm() < 1e-9 * g[i].abs().max(1e-12));
            assert!((lhs_b - z * eso.gain()[i]).norm() < 1e-9 * eso.gain()[i].abs());
        }
    }
}
