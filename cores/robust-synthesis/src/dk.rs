//! D–K iteration (seed 002 Section 5) and the bisection on the design depth ā_p.
//!
//! # D–K iteration
//!
//! On a frequency grid `ω_1 … ω_N` (the seed evaluates `σ̄` pointwise on a grid), with the
//! scaled generalised plants `P̃(iω_k)` computed once per ā_p:
//!
//! 1. **D-step**: for the current K, at every grid frequency (in parallel) the μ upper bound
//!    `D_k = argmin σ̄(D N_k D⁻¹)` ([`crate::mu::upper_bound`], warm-started from the previous
//!    D-step). `μ̂ = max_k σ̄(D_k N_k D_k⁻¹)`. If `μ̂ < 1` and the nominal loop is stable
//!    (`Ψ < 0`), K is a robust design: stop.
//! 2. **K-step**: with the `D_k` frozen, minimise (Eq. 24)
//!    `f̄(θ) = max_k σ̄(D_k N_k(θ) D_k⁻¹) + ρ max(0, Ψ(θ) τ₀)` by [`crate::optim::hanso`]
//!    (ρ = 100; Ψ is made dimensionless with τ₀, the seed gives no unit), stopping as soon as
//!    `f̄` is below `target` (a design just inside the μ bound is all the bisection needs).
//!
//! The iteration stops on success, after `max_steps` K-steps, or when a D-step improves `μ̂` by
//! less than `1e-3` (stalled). The number of D–K steps reported is the number of K-steps done.
//!
//! # Bisection
//!
//! `ā_p` is bisected on the grid `k·resolution` between a feasible lower end (0: no cut) and an
//! upper end. Each trial depth starts from the best design found so far (warm start), so the
//! sequence of trials (and the result) is deterministic. A trial counts as feasible only if the
//! design also passes [`mu_check`] on a second, finer grid (fresh scalings): a peak of `σ̄`
//! between the design grid's points must not pass unnoticed.

use crate::SynthError;
use crate::mu::{self, CMat};
use crate::optim::{Options, hanso};
use crate::plant::{Parameterisation, Problem, close, close_n, controller_frf, scaled_gain};
use rayon::prelude::*;
use std::f64::consts::PI;

/// Settings of the D–K iteration.
#[derive(Clone, Debug, PartialEq)]
pub struct DkOptions {
    /// Frequency grid \[Hz\].
    pub freqs_hz: Vec<f64>,
    /// K-steps at most.
    pub max_steps: usize,
    /// BFGS iterations of the D-step per frequency.
    pub d_iter: usize,
    /// The K-step optimiser (its `target` is overridden by `target`).
    pub k: Options,
    /// K-step stopping value of f̄.
    pub target: f64,
    /// Penalty ρ on `max(0, Ψ τ₀)`.
    pub penalty: f64,
    /// Chebyshev intervals of the abscissa.
    pub nodes: usize,
    /// The finer grid of the bisection's feasibility check \[Hz\] (empty: none).
    pub check_hz: Vec<f64>,
}

impl DkOptions {
    /// `points` frequencies spaced evenly over `[lo, hi]` Hz.
    pub fn grid(lo: f64, hi: f64, points: usize) -> Vec<f64> {
        (0..points).map(|i| lo + (hi - lo) * i as f64 / (points.max(2) - 1) as f64).collect()
    }
}

impl Default for DkOptions {
    fn default() -> Self {
        DkOptions {
            freqs_hz: Self::grid(20.0, 8000.0, 400),
            max_steps: 12,
            d_iter: 60,
            k: Options { max_iter: 150, gs_iter: 10, radius: 0.1, radius_min: 1e-4, tol: 1e-8, ..Options::default() },
            target: 0.995,
            penalty: 100.0,
            nodes: 24,
            check_hz: Self::grid(10.0, 12000.0, 1200),
        }
    }
}

/// One D–K step.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// μ̂ after the D-step.
    pub mu: f64,
    /// Ψ τ₀ of the K entering the D-step.
    pub psi: f64,
    /// f̄ at the end of the following K-step (NaN if none).
    pub f_k: f64,
    /// Function evaluations of that K-step.
    pub evaluations: usize,
}

/// Result of a D–K iteration.
#[derive(Clone, Debug, PartialEq)]
pub struct DkOutcome {
    /// Final parameters.
    pub theta: Vec<f64>,
    /// μ̂ at θ (with its own D-step).
    pub mu: f64,
    /// Ψ τ₀ at θ.
    pub psi: f64,
    /// K-steps done.
    pub steps: usize,
    /// μ̂ < 1 and Ψ < 0.
    pub feasible: bool,
    /// The steps.
    pub history: Vec<Step>,
    /// Frequency \[Hz\] of μ̂.
    pub peak_hz: f64,
}

