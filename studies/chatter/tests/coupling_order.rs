//! `chatter coupling-order --quick`: every shipped system under Gauss–Seidel and Jacobi in the
//! Rust master, with its headline metric under both (needs the packaged FMUs:
//! `cargo run --release -p packaging`).

use std::process::Command;

#[test]
fn chatter_coupling_order_quick_covers_every_shipped_system() {
    let dir = packaging::fmu_dir();
    let mut ssps: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e} (build the FMUs: cargo run --release -p packaging)", dir.display()))
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".ssp"))
        .collect();
    ssps.sort();
    assert!(ssps.len() >= 6, "{ssps:?}");
    let out = tempfile::tempdir().unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_chatter"))
        .args(["coupling-order", "--quick", "--out", out.path().to_str().unwrap()])
        .output()
        .expect("run chatter");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let csv = std::fs::read_to_string(out.path().join("coupling_order.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    // every shipped system has a row, every row two finite positive metrics and a flag that
    // agrees with the 5 % rule
    for s in &ssps {
        assert!(rows.iter().any(|r| r[0] == s), "{s} missing from\n{csv}");
    }
    for r in &rows {
        assert_eq!(r.len(), 7, "{r:?}");
        let (gs, jc): (f64, f64) = (r[3].parse().unwrap(), r[4].parse().unwrap());
        assert!(gs.is_finite() && gs > 0.0 && jc.is_finite() && jc > 0.0, "{r:?}");
        let d = (jc - gs).abs() / gs;
        assert_eq!(r[6] == "true", d > 0.05, "{r:?}");
    }
    // the documented exception: seed 003's DSMC relies on zero-delay feedback, which Jacobi
    // coupling at h = T takes away (one sample of delay); the FMUs of seed 000 do not care
    let flag = |ssp: &str| rows.iter().filter(|r| r[0] == ssp).all(|r| r[6] == "true");
    assert!(flag("SlidingModeFuzzy.ssp"), "{csv}");
    assert!(!flag("ClosedLoop.ssp") && !flag("DecomposedPlant.ssp"), "{csv}");
    let md = std::fs::read_to_string(out.path().join("coupling_order.md")).unwrap();
    assert_eq!(md.lines().count(), 2 + rows.len(), "{md}");
}
