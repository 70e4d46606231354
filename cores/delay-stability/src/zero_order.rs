//! Zero-order (Altintas–Budak) stability lobes of a one-direction regenerative system.
//!
//! # Model
//!
//! The averaged dynamic cutting force along the flexible direction is
//! `F_dyn(t) = −a·K_t·α₀·(x(t) − x(t − τ))`, `τ = 60/(Z·N)` (contract of `milling_plant`,
//! [`milling_plant::PlantParams::directional_coefficient`]), and the structure answers with the
//! receptance `Φ(iω)` (open loop) or `Φ_cl = Φ/(1 − Φ·G_a·H_c)` (closed loop, see
//! the studies' closed-loop FRFs). A chatter root `s = iω` of the characteristic equation
//!
//! ```text
//! 1 + a·K_t·α₀·f(ω) = 0,      f(ω) = (1 − e^{−iωτ})·Φ(iω)
//! ```
//!
//! requires `f(ω)` real with `α₀·Re f < 0`, and then `a = −1/(K_t α₀ Re f)`. Writing
//! `1 − e^{−iθ} = 2 sin(θ/2)·e^{i(π/2 − θ/2)}` (θ = ωτ) and `g(ω) = ωτ/2 − arg Φ − π/2`:
//!
//! ```text
//! Im f = −2 sin(θ/2)·|Φ|·sin g,     Re f = 2 sin(θ/2)·|Φ|·cos g
//! ```
//!
//! so the roots are `g(ω) = jπ` with `sign(α₀)·sin(θ/2)·(−1)^j < 0`, and there
//! `a = 1/(2 K_t |α₀| |sin(θ/2)| |Φ|) = −1/(2 K_t α₀ Re Φ)` (the classic result).
//!
//! **Both signs of α₀.** With `α₀ > 0` (e.g. up-milling along the flexible direction) chatter
//! needs `Re Φ < 0`, above the mode, and an SDOF's minimum depth is `2kζ(1+ζ)/(K_t α₀)`. With
//! `α₀ < 0` (the flexible direction normal to the feed in up-milling, or low-immersion
//! down-milling) the regenerative force pushes the other way: chatter needs `Re Φ > 0`, below
//! the mode, and the minimum is `2kζ(1−ζ)/(K_t |α₀|)`. Only `α₀ = 0` (no regenerative force
//! along the flexible direction) is unconditionally stable.
//!
//! # Two methods
//!
//! * [`LobeProblem::classic_lobes`] — the textbook construction: for every chatter frequency
//!   `ω_c` of the grid where `Re Φ < 0`, `a = −1/(2 K_t α₀ Re Φ)`,
//!   `ε = 2·atan2(−Re Φ, Im Φ) ∈ (0, 2π)` (equal to `3π + 2ψ` modulo 2π with
//!   `ψ = atan2(Im Φ, Re Φ)`), and `N_k = 60 ω_c/(Z (2πk + ε))`, k = 0, 1, …
//!   Used for plotting the individual lobes and as a cross-check.
//! * [`LobeProblem::critical_depth`] — **the method used for every envelope, b_min and b_max**:
//!   at a given speed the phase function `g(ω)` is evaluated on the frequency grid, every
//!   crossing of a multiple of π with `Re f < 0` is bracketed, the candidates are refined in
//!   the order of their interpolated depth, as long as it is within 5 % of the smallest exact
//!   depth found, by a bracketing root finder
//!   (Illinois regula falsi) on `sin g(ω)` evaluated with the **exact** FRF closure
//!   (relative tolerance 1e-12 in ω), and the smallest depth wins. The envelope is thus exact
//!   at every speed (no resampling or interpolation of lobe curves), and
//!   [`LobeProblem::extremes`] refines b_min and b_max by golden-section search on this exact
//!   function around the best point of the speed grid.
//!
//! # Frequency resolution
//!
//! [`FrfGrid::adaptive`] starts from a logarithmic grid and bisects every interval until
//! between neighbours the phase of Φ changes by at most `max_phase_step` (default 0.02 rad),
//! `ln|Φ|` by at most `max_log_mag_step` (default 0.02) and `ω·τ_max/2` by at most 0.5 rad.
//! Near a resonance of damping ratio ζ the phase turns by π over about `2ζω_n`, so the lobe
//! peak region is resolved by ≈ 150 points; because the grid only *brackets* roots that are
//! then solved exactly, the depth does not depend on the grid once every crossing is
//! bracketed (checked by a test that refines the grid tenfold). A root pair closer than one
//! grid interval (a lobe nose tangent to the speed line) can be missed; its depth then differs
//! from a neighbouring bracketed root by less than the interpolation tolerance.

