//! Oustaloup's recursive approximation of `s^r`, discretised with Tustin + prewarping.
//!
//! Continuous filter (Oustaloup 2000), order `N`, over the filter band `[ω_lo, ω_hi]`:
//!
//! ```text
//! G(s) = ω_hi^r · Π_{k=−N..N} (s + ω'_k) / (s + ω_k)
//! ω'_k = ω_lo · (ω_hi/ω_lo)^((k + N + (1 − r)/2) / (2N + 1))     (zeros)
//! ω_k  = ω_lo · (ω_hi/ω_lo)^((k + N + (1 + r)/2) / (2N + 1))     (poles)
//! ```
//!
//! The classical filter follows `(jω)^r` well in the middle of its band but not near the edges:
//! the phase error decays only like `ω_lo/ω` (e.g. 5.4° at `10·ω_lo` for r = 0.95). The user parameters
//! `[ω_b, ω_h]` are therefore the band where the approximation is *guaranteed* (0.5 dB / 2°,
//! tested) and the filter band is widened by [`BAND_EXTENSION`]: `ω_lo = ω_b / κ`,
//! `ω_hi = ω_h · κ`.
//!
//! Each first-order section is discretised with the bilinear (Tustin) transform with
//! prewarping at `ω_p = √(ω_b ω_h)`:
//!
//! ```text
//! s = c (1 − z⁻¹)/(1 + z⁻¹),   c = ω_p / tan(ω_p T / 2)
//! (s + a)/(s + b)  →  (b0 + b1 z⁻¹)/(1 + a1 z⁻¹),
//! b0 = (c + a)/(c + b),  b1 = (a − c)/(c + b),  a1 = (b − c)/(c + b)
//! ```
//!
//! Tustin maps the left half-plane into the unit disc (every section is stable for every
//! `T`) and maps the frequency axis exactly, up to the warp `ω ↦ (2/T)·tan(ωT/2)` (corrected
//! at ω_p): at 200 Hz and T = 10 µs the warp changes the frequency by 1.3·10⁻⁵ relative, so in
//! `[ω_b, ω_h]` (with `ω_h ≤ 0.1·π/T`) the discrete filter is as accurate as the continuous one.
//! Sections run in transposed direct form II (one state each).

use num_complex::Complex64;
use serde::{Deserialize, Serialize};

/// Factor by which the filter band exceeds the guaranteed band `[ω_b, ω_h]` on each side.
pub const BAND_EXTENSION: f64 = 50.0;

/// One Tustin-discretised first-order section `(b0 + b1 z⁻¹)/(1 + a1 z⁻¹)`.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
struct Section {
    b0: f64,
    b1: f64,
    a1: f64,
    s: f64,
}

/// Continuous Oustaloup filter: `(gain, zeros ω'_k, poles ω_k)` (all positive, the roots are at `−ω`).
pub fn design(r: f64, omega_lo: f64, omega_hi: f64, order: usize) -> (f64, Vec<f64>, Vec<f64>) {
    let n = order as f64;
    let m = 2.0 * n + 1.0;
    let ratio = omega_hi / omega_lo;
    let mut zeros = Vec::new();
    let mut poles = Vec::new();
    for k in 0..(2 * order + 1) {
        let kk = k as f64; // k + N in the formula
        zeros.push(omega_lo * libm::pow(ratio, (kk + (1.0 - r) / 2.0) / m));
        poles.push(omega_lo * libm::pow(ratio, (kk + (1.0 + r) / 2.0) / m));
    }
    (libm::pow(omega_hi, r), zeros, poles)
}

/// Discrete Oustaloup approximation of `s^r`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Oustaloup {
    r: f64,
    gain: f64,
    sections: Vec<Section>,
}

impl Oustaloup {
    /// A restored filter: the sections `fresh` has, with finite states.
    pub(crate) fn check(&self, fresh: &Self) -> Result<(), String> {
        let coef = |o: &Oustaloup| {
            let mut v = vec![o.r, o.gain];
            v.extend(o.sections.iter().flat_map(|s| [s.b0, s.b1, s.a1]));
            v
        };
        crate::restored::same("Oustaloup sections", &coef(self), &coef(fresh))?;
        crate::restored::finite("Oustaloup state", &self.sections.iter().map(|s| s.s).collect::<Vec<_>>())
    }

    /// Approximation of `s^r` guaranteed over `[omega_b, omega_h]` (rad/s), order `order`
    /// (`2N + 1` sections), discretised at sample period `ts`.
    pub fn new(r: f64, omega_b: f64, omega_h: f64, order: usize, ts: f64) -> Self {
        let (gain, zeros, poles) = design(r, omega_b / BAND_EXTENSION, omega_h * BAND_EXTENSION, order);
        let wp = (omega_b * omega_h).sqrt();
        let c = wp / (wp * ts / 2.0).tan();
        let sections = zeros
            .iter()
            .zip(&poles)
            .map(|(&a, &b)| Section { b0: (c + a) / (c + b), b1: (a - c) / (c + b), a1: (b - c) / (c + b), s: 0.0 })
            .collect();
        Oustaloup { r, gain, sections }
    }

