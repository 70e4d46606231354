//! Residues by least squares in the frequency domain (LSFD), with residual terms.
//!
//! With the poles λ_r fixed, every FRF is linear in its residues:
//!
//! ```text
//! H_o(ω) = Σ_r [ A_or/(iω − λ_r) + conj(A_or)/(iω − conj λ_r) ] − LR_o/ω² + UR_o,
//! ```
//!
//! where the lower residual `LR` stands for the modes below the band (mass-like) and the upper
//! residual `UR` for those above it (stiffness-like). Real and imaginary parts are stacked into
//! one real least-squares problem per FRF, solved by an SVD.

use crate::{FitError, Frfs, Pole};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// The fitted residues of every FRF.
#[derive(Clone, Debug, PartialEq)]
pub struct Residues {
    /// The poles.
    pub poles: Vec<Pole>,
    /// `residues[o][r]`: residue of FRF `o` at pole `r`.
    pub residues: Vec<Vec<Complex64>>,
    /// Lower residual of each FRF.
    pub lower: Vec<f64>,
    /// Upper residual of each FRF.
    pub upper: Vec<f64>,
    /// The band fitted \[Hz\].
    pub band: (f64, f64),
}

/// The basis functions at ω: per pole the two real unknowns' columns, then LR, then UR.
fn columns(poles: &[Pole], omega: f64) -> Vec<Complex64> {
    let s = Complex64::new(0.0, omega);
    let mut c = Vec::with_capacity(2 * poles.len() + 2);
    for p in poles {
        let (a, b) = (1.0 / (s - p.0), 1.0 / (s - p.0.conj()));
        c.push(a + b);
        c.push(Complex64::i() * (a - b));
    }
    c.push(Complex64::from(-1.0 / (omega * omega).max(f64::MIN_POSITIVE)));
    c.push(Complex64::from(1.0));
    c
}

/// Fit the residues of `poles` on `band` \[Hz\].
pub fn residues(frf: &Frfs, band: (f64, f64), poles: &[Pole]) -> Result<Residues, FitError> {
    frf.check()?;
    let idx = frf.band(band);
    let m = 2 * poles.len() + 2;
    if poles.is_empty() || idx.len() * 2 < m + 1 {
        return Err(FitError::Data(format!("{} poles, {} frequencies: nothing to fit", poles.len(), idx.len())));
    }
    let w: Vec<f64> = frf.freq_hz[idx.clone()].iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
    let rows: Vec<Vec<Complex64>> = w.iter().map(|&om| columns(poles, om)).collect();
    let n = rows.len();
    let a = DMatrix::from_fn(2 * n, m, |i, j| if i < n { rows[i][j].re } else { rows[i - n][j].im });
    // column scaling for conditioning (the residual columns differ by orders of magnitude)
    let scale: Vec<f64> = (0..m).map(|j| a.column(j).norm().max(f64::MIN_POSITIVE)).collect();
    let a = DMatrix::from_fn(2 * n, m, |i, j| a[(i, j)] / scale[j]);
    let svd = a.svd(true, true);
    let (mut residues, mut lower, mut upper) = (Vec::new(), Vec::new(), Vec::new());
    for h in &frf.outputs {
        let h = &h[idx.clone()];
        let b = DVector::from_fn(2 * n, |i, _| if i < n { h[i].re } else { h[i - n].im });
        let x = svd.solve(&b, 1e-12).map_err(|_| FitError::Singular("LSFD"))?;
        let x: Vec<f64> = (0..m).map(|j| x[j] / scale[j]).collect();
        residues.push((0..poles.len()).map(|r| Complex64::new(x[2 * r], x[2 * r + 1])).collect());
        lower.push(x[m - 2]);
        upper.push(x[m - 1]);
    }
    Ok(Residues { poles: poles.to_vec(), residues, lower, upper, band })
}

impl Residues {
    /// The synthesised FRF `o` at `omega` \[rad/s\] (modes and residuals).
    pub fn synthesise(&self, o: usize, omega: f64) -> Complex64 {
        let c = columns(&self.poles, omega);
        let mut h = Complex64::new(0.0, 0.0);
        for (r, a) in self.residues[o].iter().enumerate() {
            h += c[2 * r] * a.re + c[2 * r + 1] * a.im;
        }
        h + c[c.len() - 2] * self.lower[o] + self.upper[o]
    }

    /// The modes alone (no residual terms) of FRF `o` at `omega`: the model a structure FMU holds.
    pub fn modal(&self, o: usize, omega: f64) -> Complex64 {
        let c = columns(&self.poles, omega);
        self.residues[o].iter().enumerate().map(|(r, a)| c[2 * r] * a.re + c[2 * r + 1] * a.im).sum()
    }

    /// Relative RMS error `√(Σ|H − Ĥ|² / Σ|H|²)` over the band and every FRF.
    pub fn fit_error(&self, frf: &Frfs) -> f64 {
        let idx = frf.band(self.band);
        let (mut e, mut s) = (0.0, 0.0);
        for (o, h) in frf.outputs.iter().enumerate() {
            for k in idx.clone() {
                let om = 2.0 * std::f64::consts::PI * frf.freq_hz[k];
                e += (h[k] - self.synthesise(o, om)).norm_sqr();
                s += h[k].norm_sqr();
            }
        }
        (e / s).sqrt()
    }
}