use crate::bracket::{bisect_grid, illinois, phase_crossings, refine_best, unwrap_phase};
use num_complex::Complex64;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Cutting constants of the averaged regenerative force `F = −a K_t α₀ (x − x(t−τ))`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cutting {
    /// Tangential cutting coefficient K_t \[N/m²\].
    pub kt: f64,
    /// Directional coefficient α₀ \[-\] (includes `Z/(2π)`; see [`directional_coefficient`]).
    pub alpha0: f64,
    /// Number of teeth Z.
    pub teeth: u32,
}

impl Cutting {
    /// Tooth-passing delay τ = 60/(Z N) \[s\] at `rpm`.
    pub fn delay(&self, rpm: f64) -> f64 {
        60.0 / (self.teeth as f64 * rpm)
    }
}

/// Averaged directional coefficient α₀ of the milling contract (see `milling_plant::params`):
///
/// ```text
/// α₀ = Z/(2π) ∫_{φ_st}^{φ_ex} (d·r̂)[(cos φ + k_r sin φ) d_x + (−sin φ + k_r cos φ) d_y] dφ
/// ```
///
/// with `r̂ = (sin φ, cos φ)`, `d = (cos β, sin β)` the flexible direction and `k_r = K_r/K_t`,
/// evaluated by composite Simpson quadrature (2000 panels; the integrand is a
/// trigonometric polynomial, error < 1e-12). For half-immersion up-milling in the
/// feed direction (β = 0, φ ∈ \[0, π/2\]) the closed form is `Z/(2π)·(1/2 + k_r π/4)`.
pub fn directional_coefficient(teeth: u32, kr_ratio: f64, phi_st: f64, phi_ex: f64, beta: f64) -> f64 {
    let (dx, dy) = (beta.cos(), beta.sin());
    let integrand = |p: f64| {
        let proj = dx * p.sin() + dy * p.cos();
        proj * ((p.cos() + kr_ratio * p.sin()) * dx + (-p.sin() + kr_ratio * p.cos()) * dy)
    };
    let n = 2000;
    let h = (phi_ex - phi_st) / n as f64;
    let mut s = integrand(phi_st) + integrand(phi_ex);
    for i in 1..n {
        s += if i % 2 == 1 { 4.0 } else { 2.0 } * integrand(phi_st + i as f64 * h);
    }
    teeth as f64 / (2.0 * PI) * s * h / 3.0
}

/// Options of the adaptive frequency grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridOptions {
    /// Lowest frequency \[Hz\].
    pub f_lo: f64,
    /// Highest frequency \[Hz\].
    pub f_hi: f64,
    /// Points of the initial logarithmic grid.
    pub coarse_points: usize,
    /// Largest phase change of Φ between neighbours \[rad\].
    pub max_phase_step: f64,
    /// Largest change of `ln|Φ|` between neighbours.
    pub max_log_mag_step: f64,
    /// Largest delay τ the grid must serve \[s\] (slowest speed); `Δω·τ/2 ≤ 0.5`.
    pub tau_max: f64,
    /// Safety limit on the number of points.
    pub max_points: usize,
}

