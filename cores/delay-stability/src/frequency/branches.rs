//! The frequency grid of a receptance and the eigenvalue branches on it (parent module docs).

use super::{Receptance, eig2};
use crate::bracket::{Crossing, illinois, phase_crossings, refine_best, unwrap_phase};
use crate::zero_order::{GridOptions, LobeError};
use nalgebra::Matrix2;
use num_complex::Complex64;
use std::f64::consts::PI;

/// An eigenvalue (or entry) this much smaller than the largest at the same frequency is not
/// followed (its phase is not meaningful).
const NEGLIGIBLE: f64 = 1e-9;

/// G on the adaptive grid: frequencies \[rad/s\] and values.
pub(crate) struct Sampled {
    pub omega: Vec<f64>,
    pub g: Vec<Matrix2<Complex64>>,
}

/// Phase and log-magnitude steps between two values, or `None` where either is negligible
/// against `scale`.
fn steps(l: Complex64, r: Complex64, scale: f64) -> Option<(f64, f64)> {
    let (nl, nr) = (l.norm(), r.norm());
    (nl > NEGLIGIBLE * scale && nr > NEGLIGIBLE * scale).then(|| ((r * l.conj()).arg().abs(), (nr / nl).ln().abs()))
}

/// The two eigenvalues of `r` paired with those of `l` (the pairing with the smaller distance).
fn paired(l: [Complex64; 2], r: [Complex64; 2]) -> [Complex64; 2] {
    if (r[0] - l[0]).norm() + (r[1] - l[1]).norm() <= (r[1] - l[0]).norm() + (r[0] - l[1]).norm() {
        r
    } else {
        [r[1], r[0]]
    }
}

/// Sample G adaptively (parent module docs): every entry and both eigenvalues of `hbar·G` change
/// by at most the phase and log-magnitude steps of `opt` between neighbours, and
/// `Δω ≤ 1/τ_max` ([`GridOptions::sample`]).
pub(crate) fn sample<R: Receptance + ?Sized>(
    frf: &R,
    hbar: &Matrix2<Complex64>,
    opt: &GridOptions,
) -> Result<Sampled, LobeError> {
    let eval = |w: f64| -> Result<(Matrix2<Complex64>, [Complex64; 2]), LobeError> {
        let g = frf.receptance(w);
        if g.iter().all(|v| v.re.is_finite() && v.im.is_finite()) && g.iter().any(|v| v.norm() > 0.0) {
            Ok((g, eig2(&(hbar * g))))
        } else {
            Err(LobeError::NonFiniteFrf { freq_hz: w / (2.0 * PI) })
        }
    };
    let too_big =
        |s: Option<(f64, f64)>| s.is_some_and(|(dp, dm)| dp > opt.max_phase_step || dm > opt.max_log_mag_step);
    let split = |l: &(Matrix2<Complex64>, [Complex64; 2]), r: &(Matrix2<Complex64>, [Complex64; 2])| {
        let gs = l.0.iter().chain(r.0.iter()).map(|v| v.norm()).fold(0.0, f64::max);
        if l.0.iter().zip(r.0.iter()).any(|(a, b)| too_big(steps(*a, *b, gs))) {
            return true;
        }
        let rp = paired(l.1, r.1);
        let ps = l.1[0].norm().max(rp[0].norm());
        (0..2).any(|j| too_big(steps(l.1[j], rp[j], ps)))
    };
    let out = opt.sample(eval, split)?;
    Ok(Sampled { omega: out.iter().map(|p| p.0).collect(), g: out.into_iter().map(|p| p.1.0).collect() })
}

/// Eigenvalue branches on a frequency grid: `p[b][i]` is branch b at `omega[i]`.
#[derive(Clone, Debug)]
pub(crate) struct Branches {
    pub omega: Vec<f64>,
    p: Vec<Vec<Complex64>>,
    phase: Vec<Vec<f64>>,
    present: Vec<Vec<bool>>,
}

/// Match the eigenvalues `cur` to the predictions `pred` (greedy on the distance, smallest first;
/// exhaustive for two): `out[b]` continues branch b.
fn assign(pred: &[Complex64], cur: &[Complex64]) -> Vec<Complex64> {
    let n = pred.len();
    if n == 2 {
        let p = paired([pred[0], pred[1]], [cur[0], cur[1]]);
        return p.to_vec();
    }
    let mut pairs: Vec<(f64, usize, usize)> =
        (0..n).flat_map(|b| (0..n).map(move |e| (b, e))).map(|(b, e)| ((cur[e] - pred[b]).norm(), b, e)).collect();
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
    let (mut used_b, mut used_e) = (vec![false; n], vec![false; n]);
    let mut out = vec![Complex64::new(0.0, 0.0); n];
    for (_, b, e) in pairs {
        if !used_b[b] && !used_e[e] {
            used_b[b] = true;
            used_e[e] = true;
            out[b] = cur[e];
        }
    }
    out
}

