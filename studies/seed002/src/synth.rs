//! Seed 002 robust synthesis (Sections 4–6): §6.1's static structured gain and Table II's
//! fixed-structure controllers (n_c = 0, 2, 4), each checked by semi-discretisation over the
//! whole box [speed range] × [0, ā_p] and written as an SSP parameter set.
//!
//! The synthesis is [`robust_synthesis::dk::bisect`] (D–K iteration with bisection on ā_p on
//! the grid `k · resolution`). Cases:
//!
//! * §6.1: x_F = 1, 36000–38000 rpm, `W_KS = 1e-6 mm/N`, `D_c = [[k₁, −k₂], [k₂, k₁]]` from
//!   `k₁ = k₂ = 0` (as the seed).
//! * Table II: x_F = 0.744, 34000–36000 rpm, `W_KS` of Eq. 27; n_c = 0 (full `D_c`) from 0;
//!   n_c = 2 from the n_c = 0 design plus one 2 × 2 block of `A_c` at 2400 Hz (the tooth-passing
//!   band, damping 0.1) and small seeded `B_c`, `C_c`; n_c = 4 from the n_c = 2 design plus a
//!   second block at 1300 Hz. The seed's initial controllers (from a μ-synthesis) are not given.
//!
//! The SD check ([`delay_stability::lobes`]) bisects the depth at every speed of a grid over the
//! range with the designed controller in the loop (the time-periodic model, not the averaged
//! one): the box is stable when the smallest boundary is above ā_p; `a_p,max` is the largest
//! boundary over the range (the seed's "maximal depth of cut in the SLD for the desired
//! spindle speed interval").

use delay_stability::milling::{Controller, MillingModel};
use delay_stability::presets::{seed002_cutter, seed002_structure};
use delay_stability::{BisectionOptions, LobePoint};
use rand::{Rng, SeedableRng};
use robust_synthesis::dk::{Bisection, DkOptions, bisect, mu_check};
use robust_synthesis::plant::{Parameterisation, Problem, Weight};
use std::fmt::Write as _;
use std::path::Path;
use study_kit::StudyError;

/// Which design.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Case {
    /// §6.1 static structured gain.
    Sec61,
    /// Table II row with n_c states.
    Table2 {
        /// Controller order (0, 2, 4).
        nc: usize,
    },
}

impl Case {
    /// Name used in files.
    pub fn name(&self) -> String {
        match self {
            Case::Sec61 => "sec6_1".into(),
            Case::Table2 { nc } => format!("table2_nc{nc}"),
        }
    }
    /// x_F.
    pub fn x_f(&self) -> f64 {
        if *self == Case::Sec61 { 1.0 } else { 0.744 }
    }
    /// Speed range \[rpm\].
    pub fn rpm(&self) -> (f64, f64) {
        if *self == Case::Sec61 { (36000.0, 38000.0) } else { (34000.0, 36000.0) }
    }
    /// The paper's (D-K steps, μ, ā_p mm, a_p,max mm).
    pub fn paper(&self) -> (usize, f64, f64, f64) {
        match self {
            Case::Sec61 => (3, 0.9992, 2.35, 3.52),
            Case::Table2 { nc: 0 } => (7, 0.9983, 1.125, 1.469),
            Case::Table2 { nc: 2 } => (10, 0.9918, 1.825, 2.1456),
            Case::Table2 { .. } => (9, 0.9810, 2.0, 2.3992),
        }
    }
    /// The parameterisation.
    pub fn parameterisation(&self) -> Parameterisation {
        match *self {
            Case::Sec61 => Parameterisation::Structured,
            Case::Table2 { nc } => Parameterisation::Full { nc },
        }
    }
    /// The problem at ā_p \[m\].
    pub fn problem(&self, abar: f64) -> Result<Problem, StudyError> {
        let cutter = seed002_cutter(self.x_f()).map_err(|e| StudyError::Invalid(e.to_string()))?;
        Ok(Problem {
            structure: seed002_structure(),
            hbar: cutter.mean(),
            abar,
            rpm: self.rpm(),
            teeth: 4,
            weight: if *self == Case::Sec61 { Weight::Static(1e-9) } else { Weight::SEED002_62 },
            beta: 1.0,
        })
    }
}

/// Settings.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthOptions {
    /// The D–K settings (frequency grid, steps, optimiser).
    pub dk: DkOptions,
    /// Upper end of the ā_p bisection \[m\].
    pub hi: f64,
    /// Bisection resolution \[m\].
    pub resolution: f64,
    /// SD intervals per period and speeds of the box check.
    pub sd_m: usize,
    /// Number of speeds of the box check.
    pub sd_speeds: usize,
    /// Seed of the initial dynamic parts.
    pub seed: u64,
}

