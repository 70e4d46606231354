//! The critical depth with a choice of method ([`Method`]: converged by default), a root-finder
//! instead of bisection, and warm starts; the lobes over speeds in parallel ([`lobes_with`]).
//!
//! # Search at one speed
//!
//! As [`crate::lobes::critical_value`]: `ρ(Φ) < 1` is required at depth 0, then the geometric scan
//! `start, start·g, start·g², …` up to the first unstable depth or `max`. **The scan is kept as
//! it was**, every depth of it evaluated with the final method and order: it is the protection
//! against a thin unstable window (a flip lens near its tip) below the first boundary found. A
//! window thinner than one scan factor `g` can be stepped over, as before (default 1.1: thinner
//! than 10 % in depth); nothing else is skipped. What changed is the cost of a scan point (a
//! high-order method of small dimension, the Krylov iteration warm-started from the previous
//! depth's leading Ritz vectors) and the refinement: inside the last bracket `[lo, hi]`
//! (`ρ(lo) < 1 ≤ ρ(hi)`) Brent's method on `ln ρ(a)` (smooth there: one multiplier crossing)
//! replaces the bisection; it keeps a bracket and stops when it is narrower than `rel_tol·hi`,
//! so the reported boundary is the midpoint of a bracket with a verified stable and unstable end,
//! as before, in about a third of the evaluations.
//!
//! # Converged by default
//!
//! [`Method::Auto`] runs the search with the spectral collocation ([`crate::spectral`]) at `N`
//! nodes per element, then evaluates `ρ` at the boundary `a` with the next order
//! `N' = N + max(4, N/2)`. The depth shift that `N'` implies, `|ln ρ_{N'}(a)| / (a · d ln ρ/da)`
//! (the slope from the final bracket), is the error estimate of `a`. It must be below `tol/3`,
//! so that a convergence as slow as first order in `N` (a non-smooth coefficient the system did
//! not declare as a breakpoint) is still within `tol`; otherwise the whole search is repeated at
//! `N'`, scan included. The bracket is narrowed to `tol/30` if `rel_tol` is wider, so that it
//! does not mask the estimate. Where no boundary was found below `max`, `ρ_{N'}(max) < 1` is
//! required. The order that converged is the starting order of the next speed of the same
//! block.
//!
//! # Speeds
//!
//! [`lobes_with`] cuts the speeds into contiguous blocks, runs the blocks in parallel (rayon) and
//! each block in order, so the order, the kernel cache and the Krylov warm start carry from one
//! speed to the next; the blocks are fixed by the speed list, so results do not depend on the
//! scheduling.