/// The grid plants `P̃(iω_k)`.
pub fn plants(pr: &Problem, freqs_hz: &[f64]) -> Result<Vec<CMat>, SynthError> {
    freqs_hz.par_iter().map(|f| pr.generalized(2.0 * PI * f)).collect()
}

/// `N_k(θ)` at every grid frequency.
fn loops(
    ps: &[CMat],
    freqs_hz: &[f64],
    par: &Parameterisation,
    theta: &[f64],
    beta: f64,
) -> Result<Vec<CMat>, SynthError> {
    let c = par.controller(theta, beta);
    ps.par_iter()
        .zip(freqs_hz.par_iter())
        .map(|(p, f)| {
            let (k, _, _) = controller_frf(&c, 2.0 * PI * f)?;
            close_n(p, &k)
        })
        .collect()
}

/// The D-step: bounds and scalings at every grid frequency.
fn d_step(ns: &[CMat], warm: &[Vec<f64>], d_iter: usize) -> Vec<mu::Bound> {
    let s = Problem::mu_structure();
    ns.par_iter().zip(warm.par_iter()).map(|(n, w)| mu::upper_bound(n, &s, Some(w), d_iter)).collect()
}

/// μ̂ of θ on the grid with fresh D-scalings from θ = 0 (the check of a finished design).
pub fn mu_check(
    pr: &Problem,
    par: &Parameterisation,
    theta: &[f64],
    freqs_hz: &[f64],
    d_iter: usize,
) -> Result<(f64, f64), SynthError> {
    let ps = plants(pr, freqs_hz)?;
    let ns = loops(&ps, freqs_hz, par, theta, pr.beta)?;
    let warm = vec![vec![0.0; Problem::mu_structure().params()]; ns.len()];
    let b = d_step(&ns, &warm, d_iter);
    let (k, m) =
        b.iter().enumerate().map(|(k, b)| (k, b.value)).max_by(|a, b| a.1.total_cmp(&b.1)).unwrap_or((0, f64::NAN));
    Ok((m, freqs_hz.get(k).copied().unwrap_or(f64::NAN)))
}

/// The D–K iteration from `theta0` (module docs); `progress` gets one line per step.
pub fn dk(
    pr: &Problem,
    par: &Parameterisation,
    theta0: &[f64],
    o: &DkOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<DkOutcome, SynthError> {
    pr.validate()?;
    if theta0.len() != par.len() {
        return Err(SynthError::Invalid(format!("{} parameters for a controller with {}", theta0.len(), par.len())));
    }
    let ps = plants(pr, &o.freqs_hz)?;
    let s = Problem::mu_structure();
    let mut warm = vec![vec![0.0; s.params()]; ps.len()];
    let mut theta = theta0.to_vec();
    let mut history: Vec<Step> = Vec::new();
    loop {
        let ns = loops(&ps, &o.freqs_hz, par, &theta, pr.beta)?;
        // the abscissa (serial) beside the D-step (parallel): the same results, sooner
        let (bounds, psi) = rayon::join(
            || d_step(&ns, &warm, o.d_iter),
            || pr.abscissa(par, &theta, o.nodes).map(|r| r.0).unwrap_or(f64::INFINITY),
        );
        let (peak, mu_hat) = bounds
            .iter()
            .enumerate()
            .map(|(k, b)| (k, b.value))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, f64::NAN));
        let steps = history.len();
        progress(&format!(
            "ā_p {:.4} mm, D-K step {steps}: μ̂ {mu_hat:.4} at {:.0} Hz, Ψτ₀ {psi:.4}",
            pr.abar * 1e3,
            o.freqs_hz[peak]
        ));
        let feasible = mu_hat < 1.0 && psi < 0.0;
        let stalled = history.last().is_some_and(|h: &Step| mu_hat > h.mu - 1e-3 && h.psi < 0.0 && psi < 0.0);
        if feasible || steps >= o.max_steps || stalled {
            return Ok(DkOutcome { theta, mu: mu_hat, psi, steps, feasible, history, peak_hz: o.freqs_hz[peak] });
        }
        warm = bounds.iter().map(|b| b.theta.clone()).collect();
        let ds: Vec<(CMat, CMat)> = bounds
            .iter()
            .map(|b| {
                let d = s.scaling(&b.theta);
                let di = mu::inverse(&d);
                (d, di)
            })
            .collect();
        let f = |t: &[f64]| -> (f64, Vec<f64>) { objective(pr, par, &ps, &ds, &o.freqs_hz, t, o) };
        let k_opts = Options { target: o.target, ..o.k };
        let out = hanso(&f, &theta, &k_opts);
        history.push(Step { mu: mu_hat, psi, f_k: out.f, evaluations: out.evaluations });
        theta = out.x;
    }
}

