//! Band-limited Gaussian force noise on a fixed time grid.
//!
//! White `N(0, 1)` samples from a ChaCha8 stream seeded by the `seed` parameter, one per
//! internal step `T`, go through a 4th-order Butterworth low-pass (two bilinear-transform
//! biquads, prewarped at the cut-off) and are scaled so that the stationary output has the
//! requested RMS. The realization is therefore a function of (seed, T, cut-off) only; the
//! plant holds each sample over its grid cell, whatever the master's communication step.
//! A 4th-order Butterworth is −3 dB at the cut-off and −24 dB one octave above.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Direct-form-II-transposed biquad.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
    s: [f64; 2],
}

impl Biquad {
    /// Low-pass section with quality factor `q` at cut-off `fc` for sampling rate `fs` (bilinear, prewarped).
    fn lowpass(fc: f64, fs: f64, q: f64) -> Biquad {
        let w0 = 2.0 * PI * fc / fs;
        let alpha = w0.sin() / (2.0 * q);
        let c = w0.cos();
        let a0 = 1.0 + alpha;
        let b1 = (1.0 - c) / a0;
        Biquad { b: [b1 / 2.0, b1, b1 / 2.0], a: [-2.0 * c / a0, (1.0 - alpha) / a0], s: [0.0; 2] }
    }
    fn run(&mut self, x: f64) -> f64 {
        let y = self.b[0] * x + self.s[0];
        self.s[0] = self.b[1] * x - self.a[0] * y + self.s[1];
        self.s[1] = self.b[2] * x - self.a[1] * y;
        y
    }
}

/// The longest impulse response summed sample by sample for the filter's energy: 10⁷ samples,
/// a few tens of ms. Beyond it (a cut-off far below the sampling rate: at the declared minimum of
/// 1 mHz at 100 kHz the sum took 2·10¹⁰ samples, 118 s in fmi2ExitInitializationMode) the energy
/// comes from the closed form [`asymptotic_energy`].
pub const MAX_PROBE: usize = 10_000_000;

/// `Σ h[k]²` over the first `n` samples of the cascade's impulse response (the reference).
fn probe_energy(sections: &[Biquad; 2], n: usize) -> f64 {
    let mut probe = sections.clone();
    let mut energy = 0.0;
    let mut x = 1.0;
    for _ in 0..n {
        let y0 = probe[0].run(x);
        let y = probe[1].run(y0);
        energy += y * y;
        x = 0.0;
    }
    energy
}

/// `Σ h[k]²` for a cut-off far below the sampling rate, in closed form: the filter is then the
/// continuous 4th-order Butterworth low-pass, whose equivalent noise bandwidth is
/// `fc · (π/8)/sin(π/8)`, and unit-variance white samples at `fs` have the one-sided density
/// `2/fs`: `Σ h² = 2 (fc/fs) (π/8)/sin(π/8)`. The sum agrees to 1.5e-6 at `fc/fs = 1e-4` (the
/// bilinear transform's warping) and better below; it is used only below `fc/fs ≈ 2e-5`.
fn asymptotic_energy(cutoff: f64, fs: f64) -> f64 {
    2.0 * cutoff / fs * (PI / 8.0) / (PI / 8.0).sin()
}

/// The noise source.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BandLimitedNoise {
    rng: ChaCha8Rng,
    sections: [Biquad; 2],
    gain: f64,
}

