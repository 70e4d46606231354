//! The 2-D frequency-domain solvers ([`delay_stability::frequency`]) against the
//! semi-discretisation of the same milling model (the same `Cutter`), and their convergence.
//!
//! Machines: the 1-DOF benchmark of Insperger & Stépán (f_n = 922 Hz, ζ = 0.011,
//! m = 0.03993 kg along the feed, z = 2, K_t = 6e8, K_r = 2e8 N/m²) and the 3-mode machine of the
//! "Your own machine" issue (x: 600 Hz 2e7 N/m ζ 0.03, 1100 Hz 5e7 N/m ζ 0.02; y: 650 Hz
//! 2.5e7 N/m ζ 0.035; z = 3, K_t = 8e8, K_r = 0.3 K_t).

use delay_stability::frequency::{Lobes, ModalReceptance, MultiFrequency, Receptance, ZeroOrder2d};
use delay_stability::milling::{Cutter, ForceLaw, Milling, MillingModel, ModeShape, Structure};
use delay_stability::zero_order::{GridOptions, speed_grid};
use delay_stability::{BisectionOptions, critical_value};
use std::f64::consts::PI;

fn one_dof() -> Vec<ModeShape> {
    let m = 0.03993f64;
    vec![ModeShape { omega: 2.0 * PI * 922.0, zeta: 0.011, tool: [1.0 / m.sqrt(), 0.0], actuator: [0.0, 0.0] }]
}

fn machine() -> Vec<ModeShape> {
    vec![
        ModalReceptance::mode(600.0, 2e7, 0.03, [1.0, 0.0]),
        ModalReceptance::mode(1100.0, 5e7, 0.02, [1.0, 0.0]),
        ModalReceptance::mode(650.0, 2.5e7, 0.035, [0.0, 1.0]),
    ]
}

fn cutter(teeth: u32, frac: f64, kt: f64, kr: f64) -> Cutter {
    let (e, x) = Cutter::immersion(frac, Milling::Down);
    Cutter::new(teeth, e, x, kt, kr, ForceLaw::Linear).unwrap()
}

fn modal(modes: &[ModeShape]) -> ModalReceptance {
    ModalReceptance::new(modes).unwrap()
}

/// SD critical depth with m intervals.
fn sd(modes: &[ModeShape], c: &Cutter, rpm: f64, m: usize) -> f64 {
    let model = MillingModel::new(&Structure::from_modes(modes).unwrap(), c.clone(), None).unwrap();
    let o = BisectionOptions { m, start: 1e-5, growth: 1.1, max: 0.3, rel_tol: 1e-5 };
    critical_value(|a| model.at(rpm, a), &o).unwrap().value.unwrap()
}

#[test]
fn multi_frequency_without_harmonics_is_the_zero_order_solver() {
    for frac in [1.0, 0.1] {
        let c = cutter(3, frac, 8e8, 2.4e8);
        let zo = ZeroOrder2d::new(modal(&machine()), &c, (10.0, 4000.0), 4000.0).unwrap();
        let mf = MultiFrequency::with_harmonics(modal(&machine()), &c, (10.0, 4000.0), 4000.0, 0).unwrap();
        for rpm in speed_grid(4000.0, 30000.0, 61) {
            let (a, b) = (zo.critical_depth(rpm), mf.critical_depth(rpm));
            assert!((a.depth / b.depth - 1.0).abs() < 1e-9, "{frac} {rpm}: {a:?} vs {b:?}");
            assert!((a.chatter_hz / b.chatter_hz - 1.0).abs() < 1e-9);
        }
    }
}

#[test]
fn with_a_constant_directional_matrix_multi_frequency_is_zero_order() {
    // four teeth in slotting: always two teeth engaged and their cos 2φ, sin 2φ terms cancel, so
    // H(t) = H̄ and every harmonic vanishes; the automatic h is 0 and a fixed h changes nothing
    let c = cutter(4, 1.0, 8e8, 2.4e8);
    let zo = ZeroOrder2d::new(modal(&machine()), &c, (10.0, 4000.0), 4000.0).unwrap();
    let auto = MultiFrequency::new(modal(&machine()), &c, (10.0, 4000.0), 4000.0).unwrap();
    let fixed = MultiFrequency::with_harmonics(modal(&machine()), &c, (10.0, 4000.0), 4000.0, 3).unwrap();
    for rpm in speed_grid(5000.0, 25000.0, 9) {
        assert_eq!(auto.harmonics_at(rpm), 0);
        let z = zo.critical_depth(rpm).depth;
        assert!((auto.critical_depth(rpm).depth / z - 1.0).abs() < 1e-9);
        let f = fixed.critical_depth(rpm).depth;
        assert!((f / z - 1.0).abs() < 1e-6, "{rpm}: h = 3 {f} vs zero-order {z}");
    }
}

