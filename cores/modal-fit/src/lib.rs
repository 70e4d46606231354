//! # modal-fit: modes from measured frequency responses
//!
//! An impact-hammer tap test gives the tool-point FRFs `H_pq(ω)` (response p ∈ {x, y} to a
//! force along q) on a frequency grid. This crate identifies the modes behind them:
//!
//! 1. [`lscf`]: the poles, by the least-squares complex-frequency method (LSCF; Guillaume et
//!    al., IMAC 2003): a rational model `H_o = N_o(z)/D(z)` with one common denominator for
//!    every FRF, `z = e^{iωΔt}`, linearised least squares reduced to the denominator's normal
//!    equations; the poles are the roots of `D`.
//! 2. [`stabilisation`]: the poles of increasing model orders (the stabilisation diagram) and
//!    the physical modes picked from those that stay (frequency within 1 %, damping within 5 %)
//!    over several orders.
//! 3. [`lsfd`]: the residues of the chosen poles by linear least squares on every FRF, with a
//!    lower residual (the modes below the band, `−LR/ω²`) and an upper residual (the modes above
//!    it, a constant).
//!    The picked poles are then refined ([`refine`]): the same error, now minimised over the
//!    poles too (variable projection), which removes the linearised LSCF's damping bias.
//! 4. [`modes`]: residues to modal parameters: natural frequency, damping ratio, mass-normalised
//!    shape at the tool point (x, y), the modal stiffness along the shape, and a fit-quality
//!    number (the relative RMS error of the synthesised FRFs).
//!
//! No I/O and no FMI: the files (CSV, UFF 58) are read by the studies, the modes go into a
//! machine file and into `ModalStructure.fmu`.

pub mod lscf;
pub mod lsfd;
pub mod modes;
pub mod refine;
pub mod stabilisation;

use num_complex::Complex64;

/// The whole identification: the stabilisation diagram over `orders`, the picked poles, their
/// residues with residual terms, the modes of the FRFs `pairs`, and the fit's relative RMS error.
pub fn identify(
    frf: &Frfs,
    band: (f64, f64),
    orders: impl IntoIterator<Item = usize>,
    pairs: &[modes::Pair],
) -> Result<Identified, FitError> {
    if pairs.len() != frf.outputs.len() {
        return Err(FitError::Data(format!("{} FRFs but {} direction pairs", frf.outputs.len(), pairs.len())));
    }
    let diagram = stabilisation::diagram(frf, band, orders)?;
    let poles = stabilisation::pick(&diagram);
    if poles.is_empty() {
        return Err(FitError::Data("no pole is stable over the orders: widen the band or raise the orders".into()));
    }
    let poles = refine::refine(frf, band, &poles, 50)?;
    let residues = lsfd::residues(frf, band, &poles)?;
    let modes = modes::modes(&residues, pairs);
    let error = residues.fit_error(frf);
    Ok(Identified { diagram, residues, modes, error })
}

/// The outcome of [`identify`].
#[derive(Clone, Debug, PartialEq)]
pub struct Identified {
    /// The stabilisation diagram.
    pub diagram: stabilisation::Diagram,
    /// Residues and residual terms of the picked poles.
    pub residues: lsfd::Residues,
    /// The modes.
    pub modes: Vec<modes::Mode>,
    /// Relative RMS error of the synthesised FRFs over the band.
    pub error: f64,
}

/// Why a fit failed.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum FitError {
    /// The data cannot be fitted (too few points, a bad band, no modes).
    #[error("{0}")]
    Data(String),
    /// A linear system was singular.
    #[error("singular least-squares system ({0})")]
    Singular(&'static str),
}

/// FRFs on one frequency grid: `outputs[o][k]` is FRF `o` at `freq_hz[k]` (m/N).
#[derive(Clone, Debug, PartialEq)]
pub struct Frfs {
    /// Frequencies \[Hz\], increasing.
    pub freq_hz: Vec<f64>,
    /// The FRFs.
    pub outputs: Vec<Vec<Complex64>>,
}

impl Frfs {
    /// Check the shape: increasing positive frequencies, every FRF as long, every value finite.
    pub fn check(&self) -> Result<(), FitError> {
        let bad = |m: String| Err(FitError::Data(m));
        if self.freq_hz.len() < 8 {
            return bad(format!("{} frequencies: too few to fit", self.freq_hz.len()));
        }
        if !self.freq_hz.windows(2).all(|w| w[1] > w[0]) || self.freq_hz[0].is_nan() || self.freq_hz[0] < 0.0 {
            return bad("the frequencies must be non-negative and increasing".into());
        }
        if self.outputs.is_empty() {
            return bad("no FRF".into());
        }
        for (o, h) in self.outputs.iter().enumerate() {
            if h.len() != self.freq_hz.len() {
                return bad(format!("FRF {o}: {} values for {} frequencies", h.len(), self.freq_hz.len()));
            }
            if !h.iter().all(|v| v.re.is_finite() && v.im.is_finite()) {
                return bad(format!("FRF {o}: a value is not finite"));
            }
        }
        Ok(())
    }

