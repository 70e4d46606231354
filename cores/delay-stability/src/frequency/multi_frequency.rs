//! The multi-frequency solver (parent module docs, also for the number of harmonics).

use super::branches::{Branches, sample};
use super::{CriticalPoint, GridOptions, LobeError, Lobes, Receptance, complex, directional_harmonics, eig2, mean_of};
use crate::milling::Cutter;
use nalgebra::{DMatrix, DVector, Matrix2, Vector2};
use num_complex::Complex64;
use std::f64::consts::PI;

/// The largest automatic h.
const AUTO_MAX: usize = 16;

/// Multi-frequency lobes: per speed the eigenvalues of the block matrix
/// `B_{mk} = H_{m−k} G(i(ω + k ω_T))`, `|m|, |k| ≤ h` (parent module docs).
pub struct MultiFrequency<R> {
    frf: R,
    teeth: u32,
    /// `Some(h)`: fixed; `None`: the automatic rule (module docs).
    fixed: Option<usize>,
    /// ⌈2/d⌉ (0 if H is constant).
    h_duty: usize,
    /// The highest frequency where G is above 10 % of its peak \[Hz\].
    f_top: f64,
    /// `H_r`, r = 0..=2 h_max.
    harm: Vec<Matrix2<Complex64>>,
    /// The frequency grid of G.
    omega: Vec<f64>,
}

impl<R: Receptance> MultiFrequency<R> {
    /// The problem with the automatic number of harmonics per speed (module docs), for chatter
    /// frequencies in `band_hz` \[Hz\] and speeds from `rpm_min` up.
    pub fn new(frf: R, cutter: &Cutter, band_hz: (f64, f64), rpm_min: f64) -> Result<Self, LobeError> {
        Self::build(frf, cutter, &Self::options(cutter, band_hz, rpm_min)?, None)
    }

    /// The same with a fixed number `h` of harmonics (`h = 0` is the zero-order method).
    pub fn with_harmonics(
        frf: R,
        cutter: &Cutter,
        band_hz: (f64, f64),
        rpm_min: f64,
        h: usize,
    ) -> Result<Self, LobeError> {
        Self::build(frf, cutter, &Self::options(cutter, band_hz, rpm_min)?, Some(h))
    }

    /// The same with explicit grid options and a fixed (`Some`) or automatic (`None`) h.
    pub fn with_grid(frf: R, cutter: &Cutter, opt: &GridOptions, h: Option<usize>) -> Result<Self, LobeError> {
        Self::build(frf, cutter, opt, h)
    }

    /// The default grid: [`GridOptions::new`] with phase and log-magnitude steps of 0.1, coarser
    /// than the zero-order solver's (every grid point costs an eigenvalue problem of size
    /// 2(2h + 1) per speed, and the grid only brackets the roots, which are then solved exactly).
    fn options(cutter: &Cutter, band_hz: (f64, f64), rpm_min: f64) -> Result<GridOptions, LobeError> {
        if !(rpm_min.is_finite() && rpm_min > 0.0) {
            return Err(LobeError::Invalid(format!("the slowest speed must be > 0 (got {rpm_min} rpm)")));
        }
        let mut opt = GridOptions::new(band_hz.0, band_hz.1, cutter.teeth, rpm_min);
        opt.max_phase_step = 0.1;
        opt.max_log_mag_step = 0.1;
        Ok(opt)
    }

    fn build(frf: R, cutter: &Cutter, opt: &GridOptions, fixed: Option<usize>) -> Result<Self, LobeError> {
        if fixed.is_some_and(|h| h > 40) {
            return Err(LobeError::Invalid(format!("at most 40 harmonics (got {fixed:?})")));
        }
        let hbar = mean_of(cutter)?;
        let s = sample(&frf, &complex(&hbar), opt)?;
        let peak = |g: &Matrix2<Complex64>| g.iter().map(|v| v.norm()).fold(0.0, f64::max);
        let top = s.g.iter().map(peak).fold(0.0, f64::max);
        let i_top = s.g.iter().rposition(|g| peak(g) >= 0.1 * top).unwrap_or(0);
        let f_top = s.omega[i_top] / (2.0 * PI);
        let harm = directional_harmonics(cutter, 2 * fixed.unwrap_or(AUTO_MAX));
        let constant = harm[1..].iter().all(|m| m.norm() <= 1e-9 * harm[0].norm());
        let duty = ((cutter.exit - cutter.entry) / cutter.pitch()).min(1.0);
        let h_duty = if constant { 0 } else { (2.0 / duty - 1e-9).ceil() as usize };
        Ok(MultiFrequency { frf, teeth: cutter.teeth, fixed, h_duty, f_top, harm, omega: s.omega })
    }