impl BandLimitedNoise {
    /// Noise of standard deviation `rms` band-limited to `cutoff` [Hz], sampled every `step` [s].
    pub fn new(seed: u64, rms: f64, cutoff: f64, step: f64) -> BandLimitedNoise {
        let fs = 1.0 / step;
        // Butterworth pole pairs: Q = 1/(2 cos(π/8)), 1/(2 cos(3π/8))
        let sections = [
            Biquad::lowpass(cutoff, fs, 1.0 / (2.0 * (PI / 8.0).cos())),
            Biquad::lowpass(cutoff, fs, 1.0 / (2.0 * (3.0 * PI / 8.0).cos())),
        ];
        // stationary variance of the filter driven by unit white noise = Σ h[n]²
        let n = (200.0 * fs / cutoff).ceil() + 1000.0;
        let energy =
            if n <= MAX_PROBE as f64 { probe_energy(&sections, n as usize) } else { asymptotic_energy(cutoff, fs) };
        BandLimitedNoise { rng: ChaCha8Rng::seed_from_u64(seed), sections, gain: rms / energy.sqrt() }
    }

    /// Is this the filter `fresh` (built from the same parameters) describes, with a finite
    /// state? (Checked when a saved plant state is restored.)
    pub fn matches(&self, fresh: &BandLimitedNoise) -> Result<(), String> {
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        for (a, b) in self.sections.iter().zip(&fresh.sections) {
            if bits(&a.b) != bits(&b.b) || bits(&a.a) != bits(&b.a) {
                return Err("noise filter coefficients do not match the parameters".into());
            }
            if !a.s.iter().all(|x| x.is_finite()) {
                return Err("noise filter state is not finite".into());
            }
        }
        if self.gain.to_bits() != fresh.gain.to_bits() {
            return Err("noise gain does not match the parameters".into());
        }
        Ok(())
    }

    /// The next sample [N].
    pub fn next_sample(&mut self) -> f64 {
        let w: f64 = StandardNormal.sample(&mut self.rng);
        let y0 = self.sections[0].run(w);
        let y = self.sections[1].run(y0);
        self.gain * y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form agrees with the sample-by-sample sum (the reference: an 80-bit sum agrees
    /// with it to 5e-12 at fc = 10 Hz, fs = 100 kHz) where the cut-off is far below the sampling
    /// rate; only the noise's scale depends on it.
    #[test]
    fn the_closed_form_energy_is_the_summed_one() {
        for (fc, fs, tol) in [(10.0, 1e5, 2e-6), (1.0, 1e5, 2e-7)] {
            let sections = [
                Biquad::lowpass(fc, fs, 1.0 / (2.0 * (PI / 8.0).cos())),
                Biquad::lowpass(fc, fs, 1.0 / (2.0 * (3.0 * PI / 8.0).cos())),
            ];
            let summed = probe_energy(&sections, (200.0 * fs / fc) as usize + 1000);
            let closed = asymptotic_energy(fc, fs);
            assert!((closed / summed - 1.0).abs() < tol, "fc {fc}, fs {fs}: {closed} vs {summed}");
        }
        // the declared minimum cut-off at the default step: a finite gain, at once
        let n = BandLimitedNoise::new(1, 1.0, 1e-3, 1e-5);
        assert!(n.gain.is_finite() && n.gain > 0.0);
    }

    #[test]
    fn rms_is_as_requested() {
        let mut n = BandLimitedNoise::new(7, 50.0, 2000.0, 1e-5);
        let m = 1_000_000;
        let s: f64 = (0..m).map(|_| n.next_sample().powi(2)).sum::<f64>() / m as f64;
        assert!((s.sqrt() - 50.0).abs() < 1.0, "rms {}", s.sqrt());
    }

    #[test]
    fn same_seed_same_stream_other_seed_other_stream() {
        let mut a = BandLimitedNoise::new(3, 50.0, 2000.0, 1e-5);
        let mut b = BandLimitedNoise::new(3, 50.0, 2000.0, 1e-5);
        let mut c = BandLimitedNoise::new(4, 50.0, 2000.0, 1e-5);
        let (mut same, mut differ) = (true, false);
        for _ in 0..1000 {
            let (x, y, z) = (a.next_sample(), b.next_sample(), c.next_sample());
            same &= x.to_bits() == y.to_bits();
            differ |= x.to_bits() != z.to_bits();
        }
        assert!(same && differ);
    }
}