/// Relative error.
fn err(x: f64, reference: f64) -> f64 {
    (x / reference - 1.0).abs()
}

#[test]
fn at_low_immersion_multi_frequency_agrees_with_sd_far_better_than_zero_order() {
    // 1-DOF benchmark, a/D = 0.05 down-milling: flip lobes at 13,700-18,300 rpm. SD's own error
    // at m = 40 reaches 3 % here, so MF is also compared with the Richardson extrapolation
    // (4 SD(80) − SD(40))/3 of SD's O(1/m²) error.
    let c = cutter(2, 0.05, 6e8, 2e8);
    let mf = MultiFrequency::new(modal(&one_dof()), &c, (50.0, 5000.0), 12000.0).unwrap();
    let zo = ZeroOrder2d::new(modal(&one_dof()), &c, (50.0, 5000.0), 12000.0).unwrap();
    let (mut e_mf, mut e_zo) = (0.0, 0.0);
    println!("1-DOF, a/D = 0.05: rpm, SD(40), SD extrapolated, MF (h), zero-order [mm]");
    for rpm in [14000.0, 16000.0, 18000.0, 19000.0, 22000.0] {
        let (s40, s80) = (sd(&one_dof(), &c, rpm, 40), sd(&one_dof(), &c, rpm, 80));
        let rich = (4.0 * s80 - s40) / 3.0;
        let (m, z) = (mf.critical_depth(rpm).depth, zo.critical_depth(rpm).depth);
        println!(
            "{rpm:6.0} {:8.4} {:8.4} {:8.4} ({}) {:8.4}",
            s40 * 1e3,
            rich * 1e3,
            m * 1e3,
            mf.harmonics_at(rpm),
            z * 1e3
        );
        assert!(err(m, s40) < 0.035, "{rpm}: MF {m} vs SD {s40}");
        assert!(err(m, rich) < 0.004, "{rpm}: MF {m} vs extrapolated SD {rich}");
        if (14000.0..=18000.0).contains(&rpm) {
            // the flip lobes: zero-order does not see them
            assert!(err(z, s40) > 0.3, "{rpm}: zero-order {z} vs SD {s40}");
        }
        e_mf += err(m, s40);
        e_zo += err(z, s40);
    }
    assert!(e_mf < 0.1 * e_zo, "mean errors against SD(40): MF {e_mf}, zero-order {e_zo}");

    for frac in [0.05, 0.1] {
        let c = cutter(3, frac, 8e8, 2.4e8);
        let mf = MultiFrequency::new(modal(&machine()), &c, (10.0, 4000.0), 6000.0).unwrap();
        let zo = ZeroOrder2d::new(modal(&machine()), &c, (10.0, 4000.0), 6000.0).unwrap();
        let (mut e_mf, mut e_zo) = (0.0, 0.0);
        println!("3-mode machine, a/D = {frac}: rpm, SD(40), MF (h), zero-order [mm]");
        for rpm in [8000.0, 10000.0, 16000.0] {
            let s = sd(&machine(), &c, rpm, 40);
            let (m, z) = (mf.critical_depth(rpm).depth, zo.critical_depth(rpm).depth);
            println!("{rpm:6.0} {:8.3} {:8.3} ({}) {:8.3}", s * 1e3, m * 1e3, mf.harmonics_at(rpm), z * 1e3);
            assert!(err(m, s) < 0.01, "{frac} {rpm}: MF {m} vs SD {s}");
            e_mf += err(m, s);
            e_zo += err(z, s);
        }
        assert!(e_mf < 0.1 * e_zo, "{frac}: mean errors against SD(40): MF {e_mf}, zero-order {e_zo}");
    }
}

#[test]
fn at_slotting_multi_frequency_agrees_with_sd_and_zero_order_is_the_averaged_system() {
    // three teeth in slotting: one or two teeth cut in turn, so H(t) is not constant and the
    // zero-order (= exact averaged) boundary differs from the time-periodic one at some speeds
    let c = cutter(3, 1.0, 8e8, 2.4e8);
    let mf = MultiFrequency::new(modal(&machine()), &c, (10.0, 4000.0), 6000.0).unwrap();
    let zo = ZeroOrder2d::new(modal(&machine()), &c, (10.0, 4000.0), 6000.0).unwrap();
    let ti = MillingModel::new(&Structure::from_modes(&machine()).unwrap(), c.clone(), None).unwrap().time_invariant();
    println!("3-mode machine, slotting: rpm, SD(40), MF (h), zero-order, exact averaged [mm]");
    for rpm in [6000.0, 10000.0, 13000.0, 16000.0, 20000.0] {
        let s = sd(&machine(), &c, rpm, 40);
        let (m, z) = (mf.critical_depth(rpm).depth, zo.critical_depth(rpm).depth);
        let ex = ti.critical_depth(rpm, 40_000).unwrap().unwrap().depth;
        println!(
            "{rpm:6.0} {:7.4} {:7.4} ({}) {:7.4} {:7.4}",
            s * 1e3,
            m * 1e3,
            mf.harmonics_at(rpm),
            z * 1e3,
            ex * 1e3
        );
        assert!(err(m, s) < 0.01, "{rpm}: MF {m} vs SD {s}");
        assert!(err(z, ex) < 1e-4);
    }
}

