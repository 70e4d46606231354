//! A high-order monodromy operator: exponential spectral-element collocation of
//! `ẋ = A(t)x + B_d(t) C_d x(t − τ)`, `T = τ`.
//!
//! # Discretisation
//!
//! With the system's [`Splitting`] `A(t) = A₀ + G P(t) C₀`, `B_d(t) = G Q(t)` (milling: the
//! structure and controller `A₀`, the cutting force through `G`), variation of constants over an
//! element `[t_a, t_a + h]` gives exactly
//!
//! ```text
//! x(t_a + hθ) = e^{A₀hθ} x(t_a) + h ∫₀^θ e^{A₀h(θ−σ)} G v(t_a + hσ) dσ,   v = P C₀ x + Q C_d x(t − τ).
//! ```
//!
//! The input `v` is replaced by its polynomial interpolant of degree `N − 1` through the `N`
//! Gauss–Legendre nodes `θ_j` of the element (collocation): the structure's own dynamics are
//! integrated exactly (matrix exponentials, [`kernels`]), only `v` is approximated, and where no
//! tooth cuts (`P = Q = 0`) an element is one exponential. The period is cut into elements at the
//! system's [`PeriodicDde::breakpoints`] (tooth entry and exit: the coefficients are smooth inside
//! every element) and further into pieces of at most `oscillations` periods of the fastest
//! eigenvalue of `A₀`. For smooth coefficients the error falls exponentially with `N` (the
//! interpolation error of an analytic function), against `O(1/m²)` for the first-order
//! semi-discretisation ([`crate::sd`]).
//!
//! Where the coefficients are unbounded ([`PeriodicDde::singularities`]: the power-law force
//! `h^{x_F − 1}` at a zero chip) the elements are graded geometrically towards the singular
//! instant: layers of relative lengths `σ^L, σ^{L−1} − σ^L, …, σ − σ²` ([`GRADING`] σ = 0.15,
//! `L = ⌈N/2⌉ + 2` layers), the hp-refinement that restores exponential convergence for such
//! algebraic singularities (Schwab, *p- and hp-Finite Element Methods*, 1998): seed 002's
//! `x_F = 0.744` converges to 1e-8 at N = 12, against 2e-3 without the grading.
//!
//! Because `T = τ`, the delayed output at a node of this period is the output at the same node of
//! the previous period: the state of the period map is `(x(0), y_j of the previous period)` at
//! the nodes of the elements where `Q ≠ 0`, `y = C_d x`, dimension `n + r·(nodes with delay)`.
//! On one element the collocation equations for `z_j = C₀ x(t_j)` are
//!
//! ```text
//! z_i = C₀E_i x_a + Σ_j C₀W_ij (P_j z_j + Q_j ỹ_j),    E_i = e^{A₀hθ_i},   W_ij = h ∫₀^{θ_i} e^{A₀h(θ_i−σ)} ℓ_j(σ) dσ G,
//! ```
//!
//! a `pN` linear system; then `x_b`, the new `y_i` follow linearly. Each element is therefore a
//! small linear map `(x_a, ỹ) ↦ (x_b, y)`, built once per depth; the monodromy operator is their
//! composition ([`Operator::apply`], no allocation) and the dense matrix Φ its reference
//! ([`Operator::dense`]).
//!
//! # Without a splitting
//!
//! A system that gives no [`PeriodicDde::splitting`] uses `A₀` = the mean of `A` over the period,
//! `G = C₀ = I`, `P = A(t) − A₀`, `Q = B_d(t)` (point values from [`PeriodicDde::at`]).

pub(crate) mod kernels;
#[cfg(test)]
mod tests;

use crate::{PeriodicDde, Splitting, StabilityError};
use kernels::{Kernels, Nodes};
use nalgebra::{DMatrix, DVectorView, DVectorViewMut};

/// Settings of the spectral collocation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpectralOptions {
    /// Gauss–Legendre nodes per element (the order; ≥ 1).
    pub nodes: usize,
    /// Longest element, in periods of the fastest eigenvalue of `A₀` (`2π/max|λ|`).
    pub oscillations: f64,
}

impl SpectralOptions {
    /// `nodes` per element, elements of at most one oscillation.
    pub fn new(nodes: usize) -> SpectralOptions {
        SpectralOptions { nodes, oscillations: 1.0 }
    }

