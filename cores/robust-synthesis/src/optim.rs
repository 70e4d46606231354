//! Nonsmooth minimisation: BFGS with a weak Wolfe line search, then gradient sampling (HANSO).
//!
//! # BFGS on nonsmooth functions (Lewis & Overton 2013)
//!
//! From `x₀` with inverse Hessian `H₀ = I`, the direction is `d = −H g`. The step `t` satisfies
//! the weak Wolfe conditions
//!
//! ```text
//! f(x + t d) ≤ f(x) + c₁ t gᵀd          (Armijo, c₁ = 1e-4)
//! g(x + t d)ᵀ d ≥ c₂ gᵀd                 (weak curvature, c₂ = 0.5)
//! ```
//!
//! found by bracketing (`t = 1`; Armijo fails → upper end, curvature fails → lower end; next
//! `t` is the midpoint, or twice the lower end while no upper end exists). Only the weak
//! conditions are used because `g` jumps across the kinks of a nonsmooth `f`. `H` is updated by
//! the BFGS formula with `s = t d`, `y = g₊ − g` (`yᵀs > 0` by the curvature condition). BFGS
//! stops when the line search fails (typically at a kink it cannot cross), when `‖g‖` is below
//! `tol`, or after `max_iter` iterations.
//!
//! # Gradient sampling (Burke, Lewis & Overton 2005)
//!
//! With sampling radius `ε` (initially `radius`): sample `n + 1` points uniformly in the ball of
//! radius `ε` about `x` (a seeded ChaCha stream), take the gradients there and at `x`, and find
//! the smallest-norm element `d` of their convex hull (a quadratic programme on the simplex,
//! solved by accelerated projected gradient). If `‖d‖ ≤ tol`, `x` is ε-stationary: shrink `ε` by
//! 10 (stop below `radius_min`). Otherwise backtrack from `t = 1` along `−d` until
//! `f(x − t d) < f(x) − β t ‖d‖²` (β = 1e-6), or shrink `ε` if none is found. The sampled
//! gradients are independent and computed in parallel (rayon); the sample points come from the
//! seed alone, so runs are reproducible whatever the thread count.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use rayon::prelude::*;

/// Settings of [`hanso`] (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// BFGS iterations at most.
    pub max_iter: usize,
    /// Line-search trials per iteration at most.
    pub line_search: usize,
    /// Stationarity tolerance on ‖g‖ (BFGS) and on the sampled min-norm element (GS).
    pub tol: f64,
    /// Gradient-sampling iterations at most (0: BFGS only).
    pub gs_iter: usize,
    /// Initial sampling radius.
    pub radius: f64,
    /// Smallest sampling radius.
    pub radius_min: f64,
    /// Stop as soon as `f ≤ target` (−∞: never).
    pub target: f64,
    /// Seed of the sample points.
    pub seed: u64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            max_iter: 1000,
            line_search: 60,
            tol: 1e-10,
            gs_iter: 100,
            radius: 0.1,
            radius_min: 1e-8,
            target: f64::NEG_INFINITY,
            seed: 1,
        }
    }
}

/// Result of a minimisation.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Best point found.
    pub x: Vec<f64>,
    /// Its value.
    pub f: f64,
    /// BFGS iterations done.
    pub bfgs_iterations: usize,
    /// Gradient-sampling iterations done.
    pub gs_iterations: usize,
    /// Function evaluations (with gradient).
    pub evaluations: usize,
    /// Why BFGS stopped.
    pub bfgs_stop: &'static str,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn axpy(x: &[f64], t: f64, d: &[f64]) -> Vec<f64> {
    x.iter().zip(d).map(|(a, b)| a + t * b).collect()
}

