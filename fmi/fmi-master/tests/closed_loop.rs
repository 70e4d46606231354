//! The `cosim` command line on the project's own FMUs (`target/fmu`, built
//! by `cargo run --release -p packaging` before the tests): the shipped SSP
//! and its bare SSD with `--fmu-dir` run, malformed inputs on the real FMUs (wrong GUID, bad
//! `--set` values) give a clear error and a non-zero exit, and no temporary
//! directory is left behind on success or failure.

mod common;

use common::{cosim, fmu_dir, packaged, rewrite_zip, run};
use std::path::Path;

/// Entries left in a temporary directory (the master's extraction directories start with `fmi-master-`).
fn leftovers(tmp: &Path) -> Vec<String> {
    std::fs::read_dir(tmp).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect()
}

#[test]
fn the_shipped_ssp_and_its_bare_ssd_run_and_clean_up() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let csv = dir.path().join("ssp.csv");
    let (ok, _, err) = run(cosim()
        .env("TMPDIR", tmp.path())
        .arg("run")
        .arg(packaged("ClosedLoop.ssp"))
        .args(["--stop-time", "0.05", "--output-interval", "1e-3", "--set", "controller.structure=adrc_fopid", "-o"])
        .arg(&csv));
    assert!(ok, "{err}");
    assert!(err.contains("gauss-seidel: controller → plant"), "{err}");
    let t = fmi_master::csv::read_csv(&csv).unwrap();
    assert_eq!(t.columns[0].len(), 51, "0.05 s at a 1 ms output interval");
    assert!(t.names.contains(&"plant.x".to_string()) && t.names.contains(&"controller.u".to_string()), "{:?}", t.names);
    assert!(leftovers(tmp.path()).is_empty(), "temporary files left: {:?}", leftovers(tmp.path()));
    // The same system as a bare .ssd with the FMUs of --fmu-dir: the same numbers.
    let csv2 = dir.path().join("ssd.csv");
    let (ok, _, err) = run(cosim()
        .env("TMPDIR", tmp.path())
        .arg("run")
        .arg(common::workspace_root().join("packaging/scenarios/ClosedLoop.ssd"))
        .arg("--fmu-dir")
        .arg(fmu_dir())
        .args(["--stop-time", "0.05", "--output-interval", "1e-3", "--set", "controller.structure=adrc_fopid", "-o"])
        .arg(&csv2));
    assert!(ok, "{err}");
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), std::fs::read_to_string(&csv2).unwrap());
    assert!(leftovers(tmp.path()).is_empty(), "temporary files left: {:?}", leftovers(tmp.path()));
}

#[test]
fn failures_exit_non_zero_with_a_clear_message_and_clean_up() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let ssp = packaged("ClosedLoop.ssp");
    let csv = dir.path().join("x.csv");
    let cases: &[(&[&str], &str)] = &[
        (&["--set", "plant.seed=1.5"], "--set plant.seed=1.5: 'seed' is an Integer variable; '1.5' is not an integer"),
        (&["--set", "plant.spindle_speed=fast"], "'spindle_speed' is a Real variable; 'fast' is not a number"),
        (&["--set", "controller.structure=lqr"], "'lqr' is not an item of enumeration 'structure'"),
        (
            &["--set", "plant.no_such_parameter=1"],
            "component 'plant' (MillingPlant.fmu) has no variable 'no_such_parameter'",
        ),
        (&["--set", "plant.x=1"], "'x' cannot be set"),
        (&["--step", "3e-5"], "is not a whole number of steps"),
    ];
    for (args, expect) in cases {
        let (ok, _, err) = run(cosim()
            .env("TMPDIR", tmp.path())
            .arg("run")
            .arg(&ssp)
            .args(["--stop-time", "0.01"])
            .args(*args)
            .arg("-o")
            .arg(&csv));
        assert!(!ok, "{args:?} should fail");
        assert!(err.starts_with("error: ") && err.contains(expect), "{args:?}: expected '{expect}' in:\n{err}");
        assert!(leftovers(tmp.path()).is_empty(), "{args:?}: temporary files left: {:?}", leftovers(tmp.path()));
    }
}

#[test]
fn a_wrong_guid_exits_non_zero_quoting_the_fmu() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("MillingPlant.fmu");
    rewrite_zip(&packaged("MillingPlant.fmu"), &bad, |name, data| {
        if name != "modelDescription.xml" {
            return Some(data);
        }
        let xml = String::from_utf8(data).unwrap();
        let start = xml.find("guid=\"").expect("guid attribute") + 6;
        let end = start + xml[start..].find('"').unwrap();
        Some(format!("{}{{00000000-0000-0000-0000-000000000000}}{}", &xml[..start], &xml[end..]).into_bytes())
    });
    let (ok, _, err) =
        run(cosim().arg("run").arg(&bad).args(["--stop-time", "0.01", "-o"]).arg(dir.path().join("x.csv")));
    assert!(!ok);
    assert!(err.contains("fmi2Instantiate of instance 'MillingPlant' failed"), "{err}");
    assert!(err.contains("Wrong GUID {00000000-0000-0000-0000-000000000000}"), "{err}");
}