    /// Geometric layers towards a singularity: `⌈N/2⌉ + 2`.
    pub fn layers(&self) -> usize {
        self.nodes.div_ceil(2) + 2
    }
}

/// Ratio of successive element lengths towards a singularity.
pub const GRADING: f64 = 0.15;

/// One element of the period.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Element {
    t0: f64,
    kernel: usize,
}

/// Element layout and kernels for one system shape (speed), reused across depths.
#[derive(Clone, Debug)]
struct Cache {
    split: Splitting,
    generic: bool,
    cd: DMatrix<f64>,
    period: f64,
    breakpoints: Vec<f64>,
    elements: Vec<Element>,
    lengths: Vec<f64>,
    kernels: Vec<Kernels>,
}

/// The spectral collocation for systems of one shape: the kernels of the element lengths are
/// computed once and reused while the constant part, the period and the breakpoints stay the same
/// (every depth at one speed).
#[derive(Clone, Debug)]
pub struct Spectral {
    /// The settings.
    pub options: SpectralOptions,
    nodes: Nodes,
    cache: Option<Cache>,
}

/// The element maps of one system (module docs): `(x_a, ỹ) ↦ (x_b, y)`.
#[derive(Clone, Debug)]
enum Map {
    /// No input on the element: `x_b = e^{A₀h} x_a`.
    Free(DMatrix<f64>),
    /// `x_b = X_x x_a + X_y ỹ`, `y = Y_x x_a + Y_y ỹ` (the last three only with a delay there).
    Active { xx: DMatrix<f64>, delayed: Option<Delayed> },
}

#[derive(Clone, Debug)]
struct Delayed {
    offset: usize,
    xy: DMatrix<f64>,
    yx: DMatrix<f64>,
    yy: DMatrix<f64>,
}

/// The monodromy operator of one system: its elements' maps.
#[derive(Clone, Debug)]
pub struct Operator {
    n: usize,
    dim: usize,
    maps: Vec<Map>,
}

fn nonzero(m: &DMatrix<f64>) -> bool {
    m.iter().any(|&v| v != 0.0)
}

impl Spectral {
    /// The collocation with these settings.
    pub fn new(options: SpectralOptions) -> Result<Spectral, StabilityError> {
        if options.nodes == 0 || !(options.oscillations.is_finite() && options.oscillations > 0.0) {
            return Err(StabilityError::Invalid(format!("bad spectral options {options:?}")));
        }
        Ok(Spectral { options, nodes: Nodes::new(options.nodes), cache: None })
    }