/// f̄ of the K-step (module docs) and its gradient; NaN-free: failures give +∞.
fn objective(
    pr: &Problem,
    par: &Parameterisation,
    ps: &[CMat],
    ds: &[(CMat, CMat)],
    freqs_hz: &[f64],
    theta: &[f64],
    o: &DkOptions,
) -> (f64, Vec<f64>) {
    let bad = (f64::INFINITY, vec![0.0; theta.len()]);
    let c = par.controller(theta, pr.beta);
    // the spectral abscissa (serial, a dense eigenproblem) runs beside the frequency sweep
    // (parallel); both are what they were one after the other, so the result is the same bits
    let (gains, abscissa) = rayon::join(
        || -> Result<Vec<f64>, SynthError> {
            ps.par_iter()
                .zip(ds.par_iter())
                .zip(freqs_hz.par_iter())
                .map(|((p, (d, di)), f)| {
                    let (k, _, _) = controller_frf(&c, 2.0 * PI * f)?;
                    Ok(mu::top_singular(&(d * &close_n(p, &k)? * di)).0)
                })
                .collect()
        },
        || pr.abscissa(par, theta, o.nodes),
    );
    let Ok(gains) = gains else { return bad };
    let Some((k, &val)) = gains.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) else { return bad };
    let w = 2.0 * PI * freqs_hz[k];
    let grad = controller_frf(&c, w)
        .and_then(|(kk, _, _)| close(&ps[k], &kk))
        .and_then(|l| scaled_gain(&l, &ds[k].0, &ds[k].1, &c, w, par));
    let Ok((_, mut g)) = grad else { return bad };
    let Ok((psi, gpsi)) = abscissa else { return bad };
    let mut f = val;
    if psi > 0.0 {
        f += o.penalty * psi;
        g.iter_mut().zip(&gpsi).for_each(|(a, b)| *a += o.penalty * b);
    }
    if !f.is_finite() {
        return bad;
    }
    (f, g)
}

/// One trial of the bisection.
#[derive(Clone, Debug, PartialEq)]
pub struct Trial {
    /// ā_p \[m\].
    pub abar: f64,
    /// Its D–K iteration.
    pub outcome: DkOutcome,
    /// [`mu_check`] of its design on the check grid (μ̂, frequency \[Hz\]) where the D–K
    /// iteration was feasible and a check grid was given; NaN otherwise.
    pub check: (f64, f64),
}

/// Result of the bisection.
#[derive(Clone, Debug, PartialEq)]
pub struct Bisection {
    /// The largest feasible ā_p \[m\] (0 if none) and its design.
    pub best: Option<Trial>,
    /// Every trial in order.
    pub trials: Vec<Trial>,
}

/// Bisection of ā_p on the grid `k·resolution` in `(0, hi]` (module docs); `make(ā)` is the
/// problem at ā.
pub fn bisect(
    make: &(dyn Fn(f64) -> Problem + Sync),
    par: &Parameterisation,
    theta0: &[f64],
    hi: f64,
    resolution: f64,
    o: &DkOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Bisection, SynthError> {
    if !(resolution > 0.0 && hi > resolution) {
        return Err(SynthError::Invalid(format!("bisection: need 0 < resolution < hi (got {resolution}, {hi})")));
    }
    let (mut lo_k, mut hi_k) = (0i64, (hi / resolution).round() as i64 + 1);
    let mut best: Option<Trial> = None;
    let mut trials = Vec::new();
    while hi_k - lo_k > 1 {
        let mid = (lo_k + hi_k) / 2;
        let abar = mid as f64 * resolution;
        let start = best.as_ref().map_or(theta0, |b| b.outcome.theta.as_slice());
        let pr = make(abar);
        let mut out = dk(&pr, par, start, o, progress)?;
        let mut check = (f64::NAN, f64::NAN);
        if out.feasible && !o.check_hz.is_empty() {
            check = mu_check(&pr, par, &out.theta, &o.check_hz, 2 * o.d_iter)?;
            out.feasible = check.0 < 1.0;
        }
        progress(&format!(
            "ā_p {:.4} mm: {} (μ̂ {:.4}, check grid {:.4} at {:.0} Hz, {} D-K steps)",
            abar * 1e3,
            if out.feasible { "feasible" } else { "not reached" },
            out.mu,
            check.0,
            check.1,
            out.steps
        ));
        let t = Trial { abar, outcome: out, check };
        if t.outcome.feasible {
            lo_k = mid;
            best = Some(t.clone());
        } else {
            hi_k = mid;
        }
        trials.push(t);
    }
    Ok(Bisection { best, trials })
}
