//! The semi-discretisation boundary against `MillingPlant.fmu` in the time domain (mechanistic
//! cutting force, feed on, controller off) at three points: two Hopf points and one flip
//! (period-doubling) point of low-immersion down-milling. 3 % below the SD boundary the
//! perturbation decays, 3 % above it grows. Needs the FMUs of `target/fmu`
//! (`cargo run --release -p packaging`).

use delay_stability::{Bifurcation, BisectionOptions, critical_value};
use milling_plant::{MillingMode, PlantParams};
use studies::scenario::closed_loop_system;
use studies::sd_lobes::seed000_model;
use studies::sd_validation::SdFmuCheck;

#[test]
fn fmu_decays_below_and_grows_above_the_sd_boundary_at_hopf_and_flip_points() {
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
        let c = critical_value(|a| model.at(rpm, a), &o).unwrap();
        let a = c.value.unwrap();
        assert_eq!(c.kind(), Some(kind), "{rpm} rpm");
        let check = SdFmuCheck::new(&sys, plant).unwrap();
        let below = check.growth_ratio(rpm, 0.97 * a, 1.5).unwrap();
        let above = check.growth_ratio(rpm, 1.03 * a, 1.5).unwrap();
        eprintln!("{rpm} rpm ({kind:?}), SD a = {:.4} mm: ratio 0.97a {below:.4}, 1.03a {above:.4}", a * 1e3);
        if !(below < 1.0 && above > 1.0) {
            failures.push(format!("{rpm} rpm {kind:?}, a = {a}: below {below}, above {above}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