impl SynthOptions {
    /// The full run.
    pub fn full(seed: u64) -> SynthOptions {
        SynthOptions { dk: DkOptions::default(), hi: 4.0e-3, resolution: 0.025e-3, sd_m: 30, sd_speeds: 21, seed }
    }
    /// A coarse run for tests (≈ a minute for §6.1 on two cores).
    pub fn quick(seed: u64) -> SynthOptions {
        SynthOptions {
            dk: DkOptions {
                freqs_hz: DkOptions::grid(50.0, 6000.0, 120),
                max_steps: 6,
                check_hz: DkOptions::grid(20.0, 10000.0, 400),
                ..DkOptions::default()
            },
            hi: 3.0e-3,
            resolution: 0.3e-3,
            sd_m: 12,
            sd_speeds: 5,
            seed,
        }
    }
}

/// A finished design.
#[derive(Clone, Debug)]
pub struct Design {
    /// The case.
    pub case: Case,
    /// Parameters θ.
    pub theta: Vec<f64>,
    /// The controller (SI).
    pub controller: Controller,
    /// ā_p \[m\] (0 if no depth was feasible).
    pub abar: f64,
    /// μ̂ of the design grid's last D-step.
    pub mu: f64,
    /// μ̂ on the check grid with fresh scalings, and its frequency \[Hz\].
    pub mu_check: (f64, f64),
    /// Ψ τ₀ of the nominal loop.
    pub psi: f64,
    /// D–K steps at the final ā_p, and over the whole bisection.
    pub dk_steps: (usize, usize),
    /// SD boundary per speed.
    pub lobes: Vec<LobePoint>,
    /// Smallest SD boundary over the range \[m\].
    pub box_min: f64,
    /// Largest SD boundary over the range \[m\] and its speed.
    pub ap_max: (f64, f64),
    /// The bisection trials (ā_p, feasible, μ̂, steps).
    pub trials: Vec<(f64, bool, f64, usize)>,
}

impl Design {
    /// Stable on the whole box (SD).
    pub fn box_stable(&self) -> bool {
        self.box_min >= self.abar && self.abar > 0.0
    }
}

/// Initial θ of a case (module docs): `previous` is the design of the next lower order.
pub fn initial(case: Case, previous: Option<&[f64]>, seed: u64) -> Vec<f64> {
    let par = case.parameterisation();
    let Case::Table2 { nc } = case else { return vec![0.0; par.len()] };
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed.wrapping_add(nc as u64));
    let mut small = || 0.04 * (rng.random::<f64>() - 0.5);
    let blocks = [(2.4, 0.1), (1.3, 0.1)];
    let mut th = Vec::with_capacity(par.len());
    let prev_nc = nc.saturating_sub(2);
    // previous layout: [A blocks (4 per block) | B (prev_nc × 2) | C (2 × prev_nc) | D (4)]
    let prev = previous.filter(|p| p.len() == 6 * prev_nc + 4 && nc >= 2);
    for b in 0..nc / 2 {
        if let (Some(p), true) = (prev, b < prev_nc / 2) {
            th.extend_from_slice(&p[4 * b..4 * b + 4]);
        } else {
            let (w, z) = blocks[b % 2];
            th.extend_from_slice(&[-z * w, w, -w, -z * w]);
        }
    }
    let (pb, pc) = (4 * (prev_nc / 2), 4 * (prev_nc / 2) + 2 * prev_nc);
    for i in 0..nc {
        for j in 0..2 {
            th.push(match prev {
                Some(p) if i < prev_nc => p[pb + 2 * i + j],
                _ => small(),
            });
        }
    }
    for i in 0..2 {
        for j in 0..nc {
            th.push(match prev {
                Some(p) if j < prev_nc => p[pc + prev_nc * i + j],
                _ => small(),
            });
        }
    }
    let pd = 6 * prev_nc;
    for k in 0..4 {
        th.push(match previous {
            Some(p) if p.len() == 6 * prev_nc + 4 => p[pd + k],
            _ => 0.0,
        });
    }
    th
}

/// The SD boundary of `controller` on the case's model over its speed range.
pub fn sd_check(case: Case, controller: Option<&Controller>, o: &SynthOptions) -> Result<Vec<LobePoint>, StudyError> {
    let cutter = seed002_cutter(case.x_f()).map_err(|e| StudyError::Invalid(e.to_string()))?;
    let model =
        MillingModel::new(&seed002_structure(), cutter, controller).map_err(|e| StudyError::Invalid(e.to_string()))?;
    let (lo, hi) = case.rpm();
    let speeds = delay_stability::zero_order::speed_grid(lo, hi, o.sd_speeds);
    let b = BisectionOptions { m: o.sd_m, start: 0.05e-3, growth: 1.1, max: 10e-3, rel_tol: 1e-4 };
    delay_stability::lobes(&speeds, |rpm, a| model.at(rpm, a), &b, &|_, _| {})
        .map_err(|e| StudyError::Invalid(e.to_string()))
}

