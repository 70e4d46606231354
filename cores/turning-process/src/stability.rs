//! The exact stability limit of the linearised single-delay equation (5).
//!
//! # Maths
//!
//! `ẍ + a₁ẋ + (ω_n² + a₂)x = a₂ x(t − T)` has the characteristic function
//!
//! ```text
//! Δ(λ) = λ² + a₁λ + ω_n² + a₂ (1 − e^{−λT}).
//! ```
//!
//! On the boundary `λ = iω`. With `D(ω) = ω_n² − ω² + i a₁ω`, `Δ(iω) = 0` reads
//! `e^{−iωT} = 1 + D/a₂`; the right side has modulus 1 iff `a₂ = −|D|²/(2 Re D)`, which needs
//! `ω > ω_n`. Then `ωT = 2πk − arg(1 + D/a₂)` (k = 0, 1, …), i.e. each lobe `k` maps a chatter
//! frequency `ω` to one delay `T_k(ω)` and one gain `a₂(ω)`. The limit at a delay `T` is the
//! smallest `a₂(ω)` over all lobes and all `ω` with `T_k(ω) = T` (roots found by scanning
//! `ω ∈ (ω_n, 6ω_n)` and bisection to machine precision). At a lobe minimum
//! `a₂ = 2ζ(1+ζ)ω_n²` (`ω² = ω_n²(1 + 2ζ)`, with `a₁ = 2ζω_n`).
//!
//! This is the exact, time-invariant answer; [`crate::TurningProcess`] (time stepping of the
//! nonlinear process at small amplitude) is checked against it in the tests.

use num_complex::Complex64;
use std::f64::consts::PI;

/// The stability limit at one delay.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilityLimit {
    /// Limiting a₂ [1/s²].
    pub a2: f64,
    /// Chatter frequency ω_c [rad/s].
    pub omega: f64,
    /// Lobe number k.
    pub lobe: u32,
}

/// Δ(λ) of the linearised equation.
pub fn characteristic(lambda: Complex64, omega_n: f64, a1: f64, a2: f64, delay: f64) -> Complex64 {
    lambda * lambda + a1 * lambda + omega_n * omega_n + a2 * (1.0 - (-lambda * delay).exp())
}

/// (a₂(ω), T_k(ω)) on the boundary, for ω > ω_n.
fn lobe_point(omega: f64, k: u32, omega_n: f64, a1: f64) -> (f64, f64) {
    let d = Complex64::new(omega_n * omega_n - omega * omega, a1 * omega);
    let a2 = -d.norm_sqr() / (2.0 * d.re);
    let e = 1.0 + d / a2;
    let phase = (-e.arg()).rem_euclid(2.0 * PI);
    (a2, (2.0 * PI * k as f64 + phase) / omega)
}

/// The smallest a₂ at which `ẍ + a₁ẋ + (ω_n² + a₂)x = a₂x(t−T)` has a root on the imaginary
/// axis (`None` if no lobe reaches `T`, which cannot happen for `a₁ > 0`).
pub fn stability_limit(omega_n: f64, a1: f64, delay: f64) -> Option<StabilityLimit> {
    const GRID: usize = 4000;
    let (lo, hi) = (omega_n * (1.0 + 1e-9), 6.0 * omega_n);
    let k_max = (delay * hi / (2.0 * PI)).ceil() as u32 + 1;
    let mut best: Option<StabilityLimit> = None;
    for k in 0..=k_max {
        let f = |w: f64| lobe_point(w, k, omega_n, a1).1 - delay;
        let mut w0 = lo;
        let mut f0 = f(w0);
        for j in 1..=GRID {
            let w1 = lo * (hi / lo).powf(j as f64 / GRID as f64);
            let f1 = f(w1);
            // the phase wraps at 2π: only a genuine sign change of a continuous branch counts
            if f0.signum() != f1.signum() && (f1 - f0).abs() < 2.0 * PI / w1 {
                let (mut a, mut b, mut fa) = (w0, w1, f0);
                for _ in 0..200 {
                    let m = 0.5 * (a + b);
                    let fm = f(m);
                    if fm.signum() == fa.signum() {
                        a = m;
                        fa = fm;
                    } else {
                        b = m;
                    }
                    if b - a <= 4.0 * f64::EPSILON * b {
                        break;
                    }
                }
                let w = 0.5 * (a + b);
                let a2 = lobe_point(w, k, omega_n, a1).0;
                if best.is_none_or(|s| a2 < s.a2) {
                    best = Some(StabilityLimit { a2, omega: w, lobe: k });
                }
            }
            (w0, f0) = (w1, f1);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TurningParams;

    #[test]
    fn the_limit_root_solves_the_characteristic_equation() {
        let p = TurningParams::default();
        let (wn, a1) = (p.omega_n(), p.a1(0.1, 450.0));
        for rpm in [300.0, 450.0, 524.0, 1000.0] {
            let t = 60.0 / rpm;
            let s = stability_limit(wn, a1, t).unwrap();
            let r = characteristic(Complex64::new(0.0, s.omega), wn, a1, s.a2, t);
            assert!(r.norm() / (wn * wn) < 1e-12, "{rpm} rpm: |Δ| = {}", r.norm());
        }
    }

    #[test]
    fn at_450_rpm_is_a_lobe_minimum_and_the_limit_depth_is_4_mm() {
        let p = TurningParams::default();
        let z = p.damping_ratio;
        let s = stability_limit(p.omega_n(), p.a1(0.1, 450.0), 60.0 / 450.0).unwrap();
        let ratio = s.a2 / p.omega_n().powi(2);
        assert!((ratio - 2.0 * z * (1.0 + z)).abs() < 2e-5, "{ratio}");
        let w_lim = s.a2 / p.a2(0.1, 1.0);
        assert!((w_lim - 4.0).abs() < 0.01, "{w_lim}");
        println!("450 rpm: a2/wn2 = {ratio:.6}, f_c = {:.2} Hz, w_lim = {w_lim:.4} mm", s.omega / (2.0 * PI));
        // 5 mm is stable at the reference speed 524 rpm
        let s524 = stability_limit(p.omega_n(), p.a1(0.1, 524.0), 60.0 / 524.0).unwrap();
        assert!(s524.a2 / p.a2(0.1, 1.0) > 5.0, "{}", s524.a2 / p.a2(0.1, 1.0));
    }
}