    /// Dimension of the state `n + r·(nodes with delay)` of the last operator's layout.
    fn layout<S: PeriodicDde + ?Sized>(&mut self, sys: &S) -> Result<&Cache, StabilityError> {
        let n = sys.dim();
        let period = sys.period();
        let cd = sys.delayed_output();
        if n == 0 || cd.nrows() == 0 || cd.ncols() != n {
            return Err(StabilityError::Invalid(format!(
                "empty or inconsistent system (n = {n}, C_d {:?})",
                cd.shape()
            )));
        }
        if !(period.is_finite() && period > 0.0) {
            return Err(StabilityError::Invalid(format!("the period must be finite and > 0 (got {period})")));
        }
        let (split, generic) = match sys.splitting() {
            Some(s) => (s, false),
            None => {
                let a0 = sys.averaged(0.0, period).0;
                (Splitting { a0, g: DMatrix::identity(n, n), c0: DMatrix::identity(n, n) }, true)
            }
        };
        let (k, p) = (split.g.ncols(), split.c0.nrows());
        if split.a0.shape() != (n, n) || split.g.nrows() != n || split.c0.ncols() != n || k == 0 || p == 0 {
            return Err(StabilityError::Invalid("the splitting does not fit the system".into()));
        }
        if split.a0.iter().chain(split.g.iter()).chain(split.c0.iter()).any(|v| !v.is_finite()) {
            return Err(StabilityError::Invalid("the splitting has non-finite entries".into()));
        }
        let mut breakpoints: Vec<f64> = sys.breakpoints().into_iter().filter(|&t| t > 0.0 && t < period).collect();
        breakpoints.sort_by(f64::total_cmp);
        // the same system shape bit for bit (every depth of one speed): the kernels are valid
        #[allow(clippy::float_cmp)]
        let same = self.cache.as_ref().is_some_and(|c| {
            c.split == split && c.cd == cd && c.period == period && c.breakpoints == breakpoints && c.generic == generic
        });
        if !same {
            let omega = split.a0.complex_eigenvalues().iter().map(|z| z.norm()).fold(0.0, f64::max);
            let h_max =
                if omega > 0.0 { self.options.oscillations * 2.0 * std::f64::consts::PI / omega } else { period };
            let mut ends = vec![0.0];
            ends.extend(&breakpoints);
            ends.push(period);
            let singular = sys.singularities();
            let is_singular = |t: f64| {
                singular.iter().any(|&s| {
                    let d = (t - s).abs();
                    d <= 1e-12 * period || (s <= 1e-12 * period && (t - period).abs() <= 1e-12 * period)
                })
            };
            let mut elements = Vec::new();
            let mut lengths: Vec<f64> = Vec::new();
            let mut push = |t0: f64, h: f64, elements: &mut Vec<Element>| {
                let kernel = match lengths.iter().position(|&l| (l - h).abs() <= 1e-13 * h) {
                    Some(i) => i,
                    None => {
                        lengths.push(h);
                        lengths.len() - 1
                    }
                };
                elements.push(Element { t0, kernel });
            };
            let layers = self.options.layers();
            for w in ends.windows(2) {
                let len = w[1] - w[0];
                if len <= 1e-13 * period {
                    continue;
                }
                let (sa, sb) = (is_singular(w[0]), is_singular(w[1]));
                // geometric layers towards a singular end: [0, σ^L], [σ^L, σ^{L−1}], … [σ², σ] of
                // the distance to the piece's middle (or end)
                let reach = if sa && sb { 0.5 * len } else { len };
                let graded = |k: usize| reach * GRADING.powi(k as i32);
                let (mut a, mut b) = (w[0], w[1]);
                if sa {
                    let mut prev = 0.0;
                    for k in (1..=layers).rev() {
                        push(w[0] + prev, graded(k) - prev, &mut elements);
                        prev = graded(k);
                    }
                    a = w[0] + graded(1);
                }
                let mut tail = Vec::new();
                if sb {
                    let mut prev = 0.0;
                    for k in (1..=layers).rev() {
                        tail.push((w[1] - graded(k), graded(k) - prev));
                        prev = graded(k);
                    }
                    b = w[1] - graded(1);
                }
                let mid = b - a;
                let count = (mid / h_max).ceil().max(1.0) as usize;
                let h = mid / count as f64;
                for i in 0..count {
                    push(a + i as f64 * h, h, &mut elements);
                }
                for &(t0, h) in tail.iter().rev() {
                    push(t0, h, &mut elements);
                }
            }
            let kernels =
                lengths.iter().map(|&h| Kernels::new(&split.a0, &split.g, &split.c0, &cd, h, &self.nodes)).collect();
            self.cache = Some(Cache { split, generic, cd, period, breakpoints, elements, lengths, kernels });
        }
        Ok(self.cache.as_ref().expect("set above"))
    }

    /// The monodromy operator of `sys` (module docs).
    pub fn operator<S: PeriodicDde + ?Sized>(&mut self, sys: &S) -> Result<Operator, StabilityError> {
        let nn = self.nodes.len();
        let theta = self.nodes.theta.clone();
        let n = sys.dim();
        let cache = self.layout(sys)?;
        let (k, p, r) = (cache.split.g.ncols(), cache.split.c0.nrows(), cache.cd.nrows());
        let mut maps = Vec::with_capacity(cache.elements.len());
        let mut dim = n;
        for el in &cache.elements {
            let kern = &cache.kernels[el.kernel];
            let h = cache.lengths[el.kernel];
            let mut pb = DMatrix::<f64>::zeros(k * nn, p * nn);
            let mut qb = DMatrix::<f64>::zeros(k * nn, r * nn);
            for (j, &th) in theta.iter().enumerate() {
                let t = el.t0 + h * th;
                let (pj, qj) = if cache.generic {
                    let (a, b) = sys.at(t);
                    (a - &cache.split.a0, b)
                } else {
                    sys.gains(t)
                };
                if pj.shape() != (k, p) || qj.shape() != (k, r) {
                    return Err(StabilityError::Invalid(format!(
                        "gains of shape {:?}, {:?}, expected ({k}, {p}), ({k}, {r})",
                        pj.shape(),
                        qj.shape()
                    )));
                }
                if pj.iter().chain(qj.iter()).any(|v| !v.is_finite()) {
                    return Err(StabilityError::Invalid(format!("non-finite coefficients at t = {t}")));
                }
                pb.view_mut((k * j, p * j), (k, p)).copy_from(&pj);
                qb.view_mut((k * j, r * j), (k, r)).copy_from(&qj);
            }
            let has_p = nonzero(&pb);
            let has_q = nonzero(&qb);
            if !has_p && !has_q {
                maps.push(Map::Free(kern.eend.clone()));
                continue;
            }
            let mut az = DMatrix::<f64>::identity(p * nn, p * nn);
            if has_p {
                az -= &kern.cw0 * &pb;
            }
            let lu = az.lu();
            let singular =
                || StabilityError::Invalid("singular collocation system (a depth far beyond stability?)".into());
            let mzx = lu.solve(&kern.ce0).ok_or_else(singular)?;
            let vx = &pb * &mzx;
            let xx = &kern.eend + &kern.wend * &vx;
            let delayed = if has_q {
                let mzy = lu.solve(&(&kern.cw0 * &qb)).ok_or_else(singular)?;
                let vy = &pb * &mzy + &qb;
                let d =
                    Delayed { offset: dim, xy: &kern.wend * &vy, yx: &kern.ced + &kern.cwd * &vx, yy: &kern.cwd * &vy };
                dim += r * nn;
                Some(d)
            } else {
                None
            };
            maps.push(Map::Active { xx, delayed });
        }
        Ok(Operator { n, dim, maps })
    }

