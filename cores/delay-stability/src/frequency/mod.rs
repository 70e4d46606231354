//! Frequency-domain lobes of a 2 × 2 tool-point receptance: the 2-D zero-order method of
//! Altintas & Budak (CIRP Annals 44, 1995) and the multi-frequency method of Budak & Altintas
//! (J. Dyn. Sys. Meas. Control 120, 1998) and Merdol & Altintas (J. Manuf. Sci. Eng. 126, 2004).
//!
//! # Model and conventions
//!
//! The force model is the one of [`crate::milling`], through the same [`Cutter`]: x along the
//! feed, y normal to it, the tooth angle φ measured from +y clockwise, the linearised dynamic
//! force on the tool
//!
//! ```text
//! F̃(t) = a_p H(t) (ṽ(t) − ṽ(t − τ)),   τ = 60/(z n),   H(t) = Cutter::directional(Ω t),
//! ```
//!
//! and the structure answers with the receptance `ṽ = G(iω) F̃` ([`Receptance`]: any closure or
//! type, modal ([`ModalReceptance`]) or measured; m/N, rows = displacement (x, y), columns =
//! force (x, y)). A chatter solution `ṽ = V e^{iωt}` of the averaged system (`H(t) → H̄ =`
//! [`Cutter::mean`]) needs
//!
//! ```text
//! det(I − a_p (1 − e^{−iωτ}) H̄ G(iω)) = 0,
//! ```
//!
//! so for every eigenvalue `p_j(ω)` of `P(ω) = H̄ G(iω)` (closed-form 2 × 2) the depth is
//! `a_p = 1/((1 − e^{−iωτ}) p_j)` where that product is real and positive:
//! `a_p = 1/Re((1 − e^{−iωτ}) p_j)`. With `1 − e^{−iθ} = 2 sin(θ/2) e^{i(π − θ)/2}` (θ = ωτ) and
//! `g_j(ω) = ωτ/2 − arg p_j − π/2` the roots are `g_j = kπ` with `sin(θ/2)·(−1)^k > 0`, and then
//! `a_p = 1/(2 |sin(θ/2)| |p_j|)`: the phase condition of the 1-D solver ([`crate::zero_order`],
//! where `p = −K_t α₀ Φ`) applied to each eigenvalue branch. The boundary at a speed is the
//! smallest such `a_p` over all roots (D-subdivision: the stable region containing `a_p = 0`
//! ends there), which is the exact boundary of the averaged system (tested against
//! [`crate::exact::TimeInvariant`], an independent method on the same system).
//!
//! **Altintas' form.** With `H̄ = (z K_t/(4π)) [α]` (the closed-form `α_xx, α_xy, α_yx, α_yy` of
//! *Manufacturing Automation*, ch. 3, which equal `(4π/(z K_t)) H̄` for the linear law), Altintas
//! writes `det[I + Λ Φ₀] = 0` with `Φ₀ = [α] G`, `Λ = −(z/(4π)) a K_t (1 − e^{−iωτ})`; an eigenvalue
//! `λ₀` of `Φ₀` gives `Λ = −1/λ₀` and `a_lim = −(2π Λ_R/(z K_t)) (1 + κ²)`, `κ = Λ_I/Λ_R`. Since
//! `p_j = (z K_t/(4π)) λ₀`, `(1 − e^{−iωτ}) p_j a = 1` is the same equation, and its real part gives
//! the same `a_lim` (`tests/python/test_lobes_2d.py` implements Altintas' form independently).
//!
//! # Multi-frequency
//!
//! The periodic `H(t) = Σ_r H_r e^{i r ω_T t}` (ω_T = 2π/τ, [`directional_harmonics`]) couples a
//! chatter solution `ṽ = e^{iωt} Σ_k V_k e^{i k ω_T t}` to its tooth-passing sidebands; truncated
//! to `|k| ≤ h` the force harmonics satisfy `F = a_p (1 − e^{−iωτ}) B(ω) F` with the block matrix
//! `B_{mk} = H_{m−k} G(i(ω + k ω_T))` (`m, k = −h..h`), and the same phase and depth conditions
//! apply to the eigenvalues of `B` ([`MultiFrequency`]). `h = 0` is the zero-order matrix `H̄ G`.
//!
//! The same solution appears at `ω + j ω_T` with its harmonics shifted by j; the truncation
//! represents it well only where its dominant harmonics are central, and the copies whose
//! dominant harmonic sits near `|k| = h` give spuriously small depths. A root is therefore kept
//! only if the central sideband of its displacement `V_k = G_k F_k` (F the eigenvector, by
//! inverse iteration) is at least half the largest; its chatter frequency is that central ω.
//!
//! **Number of harmonics.** The truncation must (i) resolve the pulse of `H(t)`: a tooth cuts
//! for the fraction `d = (φ_e − φ_s)/(2π/z)` of the tooth period, and `H_r` is significant up to
//! `r ≈ 1/d`; and (ii) reach the sidebands `ω + k ω_T` that fall on the structure's response at
//! `±ω`: `h ω_T ≳ 2 ω_top`, with `ω_top` the highest frequency where some entry of G is above
//! 10 % of its peak over the band. [`MultiFrequency::new`] takes per speed
//!
//! ```text
//! h = max(⌈2/d⌉, ⌈2 f_top/f_T⌉),   at most 16,   and h = 0 if H(t) is constant
//! ```
//!
//! (`f_T` the tooth-passing frequency; [`MultiFrequency::harmonics_at`]). Tuned so that one more
//! harmonic changes the boundary by less than 0.1 % on the low-immersion cases of the tests
//! (a/D = 0.05 and 0.1 down-milling, the 1-DOF Insperger–Stépán benchmark and the 3-mode machine;
//! `⌈1.6/d⌉` was not enough: 0.15 % at 10,000 rpm, a/D = 0.05). The cost grows as `(4h + 2)³`
//! per grid point and speed; [`MultiFrequency::with_harmonics`] fixes h instead.
//!
//! # Solution per speed
//!
//! A frequency grid is built once from G ([`GridOptions`]: bisected until between neighbours the
//! phase and `ln|·|` of every non-negligible entry of G and of both eigenvalues of `H̄ G` change by
//! at most 0.02 (zero-order) or 0.1 (multi-frequency), and `Δω τ_max/2 ≤ 0.5`). The eigenvalues
//! on the grid (once for the zero-order matrix, per speed for the block matrix) are followed as
//! branches by nearest matching (with linear extrapolation); per speed every crossing of
//! `g_j = kπ` with the right side is bracketed, the candidates are refined in the order of their
//! interpolated depth while it is within 5 % of the smallest exact depth found, by Illinois
//! regula falsi on `sin g(ω)` with the **exact** G (the eigenvalue nearest the branch's
//! interpolated value; a bracket whose end is a jump between eigenvalues, `|sin g| > 1e-6`, is no
//! root), and the smallest depth wins: the same bracket-and-refine code as the 1-D solver. The
//! grid only brackets; the depths do not change when it is refined (tested). No root in the
//! band: the depth is `f64::INFINITY` and the chatter frequency NaN.
//!
//! An eigenvalue below `1e-9` of the other (e.g. the second eigenvalue of a structure flexible in
//! one direction only, which is exactly zero) is not followed.
//!
//! # Use
//!
//! ```
//! use delay_stability::frequency::{Lobes, ModalReceptance, ZeroOrder2d};
//! use delay_stability::milling::{Cutter, ForceLaw, Milling};
//! use delay_stability::zero_order::speed_grid;
//!
//! // x: 600 Hz, 2e7 N/m, ζ 0.03; y: 650 Hz, 2.5e7 N/m, ζ 0.035
//! let g = ModalReceptance::new(&[
//!     ModalReceptance::mode(600.0, 2e7, 0.03, [1.0, 0.0]),
//!     ModalReceptance::mode(650.0, 2.5e7, 0.035, [0.0, 1.0]),
//! ])?;
//! let (entry, exit) = Cutter::immersion(1.0, Milling::Down);
//! let cutter = Cutter::new(3, entry, exit, 8e8, 2.4e8, ForceLaw::Linear)?;
//! let lobes = ZeroOrder2d::new(g, &cutter, (10.0, 4000.0), 4000.0)?;
//! let diagram = lobes.diagram(&speed_grid(4000.0, 30000.0, 500));
//! let ex = lobes.extremes(&diagram).unwrap();
//! assert!(ex.min.depth > 0.0 && ex.min.depth < ex.max.depth);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod branches;
mod harmonics;
mod multi_frequency;
mod zero_order_2d;

