//! The lobes against the time domain **through the FMUs**: the plant and controller
//! FMUs of `target/fmu` (built by `cargo run --release -p packaging` before the tests) in the
//! Rust master, 3 % below the computed boundary the cut decays, 3 % above it grows — open loop,
//! the paper's Table 2 gains and the shipped (PSO-tuned) defaults.

use chatter_control::{ControllerParams, Structure};
use milling_plant::PlantParams;
use studies::fmu_validation::FmuLoop;
use studies::loop_frf;
use studies::scenario::closed_loop_system;

#[test]
fn fmu_closed_loop_decays_3_percent_below_the_lobe_and_grows_3_percent_above() {
    let dir = packaging::fmu_dir();
    assert!(
        dir.join("MillingPlant.fmu").is_file() && dir.join("ChatterController.fmu").is_file(),
        "no FMUs in {}: run `cargo run --release -p packaging` first",
        dir.display()
    );
    let sys = closed_loop_system(&dir).unwrap();
    // The FMU's default plant is the plant the lobes are computed for.
    let plant = loop_frf::seed_plant();
    assert_eq!(plant, PlantParams::default());
    let fl = FmuLoop::new(&sys, &plant).unwrap();
    let with = |base: ControllerParams, s| ControllerParams { structure: s, ..base };
    let (t2, tuned) = (ControllerParams::paper_table2(), ControllerParams::default());
    let cases = [
        (None, 2866.7),
        (Some(with(t2, Structure::Pid)), 2500.0),
        (Some(with(t2, Structure::Fopid)), 1239.0),
        (Some(with(t2, Structure::AdrcFopid)), 2181.3),
        (Some(with(tuned, Structure::Pid)), 2913.9),
        (Some(with(tuned, Structure::Fopid)), 1269.1),
        (Some(with(tuned, Structure::AdrcFopid)), 1414.1),
    ];
    let mut failures = Vec::new();
    for (ctrl, rpm) in cases {
        let b = loop_frf::problem(&plant, ctrl.as_ref(), 1000.0).unwrap().critical_depth(rpm).depth;
        let below = fl.growth_ratio(ctrl.as_ref(), rpm, 0.97 * b, 1.5).unwrap();
        let above = fl.growth_ratio(ctrl.as_ref(), rpm, 1.03 * b, 1.5).unwrap();
        let name = ctrl.map_or(Structure::Off, |c| c.structure);
        eprintln!("{name:?} {rpm} rpm, b = {:.4} mm: growth ratio 0.97b {below:.4}, 1.03b {above:.4}", b * 1e3);
        if !(below < 1.0 && above > 1.0) {
            failures.push(format!("{name:?} {rpm} rpm, b = {b}: ratio below {below}, above {above}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