impl Branches {
    /// Follow the eigenvalues `eigs[i]` (all of the same length) along `omega` by nearest matching
    /// to the linear extrapolation of each branch.
    pub fn track(omega: Vec<f64>, eigs: Vec<Vec<Complex64>>) -> Branches {
        let n = eigs.first().map_or(0, Vec::len);
        let mut p: Vec<Vec<Complex64>> = vec![Vec::with_capacity(omega.len()); n];
        for (i, e) in eigs.iter().enumerate() {
            let next = if i == 0 {
                e.clone()
            } else {
                let pred: Vec<Complex64> = (0..n)
                    .map(|b| {
                        let last = p[b][i - 1];
                        if i < 2 {
                            return last;
                        }
                        let r = (omega[i] - omega[i - 1]) / (omega[i - 1] - omega[i - 2]);
                        last + (last - p[b][i - 2]) * r.min(1.0)
                    })
                    .collect();
                assign(&pred, e)
            };
            for (b, v) in next.into_iter().enumerate() {
                p[b].push(v);
            }
        }
        let present = (0..omega.len())
            .map(|i| {
                let big = (0..n).map(|b| p[b][i].norm()).fold(0.0, f64::max);
                (0..n).map(|b| p[b][i].norm() > NEGLIGIBLE * big).collect::<Vec<bool>>()
            })
            .collect::<Vec<_>>();
        let present = (0..n).map(|b| present.iter().map(|row| row[b]).collect()).collect();
        let phase = p.iter().map(|pb| unwrap_phase(pb.iter().copied())).collect();
        Branches { omega, p, phase, present }
    }

    /// Number of branches.
    pub fn len(&self) -> usize {
        self.p.len()
    }

    /// The smallest critical depth at delay `tau` as `(ω, depth)`; `eig_at(ω)` gives the exact
    /// eigenvalues at ω, `accept(ω, p)` may reject a root (parent module docs).
    pub fn critical(
        &self,
        tau: f64,
        eig_at: impl Fn(f64) -> Vec<Complex64>,
        accept: impl Fn(f64, Complex64) -> bool,
    ) -> Option<(f64, f64)> {
        let mut cands: Vec<Crossing> = Vec::new();
        for b in 0..self.len() {
            let (pb, ok) = (&self.p[b], &self.present[b]);
            let valid = |i: usize| ok[i] && ok[i + 1];
            phase_crossings((&self.omega, &self.phase[b]), |i| pb[i].norm(), tau, (-1.0, 2.0), valid, b, &mut cands);
        }
        refine_best(&cands, |c| {
            // a root the caller rejects at both ends of its bracket is not refined
            let (b, i) = (c.tag, c.index);
            if !accept(self.omega[i], self.p[b][i]) && !accept(self.omega[i + 1], self.p[b][i + 1]) {
                return None;
            }
            self.refine(b, i, tau, &eig_at).filter(|r| accept(r.0, r.2)).map(|r| (r.0, r.1))
        })
    }

    /// Root of `sin g` of branch `b` in grid interval `i` with the exact eigenvalues: (ω, depth, p).
    fn refine(
        &self,
        b: usize,
        i: usize,
        tau: f64,
        eig_at: &impl Fn(f64) -> Vec<Complex64>,
    ) -> Option<(f64, f64, Complex64)> {
        let (wa, wb) = (self.omega[i], self.omega[i + 1]);
        let (pa, pb) = (self.p[b][i], self.p[b][i + 1]);
        let pick = |w: f64| -> Complex64 {
            let guess = pa + (pb - pa) * ((w - wa) / (wb - wa));
            let e = eig_at(w);
            e.into_iter().min_by(|x, y| (x - guess).norm().total_cmp(&(y - guess).norm())).unwrap_or(guess)
        };
        // sin g = −Re(e^{iωτ/2} p̄)/|p|
        let s = |w: f64, p: Complex64| -(Complex64::from_polar(1.0, w * tau / 2.0) * p.conj()).re / p.norm();
        let w = illinois(wa, s(wa, pa), wb, s(wb, pb), |w| s(w, pick(w)))?;
        let p = pick(w);
        // a jump between eigenvalues inside the bracket is not a root
        if s(w, p).abs() > 1e-6 {
            return None;
        }
        let c = Complex64::new(1.0, 0.0) - Complex64::from_polar(1.0, -w * tau);
        let depth = 1.0 / (c * p).re;
        (depth > 0.0 && depth.is_finite()).then_some((w, depth, p))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_jump_between_eigenvalues_is_not_a_root() {
        // branch 0 turns from arg −π/2 − 0.3 to −π/2 + 0.3 across the grid interval: a bracketed
        // crossing of g = 0 with the positive-depth side; but the exact eigenvalues are the two
        // end values, constant, so the branch only jumps from one to the other at ω = 1.5
        let (pa, pb) = (Complex64::from_polar(1.0, -PI / 2.0 - 0.3), Complex64::from_polar(1.0, -PI / 2.0 + 0.3));
        let q = Complex64::new(-5.0, 0.0);
        let b = Branches::track(vec![1.0, 2.0], vec![vec![pa, q], vec![pb, q]]);
        let tau = 1e-3;
        assert!(b.critical(tau, |_| vec![pa, pb, q], |_, _| true).is_none());
        // a smooth turn of the same eigenvalue is a root, at arg p = −π/2 + ωτ/2
        let smooth = |w: f64| vec![Complex64::from_polar(1.0, -PI / 2.0 + 0.6 * (w - 1.5)), q];
        let (w, depth) = b.critical(tau, smooth, |_, _| true).unwrap();
        let p = smooth(w)[0];
        assert!((p.arg() - (-PI / 2.0 + w * tau / 2.0)).abs() < 1e-9, "{w}: {p}");
        let c = Complex64::new(1.0, 0.0) - Complex64::from_polar(1.0, -w * tau);
        assert!(((c * p).re * depth - 1.0).abs() < 1e-9);
    }
}
