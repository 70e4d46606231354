//! The converged default ([`Method::Auto`], the spectral collocation) against the
//! semi-discretisation extrapolated in m (Richardson on m = 160 and 320, the error of first-order
//! SD being c/m² + O(1/m³)), and the search's behaviour: Brent against the bisection, the scan's
//! protection against a thin flip window, determinism over threads.
//!
//! Machines: Insperger & Stépán's 1-DOF benchmark (922 Hz, ζ = 0.011, 0.03993 kg along the feed,
//! z = 2, K_t = 6e8, K_n = 2e8 N/m², down-milling) and a symmetric 2-DOF tool (the same mode in
//! x and y).

use delay_stability::milling::{Cutter, ForceLaw, Milling, MillingModel, ModeShape, Structure};
use delay_stability::presets::seed002;
use delay_stability::sd::Bifurcation;
use delay_stability::zero_order::speed_grid;
use delay_stability::{BisectionOptions, LobeOptions, Method, critical, critical_value, lobes_with};
use std::f64::consts::PI;

fn tool(immersion: f64, directions: &[[f64; 2]]) -> MillingModel {
    let m = 0.03993f64;
    let modes: Vec<ModeShape> = directions
        .iter()
        .map(|d| ModeShape {
            omega: 2.0 * PI * 922.0,
            zeta: 0.011,
            tool: [d[0] / m.sqrt(), d[1] / m.sqrt()],
            actuator: [0.0; 2],
        })
        .collect();
    let s = Structure::from_modes(&modes).unwrap();
    let (e, x) = Cutter::immersion(immersion, Milling::Down);
    MillingModel::new(&s, Cutter::new(2, e, x, 6e8, 2e8, ForceLaw::Linear).unwrap(), None).unwrap()
}

fn auto() -> LobeOptions {
    LobeOptions { method: Method::default(), start: 1e-5, growth: 1.1, max: 0.05, rel_tol: 1e-6 }
}

/// SD at m = 160 and 320 extrapolated; the scan starts at half of `near` (the spectral value),
/// so only the neighbourhood of the boundary is searched.
fn richardson(model: &MillingModel, rpm: f64, near: f64) -> f64 {
    let sd = |m: usize| {
        let o = LobeOptions { method: Method::Sd { m }, start: 0.5 * near, growth: 1.1, max: 0.05, rel_tol: 1e-7 };
        critical(|a| model.at(rpm, a), &o).unwrap().value.unwrap()
    };
    let (a1, a2) = (sd(160), sd(320));
    a2 + (a2 - a1) / 3.0
}

fn compare(name: &str, model: &MillingModel, speeds: &[f64]) -> f64 {
    let pts = lobes_with(speeds, |r, a| model.at(r, a), &auto(), &|_, _| {}).unwrap();
    let mut worst: f64 = 0.0;
    for p in &pts {
        let ours = p.critical.value.unwrap();
        let reference = richardson(model, p.rpm, ours);
        let dev = ours / reference - 1.0;
        println!(
            "{name} {:6.0} rpm: auto {:.5} mm ({:?}, {:?}, estimate {:.1e}), SD Richardson {:.5} mm, {:+.4} %",
            p.rpm,
            ours * 1e3,
            p.critical.kind().unwrap(),
            p.critical.method,
            p.critical.error.unwrap(),
            reference * 1e3,
            100.0 * dev
        );
        assert!(p.critical.error.unwrap() <= 1e-3, "{name} {}: {:?}", p.rpm, p.critical);
        worst = worst.max(dev.abs());
    }
    worst
}

