//! The shipped closed loop (MillingPlant + ChatterController from
//! `target/fmu`) in the Rust master, through the library API: the SSP
//! archive and the embedded SSD agree, the stepping order is the documented
//! one, runs are reproducible per noise seed, and FMU errors are reported
//! with the FMU's own words. Short runs (0.05–0.2 s) keep CI fast.

use fmi_master::ssp::Order;
use tests::{Short, closed_loop_embedded, closed_loop_ssp, rms, run_short};

const REC: &[&str] = &["plant.x", "plant.u", "controller.y", "controller.u"];

#[test]
fn the_ssp_archive_and_the_embedded_ssd_give_identical_results() {
    let o = Short { stop: 0.05, set: &["controller.structure=adrc_fopid", "plant.seed=3"], record: REC, order: None };
    let a = run_short(&closed_loop_ssp(), &o).unwrap();
    let b = run_short(&closed_loop_embedded(), &o).unwrap();
    assert_eq!(a.rows.len(), 5001);
    assert_eq!(a.rows, b.rows, "ClosedLoop.ssp and the embedded ClosedLoop.ssd must be the same system");
    assert!(a.rows.iter().flatten().all(|v| v.is_finite()));
}

#[test]
fn time_is_t0_plus_n_h() {
    let o = Short { stop: 0.02, set: &[], record: &["plant.x"], order: None };
    let r = run_short(&closed_loop_ssp(), &o).unwrap();
    assert_eq!(r.time.len(), 2001);
    for (n, t) in r.time.iter().enumerate() {
        assert_eq!(t.to_bits(), (n as f64 * 1e-5).to_bits(), "sample {n}");
    }
}

/// Gauss–Seidel controller → plant (the order declared in ClosedLoop.ssd):
/// in the step from tₙ the controller sees the plant's x(tₙ), the plant sees
/// the command the controller computed in the same step. Jacobi: both see
/// the other's output at tₙ.
#[test]
fn stepping_orders_wire_the_signals_as_documented() {
    let sys = closed_loop_ssp();
    for order in [None, Some(Order::Jacobi)] {
        let o = Short { stop: 0.02, set: &["controller.structure=pid", "plant.seed=1"], record: REC, order };
        let r = run_short(&sys, &o).unwrap();
        let (x, pu, y, cu) =
            (r.column("plant.x").unwrap(), r.column("plant.u").unwrap(), r.column("controller.y").unwrap(), {
                r.column("controller.u").unwrap()
            });
        // At t0 the inputs are set from the initial outputs.
        assert_eq!(y[0].to_bits(), x[0].to_bits());
        assert_eq!(pu[0].to_bits(), cu[0].to_bits());
        for n in 0..x.len() - 1 {
            assert_eq!(y[n + 1].to_bits(), x[n].to_bits(), "{order:?}: controller.y(t{}) = plant.x(t{n})", n + 1);
            let expect = if order == Some(Order::Jacobi) { cu[n] } else { cu[n + 1] };
            assert_eq!(pu[n + 1].to_bits(), expect.to_bits(), "{order:?}: plant.u at t{}", n + 1);
        }
        assert!(cu.iter().any(|u| *u != 0.0), "the PID acts on the measured displacement");
    }
}

#[test]
fn runs_are_reproducible_per_noise_seed_and_seeds_differ() {
    let sys = closed_loop_ssp();
    let run = |seed: &str| {
        let set = ["controller.structure=fopid", seed];
        run_short(&sys, &Short { stop: 0.05, set: &set, record: &["plant.x"], order: None }).unwrap()
    };
    let a = run("plant.seed=7");
    let b = run("plant.seed=7");
    let c = run("plant.seed=8");
    assert_eq!(a.rows, b.rows, "same seed, same result");
    assert_ne!(a.rows, c.rows, "another noise seed gives another realization");
    let (ra, rc) = (rms(&a.column("plant.x").unwrap()), rms(&c.column("plant.x").unwrap()));
    assert!(ra > 0.0 && rc > 0.0);
}

#[test]
fn every_controller_structure_runs_and_acts() {
    let sys = closed_loop_ssp();
    for s in ["off", "pid", "fopid", "adrc_fopid"] {
        let set = [format!("controller.structure={s}"), "plant.seed=2".to_string()];
        let set: Vec<&str> = set.iter().map(String::as_str).collect();
        let r = run_short(&sys, &Short { stop: 0.05, set: &set, record: REC, order: None }).unwrap();
        let u = r.column("controller.u").unwrap();
        assert!(r.rows.iter().flatten().all(|v| v.is_finite()), "{s}: non-finite values");
        if s == "off" {
            assert!(u.iter().all(|u| *u == 0.0), "open loop: no command");
        } else {
            assert!(rms(&u) > 0.0, "{s}: the controller never acts");
        }
    }
}

#[test]
fn a_value_the_fmu_refuses_is_reported_with_the_fmus_log() {
    // A negative modal mass: the master type-checks the value (a number), the FMU refuses it.
    let o = Short { stop: 0.01, set: &["plant.workpiece.mass=-1"], record: &["plant.x"], order: None };
    let e = run_short(&closed_loop_ssp(), &o).unwrap_err().to_string();
    assert!(e.contains("FMU instance 'plant' (MillingPlant)"), "{e}");
    assert!(e.contains("fmi2SetReal returned fmi2Error at t = 0 s"), "{e}");
    assert!(e.contains("workpiece.mass"), "the FMU's own message must be quoted: {e}");
}
