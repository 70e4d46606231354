//! A synthetic tap test: the FRFs of a machine file's modes on a measurement grid with complex
//! noise, for trying the FRF route (fit, lobes from data) on a machine whose modes are known.
//!
//! Noise model: each value is `H(f)(1 + ε n)` with `n` a standard complex Gaussian
//! (`E|n|² = 1`, independent real and imaginary parts) and `ε` the relative level (0.05 = 5 %),
//! plus a floor `ε · 10⁻³ · max|H|` of the same kind (a measurement never reads exactly zero).
//! Cross FRFs are written only when a mode has a shape along both x and y; otherwise the
//! machine is uncoupled and, as in a tap test on such a tool, only `xx` and `yy` are measured.

use crate::Machine;
use crate::frf::{MeasuredFrf, Pair};
use num_complex::Complex64;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use std::collections::BTreeMap;
use std::f64::consts::{FRAC_1_SQRT_2, PI};

/// The measurement: grid and noise.
#[derive(Clone, Debug, PartialEq)]
pub struct TapTest {
    /// Lowest and highest frequency \[Hz\].
    pub range_hz: (f64, f64),
    /// Frequency resolution \[Hz\].
    pub resolution_hz: f64,
    /// Relative complex noise (0.05 = 5 %).
    pub noise: f64,
    /// Seed of the noise.
    pub seed: u64,
}

impl Default for TapTest {
    /// 0–5 kHz at 1 Hz with 5 % noise: the acceptance measurement.
    fn default() -> Self {
        TapTest { range_hz: (0.0, 5000.0), resolution_hz: 1.0, noise: 0.05, seed: 1 }
    }
}

/// The machine's tool-point FRFs as measured by `t`.
pub fn tap_test(m: &Machine, t: &TapTest) -> Result<MeasuredFrf, String> {
    let (lo, hi) = t.range_hz;
    if !(lo >= 0.0 && hi > lo && t.resolution_hz > 0.0 && t.noise >= 0.0 && t.noise.is_finite()) {
        return Err(format!("tap test: need 0 <= low < high, resolution > 0, noise >= 0 (got {t:?})"));
    }
    if m.modes.is_empty() {
        return Err("tap test: the machine file has no modes to measure".into());
    }
    let n = ((hi - lo) / t.resolution_hz + 1e-9).floor() as usize + 1;
    if n > 10_000_000 {
        return Err(format!("tap test: {n} frequencies; at most 1e7"));
    }
    let freq_hz: Vec<f64> = (0..n).map(|k| lo + k as f64 * t.resolution_hz).collect();
    let coupled = m.modes.iter().any(|md| md.shape[0] != 0.0 && md.shape[1] != 0.0);
    let pairs: Vec<Pair> = if coupled { Pair::ALL.to_vec() } else { vec![Pair(0, 0), Pair(1, 1)] };
    let exact: Vec<_> = freq_hz.iter().map(|f| m.receptance(2.0 * PI * f)).collect();
    let peak = exact.iter().flat_map(|g| g.iter().map(|v| v.norm())).fold(0.0, f64::max);
    let mut rng = ChaCha8Rng::seed_from_u64(t.seed);
    let mut gauss = || {
        let (a, b): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
        Complex64::new(a, b) * FRAC_1_SQRT_2
    };
    let mut h = BTreeMap::new();
    for p in pairs {
        let v: Vec<Complex64> = exact
            .iter()
            .map(|g| {
                let x = g[(p.0, p.1)];
                x + t.noise * (x * gauss() + 1e-3 * peak * gauss())
            })
            .collect();
        h.insert(p, v);
    }
    let frf = MeasuredFrf {
        source: format!("synthetic tap test of {}", m.name),
        freq_hz,
        h,
        notes: vec![format!(
            "synthetic: {} modes, {:.0}–{:.0} Hz at {} Hz, {} % complex noise (seed {})",
            m.modes.len(),
            lo,
            hi,
            t.resolution_hz,
            t.noise * 100.0,
            t.seed
        )],
    };
    frf.complete().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn end_mill() -> Machine {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/end_mill.toml");
        Machine::from_file(&dir).unwrap()
    }

    /// Without noise the values are the machine's receptance; with it the relative error has
    /// the stated RMS (5 % ± 0.5 % over 5001 points) and the seed repeats it bit for bit.
    #[test]
    fn noise_has_the_stated_level_and_repeats() {
        let m = end_mill();
        let clean = tap_test(&m, &TapTest { noise: 0.0, ..Default::default() }).unwrap();
        assert_eq!(clean.h.len(), 2, "uncoupled: xx and yy measured");
        assert!(clean.notes.iter().any(|n| n.contains("uncoupled")), "{:?}", clean.notes);
        let g = m.receptance(2.0 * PI * 600.0);
        assert_eq!(clean.h[&Pair(0, 0)][600], g[(0, 0)]);
        let noisy = tap_test(&m, &TapTest::default()).unwrap();
        let rel: Vec<f64> = (0..noisy.freq_hz.len())
            .map(|k| ((noisy.h[&Pair(0, 0)][k] - clean.h[&Pair(0, 0)][k]) / clean.h[&Pair(0, 0)][k]).norm_sqr())
            .collect();
        let rms = (rel.iter().sum::<f64>() / rel.len() as f64).sqrt();
        assert!((rms - 0.05).abs() < 0.005, "rms {rms}");
        assert_eq!(noisy, tap_test(&m, &TapTest::default()).unwrap());
        assert_ne!(noisy, tap_test(&m, &TapTest { seed: 2, ..Default::default() }).unwrap());
    }

    #[test]
    fn bad_measurements_are_refused() {
        let m = end_mill();
        for t in [
            TapTest { range_hz: (100.0, 10.0), ..Default::default() },
            TapTest { resolution_hz: 0.0, ..Default::default() },
            TapTest { noise: f64::NAN, ..Default::default() },
        ] {
            assert!(tap_test(&m, &t).is_err(), "{t:?}");
        }
    }
}
