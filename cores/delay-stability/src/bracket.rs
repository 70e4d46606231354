//! Bracket-and-refine primitives shared by the frequency-domain lobe solvers
//! ([`crate::zero_order`] for one direction, [`crate::frequency`] for 2 × 2 receptances):
//!
//! * [`bisect_grid`]: a logarithmic frequency grid whose intervals are bisected until a
//!   caller's criterion (phase and magnitude steps of the sampled values) is met;
//! * [`unwrap_phase`]: the continuous phase of a sampled complex function;
//! * [`phase_crossings`]: at one delay τ, every grid interval where the phase function
//!   `g(ω) = ωτ/2 − φ(ω) − π/2` crosses a multiple `jπ` on the side that gives a positive depth,
//!   with the depth estimated from the interpolated magnitude;
//! * [`refine_best`]: refine the candidates whose estimate is within 5 % of the smallest and keep
//!   the smallest exact depth;
//! * [`illinois`]: the bracketing root finder (Illinois regula falsi) of the exact refinement.
//!
//! The conventions (why a crossing of `jπ` is a chatter root and which side gives `a > 0`) are
//! those of [`crate::zero_order`]'s module docs: a root of `1 − a·c·(1 − e^{−iωτ})·p(ω) = 0` with
//! `a > 0` needs `g(ω) = jπ` (φ = arg p) and `c·sin(ωτ/2)·(−1)^j > 0`, and then
//! `a = 1/(2|c| |sin(ωτ/2)| |p|)`. In the callers' terms `c = −K_t α₀` (one direction, so the side
//! is `−sign α₀`) or `c = 1` (an eigenvalue `p` of `H̄ G`, [`crate::frequency`]).

use num_complex::Complex64;
use std::f64::consts::PI;

/// Sample `eval` on `[w0, w1]`: `n0` logarithmically spaced points, each interval bisected (depth
/// first, left to right) while `split(ω_l, left, ω_r, right)` asks for it and the interval is
/// wider than `1e-10 ω_r`. Fails with `too_many()` beyond `max_points` points.
pub(crate) fn bisect_grid<S: Clone, E>(
    (w0, w1): (f64, f64),
    n0: usize,
    max_points: usize,
    eval: impl Fn(f64) -> Result<S, E>,
    split: impl Fn(f64, &S, f64, &S) -> bool,
    too_many: impl Fn() -> E,
) -> Result<Vec<(f64, S)>, E> {
    let n0 = n0.max(2);
    let sample = |w: f64| eval(w).map(|s| (w, s));
    let mut out = vec![sample(w0)?];
    for i in 1..n0 {
        let w = w0 * (w1 / w0).powf(i as f64 / (n0 - 1) as f64);
        let mut stack = vec![sample(w)?];
        while let Some(r) = stack.last().cloned() {
            let l = out.last().expect("non-empty").clone();
            if r.0 - l.0 > 1e-10 * r.0 && split(l.0, &l.1, r.0, &r.1) {
                stack.push(sample(0.5 * (l.0 + r.0))?);
            } else {
                out.push(r);
                stack.pop();
            }
            if out.len() + stack.len() > max_points {
                return Err(too_many());
            }
        }
    }
    Ok(out)
}

/// The unwrapped phase of a sequence: `arg v₀`, then the principal angle between neighbours.
pub(crate) fn unwrap_phase(values: impl IntoIterator<Item = Complex64>) -> Vec<f64> {
    let mut it = values.into_iter();
    let Some(first) = it.next() else { return Vec::new() };
    let mut phase = vec![first.arg()];
    let (mut acc, mut prev) = (first.arg(), first);
    for v in it {
        acc += (v * prev.conj()).arg();
        phase.push(acc);
        prev = v;
    }
    phase
}

/// A bracketed chatter root: grid interval `index`, depth estimated by interpolation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Crossing {
    /// Estimated depth.
    pub est: f64,
    /// The root lies in `[ω_index, ω_index+1]`.
    pub index: usize,
    /// The caller's label (e.g. the eigenvalue branch).
    pub tag: usize,
}