/// Modes, cutter, band and speeds.
type Case = (Vec<ModeShape>, Cutter, (f64, f64), Vec<f64>);

#[test]
fn the_automatic_number_of_harmonics_is_converged_at_low_immersion() {
    // one more harmonic than the rule changes the boundary by less than 0.1 %
    let cases: [Case; 3] = [
        (one_dof(), cutter(2, 0.05, 6e8, 2e8), (50.0, 5000.0), vec![14000.0, 19000.0]),
        (machine(), cutter(3, 0.05, 8e8, 2.4e8), (10.0, 4000.0), vec![10000.0]),
        (machine(), cutter(3, 0.1, 8e8, 2.4e8), (10.0, 4000.0), vec![10000.0]),
    ];
    for (modes, c, band, speeds) in cases {
        let auto = MultiFrequency::new(modal(&modes), &c, band, speeds[0]).unwrap();
        for rpm in speeds {
            let h = auto.harmonics_at(rpm);
            let more = MultiFrequency::with_harmonics(modal(&modes), &c, band, rpm, h + 1).unwrap();
            let (a, b) = (auto.critical_depth(rpm).depth, more.critical_depth(rpm).depth);
            println!("{rpm} rpm: h = {h}: {:.5} mm, h + 1: {:.5} mm ({:.3} %)", a * 1e3, b * 1e3, 100.0 * err(a, b));
            assert!(err(a, b) < 1e-3, "{rpm} rpm, h = {h}: {a} vs {b}");
        }
    }
}

#[test]
fn the_depths_do_not_depend_on_the_grid() {
    let c = cutter(3, 1.0, 8e8, 2.4e8);
    let base = GridOptions::new(10.0, 4000.0, 3, 4000.0);
    let z1 = ZeroOrder2d::with_grid(modal(&machine()), &c, &base).unwrap();
    let z2 = ZeroOrder2d::with_grid(modal(&machine()), &c, &base.refined(10.0)).unwrap();
    assert!(z2.grid_len() > 5 * z1.grid_len());
    for rpm in speed_grid(4000.0, 30000.0, 97) {
        assert!(err(z1.critical_depth(rpm).depth, z2.critical_depth(rpm).depth) < 1e-9, "{rpm}");
    }
    let c = cutter(3, 0.1, 8e8, 2.4e8);
    let m1 = MultiFrequency::new(modal(&machine()), &c, (10.0, 4000.0), 8000.0).unwrap();
    let m2 =
        MultiFrequency::with_grid(modal(&machine()), &c, &GridOptions::new(10.0, 4000.0, 3, 8000.0), None).unwrap();
    assert!(m2.grid_len() > m1.grid_len());
    for rpm in [9000.0, 15000.0] {
        assert!(err(m1.critical_depth(rpm).depth, m2.critical_depth(rpm).depth) < 1e-9, "{rpm}");
    }
}

#[test]
fn the_refined_extremes_bound_the_grid_and_a_trait_object_is_a_receptance() {
    let c = cutter(3, 1.0, 8e8, 2.4e8);
    let boxed: Box<dyn Receptance> = Box::new(modal(&machine()));
    let zo = ZeroOrder2d::new(boxed, &c, (10.0, 4000.0), 4000.0).unwrap();
    let reference = ZeroOrder2d::new(modal(&machine()), &c, (10.0, 4000.0), 4000.0).unwrap();
    let d = zo.diagram(&speed_grid(4000.0, 30000.0, 261));
    assert_eq!(d, reference.diagram(&speed_grid(4000.0, 30000.0, 261)));
    let ex = zo.extremes(&d).unwrap();
    let lo = d.iter().map(|p| p.depth).fold(f64::INFINITY, f64::min);
    let hi = d.iter().map(|p| p.depth).fold(0.0, f64::max);
    assert!(ex.min.depth <= lo && ex.max.depth >= hi);
    // brute force on a 0.1 rpm grid around the refined minimum
    let fine = speed_grid(ex.min.rpm - 50.0, ex.min.rpm + 50.0, 1001);
    let brute = fine.iter().map(|&n| zo.critical_depth(n).depth).fold(f64::INFINITY, f64::min);
    assert!(ex.min.depth <= brute * (1.0 + 1e-9));
    println!(
        "3-mode machine, slotting: b_min {:.4} mm at {:.1} rpm, b_max {:.4} mm at {:.1} rpm",
        ex.min.depth * 1e3,
        ex.min.rpm,
        ex.max.depth * 1e3,
        ex.max.rpm
    );
}