pub use harmonics::directional_harmonics;
pub use multi_frequency::MultiFrequency;
pub use zero_order_2d::ZeroOrder2d;

pub use crate::zero_order::{CriticalPoint, Extremes, GridOptions, LobeError};

use crate::milling::{Cutter, ModeShape};
use crate::zero_order::{LobeProblem, extremes};
use nalgebra::Matrix2;
use num_complex::Complex64;
use rayon::prelude::*;

/// A lobe solver: the exact critical depth per speed, and from it a diagram (parallel over
/// speeds) and b_min/b_max ([`crate::zero_order::extremes`]). Implemented by [`ZeroOrder2d`],
/// [`MultiFrequency`] and the 1-D [`LobeProblem`], so that callers can hold any of them as
/// `&dyn Lobes`.
pub trait Lobes: Sync {
    /// The critical depth \[m\] at `rpm` and its chatter frequency; `f64::INFINITY` (and NaN)
    /// where no root in the band gives a positive depth.
    fn critical_depth(&self, rpm: f64) -> CriticalPoint;

    /// Critical depths on a speed grid (parallel over speeds).
    fn diagram(&self, rpm: &[f64]) -> Vec<CriticalPoint> {
        rpm.par_iter().map(|&n| self.critical_depth(n)).collect()
    }

    /// b_min and b_max of a computed diagram, refined by golden-section search on the exact depth.
    fn extremes(&self, diagram: &[CriticalPoint]) -> Option<Extremes> {
        extremes(diagram, |n| self.critical_depth(n))
    }
}