/// (min, (max, at rpm)) of the boundaries (a speed without boundary counts as the search limit).
pub fn extremes(points: &[LobePoint]) -> (f64, (f64, f64)) {
    let v = |p: &LobePoint| p.critical.value.unwrap_or(10e-3);
    let min = points.iter().map(v).fold(f64::INFINITY, f64::min);
    let max =
        points.iter().map(|p| (v(p), p.rpm)).fold((f64::NEG_INFINITY, f64::NAN), |a, b| if b.0 > a.0 { b } else { a });
    (min, max)
}

/// Synthesise one case from `theta0` (see [`initial`]).
pub fn design(
    case: Case,
    theta0: &[f64],
    o: &SynthOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Design, StudyError> {
    let par = case.parameterisation();
    let make = |abar: f64| case.problem(abar).expect("the seed's cutter is valid");
    let inv = |e: robust_synthesis::SynthError| StudyError::Invalid(e.to_string());
    let Bisection { best, trials } = bisect(&make, &par, theta0, o.hi, o.resolution, &o.dk, progress).map_err(inv)?;
    let total: usize = trials.iter().map(|t| t.outcome.steps).sum();
    let trials: Vec<_> = trials.iter().map(|t| (t.abar, t.outcome.feasible, t.outcome.mu, t.outcome.steps)).collect();
    let (theta, abar, mu, psi, steps) = match &best {
        Some(b) => (b.outcome.theta.clone(), b.abar, b.outcome.mu, b.outcome.psi, b.outcome.steps),
        None => (theta0.to_vec(), 0.0, f64::NAN, f64::NAN, 0),
    };
    let controller = par.controller(&theta, 1.0);
    // the bisection checked the best design on the check grid already (the same computation)
    let check = match &best {
        Some(b) if !b.check.0.is_nan() => b.check,
        Some(_) => mu_check(&make(abar), &par, &theta, &o.dk.check_hz, 2 * o.dk.d_iter).map_err(inv)?,
        None => (f64::NAN, f64::NAN),
    };
    progress(&format!("{}: SD box check", case.name()));
    let lobes = sd_check(case, Some(&controller), o)?;
    let (box_min, ap_max) = extremes(&lobes);
    Ok(Design {
        case,
        theta,
        controller,
        abar,
        mu,
        mu_check: check,
        psi,
        dk_steps: (steps, total),
        lobes,
        box_min,
        ap_max,
        trials,
    })
}

/// The design as an SSP parameter set (`ssv:ParameterSet`) with the `LinearController` names:
/// `Ac[i,j]`, `Bc[i,j]`, `Cc[i,j]`, `Dc[i,j]` (1-based, SI: rad/s, N/m), `beta`, `n_c`.
pub fn ssv(name: &str, c: &Controller) -> String {
    let mut s = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(s, "<ssv:ParameterSet xmlns:ssv=\"{}\" version=\"1.0\" name=\"{name}\">", ssp::NS_SSV);
    s.push_str("  <ssv:Parameters>\n");
    let mut real = |n: String, v: f64| {
        let _ = writeln!(s, "    <ssv:Parameter name=\"{n}\"><ssv:Real value=\"{v:e}\"/></ssv:Parameter>");
    };
    for (label, m) in [("Ac", &c.ac), ("Bc", &c.bc), ("Cc", &c.cc), ("Dc", &c.dc)] {
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                real(format!("{label}[{},{}]", i + 1, j + 1), m[(i, j)]);
            }
        }
    }
    real("beta".into(), c.beta);
    let _ = writeln!(s, "    <ssv:Parameter name=\"n_c\"><ssv:Integer value=\"{}\"/></ssv:Parameter>", c.ac.nrows());
    s.push_str("  </ssv:Parameters>\n</ssv:ParameterSet>\n");
    s
}

