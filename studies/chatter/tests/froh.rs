//! Seed 004 study: `chatter froh --quick` and the library's boundary and sweep.

use seed004::froh::{self, FrohStudy, Target};
use std::process::Command;

#[test]
fn the_nmp_boundary_moves_down_with_the_chip_lag() {
    // [computed] in the reading guide: −0.65, about −0.75 and about −0.85
    let expected = [-0.65, -0.75, -0.85];
    for ((reading, tau_c), e) in froh::tau_c_readings().into_iter().zip(expected) {
        let o = FrohStudy { betas: vec![0.0], ..Default::default() };
        let (_, s) = froh::sweep(&o, reading, tau_c).unwrap();
        let b = s.nmp_boundary.unwrap();
        assert!((b - e).abs() <= 0.05, "{reading}: {b}");
        // the locus agrees: stable zero just above the boundary, unstable just below
        let l = froh::zero_locus(reading, tau_c, 1e-4, &[b + 0.01, b - 0.01]).unwrap();
        assert!(l[0].modulus < 1.0 && l[1].modulus > 1.0, "{l:?}");
    }
}

#[test]
fn with_the_true_model_the_cost_is_intersample_only_and_below_the_adaptive_cost() {
    let o = FrohStudy { duration: 3.0, substeps: 10, ..Default::default() };
    let (reading, tau_c) = froh::tau_c_readings()[0];
    for beta in [-0.4, 0.0, 0.4] {
        let p = froh::sweep_point(&o, reading, tau_c, beta).unwrap();
        assert!(p.j.is_finite() && p.j > 0.0 && p.j_true_model > 0.0, "{p:?}");
        assert!(p.j_true_model < p.j, "beta {beta}: {} vs {}", p.j_true_model, p.j);
        // a 3 s run ends at the first depth step: no post-step cost
        assert!(p.j_after.is_empty(), "{p:?}");
    }
}

#[test]
fn chatter_froh_quick_writes_the_table_and_csvs() {
    let d = std::env::temp_dir().join(format!("chatter-froh-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let out = Command::new(env!("CARGO_BIN_EXE_chatter"))
        .args(["froh", "--quick", "--out", d.to_str().unwrap()])
        .output()
        .expect("run chatter");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let md = std::fs::read_to_string(d.join("froh_summary.md")).unwrap();
    assert_eq!(md.lines().count(), 5, "{md}");
    let row = md.lines().find(|l| l.starts_with("| 1/(Nn)")).unwrap();
    let cols: Vec<&str> = row.split('|').map(str::trim).collect();
    let boundary: f64 = cols[3].parse().unwrap();
    assert!((boundary + 0.65).abs() <= 0.05, "{row}");
    let argmin: f64 = cols[4].parse().unwrap();
    assert!((-0.6..=1.0).contains(&argmin), "{row}");
    let sweep = std::fs::read_to_string(d.join("froh_sweep.csv")).unwrap();
    // 9 β values (−0.6..1.0 step 0.2) for 3 readings, plus the header
    assert_eq!(sweep.lines().count(), 28);
    assert!(std::fs::read_to_string(d.join("froh_zeros.csv")).unwrap().lines().count() == 1 + 3 * 9);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn beta_values_whose_initial_model_is_non_minimum_phase_are_left_out() {
    // τ̂ = 0.5 τ_c puts the initial model's boundary at −Γ₀/(2Γ₁) ≈ −0.571: β = −0.6 cannot start
    let o = FrohStudy { betas: vec![-0.6, 0.0], duration: 3.0, substeps: 5, tau_factor: 0.5, ..Default::default() };
    let (reading, tau_c) = froh::tau_c_readings()[0];
    let (pts, s) = froh::sweep(&o, reading, tau_c).unwrap();
    assert_eq!(pts.len(), 1);
    assert!(pts[0].beta.abs() < 1e-12 && s.argmin.abs() < 1e-12);
}

/// J's target decides the sign of the best β: against the continuous reference model's
/// response to the F_ref step (the same for every β) the best β is negative for all three τ_c
/// readings and β = −0.2 beats the ZOH (the paper's claim); against the reference model driven
/// by the FROH of F_ref (which changes with β) it is positive. At β = 0 the two targets are the
/// same signal (to rounding: the controller propagates on its own step lengths).
#[test]
fn the_sign_of_the_best_beta_depends_on_the_target_of_j() {
    let betas = vec![-0.6, -0.4, -0.2, 0.0, 0.4, 0.8];
    for (reading, tau_c) in froh::tau_c_readings() {
        let o = |target| FrohStudy { betas: betas.clone(), duration: 3.0, target, ..Default::default() };
        let (step, s) = froh::sweep(&o(Target::Step), reading, tau_c).unwrap();
        assert!(s.argmin < 0.0 && s.j_m02 < s.j0, "{reading}: {s:?}");
        let (fr, f) = froh::sweep(&o(Target::Froh), reading, tau_c).unwrap();
        assert!(f.argmin > 0.0, "{reading}: {f:?}");
        let at0 = |v: &[froh::SweepPoint]| v.iter().find(|p| p.beta == 0.0).unwrap().j;
        assert!((at0(&step) / at0(&fr) - 1.0).abs() < 1e-12, "{reading}: {} vs {}", at0(&step), at0(&fr));
    }
}

/// The initial model θ₀ (not printed in the paper) moves the best β across zero under both
/// targets: at τ_c = T/2, K̂ = 0.5 K_p puts it above zero against the FROH target and below
/// against the step target, K̂ = 2 K_p the other way round. `chatter froh --theta0 --quick`
/// writes the grid (2 targets × 4 gains × 4 time constants × 3 readings).
#[test]
fn the_sign_of_the_best_beta_depends_on_the_initial_model() {
    let o = FrohStudy { betas: vec![-0.6, -0.4, -0.2, 0.0, 0.4, 0.8], duration: 3.0, ..Default::default() };
    let rows = froh::theta0_sensitivity(&o, &[0.5, 2.0], &[1.5]).unwrap();
    let argmin = |target, g: f64| {
        let r = rows
            .iter()
            .find(|r| r.target == target && (r.gain_factor - g).abs() < 1e-12 && r.reading == "T/2")
            .unwrap();
        r.summary.as_ref().unwrap().argmin
    };
    assert!(argmin(Target::Froh, 0.5) > 0.0 && argmin(Target::Froh, 2.0) < 0.0, "{rows:?}");
    assert!(argmin(Target::Step, 0.5) < 0.0 && argmin(Target::Step, 2.0) > 0.0, "{rows:?}");
    let d = std::env::temp_dir().join(format!("chatter-froh-theta0-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let out = Command::new(env!("CARGO_BIN_EXE_chatter"))
        .args(["froh", "--theta0", "--quick", "--out", d.to_str().unwrap()])
        .output()
        .expect("run chatter");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(d.join("froh_theta0.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 2 * 4 * 4 * 3, "{csv}");
    assert_eq!(std::fs::read_to_string(d.join("froh_theta0.md")).unwrap().lines().count(), 2 + 2 * 4 * 4);
    std::fs::remove_dir_all(&d).unwrap();
}
