//! The critical value of a parameter (the axial depth) where `ρ(Φ) = 1`, and lobes over a speed
//! grid.
//!
//! # Bracket and tolerance
//!
//! [`critical_value`] requires `ρ(Φ) < 1` at the parameter 0 (the structure with its controller
//! stable without cutting; otherwise [`StabilityError::UnstableAtStart`]). It then scans upwards
//! geometrically, `p = start, start·growth, start·growth², …`, until the first unstable value or
//! beyond `max` (then: stable up to `max`, no boundary), and bisects between the last stable and
//! the first unstable value until the bracket is below `rel_tol` of its upper end. The boundary
//! reported is the bracket's midpoint, the kind of instability that of the critical multiplier on
//! the unstable end. An unstable window narrower than one scan factor (`growth`) below the first
//! one found can be stepped over; with the default 1.1 this would need a flip lens whose depth
//! range is thinner than 10 %.
//!
//! Every speed is independent: [`lobes`] runs them in parallel with rayon and calls the progress
//! callback after each.

use crate::sd::{Bifurcation, Multiplier, critical_multiplier};
use crate::spectral::SpectralOptions;
use crate::{PeriodicDde, StabilityError};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Scan and bisection settings (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BisectionOptions {
    /// Semi-discretisation intervals per period.
    pub m: usize,
    /// First value of the scan (> 0).
    pub start: f64,
    /// Scan factor (> 1).
    pub growth: f64,
    /// Largest value searched.
    pub max: f64,
    /// Relative width of the final bracket.
    pub rel_tol: f64,
}

impl Default for BisectionOptions {
    fn default() -> Self {
        BisectionOptions { m: 40, start: 1e-5, growth: 1.1, max: 0.1, rel_tol: 1e-5 }
    }
}

/// The discretisation of the monodromy operator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// The spectral collocation with the order raised until the boundary moves by less than
    /// `tol` (relative) to the next order ([`crate::search`] module docs).
    Auto {
        /// Relative tolerance of the critical value.
        tol: f64,
    },
    /// The spectral collocation at a fixed order.
    Spectral(SpectralOptions),
    /// The first-order semi-discretisation with `m` intervals per period ([`crate::sd`]).
    Sd {
        /// Intervals per period.
        m: usize,
    },
}

impl Default for Method {
    fn default() -> Self {
        Method::Auto { tol: 1e-3 }
    }
}

/// The method as reports name it (`converged (spectral collocation, tolerance 1e-3)`,
/// `semi-discretisation, m = 40`, `spectral collocation, 12 nodes per element`).
impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Method::Auto { tol } => write!(f, "converged (spectral collocation, tolerance {tol:e})"),
            Method::Sd { m } => write!(f, "semi-discretisation, m = {m}"),
            Method::Spectral(s) => write!(f, "spectral collocation, {} nodes per element", s.nodes),
        }
    }
}

/// The boundary at one speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Critical {
    /// Critical value, `None` if stable up to `max`.
    pub value: Option<f64>,
    /// Critical multiplier on the unstable side.
    pub multiplier: Option<Multiplier>,
    /// Number of monodromy matrices (or operators) computed.
    pub evaluations: usize,
    /// The discretisation that gave the value (for [`Method::Auto`]: the order that converged).
    pub method: Method,
    /// [`Method::Auto`]: the estimated relative error of the value (the shift to the next
    /// order); otherwise `None`.
    pub error: Option<f64>,
}

impl Critical {
    /// Kind of the instability.
    pub fn kind(&self) -> Option<Bifurcation> {
        self.multiplier.map(|m| m.kind())
    }
}

/// The critical value of the parameter of `build` (module docs).
pub fn critical_value<S: PeriodicDde>(
    build: impl Fn(f64) -> Result<S, StabilityError>,
    o: &BisectionOptions,
) -> Result<Critical, StabilityError> {
    if !(o.start > 0.0 && o.growth > 1.0 && o.max > o.start && o.rel_tol > 0.0 && o.rel_tol < 1.0) {
        return Err(StabilityError::Invalid(format!("bad bisection options {o:?}")));
    }
    let mut evaluations = 0;
    let mut rho = |p: f64| -> Result<Multiplier, StabilityError> {
        evaluations += 1;
        critical_multiplier(&build(p)?, o.m)
    };
    let zero = rho(0.0)?;
    if zero.rho >= 1.0 {
        return Err(StabilityError::UnstableAtStart { value: 0.0, rho: zero.rho });
    }
    let (mut lo, mut hi) = (0.0, o.start);
    let mut at_hi = loop {
        let mu = rho(hi)?;
        if mu.rho >= 1.0 {
            break mu;
        }
        if hi >= o.max {
            return Ok(Critical {
                value: None,
                multiplier: None,
                evaluations,
                method: Method::Sd { m: o.m },
                error: None,
            });
        }
        lo = hi;
        hi = (hi * o.growth).min(o.max);
    };
    while hi - lo > o.rel_tol * hi {
        let mid = 0.5 * (lo + hi);
        let mu = rho(mid)?;
        if mu.rho < 1.0 {
            lo = mid;
        } else {
            hi = mid;
            at_hi = mu;
        }
    }
    Ok(Critical {
        value: Some(0.5 * (lo + hi)),
        multiplier: Some(at_hi),
        evaluations,
        method: Method::Sd { m: o.m },
        error: None,
    })
}

/// One point of a lobe diagram.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobePoint {
    /// Spindle speed \[rpm\].
    pub rpm: f64,
    /// The boundary there.
    pub critical: Critical,
}

/// The boundary at every speed of `speeds`, in parallel; `build(rpm, p)` is the system at speed
/// `rpm` and parameter `p`; `progress(done, total)` is called after each speed.
pub fn lobes<S, B>(
    speeds: &[f64],
    build: B,
    o: &BisectionOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<LobePoint>, StabilityError>
where
    S: PeriodicDde,
    B: Fn(f64, f64) -> Result<S, StabilityError> + Sync,
{
    let done = AtomicUsize::new(0);
    speeds
        .par_iter()
        .map(|&rpm| {
            let critical = critical_value(|p| build(rpm, p), o)?;
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, speeds.len());
            Ok(LobePoint { rpm, critical })
        })
        .collect()
}
