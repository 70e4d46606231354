//! The H∞ norm `‖G‖∞ = sup_ω σ̄(G(iω))` of a stable system.
//!
//! [`hinf_norm`]: the two-step algorithm of Boyd, Balakrishnan, Bruinsma and Steinbuch (1989–90).
//! `γ > σ̄(D)` is a singular value of `G(iω)` exactly when `iω` is an eigenvalue of the
//! Hamiltonian `M_γ` built from `G(iω)u = γv`, `G(iω)*v = γu` (with `x = (iω − A)⁻¹Bu`,
//! `p = (−iω − Aᵀ)⁻¹Cᵀv`, `S = γ²I − DDᵀ`):
//!
//! ```text
//! v = S⁻¹(γ C x + D Bᵀ p),  u = (Bᵀp + Dᵀv)/γ,   iω [x; p] = [A x + B u; −Aᵀp − Cᵀv] = M_γ [x; p].
//! ```
//!
//! From a lower bound `γ_lb` (σ̄ at 0, ∞ and at the poles' frequencies), set
//! `γ = (1 + 2 tol) γ_lb`; if `M_γ` has imaginary eigenvalues `iω₁ < … < iω_k`, the norm exceeds
//! `γ`, and `γ_lb` becomes the largest σ̄ at the midpoints `(ωᵢ + ωᵢ₊₁)/2`; otherwise
//! `‖G‖∞ ∈ [γ_lb, γ]`. Quadratic convergence.
//!
//! [`sweep_norm`] is the independent reference: σ̄ on a logarithmic grid, refined around the
//! largest value by golden-section search.

use crate::DesignError;
use crate::ss::{StateSpace, complex};
use nalgebra::DMatrix;
use num_complex::Complex64;

/// A norm and the frequency \[rad/s, in the system's time unit\] where it is attained.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// `‖G‖∞` (or the sweep's maximum).
    pub value: f64,
    /// Where σ̄ is largest (`∞` when the peak is `σ̄(D)` at infinite frequency).
    pub omega: f64,
}

/// σ̄(G(iω)).
pub fn sigma_max(g: &StateSpace, omega: f64) -> f64 {
    let m = g.eval(Complex64::new(0.0, omega));
    m.singular_values().iter().copied().fold(0.0, f64::max)
}

fn hamiltonian(g: &StateSpace, gamma: f64) -> Option<DMatrix<f64>> {
    let (a, b, c, d) = (&g.a, &g.b, &g.c, &g.d);
    let p = d.nrows();
    let s = DMatrix::identity(p, p) * (gamma * gamma) - d * d.transpose();
    let si = s.try_inverse()?;
    let vx = &si * c * gamma;
    let vp = &si * d * b.transpose();
    let ux = d.transpose() * &vx / gamma;
    let up = (b.transpose() + d.transpose() * &vp) / gamma;
    let n = a.nrows();
    let mut m = DMatrix::zeros(2 * n, 2 * n);
    m.view_mut((0, 0), (n, n)).copy_from(&(a + b * ux));
    m.view_mut((0, n), (n, n)).copy_from(&(b * up));
    m.view_mut((n, 0), (n, n)).copy_from(&(-(c.transpose() * vx)));
    m.view_mut((n, n), (n, n)).copy_from(&(-(a.transpose()) - c.transpose() * vp));
    Some(m)
}

/// `‖G‖∞` of a stable `G` to the relative tolerance `tol` (module docs).
pub fn hinf_norm(g: &StateSpace, tol: f64) -> Result<Peak, DesignError> {
    let abscissa = g.spectral_abscissa();
    if abscissa >= 0.0 {
        return Err(DesignError::Invalid(format!("the H∞ norm needs a stable system (abscissa {abscissa:e})")));
    }
    let sd = complex(&g.d).singular_values().iter().copied().fold(0.0, f64::max);
    let mut best = Peak { value: sd, omega: f64::INFINITY };
    let consider = |w: f64, best: &mut Peak| {
        let s = sigma_max(g, w);
        if s > best.value {
            *best = Peak { value: s, omega: w };
        }
    };
    consider(0.0, &mut best);
    for p in g.poles() {
        consider(p.im.abs().max(p.norm() * 1e-3), &mut best);
        consider(p.norm(), &mut best);
    }
    if g.order() == 0 || best.value == 0.0 {
        return Ok(best);
    }
    for _ in 0..100 {
        let gamma = (1.0 + 2.0 * tol) * best.value;
        let Some(m) = hamiltonian(g, gamma) else { break };
        let scale = m.norm().max(1.0);
        let mut omegas: Vec<f64> =
            m.complex_eigenvalues().iter().filter(|l| l.re.abs() <= 1e-9 * scale && l.im > 0.0).map(|l| l.im).collect();
        if omegas.is_empty() {
            return Ok(best);
        }
        omegas.sort_by(f64::total_cmp);
        let before = best.value;
        if omegas.len() == 1 {
            consider(omegas[0], &mut best);
        }
        for w in omegas.windows(2) {
            consider(0.5 * (w[0] + w[1]), &mut best);
        }
        if best.value <= before {
            // the imaginary eigenvalues are a numerical artefact at this γ: the bound holds
            return Ok(best);
        }
    }
    Err(DesignError::Invalid("the H∞ norm iteration did not converge".into()))
}