    /// The number of harmonics h used at `rpm` (fixed, or the rule of the module docs).
    pub fn harmonics_at(&self, rpm: f64) -> usize {
        if let Some(h) = self.fixed {
            return h;
        }
        if self.h_duty == 0 {
            return 0;
        }
        let f_t = self.teeth as f64 * rpm / 60.0;
        let h_cov = (2.0 * self.f_top / f_t).ceil();
        (self.h_duty as f64).max(h_cov).min(AUTO_MAX as f64) as usize
    }

    /// Number of points of the frequency grid.
    pub fn grid_len(&self) -> usize {
        self.omega.len()
    }

    /// `H_r` for any r (`H_{−r} = conj H_r`).
    fn hr(&self, r: i64) -> Matrix2<Complex64> {
        let m = self.harm[r.unsigned_abs() as usize];
        if r < 0 { m.map(|v| v.conj()) } else { m }
    }

    /// `G(i(ω + k ω_T))`, k = −h..h.
    fn sidebands(&self, h: usize, w: f64, w_t: f64) -> Vec<Matrix2<Complex64>> {
        let h = h as i64;
        (-h..=h).map(|k| self.frf.receptance(w + k as f64 * w_t)).collect()
    }

    /// The block matrix `B_{mk} = H_{m−k} G_k` of the sidebands `g`.
    fn block(&self, g: &[Matrix2<Complex64>]) -> DMatrix<Complex64> {
        let h = (g.len() / 2) as i64;
        let n = 2 * g.len();
        let mut b = DMatrix::<Complex64>::zeros(n, n);
        for m in -h..=h {
            for k in -h..=h {
                let blk = self.hr(m - k) * g[(k + h) as usize];
                b.view_mut((2 * (m + h) as usize, 2 * (k + h) as usize), (2, 2)).copy_from(&blk);
            }
        }
        b
    }

    /// The eigenvalues of the block matrix at ω.
    fn eigs(&self, h: usize, w: f64, w_t: f64) -> Vec<Complex64> {
        if h == 0 {
            return eig2(&(self.harm[0] * self.frf.receptance(w))).to_vec();
        }
        let b = self.block(&self.sidebands(h, w, w_t));
        let n = b.nrows();
        b.eigenvalues().map(|v| v.iter().copied().collect()).unwrap_or_else(|| vec![Complex64::new(f64::NAN, 0.0); n])
    }

    /// Is the central sideband (k = 0) of the root's displacement `V_k = G_k F_k` at least half
    /// the largest? The same solution appears at ω + j ω_T with its harmonics shifted by j; the
    /// truncation represents it well only where its dominant harmonics are central, and the
    /// shifted copies with a dominant harmonic near `|k| = h` give spurious (too small) depths.
    /// The force harmonics F are the eigenvector of `p`, by two steps of inverse iteration.
    fn centred(&self, h: usize, w: f64, w_t: f64, p: Complex64) -> bool {
        if h == 0 {
            return true;
        }
        let g = self.sidebands(h, w, w_t);
        let b = self.block(&g);
        let n = b.nrows();
        let lu = (b - DMatrix::<Complex64>::identity(n, n) * (p * (1.0 + 1e-9))).lu();
        let mut x = DVector::<Complex64>::from_element(n, Complex64::new(1.0, 0.3));
        for _ in 0..2 {
            match lu.solve(&x) {
                Some(y) if y.norm().is_finite() && y.norm() > 0.0 => x = &y / Complex64::from(y.norm()),
                _ => return true,
            }
        }
        let v: Vec<f64> =
            g.iter().enumerate().map(|(k, gk)| (gk * Vector2::new(x[2 * k], x[2 * k + 1])).norm()).collect();
        v[h] >= 0.5 * v.iter().copied().fold(0.0, f64::max)
    }
}

impl<R: Receptance> Lobes for MultiFrequency<R> {
    /// The critical depth \[m\] at `rpm` and its chatter frequency: the base frequency ω of the
    /// root in the band whose central harmonic dominates (the vibration also contains
    /// ω + k ω_T); `f64::INFINITY` (and NaN) where no root gives a positive depth.
    fn critical_depth(&self, rpm: f64) -> CriticalPoint {
        let none = CriticalPoint { rpm, depth: f64::INFINITY, chatter_hz: f64::NAN };
        if !(rpm.is_finite() && rpm > 0.0) {
            return none;
        }
        let h = self.harmonics_at(rpm);
        let tau = 60.0 / (self.teeth as f64 * rpm);
        let w_t = 2.0 * PI / tau;
        let eigs = self.omega.iter().map(|&w| self.eigs(h, w, w_t)).collect();
        let branches = Branches::track(self.omega.clone(), eigs);
        match branches.critical(tau, |w| self.eigs(h, w, w_t), |w, p| self.centred(h, w, w_t, p)) {
            Some((w, depth)) => CriticalPoint { rpm, depth, chatter_hz: w / (2.0 * PI) },
            None => none,
        }
    }
}