/// BFGS with the weak Wolfe line search (module docs). `f` returns the value and the gradient.
pub fn bfgs<F>(f: &F, x0: &[f64], o: &Options) -> Outcome
where
    F: Fn(&[f64]) -> (f64, Vec<f64>),
{
    let n = x0.len();
    let mut x = x0.to_vec();
    let (mut fx, mut g) = f(&x);
    let mut evaluations = 1;
    let mut h = vec![0.0; n * n];
    for i in 0..n {
        h[i * n + i] = 1.0;
    }
    let mut stop = "max_iter";
    let mut it = 0;
    while it < o.max_iter {
        if !fx.is_finite() {
            stop = "non-finite value";
            break;
        }
        if fx <= o.target {
            stop = "target";
            break;
        }
        if dot(&g, &g).sqrt() <= o.tol {
            stop = "gradient";
            break;
        }
        let d: Vec<f64> = (0..n).map(|i| -(0..n).map(|j| h[i * n + j] * g[j]).sum::<f64>()).collect();
        let gd = dot(&g, &d);
        if gd >= 0.0 {
            stop = "not a descent direction";
            break;
        }
        let (mut lo, mut hi, mut t) = (0.0, f64::INFINITY, 1.0);
        let mut accepted = None;
        for _ in 0..o.line_search {
            let xt = axpy(&x, t, &d);
            let (ft, gt) = f(&xt);
            evaluations += 1;
            if !(ft.is_finite() && ft <= fx + 1e-4 * t * gd) {
                hi = t;
            } else if dot(&gt, &d) < 0.5 * gd {
                lo = t;
            } else {
                accepted = Some((xt, ft, gt));
                break;
            }
            t = if hi.is_finite() { 0.5 * (lo + hi) } else { 2.0 * lo.max(0.5) };
            if hi.is_finite() && hi - lo < 1e-16 * hi.max(1.0) {
                break;
            }
        }
        let Some((xn, fn_, gn)) = accepted else {
            stop = "line search";
            break;
        };
        it += 1;
        let s: Vec<f64> = xn.iter().zip(&x).map(|(a, b)| a - b).collect();
        let y: Vec<f64> = gn.iter().zip(&g).map(|(a, b)| a - b).collect();
        let sy = dot(&s, &y);
        if sy > 0.0 {
            if it == 1 {
                // scale H₀ by sᵀy / yᵀy before the first update (Nocedal & Wright 6.20)
                let scale = sy / dot(&y, &y);
                h.iter_mut().for_each(|v| *v *= scale);
            }
            let hy: Vec<f64> = (0..n).map(|i| (0..n).map(|j| h[i * n + j] * y[j]).sum()).collect();
            let yhy = dot(&y, &hy);
            let r = 1.0 / sy;
            for i in 0..n {
                for j in 0..n {
                    h[i * n + j] += -r * (hy[i] * s[j] + s[i] * hy[j]) + (r * r * yhy + r) * s[i] * s[j];
                }
            }
        }
        x = xn;
        fx = fn_;
        g = gn;
    }
    Outcome { x, f: fx, bfgs_iterations: it, gs_iterations: 0, evaluations, bfgs_stop: stop }
}

/// The smallest-norm point of the convex hull of the columns `g[k]` (accelerated projected
/// gradient on the simplex; returns the point).
pub fn min_norm_in_hull(g: &[Vec<f64>]) -> Vec<f64> {
    let m = g.len();
    let q: Vec<f64> = (0..m * m).map(|k| dot(&g[k / m], &g[k % m])).collect();
    let lip = (0..m).map(|i| q[i * m + i]).sum::<f64>().max(1e-300);
    let mut lam = vec![1.0 / m as f64; m];
    let mut yk = lam.clone();
    let mut tk = 1.0f64;
    for _ in 0..3000 {
        let grad: Vec<f64> = (0..m).map(|i| (0..m).map(|j| q[i * m + j] * yk[j]).sum()).collect();
        let step: Vec<f64> = yk.iter().zip(&grad).map(|(y, gr)| y - gr / lip).collect();
        let next = project_simplex(&step);
        let tn = 0.5 * (1.0 + (1.0 + 4.0 * tk * tk).sqrt());
        yk = next.iter().zip(&lam).map(|(a, b)| a + (tk - 1.0) / tn * (a - b)).collect();
        lam = next;
        tk = tn;
    }
    let n = g[0].len();
    (0..n).map(|i| (0..m).map(|k| lam[k] * g[k][i]).sum()).collect()
}

/// Euclidean projection onto the probability simplex.
fn project_simplex(v: &[f64]) -> Vec<f64> {
    let mut u = v.to_vec();
    u.sort_by(|a, b| b.total_cmp(a));
    let (mut css, mut theta) = (0.0, 0.0);
    for (i, &ui) in u.iter().enumerate() {
        css += ui;
        let t = (css - 1.0) / (i + 1) as f64;
        if ui - t > 0.0 {
            theta = t;
        }
    }
    v.iter().map(|&x| (x - theta).max(0.0)).collect()
}

/// Gradient sampling from `x0` (module docs).
pub fn gradient_sampling<F>(f: &F, x0: &[f64], o: &Options) -> Outcome
where
    F: Fn(&[f64]) -> (f64, Vec<f64>) + Sync,
{
    let n = x0.len();
    let mut rng = ChaCha8Rng::seed_from_u64(o.seed);
    let mut x = x0.to_vec();
    let (mut fx, mut g) = f(&x);
    let mut evaluations = 1;
    let mut eps = o.radius;
    let mut it = 0;
    while it < o.gs_iter && eps >= o.radius_min && fx > o.target {
        it += 1;
        let points: Vec<Vec<f64>> = (0..=n)
            .map(|_| {
                let dir: Vec<f64> = (0..n).map(|_| rng.sample::<f64, _>(StandardNormal)).collect();
                let norm = dot(&dir, &dir).sqrt().max(1e-300);
                let r = eps * rng.random::<f64>().powf(1.0 / n as f64);
                axpy(&x, r / norm, &dir)
            })
            .collect();
        let mut grads: Vec<Vec<f64>> = points.par_iter().map(|p| f(p).1).collect();
        evaluations += points.len();
        grads.push(g.clone());
        let d = min_norm_in_hull(&grads);
        let dn2 = dot(&d, &d);
        if dn2.sqrt() <= o.tol {
            eps *= 0.1;
            continue;
        }
        let mut t = 1.0;
        let mut moved = false;
        for _ in 0..50 {
            let xt = axpy(&x, -t, &d);
            let (ft, gt) = f(&xt);
            evaluations += 1;
            if ft.is_finite() && ft < fx - 1e-6 * t * dn2 {
                x = xt;
                fx = ft;
                g = gt;
                moved = true;
                break;
            }
            t *= 0.5;
        }
        if !moved {
            eps *= 0.1;
        }
    }
    Outcome { x, f: fx, bfgs_iterations: 0, gs_iterations: it, evaluations, bfgs_stop: "" }
}