    /// The dense monodromy matrix of `sys` (the reference; [`Operator::dense`]).
    pub fn monodromy<S: PeriodicDde + ?Sized>(&mut self, sys: &S) -> Result<DMatrix<f64>, StabilityError> {
        Ok(self.operator(sys)?.dense())
    }

    /// Number of elements and of nodes with a delayed term in the current layout.
    pub fn elements(&self) -> usize {
        self.cache.as_ref().map_or(0, |c| c.elements.len())
    }
}

impl Operator {
    /// Dimension of the state (module docs).
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// `out = Φ z`; `work` holds two scratch vectors of length n (resized once).
    pub fn apply(&self, z: &[f64], out: &mut [f64], work: &mut Vec<f64>) {
        let n = self.n;
        work.resize(2 * n, 0.0);
        let (xa, xb) = work.split_at_mut(n);
        xa.copy_from_slice(&z[..n]);
        let (mut xa, mut xb) = (xa, xb);
        for map in &self.maps {
            {
                let x = DVectorView::from_slice(xa, n);
                let mut xo = DVectorViewMut::from_slice(xb, n);
                match map {
                    Map::Free(e) => xo.gemv(1.0, e, &x, 0.0),
                    Map::Active { xx, delayed } => {
                        xo.gemv(1.0, xx, &x, 0.0);
                        if let Some(d) = delayed {
                            let len = d.yy.nrows();
                            let y = DVectorView::from_slice(&z[d.offset..d.offset + len], len);
                            xo.gemv(1.0, &d.xy, &y, 1.0);
                            let mut yo = DVectorViewMut::from_slice(&mut out[d.offset..d.offset + len], len);
                            yo.gemv(1.0, &d.yx, &x, 0.0);
                            yo.gemv(1.0, &d.yy, &y, 1.0);
                        }
                    }
                }
            }
            std::mem::swap(&mut xa, &mut xb);
        }
        out[..n].copy_from_slice(xa);
    }

    /// The dense matrix Φ (the elements' maps composed on the identity).
    pub fn dense(&self) -> DMatrix<f64> {
        let (n, dim) = (self.n, self.dim);
        let mut phi = DMatrix::<f64>::zeros(dim, dim);
        let mut t = DMatrix::<f64>::zeros(n, dim);
        t.view_mut((0, 0), (n, n)).fill_with_identity();
        for map in &self.maps {
            t = match map {
                Map::Free(e) => e * &t,
                Map::Active { xx, delayed } => {
                    let mut next = xx * &t;
                    if let Some(d) = delayed {
                        let len = d.yy.nrows();
                        let mut rows = &d.yx * &t;
                        let mut block = rows.columns_mut(d.offset, len);
                        block += &d.yy;
                        phi.rows_mut(d.offset, len).copy_from(&rows);
                        let mut nb = next.columns_mut(d.offset, len);
                        nb += &d.xy;
                    }
                    next
                }
            };
        }
        phi.rows_mut(0, n).copy_from(&t);
        phi
    }
}
