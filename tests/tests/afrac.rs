//! Seed 001 through the packaged FMUs (`target/fmu`):
//!
//! * the shipped system `Afrac.ssp` (TurningProcess + AfracController) in the Rust master
//!   equals the cores' loop `seed001::afrac::run` (same coupling: Gauss–Seidel controller →
//!   plant, step = the sample period), switched and bumpless;
//! * `TurningProcess.fmu` alone (open loop at 450 rpm, the master's single-FMU run) decays at
//!   0.97 and grows at 1.03 of the exact limiting depth of `turning_process::stability_limit`,
//!   and Table 2's 5 mm grows while 2 mm decays.

use afrac_control::AfracParams;
use fmi_master::SystemFile;
use seed001::afrac::{Case, run};
use tests::{Short, packaged, run_short};
use turning_process::{TurningParams, stability_limit};

const REC: &[&str] = &[
    "plant.x",
    "plant.v",
    "plant.spindle_speed",
    "plant.feed",
    "controller.spindle_speed",
    "controller.beta",
    "controller.G",
];

#[test]
fn the_shipped_system_equals_the_core_loop() {
    let sys = SystemFile::open(&packaged("Afrac.ssp"), None).expect("opening Afrac.ssp");
    // 1 s: across the pulse (0.02 s), the growth and the first two switches of Table 5
    let stop = 1.0;
    for (bumpless, set) in [(false, None), (true, Some("controller.bumpless=true"))] {
        let sets: Vec<&str> = set.into_iter().collect();
        let r = run_short(&sys, &Short { stop, set: &sets, record: REC, order: None }).unwrap();
        let case = Case {
            label: "core".into(),
            plant: TurningParams::default(),
            controller: Some(AfracParams { bumpless, ..Default::default() }),
            duration: stop,
        };
        let core = run(&case).unwrap();
        assert_eq!(r.time.len(), core.len());
        let col = |n: &str| r.column(n).unwrap();
        let (x, v, n_plant, f_plant, beta) =
            (col("plant.x"), col("plant.v"), col("plant.spindle_speed"), col("plant.feed"), col("controller.beta"));
        let peak = core.iter().map(|p| p.x.abs()).fold(0.0, f64::max);
        let vpeak = core.iter().map(|p| p.v.abs()).fold(0.0, f64::max);
        let mut worst = 0.0f64;
        for (k, c) in core.iter().enumerate() {
            assert!((r.time[k] - c.t).abs() < 1e-12, "time at {k}");
            worst = worst.max((x[k] - c.x).abs() / peak).max((v[k] - c.v).abs() / vpeak);
            assert!((x[k] - c.x).abs() <= 1e-12 * peak, "bumpless {bumpless}, step {k}: x {} vs {}", x[k], c.x);
            assert!((v[k] - c.v).abs() <= 1e-12 * vpeak, "bumpless {bumpless}, step {k}: v {} vs {}", v[k], c.v);
            // recorded at t_k before the controller's sample k: the plant holds the command of
            // sample k − 1 (the start value 450 rpm / 0.1 mm/rev at t = 0)
            let (n_held, f_held) = if k == 0 { (450.0, 0.1) } else { (core[k - 1].speed, core[k - 1].feed) };
            assert!((n_plant[k] - n_held).abs() <= 1e-12 * n_held, "speed at {k}: {} vs {n_held}", n_plant[k]);
            assert!((f_plant[k] - f_held).abs() <= 1e-12 * f_held, "feed at {k}: {} vs {f_held}", f_plant[k]);
            if k > 0 {
                assert_eq!(beta[k].to_bits(), core[k - 1].beta.to_bits(), "beta at {k}");
            }
        }
        println!("bumpless {bumpless}: largest difference {worst:e} of the peak over {} steps", core.len() - 1);
        // the controller acted: the speed moved and β stepped down from 1.9 to 1.5
        assert!(core.iter().any(|p| (p.speed - 450.0).abs() > 5.0));
        assert_eq!(beta[beta.len() - 1].to_bits(), 1.5f64.to_bits());
    }
}

/// Peak |x| of `TurningProcess.fmu` alone at depth `w` (450 rpm, 0.1 mm/rev: the FMU's start
/// values) in each window, recorded at every step of 0.1 ms by the master.
fn fmu_peaks(w: f64, windows: &[(f64, f64)]) -> Vec<f64> {
    let sys = SystemFile::open(&packaged("TurningProcess.fmu"), None).expect("opening TurningProcess.fmu");
    let stop = windows.iter().map(|w| w.1).fold(0.0, f64::max);
    let depth = format!("depth={w}");
    let r = run_short(&sys, &Short { stop, set: &[depth.as_str()], record: &["x"], order: None }).unwrap();
    let x = r.column("x").unwrap();
    windows
        .iter()
        .map(|(a, b)| {
            r.time.iter().zip(&x).filter(|(t, _)| **t >= *a && **t < *b).map(|(_, x)| x.abs()).fold(0.0, f64::max)
        })
        .collect()
}

#[test]
fn the_turning_fmu_decays_at_097_and_grows_at_103_of_the_exact_limit() {
    let p = TurningParams::default();
    let lim = stability_limit(p.omega_n(), p.a1(0.1, 450.0), 60.0 / 450.0).unwrap();
    let w_lim = lim.a2 / p.a2(0.1, 1.0);
    let win = [(1.0, 1.5), (3.5, 4.0)];
    let below = fmu_peaks(0.97 * w_lim, &win);
    let above = fmu_peaks(1.03 * w_lim, &win);
    println!("TurningProcess.fmu, w_lim = {w_lim:.4} mm; 0.97: {below:?}; 1.03: {above:?}");
    assert!(below[1] < 0.8 * below[0], "0.97 w_lim must decay: {below:?}");
    assert!(above[1] > 1.25 * above[0], "1.03 w_lim must grow: {above:?}");
}

#[test]
fn the_turning_fmu_grows_at_5_mm_and_decays_at_2_mm() {
    let win = [(0.2, 0.4), (1.6, 1.8)];
    let five = fmu_peaks(5.0, &win);
    let two = fmu_peaks(2.0, &win);
    println!("TurningProcess.fmu open loop, peaks |x| [mm] in 0.2-0.4 s / 1.6-1.8 s: 5 mm {five:?}; 2 mm {two:?}");
    assert!(five[1] > 2.0 * five[0], "{five:?}");
    assert!(two[1] < 0.1 * two[0], "{two:?}");
}