/// CSV header and one row per design.
pub fn csv(designs: &[Design]) -> String {
    let mut s = String::from(
        "case,n_c,parameters,dk_steps,dk_steps_total,mu,mu_check,mu_check_hz,psi_tau0,abar_mm,ap_max_mm,ap_max_rpm,box_min_mm,box_stable,paper_dk_steps,paper_mu,paper_abar_mm,paper_ap_max_mm\n",
    );
    for d in designs {
        let p = d.case.paper();
        let _ = writeln!(
            s,
            "{},{},{},{},{},{:.4},{:.4},{:.1},{:.4},{:.4},{:.4},{:.0},{:.4},{},{},{},{},{}",
            d.case.name(),
            d.case.parameterisation().order(),
            d.theta.len(),
            d.dk_steps.0,
            d.dk_steps.1,
            d.mu,
            d.mu_check.0,
            d.mu_check.1,
            d.psi,
            d.abar * 1e3,
            d.ap_max.0 * 1e3,
            d.ap_max.1,
            d.box_min * 1e3,
            d.box_stable(),
            p.0,
            p.1,
            p.2,
            p.3
        );
    }
    s
}

/// Markdown table, ours beside the paper's.
pub fn markdown(designs: &[Design]) -> String {
    let mut s = String::from(
        "| case | n_c | D-K steps (paper) | μ̂ (paper) | μ̂ fine grid | ā_p mm (paper) | a_p,max mm (paper) | ≥ 90 % | SD box [0, ā_p] |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for d in designs {
        let p = d.case.paper();
        let _ = writeln!(
            s,
            "| {} | {} | {} ({}) | {:.4} ({}) | {:.4} | {:.3} ({}) | {:.3} at {:.0} rpm ({}) | {} | {} (min {:.3} mm) |",
            d.case.name(),
            d.case.parameterisation().order(),
            d.dk_steps.0,
            p.0,
            d.mu,
            p.1,
            d.mu_check.0,
            d.abar * 1e3,
            p.2,
            d.ap_max.0 * 1e3,
            d.ap_max.1,
            p.3,
            if d.ap_max.0 * 1e3 >= 0.9 * p.3 { "yes" } else { "no" },
            if d.box_stable() { "stable" } else { "NOT stable" },
            d.box_min * 1e3
        );
    }
    s
}

/// Write the outputs of `designs` into `dir`: `<case>.ssv`, `synth.csv`, `synth.md`.
pub fn write(dir: &Path, designs: &[Design]) -> Result<(), StudyError> {
    std::fs::create_dir_all(dir).map_err(|e| StudyError::io(dir, e))?;
    for d in designs {
        let path = dir.join(format!("{}.ssv", d.case.name()));
        std::fs::write(&path, ssv(&d.case.name(), &d.controller)).map_err(|e| StudyError::io(&path, e))?;
    }
    for (name, text) in [("synth.csv", csv(designs)), ("synth.md", markdown(designs))] {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| StudyError::io(&path, e))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn higher_orders_start_from_the_lower_design() {
        let p2: Vec<f64> = (0..16).map(|k| k as f64 * 0.1 - 0.7).collect();
        let c2 = Case::Table2 { nc: 2 }.parameterisation().controller(&p2, 1.0);
        let t4 = initial(Case::Table2 { nc: 4 }, Some(&p2), 1);
        assert_eq!(t4.len(), 28);
        let c4 = Case::Table2 { nc: 4 }.parameterisation().controller(&t4, 1.0);
        assert_eq!(c4.dc, c2.dc);
        assert_eq!(c4.ac.view((0, 0), (2, 2)), c2.ac.view((0, 0), (2, 2)));
        assert_eq!(c4.bc.rows(0, 2), c2.bc.rows(0, 2));
        assert_eq!(c4.cc.columns(0, 2), c2.cc.columns(0, 2));
        // the new block is the 1300 Hz one, damping 0.1
        assert!((c4.ac[(2, 3)] - 2.0 * std::f64::consts::PI * 1300.0).abs() < 1e-6);
        // n_c = 2 from n_c = 0: D_c kept
        let t2 = initial(Case::Table2 { nc: 2 }, Some(&[0.1, 0.2, 0.3, 0.4]), 1);
        assert_eq!(&t2[12..], &[0.1, 0.2, 0.3, 0.4]);
    }

    #[test]
    fn ssv_round_trips_through_the_ssp_reader() {
        let c = Case::Table2 { nc: 2 }.parameterisation().controller(&initial(Case::Table2 { nc: 2 }, None, 3), 1.0);
        let params = ssp::parse_ssv(&ssv("x", &c), "x.ssv", "").unwrap();
        assert_eq!(params.len(), 4 + 4 + 4 + 4 + 2);
        let get = |n: &str| params.iter().find(|p| p.name == n).unwrap_or_else(|| panic!("{n}")).value.clone();
        assert_eq!(get("Ac[1,2]"), ssp::ParamValue::Real(c.ac[(0, 1)], None));
        assert_eq!(get("Bc[2,1]"), ssp::ParamValue::Real(c.bc[(1, 0)], None));
        assert_eq!(get("n_c"), ssp::ParamValue::Integer(2));
    }
}
