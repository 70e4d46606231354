//! Seed 003's shipped system `SlidingModeFuzzy.ssp` (ToolXyPlant + SlidingModeFuzzyController
//! from `target/fmu`) in the Rust master: the same numbers as the cores' loop
//! (`sliding_fuzzy_control::simulate`) for DSMC-T2 (the default) and D-PID (set through the
//! master's overrides).

use fmi_master::SystemFile;
use sliding_fuzzy_control::{ControlMode, SlidingFuzzyParams, ToolParams, simulate};
use tests::{Short, packaged, run_short};

const REC: &[&str] = &["plant.x", "plant.y", "controller.u_x", "controller.u_y", "controller.j_hat_x"];

fn system() -> SystemFile {
    SystemFile::open(&packaged("SlidingModeFuzzy.ssp"), None).expect("opening SlidingModeFuzzy.ssp")
}

#[test]
fn the_shipped_system_equals_the_core_loop() {
    // the SSP binds the forcing amplitudes of the calibration (rounded)
    let tool = ToolParams { forcing_amplitude: [0.2948, 47.67], ..Default::default() };
    for (mode, set) in [(ControlMode::DsmcT2, None), (ControlMode::Dpid, Some("controller.mode=dpid"))] {
        let sets: Vec<&str> = set.into_iter().collect();
        let stop = 0.05; // 500 samples: ten delay periods
        let r = run_short(&system(), &Short { stop, set: &sets, record: REC, order: None }).unwrap();
        let (core, _) = simulate(&tool, &SlidingFuzzyParams { mode, ..Default::default() }, stop).unwrap();
        assert_eq!(r.time.len(), core.t.len());
        let (x, y, ux) =
            (r.column("plant.x").unwrap(), r.column("plant.y").unwrap(), r.column("controller.u_x").unwrap());
        for j in 0..core.t.len() {
            assert!((x[j] - core.x[j]).abs() <= 1e-12 * core.x[j].abs().max(1e-9), "{mode:?} x at step {j}");
            assert!((y[j] - core.y[j]).abs() <= 1e-12 * core.y[j].abs().max(1e-9), "{mode:?} y at step {j}");
            if j >= 1 {
                let u = core.ux[j - 1];
                assert!((ux[j] - u).abs() <= 1e-12 * u.abs().max(1.0), "{mode:?} u_x at step {j}: {} vs {u}", ux[j]);
            }
        }
        assert!(x.iter().any(|v| v.abs() > 1e-9), "the forcing reaches the tool");
    }
}