/// The largest σ̄ over `points` logarithmic frequencies in `[lo, hi]`, refined by golden-section
/// search between the neighbours of the largest (the reference for [`hinf_norm`]).
pub fn sweep_norm(g: &StateSpace, lo: f64, hi: f64, points: usize) -> Peak {
    let grid: Vec<f64> = (0..points).map(|i| lo * (hi / lo).powf(i as f64 / (points.max(2) - 1) as f64)).collect();
    let (k, _) =
        grid.iter().map(|&w| sigma_max(g, w)).enumerate().max_by(|x, y| x.1.total_cmp(&y.1)).expect("a nonempty grid");
    let (mut a, mut b) = (grid[k.saturating_sub(1)].ln(), grid[(k + 1).min(points - 1)].ln());
    let f = |x: f64| -sigma_max(g, x.exp());
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..80 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - r * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    let w = (0.5 * (a + b)).exp();
    Peak { value: sigma_max(g, w).max(sigma_max(g, grid[k])), omega: w }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    fn second_order(zeta: f64, wn: f64) -> StateSpace {
        StateSpace::new(
            DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -wn * wn, -2.0 * zeta * wn]),
            DMatrix::from_row_slice(2, 1, &[0.0, 1.0]),
            DMatrix::from_row_slice(1, 2, &[wn * wn, 0.0]),
            DMatrix::zeros(1, 1),
        )
        .unwrap()
    }

    /// Closed forms: `a/(s + a)` has norm 1 at ω = 0; `ωₙ²/(s² + 2ζωₙs + ωₙ²)` has
    /// `1/(2ζ√(1 − ζ²))` at `ωₙ√(1 − 2ζ²)` (ζ < 1/√2); a static 2 × 2 gain its σ̄.
    #[test]
    fn closed_forms() {
        let lag = StateSpace::new(
            DMatrix::from_element(1, 1, -3.0),
            DMatrix::from_element(1, 1, 1.0),
            DMatrix::from_element(1, 1, 3.0),
            DMatrix::zeros(1, 1),
        )
        .unwrap();
        assert!((hinf_norm(&lag, 1e-10).unwrap().value - 1.0).abs() < 1e-9);
        for (zeta, wn) in [(0.0088, 892.8), (0.05, 1.0), (0.3, 20.0), (0.6, 5.0)] {
            let p = hinf_norm(&second_order(zeta, wn), 1e-12).unwrap();
            let want = 1.0 / (2.0 * zeta * (1.0 - zeta * zeta).sqrt());
            assert!((p.value / want - 1.0).abs() < 1e-9, "ζ = {zeta}: {} vs {want}", p.value);
            let w = wn * (1.0 - 2.0 * zeta * zeta).sqrt();
            assert!((p.omega / w - 1.0).abs() < 1e-4, "ζ = {zeta}: ω {} vs {w}", p.omega);
        }
        let d = StateSpace::new(
            DMatrix::zeros(0, 0),
            DMatrix::zeros(0, 2),
            DMatrix::zeros(2, 0),
            DMatrix::from_row_slice(2, 2, &[3.0, 0.0, 4.0, 0.0]),
        )
        .unwrap();
        assert!((hinf_norm(&d, 1e-10).unwrap().value - 5.0).abs() < 1e-12);
    }

    /// A two-peak MIMO system with feedthrough: the Hamiltonian bisection equals the sweep
    /// (independent method) to 1e-8, and an unstable system is refused.
    #[test]
    fn equals_the_frequency_sweep_on_a_two_peak_mimo_system() {
        let g1 = second_order(0.02, 10.0);
        let g2 = second_order(0.05, 37.0);
        let mut a = DMatrix::zeros(4, 4);
        a.view_mut((0, 0), (2, 2)).copy_from(&g1.a);
        a.view_mut((2, 2), (2, 2)).copy_from(&g2.a);
        let b = DMatrix::from_row_slice(4, 2, &[0.0, 0.0, 1.0, 0.5, 0.0, 0.0, -0.3, 1.0]);
        let c = DMatrix::from_row_slice(2, 4, &[100.0, 0.0, 1369.0, 2.0, -40.0, 1.0, 700.0, 0.0]);
        let d = DMatrix::from_row_slice(2, 2, &[0.1, 0.0, 0.2, -0.3]);
        let g = StateSpace::new(a, b, c, d).unwrap();
        let h = hinf_norm(&g, 1e-12).unwrap();
        let s = sweep_norm(&g, 0.1, 1000.0, 20_001);
        assert!((h.value / s.value - 1.0).abs() < 1e-8, "Hamiltonian {} vs sweep {}", h.value, s.value);
        assert!((h.omega / s.omega - 1.0).abs() < 1e-3);
        let unstable = second_order(-0.01, 1.0);
        assert!(hinf_norm(&unstable, 1e-6).is_err());
    }
}
