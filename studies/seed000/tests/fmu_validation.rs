//! The lobes against the time domain **through the FMUs**: the plant and controller
//! FMUs of `target/fmu` (built by `cargo run --release -p packaging` before the tests) in the
//! Rust master, 3 % below the computed boundary the cut decays, 3 % above it grows — open loop,
//! the paper's Table 2 gains and the shipped (PSO-tuned) defaults.

use chatter_control::{ControllerParams, Structure};
use milling_plant::PlantParams;
use seed000::fmu_validation::FmuLoop;
use seed000::loop_frf;
use seed000::scenario::closed_loop_system;

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
        (Some(with(tuned, Structure::Fopid)), 2935.8),
        (Some(with(tuned, Structure::AdrcFopid)), 1367.5),
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

/// The lobes for a negative directional factor α₀ (chatter below the mode) agree with the FMU
/// time domain: the seed plant bending normal to the feed in up-milling (α₀ = −0.180) and along
/// the feed in low-immersion down-milling (a_e = 2 mm of R = 8 mm, α₀ = −0.119), open loop and
/// with the shipped FOPID, each at its own lobe minimum over 1000–3000 rpm. The FMU gets the
/// same machine as the lobes, parameter by parameter.
#[test]
fn negative_directional_factor_cases_decay_below_and_grow_above_the_lobe() {
    let sys = closed_loop_system(&packaging::fmu_dir()).unwrap();
    let mut normal = PlantParams::default();
    normal.cutting.direction_angle = std::f64::consts::FRAC_PI_2;
    let mut down = PlantParams::default();
    down.cutting.milling = milling_plant::MillingMode::Down;
    down.cutting.radial_engagement = 2e-3;
    let fopid = ControllerParams { structure: Structure::Fopid, ..ControllerParams::default() };
    let mut failures = Vec::new();
    for plant in [normal, down] {
        assert!(plant.directional_coefficient() < -0.1, "α₀ = {}", plant.directional_coefficient());
        let fl = FmuLoop::new(&sys, &plant).unwrap();
        for ctrl in [None, Some(fopid)] {
            let prob = loop_frf::problem(&plant, ctrl.as_ref(), 1000.0).unwrap();
            let ex =
                prob.extremes(&prob.diagram(&delay_stability::zero_order::speed_grid(1000.0, 3000.0, 401))).unwrap();
            let (rpm, b) = (ex.min.rpm, ex.min.depth);
            let below = fl.growth_ratio(ctrl.as_ref(), rpm, 0.97 * b, 1.5).unwrap();
            let above = fl.growth_ratio(ctrl.as_ref(), rpm, 1.03 * b, 1.5).unwrap();
            let what = format!(
                "α₀ {:.3}, {:?}, {rpm:.1} rpm, b = {:.4} mm ({:.1} Hz): ratio 0.97b {below:.4}, 1.03b {above:.4}",
                plant.directional_coefficient(),
                ctrl.map_or(Structure::Off, |c| c.structure),
                b * 1e3,
                ex.min.chatter_hz
            );
            eprintln!("{what}");
            if !(below < 1.0 && above > 1.0) {
                failures.push(what);
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