/// HANSO: [`bfgs`], then [`gradient_sampling`] from its result (unless the target is reached).
pub fn hanso<F>(f: &F, x0: &[f64], o: &Options) -> Outcome
where
    F: Fn(&[f64]) -> (f64, Vec<f64>) + Sync,
{
    let b = bfgs(f, x0, o);
    if o.gs_iter == 0 || b.f <= o.target {
        return b;
    }
    let gs = gradient_sampling(f, &b.x, o);
    let mut out = if gs.f <= b.f { gs } else { Outcome { evaluations: gs.evaluations, ..b.clone() } };
    out.bfgs_iterations = b.bfgs_iterations;
    out.bfgs_stop = b.bfgs_stop;
    out.evaluations += b.evaluations;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nesterov's nonsmooth Chebyshev–Rosenbrock function (Gurbuzbalaban & Overton 2012):
    /// `¼|x₁ − 1| + Σ |x_{i+1} − 2|x_i| + 1|`, minimum 0 at (1, …, 1).
    fn cheb_rosen(x: &[f64]) -> (f64, Vec<f64>) {
        let n = x.len();
        let mut f = 0.25 * (x[0] - 1.0).abs();
        let mut g = vec![0.0; n];
        g[0] = 0.25 * (x[0] - 1.0).signum();
        for i in 0..n - 1 {
            let r = x[i + 1] - 2.0 * x[i].abs() + 1.0;
            f += r.abs();
            let s = r.signum();
            g[i + 1] += s;
            g[i] -= 2.0 * s * x[i].signum();
        }
        (f, g)
    }

    #[test]
    fn nonsmooth_chebyshev_rosenbrock_is_solved_to_1e_6() {
        let o = Options { max_iter: 2000, gs_iter: 400, radius: 0.1, radius_min: 1e-9, ..Options::default() };
        let out = hanso(&cheb_rosen, &[-1.0, 1.0], &o);
        println!("{out:?}");
        assert!(out.f < 1e-6, "f = {}", out.f);
        assert!(out.x.iter().all(|v| (v - 1.0).abs() < 1e-5), "{:?}", out.x);
        // reproducible: the same seed gives the same point
        let again = hanso(&cheb_rosen, &[-1.0, 1.0], &o);
        assert_eq!(out.x, again.x);
    }

    #[test]
    fn smooth_quadratic_converges_to_the_solution() {
        // f = ½ xᵀQx − bᵀx, Q SPD, solution Q⁻¹b = (1, −2, 0.5)
        let q = [[4.0, 1.0, 0.0], [1.0, 3.0, 0.5], [0.0, 0.5, 2.0]];
        let sol = [1.0, -2.0, 0.5];
        let b: Vec<f64> = (0..3).map(|i| (0..3).map(|j| q[i][j] * sol[j]).sum()).collect();
        let f = |x: &[f64]| {
            let qx: Vec<f64> = (0..3).map(|i| (0..3).map(|j| q[i][j] * x[j]).sum()).collect();
            (0.5 * dot(x, &qx) - dot(&b, x), qx.iter().zip(&b).map(|(a, c)| a - c).collect())
        };
        let out = bfgs(&f, &[0.0, 0.0, 0.0], &Options::default());
        for (x, s) in out.x.iter().zip(sol) {
            assert!((x - s).abs() < 1e-8, "{:?}", out.x);
        }
        assert!(out.bfgs_iterations < 30, "{}", out.bfgs_iterations);
    }

    #[test]
    fn min_norm_point_of_a_segment() {
        // hull of (1, 1) and (1, −1): min-norm point (1, 0); of (2, 0) and (−1, 0): the origin
        let d = min_norm_in_hull(&[vec![1.0, 1.0], vec![1.0, -1.0]]);
        assert!((d[0] - 1.0).abs() < 1e-9 && d[1].abs() < 1e-9, "{d:?}");
        let d = min_norm_in_hull(&[vec![2.0, 0.0], vec![-1.0, 0.0]]);
        assert!(d[0].abs() < 1e-9, "{d:?}");
    }
}