impl GridOptions {
    /// Defaults for a band and the slowest speed of interest.
    pub fn new(f_lo: f64, f_hi: f64, teeth: u32, rpm_min: f64) -> GridOptions {
        GridOptions {
            f_lo,
            f_hi,
            coarse_points: 400,
            max_phase_step: 0.02,
            max_log_mag_step: 0.02,
            tau_max: 60.0 / (teeth as f64 * rpm_min),
            max_points: 2_000_000,
        }
    }

    /// Sample `eval` on the band (validated) by bisecting the logarithmic grid wherever
    /// `split(left, right)` asks for it or `Δω > 1/τ_max` ([`crate::bracket`]).
    pub(crate) fn sample<S: Clone>(
        &self,
        eval: impl Fn(f64) -> Result<S, LobeError>,
        split: impl Fn(&S, &S) -> bool,
    ) -> Result<Vec<(f64, S)>, LobeError> {
        if !(self.f_lo > 0.0 && self.f_hi > self.f_lo && self.f_hi.is_finite()) {
            return Err(LobeError::InvalidBand { f_lo: self.f_lo, f_hi: self.f_hi });
        }
        let max_dw = 1.0 / self.tau_max.max(1e-300);
        bisect_grid(
            (2.0 * PI * self.f_lo, 2.0 * PI * self.f_hi),
            self.coarse_points,
            self.max_points,
            eval,
            |wl, l, wr, r| wr - wl > max_dw || split(l, r),
            || LobeError::TooManyPoints { max_points: self.max_points },
        )
    }

    /// The same grid with every step limit divided by `factor` (for convergence checks).
    pub fn refined(mut self, factor: f64) -> GridOptions {
        self.max_phase_step /= factor;
        self.max_log_mag_step /= factor;
        self.tau_max *= factor;
        self
    }
}

/// Errors of the lobe computation.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum LobeError {
    /// The band is empty or not finite.
    #[error("invalid frequency band [{f_lo}, {f_hi}] Hz")]
    InvalidBand {
        /// Lower edge \[Hz\].
        f_lo: f64,
        /// Upper edge \[Hz\].
        f_hi: f64,
    },
    /// The FRF returned a non-finite value.
    #[error("FRF is not finite at {freq_hz} Hz")]
    NonFiniteFrf {
        /// Frequency \[Hz\].
        freq_hz: f64,
    },
    /// The adaptive grid would exceed its point limit.
    #[error("adaptive frequency grid exceeds {max_points} points")]
    TooManyPoints {
        /// The limit.
        max_points: usize,
    },
    /// Invalid cutting constants or speeds.
    #[error("invalid input: {0}")]
    Invalid(String),
}

/// An FRF sampled on an adaptive frequency grid, with its unwrapped phase.
#[derive(Clone, Debug)]
pub struct FrfGrid {
    /// Angular frequencies \[rad/s\], increasing.
    pub omega: Vec<f64>,
    /// FRF values.
    pub frf: Vec<Complex64>,
    /// Unwrapped phase of the FRF \[rad\].
    pub phase: Vec<f64>,
}

impl FrfGrid {
    /// Sample `frf` adaptively (see the module documentation).
    pub fn adaptive<F: Fn(f64) -> Complex64>(frf: &F, opt: &GridOptions) -> Result<FrfGrid, LobeError> {
        let eval = |w: f64| -> Result<Complex64, LobeError> {
            let v = frf(w);
            if v.re.is_finite() && v.im.is_finite() && v.norm() > 0.0 {
                Ok(v)
            } else {
                Err(LobeError::NonFiniteFrf { freq_hz: w / (2.0 * PI) })
            }
        };
        let split = |l: &Complex64, r: &Complex64| {
            let dphi = (r * l.conj()).arg().abs();
            let dmag = (r.norm() / l.norm()).ln().abs();
            dphi > opt.max_phase_step || dmag > opt.max_log_mag_step
        };
        let out = opt.sample(eval, split)?;
        let phase = unwrap_phase(out.iter().map(|p| p.1));
        Ok(FrfGrid { omega: out.iter().map(|p| p.0).collect(), frf: out.iter().map(|p| p.1).collect(), phase })
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.omega.len()
    }

