//! Seed 003 study: `chatter dsmc --quick` and the library's calibration and ranking.

use seed003::dsmc::{self, DsmcStudy, Row};
use seed003::readings::{self, SweepSpec};
use std::process::Command;

fn row(label: &str, paper: &'static str, mse: [f64; 2]) -> Row {
    Row {
        label: label.into(),
        paper,
        mse,
        reduction: [0.0; 2],
        max_force: [0.0; 2],
        max_stroke_mm: [0.0; 2],
        updates: [0.0; 2],
    }
}

#[test]
fn the_ranking_check_reads_table_2_and_can_fail() {
    let paper: Vec<Row> = dsmc::TABLE2.iter().map(|(n, x, y)| row(n, n, [*x, *y])).collect();
    assert!(dsmc::ranking_holds(&paper, 0) && dsmc::ranking_holds(&paper, 1));
    let mut swapped = paper.clone();
    swapped[1].mse[0] = 0.15; // DSMC better than D-PID on x
    assert!(!dsmc::ranking_holds(&swapped, 0) && dsmc::ranking_holds(&swapped, 1));
    // Table 2's own reductions: the text's 70.20 % for DSMC-T1 on x is 69.34 % by the table
    let t1x: f64 = 100.0 * (1.0 - 0.1172 / 0.3823);
    assert!((t1x - 69.34).abs() < 0.01, "{t1x}");
}

#[test]
fn the_coupled_calibration_hits_table_2s_open_loop() {
    let s = DsmcStudy { t_end: 0.3, ..Default::default() };
    let (amp, open) = dsmc::calibrate(&s).unwrap();
    assert!(amp.iter().all(|a| a.is_finite() && *a > 0.0), "{amp:?}");
    // superposition holds to the damper's tanh friction: the check run is within 1e-3
    assert!((open[0] / 0.3823 - 1.0).abs() < 1e-3 && (open[1] / 0.3702 - 1.0).abs() < 1e-3, "{open:?}");
}

#[test]
fn chatter_dsmc_quick_writes_the_table_and_csv() {
    let d = std::env::temp_dir().join(format!("chatter-dsmc-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let out = Command::new(env!("CARGO_BIN_EXE_chatter"))
        .args(["dsmc", "--quick", "--out", d.to_str().unwrap()])
        .output()
        .expect("run chatter");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(d.join("dsmc_table2.csv")).unwrap();
    let rows: Vec<Vec<String>> = csv.lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect();
    assert_eq!(rows.len(), 7, "{csv}");
    let mse = |label: &str, axis: usize| -> f64 {
        rows.iter().find(|r| r[0] == label).unwrap_or_else(|| panic!("no row {label}"))[2 + axis].parse().unwrap()
    };
    for a in 0..2 {
        let none = mse("none", a);
        // every controller reduces the vibration; the sliding-mode family beats the D-PID
        // (the one swap against the paper's ranking, README)
        for c in ["dsmc", "dpid (error in mm)", "dsmc_t1", "dsmc_t2"] {
            assert!(mse(c, a) < none, "{c} axis {a}");
        }
        assert!(mse("dsmc", a) < mse("dpid (error in mm)", a), "axis {a}");
    }
    let md = std::fs::read_to_string(d.join("dsmc_table2.md")).unwrap();
    assert!(md.contains("ranking T2 < T1 < D-PID < DSMC < none on x"), "{md}");
    // the readings grid of --quick: 4 readings × T = 1e-4, 3e-4 s × 2 kN, 5 controllers each
    let grid = std::fs::read_to_string(d.join("dsmc_readings.csv")).unwrap();
    assert_eq!(grid.lines().count(), 1 + 4 * 2 * 5, "{grid}");
    // a reading's label must not split a CSV row
    assert!(grid.lines().all(|l| l.split(',').count() == 12), "{grid}");
    let md = std::fs::read_to_string(d.join("dsmc_readings.md")).unwrap();
    assert!(md.contains("| Euler (j = p + T v) | 3e-4 | 2000 |"), "{md}");
    std::fs::remove_dir_all(&d).unwrap();
}

/// Eq. 22 calls A_dis unknown: with the Euler model (j = p + T v) at T = 3e-4 s the plain DSMC
/// leaves most of the y vibration and the fuzzy compensation removes it (T1, T2 below the
/// DSMC on both axes, by far on y); with the exact model the DSMC alone leaves little.
#[test]
fn an_imperfect_nominal_model_leaves_a_residual_the_fuzzy_compensation_removes() {
    let s = DsmcStudy { t_end: 0.3, ..Default::default() };
    let all = readings::readings();
    let spec = SweepSpec { readings: vec![all[1], all[0]], periods: vec![3e-4], force_limits: vec![2000.0] };
    assert_eq!(spec.readings[0].nominal_model, sliding_fuzzy_control::NominalModel::Euler);
    let pts = readings::sweep(&s, &spec).unwrap();
    let (euler, exact) = (&pts[0], &pts[1]);
    assert!(euler.reduction("dsmc", 1) < 50.0, "{euler:?}");
    for c in ["dsmc_t1", "dsmc_t2"] {
        assert!(euler.reduction(c, 1) > 90.0, "{c}: {euler:?}");
        for a in 0..2 {
            assert!(euler.mse_of(c, a) < euler.mse_of("dsmc", a), "{c} axis {a}: {euler:?}");
        }
    }
    assert!(exact.reduction("dsmc", 1) > 90.0, "{exact:?}");
    // the paper's y ranking under this reading: T2 < T1 < D-PID < DSMC < none
    assert_eq!(euler.ranking(1), ["dsmc_t2", "dsmc_t1", "dpid", "dsmc", "none"]);
}
