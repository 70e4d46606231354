//! The plant FMU's exact integrator (default) against its RK4 reference (`integrator =
//! reference`) where it matters most: the stability boundary found in the time domain through
//! the FMUs (Rust master, `target/fmu` built by `cargo run --release -p packaging`), open loop
//! and with the shipped FOPID, must not move by more than 0.1 %.

use chatter_control::{ControllerParams, Structure};
use milling_plant::{Integrator, PlantParams};
use seed000::fmu_validation::FmuLoop;
use seed000::loop_frf;
use seed000::scenario::closed_loop_system;

#[test]
fn the_lobe_boundary_through_the_fmus_does_not_move_with_the_integrator() {
    let sys = closed_loop_system(&packaging::fmu_dir()).unwrap();
    let plant = loop_frf::seed_plant();
    let fopid = ControllerParams { structure: Structure::Fopid, ..ControllerParams::default() };
    for (ctrl, rpm) in [(None, 2866.7), (Some(fopid), 2935.8)] {
        let b = loop_frf::problem(&plant, ctrl.as_ref(), 1000.0).unwrap().critical_depth(rpm).depth;
        let boundary = |integrator| {
            let fl = FmuLoop::new(&sys, &PlantParams { integrator, ..plant.clone() }).unwrap();
            fl.boundary(ctrl.as_ref(), rpm, (0.985 * b, 1.015 * b), 1.0, 3e-4).unwrap()
        };
        let (fast, slow) = (boundary(Integrator::Exact), boundary(Integrator::Reference));
        let rel = (fast / slow - 1.0).abs();
        eprintln!(
            "{:?} {rpm} rpm: lobe {:.5} mm, FMU boundary exact {:.5} mm, reference {:.5} mm (rel {rel:.1e})",
            ctrl.map_or(Structure::Off, |c| c.structure),
            b * 1e3,
            fast * 1e3,
            slow * 1e3
        );
        assert!(rel < 1e-3, "boundary moved by {rel:.2e}");
    }
}