    /// Is the grid empty?
    pub fn is_empty(&self) -> bool {
        self.omega.is_empty()
    }
}

/// The critical (limiting) depth at one speed.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CriticalPoint {
    /// Spindle speed \[rpm\].
    pub rpm: f64,
    /// Critical axial depth \[m\] (`f64::INFINITY` if no chatter root in the band).
    pub depth: f64,
    /// Chatter frequency \[Hz\] (NaN if none).
    pub chatter_hz: f64,
}

/// One classic lobe: points `(rpm, depth [m], chatter frequency [Hz])` for lobe number `k`.
#[derive(Clone, Debug)]
pub struct Lobe {
    /// Lobe number k (number of whole waves between teeth).
    pub k: u32,
    /// Points `(rpm, depth_m, chatter_hz)` in order of increasing chatter frequency.
    pub points: Vec<(f64, f64, f64)>,
}

/// Minimum and maximum of the critical depth over a speed range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extremes {
    /// Smallest critical depth (worst case) and where.
    pub min: CriticalPoint,
    /// Largest critical depth (best lobe peak) and where.
    pub max: CriticalPoint,
}

/// A stability problem: FRF closure + cutting constants + the adaptive grid of the FRF.
pub struct LobeProblem<F> {
    frf: F,
    cutting: Cutting,
    grid: FrfGrid,
}

impl<F: Fn(f64) -> Complex64 + Sync> LobeProblem<F> {
    /// Sample the FRF on the adaptive grid for the band and slowest speed in `opt`.
    pub fn new(frf: F, cutting: Cutting, opt: &GridOptions) -> Result<Self, LobeError> {
        if !(cutting.kt > 0.0 && cutting.alpha0.is_finite() && cutting.teeth > 0) {
            return Err(LobeError::Invalid(format!("cutting constants {cutting:?}")));
        }
        let grid = FrfGrid::adaptive(&frf, opt)?;
        Ok(LobeProblem { frf, cutting, grid })
    }

    /// The frequency grid.
    pub fn grid(&self) -> &FrfGrid {
        &self.grid
    }

    /// Cutting constants.
    pub fn cutting(&self) -> &Cutting {
        &self.cutting
    }

    /// Exact FRF at `omega`.
    pub fn frf(&self, omega: f64) -> Complex64 {
        (self.frf)(omega)
    }

    /// Exact critical depth at `rpm` (see the module documentation).
    ///
    /// With `α₀ ≤ 0` the averaged force does not feed back regeneratively in this direction:
    /// every chatter root needs `a < 0`, and the depth is infinite.
    pub fn critical_depth(&self, rpm: f64) -> CriticalPoint {
        let none = CriticalPoint { rpm, depth: f64::INFINITY, chatter_hz: f64::NAN };
        let c = &self.cutting;
        if c.alpha0 == 0.0 || rpm.is_nan() || rpm <= 0.0 {
            return none;
        }
        let tau = c.delay(rpm);
        let g = &self.grid;
        let mut cands = Vec::new();
        let mag = |i: usize| g.frf[i].norm();
        let side_scale = (c.alpha0.signum(), 2.0 * c.kt * c.alpha0.abs());
        phase_crossings((&g.omega, &g.phase), mag, tau, side_scale, |_| true, 0, &mut cands);
        match refine_best(&cands, |x| self.refine(tau, x.index)) {
            Some((w, depth)) => CriticalPoint { rpm, depth, chatter_hz: w / (2.0 * PI) },
            None => none,
        }
    }

