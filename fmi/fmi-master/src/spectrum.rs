//! Single-sided amplitude spectrum |P1(f)| (the convention of the seed's
//! Figure 7 and of MATLAB's `fft` examples): `P2 = |FFT(x)|/L`,
//! `P1 = P2[0..=L/2]`, interior bins doubled. A sinusoid of amplitude A at a
//! bin frequency shows as a peak of height A.

use num_complex::Complex;

/// A spectrum: bin frequencies [Hz] and amplitudes (units of the signal).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Spectrum {
    /// Frequencies, `k·fs/L`.
    pub freq: Vec<f64>,
    /// Amplitudes.
    pub amp: Vec<f64>,
}

impl Spectrum {
    /// Keep the bins with `f ≤ f_max`.
    pub fn up_to(mut self, f_max: f64) -> Spectrum {
        let n = self.freq.iter().take_while(|&&f| f <= f_max).count();
        self.freq.truncate(n);
        self.amp.truncate(n);
        self
    }

    /// The largest amplitude within `[lo, hi]` and its frequency.
    pub fn peak_in(&self, lo: f64, hi: f64) -> Option<(f64, f64)> {
        self.freq
            .iter()
            .zip(&self.amp)
            .filter(|(f, _)| **f >= lo && **f <= hi)
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map(|(f, a)| (*f, *a))
    }
}

/// Single-sided amplitude spectrum of `x` sampled at `fs` Hz.
pub fn single_sided(x: &[f64], fs: f64) -> Spectrum {
    let l = x.len();
    if l == 0 {
        return Spectrum { freq: Vec::new(), amp: Vec::new() };
    }
    let mut buf: Vec<Complex<f64>> = x.iter().map(|&v| Complex::new(v, 0.0)).collect();
    let mut planner = rustfft::FftPlanner::new();
    planner.plan_fft_forward(l).process(&mut buf);
    let half = l / 2;
    let mut amp: Vec<f64> = buf[..=half].iter().map(|c| c.norm() / l as f64).collect();
    let last = if l.is_multiple_of(2) { half } else { half + 1 };
    for a in amp.iter_mut().take(last).skip(1) {
        *a *= 2.0;
    }
    let freq = (0..=half).map(|k| k as f64 * fs / l as f64).collect();
    Spectrum { freq, amp }
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // exact values are intended in these tests
mod tests {
    use super::*;

    #[test]
    fn a_sine_shows_its_amplitude_at_its_frequency() {
        let fs = 1000.0;
        let n = 2000;
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                0.5 + 3.0 * (2.0 * std::f64::consts::PI * 50.0 * t).sin()
                    + 1.5 * (2.0 * std::f64::consts::PI * 133.5 * t).cos()
            })
            .collect();
        let s = single_sided(&x, fs);
        assert_eq!(s.freq.len(), n / 2 + 1);
        approx::assert_abs_diff_eq!(s.amp[0], 0.5, epsilon = 1e-12);
        let (f, a) = s.peak_in(40.0, 60.0).unwrap();
        assert_eq!(f, 50.0);
        approx::assert_abs_diff_eq!(a, 3.0, epsilon = 1e-9);
        let (f, a) = s.peak_in(120.0, 140.0).unwrap();
        assert_eq!(f, 133.5);
        approx::assert_abs_diff_eq!(a, 1.5, epsilon = 1e-9);
        let s = s.up_to(400.0);
        assert_eq!(*s.freq.last().unwrap(), 400.0);
    }
}
