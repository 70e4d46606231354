//! The converged boundary (`delay_stability::Method::Auto`, the spectral collocation) against
//! `MillingPlant.fmu` in the time domain (mechanistic cutting force, feed on, controller off) at
//! three points: a Hopf point of the seed plant, a low-speed Hopf point and a flip
//! (period-doubling) point of low-immersion down-milling. 3 % below the boundary the
//! perturbation decays, 3 % above it grows. Needs the FMUs of `target/fmu`
//! (`cargo run --release -p packaging`).

use delay_stability::{Bifurcation, BisectionOptions, critical, critical_value};
use milling_plant::{MillingMode, PlantParams};
use seed000::scenario::closed_loop_system;
use seed000::sd_lobes::seed000_model;
use seed000::sd_validation::SdFmuCheck;

#[test]
fn fmu_decays_below_and_grows_above_the_converged_boundary_at_hopf_low_speed_and_flip_points() {
    let dir = packaging::fmu_dir();
    assert!(
        dir.join("MillingPlant.fmu").is_file(),
        "no FMUs in {}: run `cargo run --release -p packaging`",
        dir.display()
    );
    let sys = closed_loop_system(&dir).unwrap();
    let seed = PlantParams::default();
    let mut down = PlantParams::default();
    down.cutting.milling = MillingMode::Down;
    down.cutting.radial_engagement = 0.8e-3; // a_e/D = 0.05
    let o = BisectionOptions { m: 40, start: 0.3e-3, growth: 1.1, max: 0.1, rel_tol: 1e-5 };
    let cases =
        [(&seed, 2600.0, Bifurcation::Hopf), (&down, 1700.0, Bifurcation::Hopf), (&down, 4200.0, Bifurcation::Flip)];
    let mut failures = Vec::new();
    for (plant, rpm, kind) in cases {
        let model = seed000_model(plant).unwrap();
        let c = critical(|a| model.at(rpm, a), &o.converged()).unwrap();
        let a = c.value.unwrap();
        assert_eq!(c.kind(), Some(kind), "{rpm} rpm");
        let sd = critical_value(|a| model.at(rpm, a), &o).unwrap().value.unwrap();
        let check = SdFmuCheck::new(&sys, plant).unwrap();
        let below = check.growth_ratio(rpm, 0.97 * a, 1.5).unwrap();
        let above = check.growth_ratio(rpm, 1.03 * a, 1.5).unwrap();
        eprintln!(
            "{rpm} rpm ({kind:?}), converged a = {:.4} mm ({:?}, estimate {:.1e}; SD m = 40 {:.4} mm): ratio 0.97a {below:.4}, 1.03a {above:.4}",
            a * 1e3,
            c.method,
            c.error.unwrap_or(f64::NAN),
            sd * 1e3
        );
        if !(below < 1.0 && above > 1.0) {
            failures.push(format!("{rpm} rpm {kind:?}, a = {a}: below {below}, above {above}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Issue 12: the time-domain stability boundary of the decomposed plant (MillingProcess +
/// ModalStructure + InertialActuator FMUs) equals that of the monolithic `MillingPlant.fmu`
/// within 2 % at a Hopf point of the seed plant, both found by bisection through the FMUs
/// (and both within 3 % of the SD boundary).
#[test]
fn the_decomposed_plant_has_the_monolithic_plants_boundary() {
    let dir = packaging::fmu_dir();
    let mono = closed_loop_system(&dir).unwrap();
    let dec = seed000::decomposed::decomposed_system(&dir).unwrap();
    let plant = PlantParams::default();
    let rpm = 2600.0;
    let o = BisectionOptions { m: 40, start: 0.3e-3, growth: 1.1, max: 0.1, rel_tol: 1e-5 };
    let model = seed000_model(&plant).unwrap();
    let a = critical_value(|a| model.at(rpm, a), &o).unwrap().value.unwrap();
    let bracket = (0.94 * a, 1.06 * a);
    let b_mono = SdFmuCheck::new(&mono, &plant).unwrap().boundary(rpm, bracket, 1.5, 2e-3).unwrap();
    let check = SdFmuCheck::decomposed(&dec, &milling_process::ProcessParams::default()).unwrap();
    let b_dec = check.boundary(rpm, bracket, 1.5, 2e-3).unwrap();
    let diff = b_dec / b_mono - 1.0;
    eprintln!(
        "{rpm} rpm: SD {:.4} mm, monolithic FMU {:.4} mm, decomposed FMUs {:.4} mm ({:+.2} %)",
        a * 1e3,
        b_mono * 1e3,
        b_dec * 1e3,
        100.0 * diff
    );
    assert!(diff.abs() < 0.02, "decomposed {b_dec} vs monolithic {b_mono}: {:.2} %", 100.0 * diff);
}