    /// Root of `sin g(ω)` in grid bracket `i` with the exact FRF; returns (ω, depth).
    fn refine(&self, tau: f64, i: usize) -> Option<(f64, f64)> {
        // sin g = −cos(ωτ/2 − arg Φ) = −Re(e^{iωτ/2} Φ̄)/|Φ|
        let s = |w: f64, phi: Complex64| -> f64 {
            -(Complex64::from_polar(1.0, w * tau / 2.0) * phi.conj()).re / phi.norm()
        };
        let g = &self.grid;
        let (a, b) = (g.omega[i], g.omega[i + 1]);
        let w = illinois(a, s(a, g.frf[i]), b, s(b, g.frf[i + 1]), |w| s(w, (self.frf)(w)))?;
        let phi = (self.frf)(w);
        let f = (Complex64::new(1.0, 0.0) - Complex64::from_polar(1.0, -w * tau)) * phi;
        let depth = -1.0 / (self.cutting.kt * self.cutting.alpha0 * f.re);
        (depth > 0.0 && depth.is_finite()).then_some((w, depth))
    }

    /// Critical depths on a speed grid (parallel over speeds).
    pub fn diagram(&self, rpm: &[f64]) -> Vec<CriticalPoint> {
        rpm.par_iter().map(|&n| self.critical_depth(n)).collect()
    }

    /// Minimum over a speed set (sequential; for cost functions inside parallel loops).
    pub fn min_depth(&self, rpm: &[f64]) -> CriticalPoint {
        rpm.iter()
            .map(|&n| self.critical_depth(n))
            .min_by(|a, b| a.depth.total_cmp(&b.depth))
            .unwrap_or(CriticalPoint { rpm: f64::NAN, depth: f64::INFINITY, chatter_hz: f64::NAN })
    }

    /// b_min and b_max of a computed diagram ([`extremes`]).
    pub fn extremes(&self, diagram: &[CriticalPoint]) -> Option<Extremes> {
        extremes(diagram, |n| self.critical_depth(n))
    }

    /// Classic lobes `k = 0..=k_max` from every grid frequency with `α₀ Re Φ < 0`. For `α₀ < 0`
    /// the equation is that of `|α₀|` with `−Φ`, so the same construction runs on `−Φ`.
    pub fn classic_lobes(&self, k_max: u32) -> Vec<Lobe> {
        let c = &self.cutting;
        let side = c.alpha0.signum();
        (0..=k_max)
            .map(|k| {
                let points = self
                    .grid
                    .omega
                    .iter()
                    .zip(&self.grid.frf)
                    .map(|(w, p)| (w, *p * side))
                    .filter(|(_, p)| p.re < 0.0)
                    .map(|(&w, p)| {
                        let depth = -1.0 / (2.0 * c.kt * c.alpha0.abs() * p.re);
                        let eps = 2.0 * (-p.re).atan2(p.im);
                        let rpm = 60.0 * w / (c.teeth as f64 * (2.0 * PI * k as f64 + eps));
                        (rpm, depth, w / (2.0 * PI))
                    })
                    .collect();
                Lobe { k, points }
            })
            .collect()
    }
}

/// b_min and b_max of a computed diagram, each refined by golden-section search on the exact
/// per-speed depth `depth_at` within one grid step of the best grid point (clamped to the range).
/// Shared by every solver that gives an exact depth per speed ([`LobeProblem`],
/// [`crate::frequency::ZeroOrder2d`], [`crate::frequency::MultiFrequency`]).
pub fn extremes(diagram: &[CriticalPoint], depth_at: impl Fn(f64) -> CriticalPoint) -> Option<Extremes> {
    if diagram.is_empty() {
        return None;
    }
    let lo = diagram.first()?.rpm;
    let hi = diagram.last()?.rpm;
    let imin = (0..diagram.len()).min_by(|&a, &b| diagram[a].depth.total_cmp(&diagram[b].depth))?;
    let imax = (0..diagram.len()).max_by(|&a, &b| diagram[a].depth.total_cmp(&diagram[b].depth))?;
    let bracket = |i: usize| {
        let l = if i > 0 { diagram[i - 1].rpm } else { lo };
        let r = if i + 1 < diagram.len() { diagram[i + 1].rpm } else { hi };
        (l, r)
    };
    let refine = |i: usize, sign: f64| {
        let (l, r) = bracket(i);
        let p = golden(|n| sign * depth_at(n).depth, l, r, 1e-6);
        let cp = depth_at(p);
        if sign * cp.depth < sign * diagram[i].depth { cp } else { diagram[i] }
    };
    Some(Extremes { min: refine(imin, 1.0), max: refine(imax, -1.0) })
}