    /// The indices of the frequencies in `[lo, hi]` Hz.
    pub fn band(&self, (lo, hi): (f64, f64)) -> std::ops::Range<usize> {
        let a = self.freq_hz.partition_point(|f| *f < lo);
        let b = self.freq_hz.partition_point(|f| *f <= hi);
        a..b.max(a)
    }
}

/// A pole `λ = −ζω_n + iω_n√(1 − ζ²)` (upper half plane).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pole(pub Complex64);

impl Pole {
    /// Undamped natural frequency \[Hz\].
    pub fn frequency_hz(&self) -> f64 {
        self.0.norm() / (2.0 * std::f64::consts::PI)
    }

    /// Damping ratio.
    pub fn damping(&self) -> f64 {
        -self.0.re / self.0.norm()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    /// The identification criteria of a tap test: synthetic FRFs (xx, xy, yx, yy) of two and of
    /// three modes (one cross-coupled), 5 % complex noise, 1 Hz over 0–5 kHz: every mode's
    /// frequency within 0.5 %, damping within 10 %, modal stiffness within 5 %.
    #[test]
    fn noisy_tap_tests_give_the_modes() {
        let s = |k: f64, f: f64| (2.0 * std::f64::consts::PI * f) / k.sqrt();
        let three: Vec<SynthMode> = vec![
            (600.0, 0.03, [s(2e7, 600.0), 0.0]),
            (650.0, 0.035, [0.0, s(2.5e7, 650.0)]),
            (1100.0, 0.02, [s(5e7, 1100.0) * 0.8, s(5e7, 1100.0) * 0.6]),
        ];
        for (name, truth, band) in
            [("two modes", two_modes(), (200.0, 1500.0)), ("three modes", three, (200.0, 2000.0))]
        {
            for seed in [1, 2, 3] {
                let (_, frf) = synthetic(&truth, 0.05, seed);
                let id = identify(&frf, band, (8..=40).step_by(2), &[(0, 0), (0, 1), (1, 0), (1, 1)]).unwrap();
                assert_eq!(id.modes.len(), truth.len(), "{name} seed {seed}: {:?}", id.modes);
                for (m, (f, z, shape)) in id.modes.iter().zip(&truth) {
                    let k_true = (2.0 * std::f64::consts::PI * f).powi(2) / (shape[0].powi(2) + shape[1].powi(2));
                    let (ef, ez, ek) = (m.frequency_hz / f - 1.0, m.damping / z - 1.0, m.stiffness() / k_true - 1.0);
                    assert!(
                        ef.abs() < 0.005 && ez.abs() < 0.10 && ek.abs() < 0.05,
                        "{name} seed {seed}: {m:?} vs {f} Hz {z} {k_true:e}: {ef:.4} {ez:.4} {ek:.4}"
                    );
                    let (dir, true_dir) = (m.direction(), [shape[0], shape[1]]);
                    let cos = (dir[0] * true_dir[0] + dir[1] * true_dir[1]).abs() / true_dir[0].hypot(true_dir[1]);
                    assert!(cos > 0.99, "{name}: direction {dir:?} vs {true_dir:?}");
                }
                assert!(id.error < 0.08, "{name}: fit error {}", id.error);
            }
        }
    }

    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    /// (frequency Hz, damping, mass-normalised shape (x, y)).
    pub type SynthMode = (f64, f64, [f64; 2]);

    /// Two modes: x 600 Hz, y 650 Hz.
    pub fn two_modes() -> Vec<SynthMode> {
        let s = |k: f64, f: f64| (2.0 * std::f64::consts::PI * f) / k.sqrt();
        vec![(600.0, 0.03, [s(2e7, 600.0), 0.0]), (650.0, 0.035, [0.0, s(2.5e7, 650.0)])]
    }

    /// FRFs xx, xy, yx, yy of `modes` at 1 Hz steps over 0–5 kHz, each value times
    /// `1 + noise·(n₁ + i n₂)/√2` with standard normal n (multiplicative complex noise).
    pub fn synthetic(modes: &[SynthMode], noise: f64, seed: u64) -> (Vec<(f64, f64)>, Frfs) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let n = Normal::new(0.0, 1.0).unwrap();
        let freq_hz: Vec<f64> = (1..=5000).map(f64::from).collect();
        let pairs = [(0, 0), (0, 1), (1, 0), (1, 1)];
        let outputs = pairs
            .iter()
            .map(|&(p, q)| {
                freq_hz
                    .iter()
                    .map(|f| {
                        let w = 2.0 * std::f64::consts::PI * f;
                        let h: Complex64 = modes
                            .iter()
                            .map(|(fm, z, s)| {
                                let wn = 2.0 * std::f64::consts::PI * fm;
                                s[p] * s[q] / Complex64::new(wn * wn - w * w, 2.0 * z * wn * w)
                            })
                            .sum();
                        let e = Complex64::new(n.sample(&mut rng), n.sample(&mut rng)) * (noise / 2f64.sqrt());
                        h * (Complex64::new(1.0, 0.0) + e)
                    })
                    .collect()
            })
            .collect();
        (modes.iter().map(|m| (m.0, m.1)).collect(), Frfs { freq_hz, outputs })
    }
}
