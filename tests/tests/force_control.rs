//! Seed 004's shipped system `ForceControl.ssp` (MillingForcePlant + FrohMracController from
//! `target/fmu`) in the Rust master: the same numbers as the cores' loop
//! (`froh_mrac::simulate`), the FROH ramp reaching the plant, and β set through the SSP
//! master's overrides.

use fmi_master::SystemFile;
use froh_mrac::{MracParams, simulate};
use milling_force_plant::ForcePlantParams;
use tests::{Short, packaged, run_short};

const REC: &[&str] = &["plant.F_p", "plant.f_c", "plant.f_c_rate", "controller.F_m", "controller.b0_hat"];

fn system() -> SystemFile {
    SystemFile::open(&packaged("ForceControl.ssp"), None).expect("opening ForceControl.ssp")
}

#[test]
fn the_shipped_system_equals_the_core_loop() {
    for (beta, set) in [(-0.2, None), (0.4, Some("controller.beta=0.4"))] {
        let sets: Vec<&str> = set.into_iter().collect();
        let stop = 6.0; // 1430 steps of T/20, across the depth step at 3 s
        let r = run_short(&system(), &Short { stop, set: &sets, record: REC, order: None }).unwrap();
        let ctrl = MracParams { beta, ..Default::default() };
        let core = simulate(&ForcePlantParams::default(), &ctrl, 1200.0, 20, 1430).unwrap();
        assert_eq!(r.time.len(), core.len());
        let (f, fm, b0) = (
            r.column("plant.F_p").unwrap(),
            r.column("controller.F_m").unwrap(),
            r.column("controller.b0_hat").unwrap(),
        );
        for (j, c) in core.iter().enumerate() {
            assert!(
                (f[j] - c.force).abs() <= 1e-12 * c.force.abs().max(1.0),
                "beta {beta}, step {j}: {} vs {}",
                f[j],
                c.force
            );
            assert!((fm[j] - c.reference_force).abs() <= 1e-12 * 1200.0, "F_m at step {j}");
            assert!((b0[j] - c.controller.b0_hat).abs() <= 1e-12 * b0[j].abs(), "b0_hat at step {j}");
        }
        // the slope reaches the plant (Gauss–Seidel: same step) and is β(u_k − u_{k−1})/T
        let (pr, pc) = (r.column("plant.f_c_rate").unwrap(), r.column("plant.f_c").unwrap());
        assert!(pr.iter().any(|x| *x != 0.0));
        assert!(
            pc[1..]
                .iter()
                .zip(&core[1..])
                .all(|(a, c)| (a - c.feed_command).abs() <= 1e-12 * c.feed_command.abs().max(1.0))
        );
    }
}