/// Golden-section minimisation of a unimodal `f` on `[a, b]` to width `tol`.
fn golden<G: Fn(f64) -> f64>(f: G, mut a: f64, mut b: f64, tol: f64) -> f64 {
    let r = (5f64.sqrt() - 1.0) / 2.0;
    let mut c = b - r * (b - a);
    let mut d = a + r * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    while (b - a).abs() > tol {
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
    0.5 * (a + b)
}

/// A uniform speed grid `[lo, hi]` with `n` points.
pub fn speed_grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    if n < 2 {
        return vec![lo];
    }
    (0..n).map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Analytic SDOF receptance `1/(k − mω² + icω)`.
    fn sdof(m: f64, k: f64, zeta: f64) -> impl Fn(f64) -> Complex64 + Sync {
        let c = 2.0 * zeta * (m * k).sqrt();
        move |w: f64| Complex64::new(k - m * w * w, c * w).inv()
    }

    const M: f64 = 30.0;
    const K: f64 = 2.4e7;
    const ZETA: f64 = 0.0088;

    fn cutting() -> Cutting {
        Cutting { kt: 760e6, alpha0: 4.0 / (2.0 * PI) * (0.5 + 210.0 / 760.0 * PI / 4.0), teeth: 4 }
    }

    fn problem() -> LobeProblem<impl Fn(f64) -> Complex64 + Sync> {
        LobeProblem::new(sdof(M, K, ZETA), cutting(), &GridOptions::new(10.0, 2000.0, 4, 1000.0)).unwrap()
    }

    #[test]
    fn half_immersion_directional_factor_matches_closed_form() {
        let kr = 210.0 / 760.0;
        let closed = 4.0 / (2.0 * PI) * (0.5 + kr * PI / 4.0);
        assert_relative_eq!(directional_coefficient(4, kr, 0.0, PI / 2.0, 0.0), closed, max_relative = 1e-12);
        // down-milling, flexible normal to the feed: the same value by symmetry
        assert_relative_eq!(directional_coefficient(4, kr, PI / 2.0, PI, PI / 2.0), closed, max_relative = 1e-12);
        // and the plant's own closed-form antiderivatives agree
        let p = milling_plant::PlantParams::default();
        assert_relative_eq!(p.directional_coefficient(), closed, max_relative = 1e-12);
    }

    #[test]
    fn sdof_minimum_depth_is_analytic() {
        // min over N of −1/(2 Kt α0 Re Φ) with min Re Φ = −1/(4 k ζ (1 + ζ))
        let p = problem();
        let c = cutting();
        let analytic = 2.0 * K * ZETA * (1.0 + ZETA) / (c.kt * c.alpha0);
        let d = p.diagram(&speed_grid(1000.0, 3000.0, 2001));
        let ex = p.extremes(&d).unwrap();
        assert_relative_eq!(ex.min.depth, analytic, max_relative = 1e-3);
        // the golden refinement reaches the analytic value much more closely
        assert_relative_eq!(ex.min.depth, analytic, max_relative = 1e-6);
        // chatter frequency at the minimum: ω_n √(1 + 2ζ) ≈ ω_n (1 + ζ)
        let wn = (K / M).sqrt();
        assert_relative_eq!(2.0 * PI * ex.min.chatter_hz, wn * (1.0 + 2.0 * ZETA).sqrt(), max_relative = 1e-4);
    }

    #[test]
    fn envelope_lies_on_and_below_the_classic_lobes() {
        let p = problem();
        let lobes = p.classic_lobes(6);
        let mut on = 0;
        for lobe in &lobes {
            for &(rpm, depth, hz) in lobe.points.iter().step_by(7) {
                if !(1000.0..=3000.0).contains(&rpm) {
                    continue;
                }
                let cp = p.critical_depth(rpm);
                assert!(cp.depth <= depth * (1.0 + 1e-9), "rpm {rpm}: envelope {} above lobe {depth}", cp.depth);
                if (cp.depth - depth).abs() < 1e-9 * depth {
                    on += 1;
                    assert_relative_eq!(cp.chatter_hz, hz, max_relative = 1e-8);
                }
            }
        }
        assert!(on > 50, "only {on} classic lobe points are on the envelope");
    }

    #[test]
    fn depth_is_independent_of_grid_refinement() {
        let base = GridOptions::new(10.0, 2000.0, 4, 1000.0);
        let p1 = LobeProblem::new(sdof(M, K, ZETA), cutting(), &base).unwrap();
        let p2 = LobeProblem::new(sdof(M, K, ZETA), cutting(), &base.refined(10.0)).unwrap();
        assert!(p2.grid().len() > 5 * p1.grid().len());
        for rpm in speed_grid(1000.0, 3000.0, 97) {
            assert_relative_eq!(p1.critical_depth(rpm).depth, p2.critical_depth(rpm).depth, max_relative = 1e-9);
        }
    }

    #[test]
    fn refined_maximum_is_the_cusp_of_the_envelope() {
        let p = problem();
        let d = p.diagram(&speed_grid(1000.0, 3000.0, 2001));
        let ex = p.extremes(&d).unwrap();
        let grid_max = d.iter().map(|c| c.depth).fold(0.0, f64::max);
        assert!(ex.max.depth >= grid_max);
        // brute force on a 0.001 rpm grid around the refined peak
        let fine = speed_grid(ex.max.rpm - 0.5, ex.max.rpm + 0.5, 1001);
        let brute = fine.iter().map(|&n| p.critical_depth(n).depth).fold(0.0, f64::max);
        assert!(ex.max.depth >= brute * (1.0 - 1e-9));
        assert_relative_eq!(ex.max.depth, brute, max_relative = 1e-3);
    }

    #[test]
    fn the_minimum_is_analytic_for_both_signs_of_alpha0_and_zero_is_stable() {
        let grid = GridOptions::new(10.0, 2000.0, 4, 1000.0);
        for alpha0 in [0.4563, 0.2, -0.18, -0.4563] {
            let c = Cutting { alpha0, ..cutting() };
            let p = LobeProblem::new(sdof(M, K, ZETA), c, &grid).unwrap();
            let ex = p.extremes(&p.diagram(&speed_grid(1000.0, 3000.0, 2001))).unwrap();
            let analytic = if alpha0 > 0.0 {
                2.0 * K * ZETA * (1.0 + ZETA) / (c.kt * alpha0)
            } else {
                2.0 * K * ZETA * (1.0 - ZETA) / (c.kt * alpha0.abs())
            };
            assert_relative_eq!(ex.min.depth, analytic, max_relative = 1e-3);
            // chatter above the mode for α₀ > 0, below it for α₀ < 0
            let f_n = (K / M).sqrt() / (2.0 * PI);
            assert_eq!(ex.min.chatter_hz > f_n, alpha0 > 0.0, "α₀ {alpha0}: {} Hz vs {f_n} Hz", ex.min.chatter_hz);
            // the classic construction agrees on its lowest point
            let classic_min =
                p.classic_lobes(3).iter().flat_map(|l| l.points.iter()).map(|q| q.1).fold(f64::INFINITY, f64::min);
            assert_relative_eq!(classic_min, analytic, max_relative = 2e-3);
        }
        let c = Cutting { alpha0: 0.0, ..cutting() };
        let p = LobeProblem::new(sdof(M, K, ZETA), c, &grid).unwrap();
        assert!(p.critical_depth(2000.0).depth.is_infinite());
    }
}
