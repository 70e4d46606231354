//! The stabilisation diagram and the choice of the physical poles.
//!
//! The LSCF model is fitted for increasing orders; a physical pole reappears at nearly the same
//! frequency and damping at every order, a computational (noise) pole does not. A pole is
//! *stable* at order n when the previous order has a pole within 1 % in frequency and 5 % in
//! damping. [`pick`] keeps the poles that are stable at [`MIN_STABLE`] consecutive orders up to
//! the highest, one per frequency cluster (within 1 %), taking its value at the highest order.

use crate::{FitError, Frfs, Pole, lscf};

/// Relative frequency tolerance of a stable pole.
pub const FREQUENCY_TOL: f64 = 0.01;
/// Relative damping tolerance of a stable pole.
pub const DAMPING_TOL: f64 = 0.05;
/// Consecutive stable orders a pole needs to be picked.
pub const MIN_STABLE: usize = 5;

/// What a pole of the diagram agrees with at the previous order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stability {
    /// Nothing at the previous order.
    New,
    /// Frequency within [`FREQUENCY_TOL`].
    Frequency,
    /// Frequency and damping within tolerance.
    Stable,
}

/// The poles of every order.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagram {
    /// The band \[Hz\].
    pub band: (f64, f64),
    /// `(order, poles with their stability)`, orders increasing.
    pub orders: Vec<(usize, Vec<(Pole, Stability)>)>,
}

fn close(a: &Pole, b: &Pole) -> Stability {
    let df = (a.frequency_hz() / b.frequency_hz() - 1.0).abs();
    let dz = (a.damping() / b.damping() - 1.0).abs();
    if df > FREQUENCY_TOL {
        Stability::New
    } else if dz > DAMPING_TOL {
        Stability::Frequency
    } else {
        Stability::Stable
    }
}

/// The diagram for `orders` (increasing) on `band`.
pub fn diagram(frf: &Frfs, band: (f64, f64), orders: impl IntoIterator<Item = usize>) -> Result<Diagram, FitError> {
    let mut out: Vec<(usize, Vec<(Pole, Stability)>)> = Vec::new();
    for n in orders {
        let poles = lscf::poles(frf, band, n)?;
        let prev: Vec<Pole> = out.last().map_or(Vec::new(), |(_, p)| p.iter().map(|x| x.0).collect());
        let marked = poles
            .into_iter()
            .map(|p| {
                let best = prev.iter().map(|q| close(&p, q)).max_by_key(|s| match s {
                    Stability::New => 0,
                    Stability::Frequency => 1,
                    Stability::Stable => 2,
                });
                (p, best.unwrap_or(Stability::New))
            })
            .collect();
        out.push((n, marked));
    }
    Ok(Diagram { band, orders: out })
}

/// The physical poles (module docs), sorted by frequency.
pub fn pick(d: &Diagram) -> Vec<Pole> {
    let Some((_, top)) = d.orders.last() else { return Vec::new() };
    let mut picked: Vec<Pole> = Vec::new();
    for (p, _) in top {
        // walk down the orders while a stable pole continues the chain
        let mut run = 0;
        let mut cur = *p;
        for (_, poles) in d.orders.iter().rev() {
            match poles.iter().find(|(q, s)| close(&cur, q) == Stability::Stable && *s == Stability::Stable) {
                Some((q, _)) => {
                    run += 1;
                    cur = *q;
                }
                None => break,
            }
        }
        if run >= MIN_STABLE && !picked.iter().any(|q| close(p, q) != Stability::New) {
            picked.push(*p);
        }
    }
    picked.sort_by(|a, b| a.frequency_hz().total_cmp(&b.frequency_hz()));
    picked
}
