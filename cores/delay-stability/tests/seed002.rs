//! Seed 002 (Section 6, Table I): the semi-discretisation against the exact boundary of the
//! time-invariant case, its convergence in m, and the closed loop with the printed gains.

use delay_stability::presets::{SEED002_GAINS, seed002, seed002_gain};
use delay_stability::sd::{critical_multiplier, eigenvalues};
use delay_stability::{BisectionOptions, critical_value, monodromy, monodromy_dense};

fn sd_depth(x_f: f64, gain: Option<nalgebra::DMatrix<f64>>, rpm: f64, m: usize) -> f64 {
    let model = seed002(x_f, gain).unwrap();
    let o = BisectionOptions { m, start: 0.2e-3, growth: 1.1, max: 0.02, rel_tol: 1e-6 };
    critical_value(|a| model.at(rpm, a), &o).unwrap().value.expect("a boundary below 20 mm")
}

#[test]
fn time_invariant_open_loop_matches_the_exact_boundary() {
    let model = seed002(1.0, None).unwrap();
    // x_F = 1, full immersion, z = 4: H(t) is constant, −K_r I + K_t J
    let h = model.cutter.mean();
    for phi in [0.1, 0.7, 1.3] {
        let hd = model.cutter.directional(phi);
        assert!((hd - h).norm() < 1e-9 * h.norm(), "H({phi}) = {hd} differs from H̄ = {h}");
    }
    assert!((h[(0, 0)] + 38.6e6).abs() < 1.0 && (h[(1, 0)] - 462e6).abs() < 1.0, "{h}");
    let ti = model.time_invariant();
    for rpm in [36000.0, 38000.0] {
        let exact = ti.critical_depth(rpm, 40_000).unwrap().unwrap().depth;
        let sd = sd_depth(1.0, None, rpm, 40);
        println!("open loop {rpm} rpm: exact {:.5} mm, SD(m=40) {:.5} mm", exact * 1e3, sd * 1e3);
        assert!((sd / exact - 1.0).abs() < 2e-3, "SD {sd} vs exact {exact}");
    }
}

#[test]
fn closed_loop_with_the_printed_gains() {
    let (k1, k2) = SEED002_GAINS;
    let model = seed002(1.0, Some(seed002_gain(k1, k2))).unwrap();
    let exact = model.time_invariant().critical_depth(37800.0, 40_000).unwrap().unwrap().depth;
    let sd = sd_depth(1.0, Some(seed002_gain(k1, k2)), 37800.0, 40);
    println!("closed loop 37800 rpm: exact {:.4} mm, SD(m=40) {:.4} mm (paper 3.52)", exact * 1e3, sd * 1e3);
    assert!((sd / exact - 1.0).abs() < 5e-3, "SD {sd} vs exact {exact}");
    assert!(exact > 3.0e-3 && exact < 4.0e-3);
}

#[test]
fn reduced_monodromy_has_the_eigenvalues_of_the_dense_one() {
    let (k1, k2) = SEED002_GAINS;
    let model = seed002(0.744, Some(seed002_gain(k1, k2))).unwrap();
    let sys = model.at(36000.0, 1.0e-3).unwrap();
    let m = 12;
    let small = eigenvalues(&monodromy(&sys, m).unwrap()).unwrap();
    let big = eigenvalues(&monodromy_dense(&sys, m).unwrap()).unwrap();
    assert_eq!(monodromy(&sys, m).unwrap().nrows(), 8 + 4 * m);
    assert_eq!(monodromy_dense(&sys, m).unwrap().nrows(), 8 * (m + 1));
    // the multipliers away from the (defective, so sensitive) zero eigenvalues agree
    let count = small.iter().filter(|z| z.norm() > 0.1).count();
    assert!(count >= 4, "{count}");
    for k in 0..count {
        assert!((small[k].norm() - big[k].norm()).abs() < 1e-7, "{k}: {} vs {}", small[k], big[k]);
    }
    let c = critical_multiplier(&sys, m).unwrap();
    assert!((c.rho - small[0].norm()).abs() < 1e-15);
}

#[test]
fn the_sign_and_the_transpose_of_the_gain_matter() {
    // F_a = +D_c Δv_a as printed; −D_c and D_cᵀ destabilise the cut (spec §3.2: 0.10–0.15 mm)
    let (k1, k2) = SEED002_GAINS;
    let dc = seed002_gain(k1, k2);
    let o = BisectionOptions { m: 30, start: 1e-5, growth: 1.15, max: 0.02, rel_tol: 1e-4 };
    for (name, gain) in [("−D_c", -dc.clone()), ("D_cᵀ", dc.transpose())] {
        let model = seed002(1.0, Some(gain)).unwrap();
        let c = critical_value(|a| model.at(37800.0, a), &o);
        let depth = match c {
            Ok(c) => c.value.unwrap(),
            Err(delay_stability::StabilityError::UnstableAtStart { .. }) => 0.0,
            Err(e) => panic!("{e}"),
        };
        println!("{name}: {:.4} mm at 37800 rpm", depth * 1e3);
        assert!(depth < 0.2e-3, "{name}: {depth}");
    }
}

#[test]
fn exact_boundary_of_a_single_mode_has_the_classic_minimum() {
    // one mode along x, full immersion, z = 4: H_xx = −K_r exactly, so F_x = −a K_r (x − x(t−τ))
    // and the lobe minimum over speed is 2kζ(1 + ζ)/K_r
    use delay_stability::milling::{Cutter, ForceLaw, MillingModel, ModeShape, Structure};
    let (m, k, zeta, kr) = (30.0f64, 2.4e7f64, 0.0088, 210e6);
    let mode = ModeShape { omega: (k / m).sqrt(), zeta, tool: [1.0 / m.sqrt(), 0.0], actuator: [0.0, 0.0] };
    let s = Structure::from_modes(&[mode]).unwrap();
    let cutter = Cutter::new(4, 0.0, std::f64::consts::PI, 760e6, kr, ForceLaw::Linear).unwrap();
    let model = MillingModel::new(&s, cutter, None).unwrap();
    let ti = model.time_invariant();
    // the lobe between 2000 and 3000 rpm, 10 rpm steps (its bottom is flat to 1e-4 over a step)
    let min = (0..=100)
        .map(|i| ti.critical_depth(2000.0 + 10.0 * i as f64, 3000).unwrap().unwrap().depth)
        .fold(f64::INFINITY, f64::min);
    let analytic = 2.0 * k * zeta * (1.0 + zeta) / kr;
    assert!((min / analytic - 1.0).abs() < 1e-3, "{min} vs {analytic}");
    // and the SD agrees with the exact boundary at one speed
    let o = BisectionOptions { m: 40, start: 1e-3, growth: 1.1, max: 0.5, rel_tol: 1e-6 };
    let sd = critical_value(|a| model.at(2500.0, a), &o).unwrap().value.unwrap();
    let exact = ti.critical_depth(2500.0, 40_000).unwrap().unwrap().depth;
    assert!((sd / exact - 1.0).abs() < 2e-3, "{sd} vs {exact}");
}