/// Append to `out` every crossing of `g(ω) = ωτ/2 − φ(ω) − π/2` through a multiple `jπ` in the
/// intervals `valid(i)` of the grid `omega` (unwrapped phase `phase`, magnitude `mag(i)`) where
/// `side·sin(ωτ/2)·(−1)^j < 0` (a positive depth); the estimate is
/// `1/(scale·|sin(ωτ/2)|·|p|)` at the linearly interpolated crossing, `|p|` interpolated
/// geometrically. Each crossing carries `tag`.
pub(crate) fn phase_crossings(
    (omega, phase): (&[f64], &[f64]),
    mag: impl Fn(usize) -> f64,
    tau: f64,
    (side, scale): (f64, f64),
    valid: impl Fn(usize) -> bool,
    tag: usize,
    out: &mut Vec<Crossing>,
) {
    let gfun = |i: usize| omega[i] * tau / 2.0 - phase[i] - PI / 2.0;
    let Some(mut g_prev) = (!omega.is_empty()).then(|| gfun(0)) else { return };
    for i in 0..omega.len().saturating_sub(1) {
        let g_next = gfun(i + 1);
        let (m0, m1) = ((g_prev / PI).floor() as i64, (g_next / PI).floor() as i64);
        if m0 != m1 && valid(i) {
            for j in m0.min(m1) + 1..=m0.max(m1) {
                let t = (j as f64 * PI - g_prev) / (g_next - g_prev);
                let w = omega[i] + t * (omega[i + 1] - omega[i]);
                let s_half = (w * tau / 2.0).sin();
                let sign = if j.rem_euclid(2) == 0 { 1.0 } else { -1.0 };
                if side * s_half * sign < 0.0 {
                    let m = mag(i).powf(1.0 - t) * mag(i + 1).powf(t);
                    out.push(Crossing { est: 1.0 / (scale * s_half.abs() * m), index: i, tag });
                }
            }
        }
        g_prev = g_next;
    }
}

/// Refine the crossings in order of their estimate; `refine` returns the exact `(ω, depth)` of a
/// crossing or `None` (no root, or one the caller rejects). Every crossing whose estimate is
/// within 5 % of the smallest exact depth found so far is refined (and all of them until one
/// succeeds), and the smallest exact depth wins.
pub(crate) fn refine_best(
    cands: &[Crossing],
    mut refine: impl FnMut(&Crossing) -> Option<(f64, f64)>,
) -> Option<(f64, f64)> {
    let mut order: Vec<&Crossing> = cands.iter().collect();
    order.sort_by(|a, b| a.est.total_cmp(&b.est));
    let mut best: Option<(f64, f64)> = None;
    for c in order {
        if best.is_some_and(|b| c.est > 1.05 * b.1) {
            break;
        }
        if let Some((w, depth)) = refine(c)
            && best.is_none_or(|b| depth < b.1)
        {
            best = Some((w, depth));
        }
    }
    best
}

/// Root of `f` in `[a, b]` with `f(a) = fa`, `f(b) = fb` of opposite signs, by Illinois regula
/// falsi to a relative width of 1e-12 (at most 200 steps). If the signs agree, an end where
/// `|f| ≤ 1e-9` is taken as the root (a root on a grid point, up to rounding); otherwise `None`.
pub(crate) fn illinois(mut a: f64, mut fa: f64, mut b: f64, mut fb: f64, f: impl Fn(f64) -> f64) -> Option<f64> {
    let mut w = 0.5 * (a + b);
    let mut iterations = 200;
    if fa * fb > 0.0 {
        if fa.abs().min(fb.abs()) > 1e-9 {
            return None;
        }
        w = if fa.abs() < fb.abs() { a } else { b };
        iterations = 0;
    }
    for _ in 0..iterations {
        // b is the newest point, [a, b] always brackets the root
        w = (a * fb - b * fa) / (fb - fa);
        if !w.is_finite() || w <= a.min(b) || w >= a.max(b) {
            w = 0.5 * (a + b);
        }
        let fw = f(w);
        if fw == 0.0 {
            break;
        }
        if fw * fb < 0.0 {
            a = b;
            fa = fb;
        } else {
            fa *= 0.5;
        }
        b = w;
        fb = fw;
        if (b - a).abs() < 1e-12 * w {
            break;
        }
    }
    Some(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn illinois_finds_a_simple_root_and_refuses_an_unbracketed_one() {
        let f = |x: f64| x * x - 2.0;
        let r = illinois(1.0, f(1.0), 2.0, f(2.0), f).unwrap();
        assert!((r - 2f64.sqrt()).abs() < 1e-12);
        assert!(illinois(2.0, f(2.0), 3.0, f(3.0), f).is_none());
        // a root on the end of the bracket (same sign up to rounding) is accepted as it is
        assert_eq!(illinois(2f64.sqrt(), 1e-12, 3.0, f(3.0), f), Some(2f64.sqrt()));
    }

    #[test]
    fn the_grid_is_refined_where_asked() {
        let g = bisect_grid((1.0, 100.0), 3, 1000, Ok::<f64, ()>, |wl, _, wr, _| wl < 10.0 && wr - wl > 1.0, || ())
            .unwrap();
        let w: Vec<f64> = g.iter().map(|p| p.0).collect();
        assert!(w.windows(2).all(|p| p[1] > p[0]));
        assert!(w.windows(2).filter(|p| p[0] < 10.0).all(|p| p[1] - p[0] <= 1.0));
        assert!(bisect_grid((1.0, 100.0), 3, 5, Ok::<f64, ()>, |_, _, _, _| true, || ()).is_err());
    }
}