    /// The approximated order r.
    pub fn order_r(&self) -> f64 {
        self.r
    }

    /// One sample.
    #[inline]
    pub fn step(&mut self, x: f64) -> f64 {
        let mut v = x * self.gain;
        for s in &mut self.sections {
            let y = s.b0 * v + s.s;
            s.s = s.b1 * v - s.a1 * y;
            v = y;
        }
        v
    }

    /// Discrete transfer function at `z` (same coefficients as [`step`](Self::step)).
    pub fn response(&self, z: Complex64) -> Complex64 {
        let zinv = z.inv();
        self.sections
            .iter()
            .fold(Complex64::new(self.gain, 0.0), |acc, s| acc * (s.b0 + s.b1 * zinv) / (1.0 + s.a1 * zinv))
    }

    /// Continuous-time response of the undiscretised filter at `s = jω` (for tests and docs).
    pub fn continuous_response(r: f64, omega_b: f64, omega_h: f64, order: usize, omega: f64) -> Complex64 {
        let (gain, zeros, poles) = design(r, omega_b / BAND_EXTENSION, omega_h * BAND_EXTENSION, order);
        let s = Complex64::new(0.0, omega);
        zeros.iter().zip(&poles).fold(Complex64::new(gain, 0.0), |acc, (&a, &b)| acc * (s + a) / (s + b))
    }

    /// Clear the section states.
    pub fn reset(&mut self) {
        self.sections.iter_mut().for_each(|s| s.s = 0.0);
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    /// Worst (dB, degree) deviation of `h(ω)` from `(jω)^r` over a log grid of `[wb, wh]`.
    pub(crate) fn worst(r: f64, wb: f64, wh: f64, h: impl Fn(f64) -> Complex64) -> (f64, f64) {
        let mut worst = (0.0f64, 0.0f64);
        for i in 0..=400 {
            let w = wb * (wh / wb).powf(i as f64 / 400.0);
            let g = h(w) / Complex64::new(0.0, w).powf(r);
            worst.0 = worst.0.max((20.0 * g.norm().log10()).abs());
            worst.1 = worst.1.max(g.arg().to_degrees().abs());
        }
        worst
    }

    /// The discretised filter (N = 5, T = 10 µs; default band 100..2e4 rad/s and 10..1e4 rad/s)
    /// stays within 0.5 dB and 2° of (jω)^r over the whole guaranteed band, for orders across
    /// [0, 1) (the range [`crate::fractional`] uses, including the paper's 0.15). Measured
    /// worst case: 0.02 dB, 1.1° (r = 0.95).
    #[test]
    fn discrete_filter_follows_power_law_in_band() {
        for (wb, wh, n, ts) in [(100.0, 2e4, 5, 1e-5), (10.0, 1e4, 5, 1e-5)] {
            for &r in &[0.05, 0.15, 0.3, 0.5, 0.7, 0.85, 0.95] {
                let f = Oustaloup::new(r, wb, wh, n, ts);
                let (db, deg) = worst(r, wb, wh, |w| f.response(Complex64::from_polar(1.0, w * ts)));
                assert!(db < 0.5 && deg < 2.0, "r = {r}: {db:.3} dB, {deg:.3} deg");
                let (cdb, cdeg) = worst(r, wb, wh, |w| Oustaloup::continuous_response(r, wb, wh, n, w));
                assert!(cdb < 0.5 && cdeg < 2.0, "continuous r = {r}: {cdb:.3} dB, {cdeg:.3} deg");
            }
        }
    }

    /// Without the band extension the classical filter misses the 2° bound at the edges:
    /// the test above can fail.
    #[test]
    fn classical_band_edges_are_inaccurate() {
        let (wb, wh, n) = (10.0, 1e4, 5);
        let r: f64 = 0.15;
        let (gain, z, p) = design(r, wb, wh, n);
        let h = |w: f64| {
            let s = Complex64::new(0.0, w);
            z.iter().zip(&p).fold(Complex64::new(gain, 0.0), |acc, (&a, &b)| acc * (s + a) / (s + b))
        };
        let (_, deg) = worst(r, wb, wh, h);
        assert!(deg > 2.0, "edge phase error only {deg}");
    }

    #[test]
    fn stepping_matches_response() {
        let ts = 1e-5;
        let mut f = Oustaloup::new(0.15, 10.0, 1e4, 5, ts);
        let w = 2.0 * std::f64::consts::PI * 143.0;
        // impulse response, then its DTFT at w vs response()
        let mut acc = Complex64::new(0.0, 0.0);
        for k in 0..3_000_000 {
            let y = f.step(if k == 0 { 1.0 } else { 0.0 });
            acc += y * Complex64::from_polar(1.0, -w * ts * k as f64);
        }
        let want = f.response(Complex64::from_polar(1.0, w * ts));
        assert!((acc - want).norm() / want.norm() < 1e-3, "{acc} vs {want}");
    }
}
