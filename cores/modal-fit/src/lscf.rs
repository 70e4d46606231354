//! Poles by the least-squares complex-frequency method (LSCF).
//!
//! Model of every FRF `o` on the band `[f_lo, f_hi]`: `H_o(ω) = N_o(z)/D(z)`, `z = e^{−iωΔt}`,
//! `Δt = 1/(2 f_hi)` (the band's top at the Nyquist frequency), `N_o` and the common `D`
//! polynomials of order n with real coefficients. The linearised error
//! `ε_o(ω_k) = N_o(z_k) − H_o(ω_k) D(z_k)` is minimised in least squares; eliminating the
//! numerators leaves the reduced normal equations of the denominator,
//!
//! ```text
//! M α = 0,   M = Σ_o (T_o − S_oᵀ R⁻¹ S_o),   R = Re XᴴX,  S_o = Re XᴴY_o,  T_o = Re Y_oᴴY_o,
//! X_kj = z_k^j,  Y_o,kj = −H_o(ω_k) z_k^j,
//! ```
//!
//! solved with the highest coefficient fixed to 1. With the polynomial basis every matrix is
//! Toeplitz in `j − l`, so it is built from `2n + 1` sums per FRF (O(N n), not O(N n²)). The
//! poles are `λ = −ln(z_r)/Δt` for the roots `z_r` of `D` (with `z = e^{+iωΔt}` the fit would be
//! that of the conjugate, time-reversed data, and the poles would come out mirrored into the
//! right half plane); the physical ones are stable
//! (Re λ < 0), in the upper half plane and in the band.

use crate::{FitError, Frfs, Pole};
use nalgebra::DMatrix;
use num_complex::Complex64;

/// The denominator's coefficients `α_0 … α_n` (`α_n = 1`) of order `n` on `band` \[Hz\], and Δt.
pub fn denominator(frf: &Frfs, band: (f64, f64), n: usize) -> Result<(Vec<f64>, f64), FitError> {
    frf.check()?;
    let idx = frf.band(band);
    if idx.len() < 2 * n + 2 {
        return Err(FitError::Data(format!("{} frequencies in the band for order {n}", idx.len())));
    }
    if n == 0 {
        return Err(FitError::Data("model order 0".into()));
    }
    let dt = 1.0 / (2.0 * band.1);
    let w: Vec<f64> = frf.freq_hz[idx.clone()].iter().map(|f| 2.0 * std::f64::consts::PI * f * dt).collect();
    // Σ_k weight_k e^{−i ω_k Δt d} for d = −n..=n, stored at d + n
    let toeplitz = |weights: &dyn Fn(usize) -> Complex64| -> Vec<Complex64> {
        (0..=2 * n)
            .map(|i| {
                let d = i as f64 - n as f64;
                (0..w.len()).map(|k| weights(k) * Complex64::from_polar(1.0, -w[k] * d)).sum()
            })
            .collect()
    };
    let at = |v: &[Complex64], d: isize| v[(d + n as isize) as usize];
    let r_sums = toeplitz(&|_| Complex64::new(1.0, 0.0));
    let r = DMatrix::from_fn(n + 1, n + 1, |j, l| at(&r_sums, l as isize - j as isize).re);
    let r_chol = r.clone().cholesky().ok_or(FitError::Singular("R"))?;
    let mut m = DMatrix::<f64>::zeros(n + 1, n + 1);
    for h in &frf.outputs {
        let h = &h[idx.clone()];
        // S_jl = Re Σ conj(z^j) (−H z^l) = −Re Σ H e^{iω(l−j)};  T_jl = Re Σ |H|² e^{iω(l−j)}
        let s_sums = toeplitz(&|k| h[k]);
        let t_sums = toeplitz(&|k| Complex64::from(h[k].norm_sqr()));
        let s = DMatrix::from_fn(n + 1, n + 1, |j, l| -at(&s_sums, l as isize - j as isize).re);
        let t = DMatrix::from_fn(n + 1, n + 1, |j, l| at(&t_sums, l as isize - j as isize).re);
        let rs = r_chol.solve(&s);
        m += t - s.transpose() * rs;
    }
    let a = m.view((0, 0), (n, n)).into_owned();
    let b = -m.view((0, n), (n, 1)).into_owned();
    let x = a.lu().solve(&b).ok_or(FitError::Singular("reduced normal equations"))?;
    let mut alpha: Vec<f64> = x.iter().copied().collect();
    alpha.push(1.0);
    Ok((alpha, dt))
}

/// Roots of `Σ α_j z^j` (monic, `α_n = 1`) by the companion matrix's eigenvalues.
pub fn roots(alpha: &[f64]) -> Vec<Complex64> {
    let n = alpha.len() - 1;
    let mut c = DMatrix::<f64>::zeros(n, n);
    for i in 1..n {
        c[(i, i - 1)] = 1.0;
    }
    for i in 0..n {
        c[(i, n - 1)] = -alpha[i];
    }
    c.complex_eigenvalues().iter().copied().collect()
}

/// The physical poles of the order-`n` model on `band`: stable, upper half plane, natural
/// frequency inside the band, damping below 50 %; sorted by frequency.
pub fn poles(frf: &Frfs, band: (f64, f64), n: usize) -> Result<Vec<Pole>, FitError> {
    let (alpha, dt) = denominator(frf, band, n)?;
    let mut p: Vec<Pole> = roots(&alpha)
        .into_iter()
        .filter(|z| z.norm() > 0.0)
        .map(|z| Pole(-z.ln() / dt))
        .filter(|p| p.0.im > 0.0 && p.0.re < 0.0 && p.damping() < 0.5)
        .filter(|p| (band.0..=band.1).contains(&p.frequency_hz()))
        .collect();
    p.sort_by(|a, b| a.frequency_hz().total_cmp(&b.frequency_hz()));
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::{synthetic, two_modes};

    /// Noise-free FRFs of two modes: an over-modelled fit (order 16, the z-domain model only
    /// approximates a continuous system) holds both poles to 1e-7 (and computational poles
    /// elsewhere, which the stabilisation diagram removes).
    #[test]
    fn exact_data_gives_the_exact_poles() {
        let (modes, frf) = synthetic(&two_modes(), 0.0, 1);
        let p = poles(&frf, (100.0, 2000.0), 16).unwrap();
        for m in &modes {
            let best = p
                .iter()
                .min_by(|a, b| (a.frequency_hz() - m.0).abs().total_cmp(&(b.frequency_hz() - m.0).abs()))
                .unwrap();
            assert!((best.frequency_hz() / m.0 - 1.0).abs() < 1e-7, "{best:?} vs {m:?}");
            assert!((best.damping() / m.1 - 1.0).abs() < 1e-6, "{best:?} vs {m:?}");
        }
    }

    #[test]
    fn roots_of_a_known_polynomial() {
        // (z − 0.5)(z + 0.25) = z² − 0.25 z − 0.125
        let mut r: Vec<f64> = roots(&[-0.125, -0.25, 1.0]).iter().map(|z| z.re).collect();
        r.sort_by(f64::total_cmp);
        assert!((r[0] + 0.25).abs() < 1e-12 && (r[1] - 0.5).abs() < 1e-12);
    }
}