use crate::krylov::Krylov;
pub use crate::lobes::Method;
use crate::lobes::{BisectionOptions, Critical, LobePoint};
use crate::sd::{Multiplier, SdOperator, critical_multiplier, eigenvalues_unshifted_first};
use crate::spectral::{Spectral, SpectralOptions};
use crate::{PeriodicDde, StabilityError};
use num_complex::Complex64;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Options of [`critical`] and [`lobes_with`]: the method and the scan (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeOptions {
    /// The discretisation.
    pub method: Method,
    /// First value of the scan (> 0).
    pub start: f64,
    /// Scan factor (> 1).
    pub growth: f64,
    /// Largest value searched.
    pub max: f64,
    /// Relative width of the final bracket.
    pub rel_tol: f64,
}

impl Default for LobeOptions {
    fn default() -> Self {
        let b = BisectionOptions::default();
        LobeOptions { method: Method::default(), start: b.start, growth: b.growth, max: b.max, rel_tol: b.rel_tol }
    }
}

impl BisectionOptions {
    /// The same scan, converged by default ([`Method::Auto`], tolerance 1e-3) and with the
    /// root-finder: the one-line switch of a caller of [`crate::lobes()`] to [`lobes_with`].
    pub fn converged(&self) -> LobeOptions {
        LobeOptions {
            method: Method::default(),
            start: self.start,
            growth: self.growth,
            max: self.max,
            rel_tol: self.rel_tol,
        }
    }
}

/// First order of [`Method::Auto`] (nodes per element).
pub const AUTO_START: usize = 8;
/// Highest order [`Method::Auto`] tries.
pub const AUTO_MAX: usize = 96;
/// Dimension up to which the multipliers come from the dense matrix (above: Krylov).
pub const DENSE_MAX: usize = 40;

/// A spectral-radius evaluator with its caches and warm start.
struct Evaluator {
    kind: Kind,
    krylov: Krylov,
    work: Vec<f64>,
    evaluations: usize,
}

enum Kind {
    Sd(usize),
    Spectral(Box<Spectral>),
}

fn leading(values: &[Complex64]) -> Result<Multiplier, StabilityError> {
    let mu = *values.first().ok_or(StabilityError::Eigen { dim: 0 })?;
    Ok(Multiplier { mu, rho: mu.norm() })
}

impl Evaluator {
    fn new(method: Method, order: usize) -> Result<Evaluator, StabilityError> {
        let kind = match method {
            Method::Sd { m } => Kind::Sd(m),
            Method::Spectral(o) => Kind::Spectral(Box::new(Spectral::new(o)?)),
            Method::Auto { .. } => Kind::Spectral(Box::new(Spectral::new(SpectralOptions::new(order))?)),
        };
        Ok(Evaluator { kind, krylov: Krylov::default(), work: Vec::new(), evaluations: 0 })
    }

    fn method(&self) -> Method {
        match &self.kind {
            Kind::Sd(m) => Method::Sd { m: *m },
            Kind::Spectral(s) => Method::Spectral(s.options),
        }
    }

    fn multiplier<S: PeriodicDde>(&mut self, sys: &S) -> Result<Multiplier, StabilityError> {
        self.evaluations += 1;
        let work = &mut self.work;
        match &mut self.kind {
            Kind::Sd(m) => {
                let dim = sys.dim() + sys.delayed_output().nrows() * *m;
                if dim <= DENSE_MAX {
                    return critical_multiplier(sys, *m);
                }
                let op = SdOperator::new(sys, *m)?;
                leading(&self.krylov.dominant(dim, &mut |z, out| op.apply(z, out, work))?.values)
            }
            Kind::Spectral(s) => {
                let op = s.operator(sys)?;
                if op.dim() <= DENSE_MAX {
                    return leading(&eigenvalues_unshifted_first(&op.dense())?);
                }
                leading(&self.krylov.dominant(op.dim(), &mut |z, out| op.apply(z, out, work))?.values)
            }
        }
    }
}

fn check_options(o: &LobeOptions) -> Result<(), StabilityError> {
    let ok = o.start > 0.0 && o.growth > 1.0 && o.max > o.start && o.rel_tol > 0.0 && o.rel_tol < 1.0;
    let method_ok = match o.method {
        Method::Auto { tol } => tol > 0.0 && tol < 1.0,
        Method::Spectral(s) => s.nodes > 0,
        Method::Sd { m } => m > 0,
    };
    if !(ok && method_ok) {
        return Err(StabilityError::Invalid(format!("bad lobe options {o:?}")));
    }
    Ok(())
}

/// The boundary at one speed with one evaluator; also `ln ρ` at the final bracket's ends.
struct Found {
    critical: Critical,
    slope: f64,
}

fn search<S: PeriodicDde>(
    build: &impl Fn(f64) -> Result<S, StabilityError>,
    o: &LobeOptions,
    ev: &mut Evaluator,
) -> Result<Found, StabilityError> {
    let first = ev.evaluations;
    let rho = |p: f64, ev: &mut Evaluator| ev.multiplier(&build(p)?);
    let zero = rho(0.0, ev)?;
    if zero.rho >= 1.0 {
        return Err(StabilityError::UnstableAtStart { value: 0.0, rho: zero.rho });
    }
    let (mut lo, mut hi) = (0.0, o.start);
    let mut f_lo = zero.rho.ln();
    let mut at_hi = loop {
        let mu = rho(hi, ev)?;
        if mu.rho >= 1.0 {
            break mu;
        }
        if hi >= o.max {
            let critical = Critical {
                value: None,
                multiplier: None,
                evaluations: ev.evaluations - first,
                method: ev.method(),
                error: None,
            };
            return Ok(Found { critical, slope: f64::NAN });
        }
        lo = hi;
        f_lo = mu.rho.ln();
        hi = (hi * o.growth).min(o.max);
    };
    let mut f_hi = at_hi.rho.ln();
    // Brent's method on ln ρ (Numerical Recipes' zbrent); [lo (stable), hi (unstable)] is the
    // tightest bracket evaluated so far
    let (mut a, mut fa, mut b, mut fb) = (lo, f_lo, hi, f_hi);
    let (mut c, mut fc) = (b, fb);
    let (mut d, mut e) = (b - a, b - a);
    for _ in 0..200 {
        if hi - lo <= o.rel_tol * hi {
            break;
        }
        if (fb >= 0.0) == (fc >= 0.0) {
            (c, fc) = (a, fa);
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            (a, fa) = (b, fb);
            (b, fb) = (c, fc);
            (c, fc) = (a, fa);
        }
        let tol1 = 0.25 * o.rel_tol * hi;
        let xm = 0.5 * (c - b);
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            #[allow(clippy::float_cmp)] // Brent: the secant case is when a and c are the same point
            let secant = a == c;
            let (mut p, mut q) = if secant {
                (2.0 * xm * s, 1.0 - s)
            } else {
                let (qq, r) = (fa / fc, fb / fc);
                (s * (2.0 * xm * qq * (qq - r) - (b - a) * (r - 1.0)), (qq - 1.0) * (r - 1.0) * (s - 1.0))
            };
            if p > 0.0 {
                q = -q;
            }
            p = p.abs();
            if 2.0 * p < (3.0 * xm * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        (a, fa) = (b, fb);
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        let mu = rho(b, ev)?;
        fb = mu.rho.ln();
        if mu.rho >= 1.0 {
            if b < hi {
                (hi, f_hi, at_hi) = (b, fb, mu);
            }
        } else if b > lo {
            (lo, f_lo) = (b, fb);
        }
    }
    let slope = (f_hi - f_lo) / (hi - lo);
    let critical = Critical {
        value: Some(0.5 * (lo + hi)),
        multiplier: Some(at_hi),
        evaluations: ev.evaluations - first,
        method: ev.method(),
        error: None,
    };
    Ok(Found { critical, slope })
}

/// The next order of [`Method::Auto`].
fn next_order(n: usize) -> usize {
    n + (n / 2).max(4)
}

/// The critical value of the parameter of `build` (module docs); `order` is the first order of
/// [`Method::Auto`] (the last speed's), updated to the order that converged.
fn critical_from<S: PeriodicDde>(
    build: &impl Fn(f64) -> Result<S, StabilityError>,
    o: &LobeOptions,
    order: &mut usize,
    cache: &mut Option<Evaluator>,
) -> Result<Critical, StabilityError> {
    check_options(o)?;
    let Method::Auto { tol } = o.method else {
        let ev = match cache {
            Some(ev) => ev,
            None => cache.insert(Evaluator::new(o.method, 0)?),
        };
        return Ok(search(build, o, ev)?.critical);
    };
    // the error estimate cannot resolve less than the bracket: keep it well inside the tolerance
    let o = &LobeOptions { rel_tol: o.rel_tol.min(tol / 30.0), ..*o };
    let mut total = 0;
    loop {
        let n = *order;
        let ev = match cache {
            Some(ev) if ev.method() == Method::Spectral(SpectralOptions::new(n)) => ev,
            _ => cache.insert(Evaluator::new(o.method, n)?),
        };
        let found = search(build, o, ev)?;
        total += found.critical.evaluations;
        let higher = next_order(n);
        let mut check = Evaluator::new(o.method, higher)?;
        let point = found.critical.value.unwrap_or(o.max);
        let mu = check.multiplier(&build(point)?)?;
        total += 1;
        let error = match found.critical.value {
            Some(a) => mu.rho.ln().abs() / (a * found.slope.abs()),
            None if mu.rho < 1.0 => 0.0,
            None => f64::INFINITY,
        };
        if error <= tol / 3.0 || higher > AUTO_MAX {
            if error > tol / 3.0 {
                return Err(StabilityError::Invalid(format!(
                    "the spectral collocation did not converge to {tol} up to {n} nodes per element (estimate {error:.2e})"
                )));
            }
            let mut c = found.critical;
            c.evaluations = total;
            c.error = Some(error);
            return Ok(c);
        }
        *order = higher;
    }
}

/// The critical value of the parameter of `build` with the method and scan of `o` (module docs).
pub fn critical<S: PeriodicDde>(
    build: impl Fn(f64) -> Result<S, StabilityError>,
    o: &LobeOptions,
) -> Result<Critical, StabilityError> {
    critical_from(&build, o, &mut AUTO_START.clone(), &mut None)
}

/// Speeds per block of [`lobes_with`].
pub const BLOCK: usize = 8;

/// The boundary at every speed of `speeds` (module docs); `build(rpm, p)` is the system at speed
/// `rpm` and parameter `p`; `progress(done, total)` is called after each speed.
pub fn lobes_with<S, B>(
    speeds: &[f64],
    build: B,
    o: &LobeOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<LobePoint>, StabilityError>
where
    S: PeriodicDde,
    B: Fn(f64, f64) -> Result<S, StabilityError> + Sync,
{
    check_options(o)?;
    let done = AtomicUsize::new(0);
    let blocks: Vec<Vec<LobePoint>> = speeds
        .par_chunks(BLOCK)
        .map(|chunk| {
            let mut order = AUTO_START;
            let mut cache = None;
            chunk
                .iter()
                .map(|&rpm| {
                    let critical = critical_from(&|p| build(rpm, p), o, &mut order, &mut cache)?;
                    progress(done.fetch_add(1, Ordering::Relaxed) + 1, speeds.len());
                    Ok(LobePoint { rpm, critical })
                })
                .collect::<Result<Vec<_>, StabilityError>>()
        })
        .collect::<Result<_, _>>()?;
    Ok(blocks.into_iter().flatten().collect())
}
