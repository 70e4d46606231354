//! The 2-D zero-order (Altintas–Budak) solver (parent module docs).

use super::branches::{Branches, sample};
use super::{CriticalPoint, GridOptions, LobeError, Lobes, Receptance, complex, eig2, mean_of};
use crate::milling::Cutter;
use nalgebra::Matrix2;
use num_complex::Complex64;
use std::f64::consts::PI;

/// Zero-order lobes of a 2 × 2 receptance under a [`Cutter`]: the exact boundary of the averaged
/// system `det(I − a_p (1 − e^{−iωτ}) H̄ G(iω)) = 0` per speed (parent module docs).
pub struct ZeroOrder2d<R> {
    frf: R,
    teeth: u32,
    hbar: Matrix2<f64>,
    hbar_c: Matrix2<Complex64>,
    branches: Branches,
}

impl<R: Receptance> ZeroOrder2d<R> {
    /// The problem for chatter frequencies in `band_hz = (f_lo, f_hi)` \[Hz\] and speeds from
    /// `rpm_min` up (the grid's default options, [`GridOptions::new`]).
    pub fn new(frf: R, cutter: &Cutter, band_hz: (f64, f64), rpm_min: f64) -> Result<Self, LobeError> {
        if !(rpm_min.is_finite() && rpm_min > 0.0) {
            return Err(LobeError::Invalid(format!("the slowest speed must be > 0 (got {rpm_min} rpm)")));
        }
        Self::with_grid(frf, cutter, &GridOptions::new(band_hz.0, band_hz.1, cutter.teeth, rpm_min))
    }

    /// The same with explicit grid options.
    pub fn with_grid(frf: R, cutter: &Cutter, opt: &GridOptions) -> Result<Self, LobeError> {
        let hbar = mean_of(cutter)?;
        let hbar_c = complex(&hbar);
        let s = sample(&frf, &hbar_c, opt)?;
        let eigs = s.g.iter().map(|g| eig2(&(hbar_c * g)).to_vec()).collect();
        let branches = Branches::track(s.omega, eigs);
        Ok(ZeroOrder2d { frf, teeth: cutter.teeth, hbar, hbar_c, branches })
    }

    /// The mean directional matrix `H̄` \[N/m²\].
    pub fn mean_directional(&self) -> Matrix2<f64> {
        self.hbar
    }

    /// Number of points of the frequency grid.
    pub fn grid_len(&self) -> usize {
        self.branches.omega.len()
    }

    /// The receptance.
    pub fn receptance(&self) -> &R {
        &self.frf
    }
}

impl<R: Receptance> Lobes for ZeroOrder2d<R> {
    /// The critical depth \[m\] at `rpm` and its chatter frequency; `f64::INFINITY` (and NaN)
    /// where no eigenvalue gives a positive depth in the band.
    fn critical_depth(&self, rpm: f64) -> CriticalPoint {
        let none = CriticalPoint { rpm, depth: f64::INFINITY, chatter_hz: f64::NAN };
        if !(rpm.is_finite() && rpm > 0.0) {
            return none;
        }
        let tau = 60.0 / (self.teeth as f64 * rpm);
        let eig_at = |w: f64| eig2(&(self.hbar_c * self.frf.receptance(w))).to_vec();
        match self.branches.critical(tau, eig_at, |_, _| true) {
            Some((w, depth)) => CriticalPoint { rpm, depth, chatter_hz: w / (2.0 * PI) },
            None => none,
        }
    }
}