impl<F: Fn(f64) -> Complex64 + Sync> Lobes for LobeProblem<F> {
    fn critical_depth(&self, rpm: f64) -> CriticalPoint {
        LobeProblem::critical_depth(self, rpm)
    }
}

/// A 2 × 2 tool-point receptance `G(iω)` \[m/N\] (rows: displacement x, y; columns: force x, y).
///
/// Implemented by closures `Fn(f64) -> Matrix2<Complex64> + Sync`, by [`ModalReceptance`] and by
/// `Box<dyn Receptance>`. `ω` is in rad/s; the multi-frequency solver also asks for `ω` outside
/// the band and for `ω < 0`, where a real system has `G(−iω) = conj G(iω)`.
pub trait Receptance: Sync {
    /// `G(iω)`.
    fn receptance(&self, omega: f64) -> Matrix2<Complex64>;
}

impl<F: Fn(f64) -> Matrix2<Complex64> + Sync> Receptance for F {
    fn receptance(&self, omega: f64) -> Matrix2<Complex64> {
        self(omega)
    }
}

impl Receptance for Box<dyn Receptance> {
    fn receptance(&self, omega: f64) -> Matrix2<Complex64> {
        (**self).receptance(omega)
    }
}

impl Receptance for Box<dyn Receptance + Send> {
    fn receptance(&self, omega: f64) -> Matrix2<Complex64> {
        (**self).receptance(omega)
    }
}

/// The receptance of modes with mass-normalised shapes at the tool point, the same structure as
/// [`crate::milling::Structure::from_modes`]: `G(iω) = Σ u uᵀ/(ω_n² − ω² + 2iζω_nω)`, `u` =
/// [`ModeShape::tool`] (the actuator shapes do not enter).
#[derive(Clone, Debug, PartialEq)]
pub struct ModalReceptance {
    modes: Vec<ModeShape>,
}

impl ModalReceptance {
    /// From modes; at least one, each with `ω_n > 0`, `ζ ≥ 0` and a finite shape.
    pub fn new(modes: &[ModeShape]) -> Result<ModalReceptance, LobeError> {
        if modes.is_empty() {
            return Err(LobeError::Invalid("a modal receptance needs at least one mode".into()));
        }
        for (k, m) in modes.iter().enumerate() {
            let ok = m.omega.is_finite() && m.omega > 0.0 && m.zeta.is_finite() && m.zeta >= 0.0;
            if !ok || !m.tool.iter().all(|v| v.is_finite()) {
                return Err(LobeError::Invalid(format!("mode {}: need ω > 0, ζ ≥ 0, finite shape ({m:?})", k + 1)));
            }
        }
        Ok(ModalReceptance { modes: modes.to_vec() })
    }

    /// A mode of natural frequency `hz`, stiffness `k` \[N/m\] and damping `zeta` along the unit
    /// direction `dir` (x, y): `u = dir·ω_n/√k` (modal mass `k/ω_n²`).
    pub fn mode(hz: f64, k: f64, zeta: f64, dir: [f64; 2]) -> ModeShape {
        let omega = 2.0 * std::f64::consts::PI * hz;
        let s = omega / k.sqrt();
        ModeShape { omega, zeta, tool: [dir[0] * s, dir[1] * s], actuator: [0.0, 0.0] }
    }

    /// The modes.
    pub fn modes(&self) -> &[ModeShape] {
        &self.modes
    }
}

impl Receptance for ModalReceptance {
    fn receptance(&self, omega: f64) -> Matrix2<Complex64> {
        let mut g = Matrix2::zeros();
        for m in &self.modes {
            let d = Complex64::new(m.omega * m.omega - omega * omega, 2.0 * m.zeta * m.omega * omega).inv();
            let u = m.tool;
            g += Matrix2::new(u[0] * u[0], u[0] * u[1], u[1] * u[0], u[1] * u[1]).map(|v| d * v);
        }
        g
    }
}

/// The eigenvalues of a complex 2 × 2 matrix, the larger first, the smaller as `det/larger` (no
/// cancellation when they differ much; exactly 0 for a singular matrix).
pub(crate) fn eig2(m: &Matrix2<Complex64>) -> [Complex64; 2] {
    let half = (m[(0, 0)] + m[(1, 1)]) * 0.5;
    let det = m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)];
    let mut d = (half * half - det).sqrt();
    if (half.conj() * d).re < 0.0 {
        d = -d;
    }
    let big = half + d;
    if big.norm() == 0.0 {
        return [big, big];
    }
    [big, det / big]
}

/// `H̄` of a cutter as a complex matrix.
pub(crate) fn complex(m: &Matrix2<f64>) -> Matrix2<Complex64> {
    m.map(Complex64::from)
}

/// Validate a cutter's mean directional matrix.
pub(crate) fn mean_of(cutter: &Cutter) -> Result<Matrix2<f64>, LobeError> {
    let h = cutter.mean();
    if h.iter().all(|v| v.is_finite()) && h.iter().any(|&v| v != 0.0) {
        Ok(h)
    } else {
        Err(LobeError::Invalid(format!("the cutter's mean directional matrix is zero or not finite: {h:?}")))
    }
}

#[cfg(test)]
mod tests;