#[test]
fn the_converged_default_matches_extrapolated_sd_on_the_benchmark() {
    let speeds = speed_grid(5000.0, 25000.0, 9);
    for frac in [1.0, 0.5, 0.1, 0.05] {
        let worst = compare(&format!("1-DOF a/D = {frac}"), &tool(frac, &[[1.0, 0.0]]), &speeds);
        assert!(worst < 1e-3, "a/D = {frac}: {worst}");
    }
    // the symmetric 2-DOF tool, slotting and half immersion, the low speeds included
    let speeds = speed_grid(5000.0, 12000.0, 4);
    for frac in [1.0, 0.5] {
        let worst = compare(&format!("2-DOF a/D = {frac}"), &tool(frac, &[[1.0, 0.0], [0.0, 1.0]]), &speeds);
        assert!(worst < 1e-3, "2-DOF a/D = {frac}: {worst}");
    }
}

#[test]
fn brent_ends_in_the_bisections_bracket_with_fewer_evaluations() {
    let model = seed002(1.0, None).unwrap();
    let b = BisectionOptions { m: 40, start: 0.2e-3, growth: 1.1, max: 0.02, rel_tol: 1e-6 };
    let old = critical_value(|a| model.at(38000.0, a), &b).unwrap();
    let new =
        critical(|a| model.at(38000.0, a), &LobeOptions { method: Method::Sd { m: 40 }, ..b.converged() }).unwrap();
    let (x, y) = (old.value.unwrap(), new.value.unwrap());
    println!("bisection {x:.9} ({} evaluations), Brent {y:.9} ({})", old.evaluations, new.evaluations);
    assert!((x / y - 1.0).abs() < 1e-6, "{x} vs {y}");
    assert!(new.evaluations + 8 < old.evaluations, "{} vs {}", new.evaluations, old.evaluations);
    assert_eq!(new.kind(), old.kind());
}

#[test]
fn the_scan_finds_a_thin_flip_window_below_the_hopf_boundary() {
    // a/D = 0.05 at 18298 rpm, near the tip of the flip lobe: unstable (flip) on
    // ≈ [1.81, 2.01] mm, stable again up to the Hopf boundary at ≈ 7.47 mm
    let model = tool(0.05, &[[1.0, 0.0]]);
    let rpm = 18298.0;
    let o = LobeOptions { growth: 1.05, ..auto() };
    let c = critical(|a| model.at(rpm, a), &o).unwrap();
    println!("{:?}", c);
    let a = c.value.unwrap();
    assert_eq!(c.kind(), Some(Bifurcation::Flip));
    assert!((a - 1.812e-3).abs() < 0.01e-3, "{a}");
    // the same search with a scan factor wider than the window, aligned to step over it, finds
    // the Hopf boundary: the protection is the scan's, not the root-finder's
    let o = LobeOptions { start: 1.7e-3, growth: 1.25, ..auto() };
    let coarse = critical(|a| model.at(rpm, a), &o).unwrap();
    assert_eq!(coarse.kind(), Some(Bifurcation::Hopf));
    assert!(coarse.value.unwrap() > 7e-3);
}

#[test]
fn the_diagram_does_not_depend_on_the_number_of_threads() {
    let model = tool(0.1, &[[1.0, 0.0]]);
    let speeds = speed_grid(6000.0, 20000.0, 11);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| lobes_with(&speeds, |r, a| model.at(r, a), &auto(), &|_, _| {}).unwrap())
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn a_tighter_tolerance_raises_the_order() {
    let model = tool(1.0, &[[1.0, 0.0]]);
    let at =
        |tol: f64| critical(|a| model.at(25000.0, a), &LobeOptions { method: Method::Auto { tol }, ..auto() }).unwrap();
    let (loose, tight) = (at(1e-3), at(1e-7));
    let nodes = |c: &delay_stability::lobes::Critical| match c.method {
        Method::Spectral(s) => s.nodes,
        m => panic!("{m:?}"),
    };
    println!("{loose:?}\n{tight:?}");
    assert!(nodes(&tight) > nodes(&loose));
    assert!(tight.error.unwrap() <= 1e-7 / 3.0);
    // the loose answer is within its tolerance of the tight one
    assert!((loose.value.unwrap() / tight.value.unwrap() - 1.0).abs() < 1e-3 / 3.0);
}
