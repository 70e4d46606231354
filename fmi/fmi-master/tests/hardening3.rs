//! Regression tests of the third hardening round (issue 31) through the `cosim` command line;
//! each failed before its fix: an unbounded grid, a CSV written over the run's own input, into
//! a directory or over a CSV another run is writing, duplicate `--set` and `--record`, an
//! algebraic loop that ran silently, and an SSD with too many attributes.

mod common;

use common::{cosim, packaged, rewrite_zip, run};
use model_description::ModelDescription;
use std::path::Path;

fn closed_loop() -> std::path::PathBuf {
    packaged("ClosedLoop.ssp")
}

/// `--stop-time 0.01 --step 1e-300` planned 1e298 steps and wrote 361 MB of CSV in 12 s.
#[test]
fn an_unbounded_grid_is_refused_before_any_fmu_runs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.csv");
    let (ok, _, err) =
        run(cosim().arg("run").arg(closed_loop()).args(["--stop-time", "0.01", "--step", "1e-300", "-o"]).arg(&out));
    assert!(!ok);
    assert!(err.contains("more than the limit of 100000000") && err.contains("--max-steps"), "{err}");
    assert!(!out.exists(), "nothing written");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(closed_loop())
        .args(["--stop-time", "0.001", "--max-steps", "99", "--quiet", "-o"])
        .arg(&out));
    assert!(!ok && err.contains("more than the limit of 99"), "{err}");
}

/// `cosim run v.fmu -o v.fmu` replaced the FMU with a CSV (exit 0); `-o <directory>` left a
/// stray `<directory>.incomplete`.
#[test]
fn the_results_never_overwrite_an_input_a_directory_or_an_archive() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = dir.path().join("v.fmu");
    std::fs::copy(packaged("MillingPlant.fmu"), &fmu).unwrap();
    let before = std::fs::read(&fmu).unwrap();
    let (ok, _, err) = run(cosim().arg("run").arg(&fmu).args(["--stop-time", "0.001", "-o"]).arg(&fmu));
    assert!(!ok && err.contains("is an input of this run"), "{err}");
    assert_eq!(std::fs::read(&fmu).unwrap(), before, "the FMU is untouched");
    let ssp = dir.path().join("c.ssp");
    std::fs::copy(closed_loop(), &ssp).unwrap();
    let (ok, _, err) = run(cosim().arg("run").arg(&ssp).args(["--stop-time", "0.001", "-o"]).arg(&ssp));
    assert!(!ok && err.contains("is an input of this run"), "{err}");
    // another FMU than the input: an archive is never a results CSV
    let (ok, _, err) = run(cosim().arg("run").arg(&ssp).args(["--stop-time", "0.001", "-o"]).arg(&fmu));
    assert!(!ok && err.contains("is a zip archive"), "{err}");
    assert_eq!(std::fs::read(&fmu).unwrap(), before);
    let sub = dir.path().join("out");
    std::fs::create_dir(&sub).unwrap();
    let (ok, _, err) = run(cosim().arg("run").arg(&ssp).args(["--stop-time", "0.001", "-o"]).arg(&sub));
    assert!(!ok && err.contains("is a directory"), "{err}");
    assert!(!dir.path().join("out.incomplete").exists(), "no stray marker");
    // `cosim plot r.csv -o r.csv` would replace the CSV with its plot
    let csv = dir.path().join("r.csv");
    let (ok, _, err) = run(cosim().arg("run").arg(&ssp).args(["--stop-time", "0.001", "--quiet", "-o"]).arg(&csv));
    assert!(ok, "{err}");
    let (ok, _, err) = run(cosim().arg("plot").arg(&csv).arg("-o").arg(&csv));
    assert!(!ok && err.contains("is an input of this command"), "{err}");
}

/// Two runs writing the same CSV both exited 0, and the file held NUL bytes. The second run is
/// refused while the first one writes (its marker is locked).
#[test]
fn a_second_run_writing_the_same_csv_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("results.csv");
    let mut first = cosim()
        .arg("run")
        .arg(closed_loop())
        .args(["--stop-time", "2", "--quiet", "-o"])
        .arg(&csv)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // wait until the first run has its header out (it holds the lock from before that)
    let t0 = std::time::Instant::now();
    while std::fs::read_to_string(&csv).map_or(true, |s| !s.contains('\n')) {
        assert!(t0.elapsed().as_secs() < 60, "the first run did not start");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let (ok, _, err) = run(cosim().arg("run").arg(closed_loop()).args(["--stop-time", "0.001", "-o"]).arg(&csv));
    let status = first.wait().unwrap();
    assert!(status.success(), "the first run failed");
    assert!(!ok && err.contains("another run is writing this CSV now"), "{err}");
    let text = std::fs::read(&csv).unwrap();
    assert!(!text.contains(&0u8), "no NUL bytes");
    assert_eq!(fmi_master::csv::read_csv(&csv).unwrap().columns[0].len(), 200_001, "the first run's rows, whole");
    assert!(!fmi_master::csv::incomplete_marker(&csv).exists(), "the first run completed");
}

/// A duplicate `--set` was accepted (last wins) although the same duplicate in an SSD binding is
/// refused; `--record plant.x,plant.x` wrote two columns of one name.
#[test]
fn duplicate_sets_and_records_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.csv");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(closed_loop())
        .args(["--stop-time", "0.001", "--set", "controller.u_max=10", "--set", "controller.u_max=20", "-o"])
        .arg(&out));
    assert!(!ok && err.contains("controller.u_max is already set by --set controller.u_max=10"), "{err}");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(closed_loop())
        .args(["--stop-time", "0.001", "--record", "plant.x,controller.u,plant.x", "-o"])
        .arg(&out));
    assert!(!ok && err.contains("--record: plant.x is named twice"), "{err}");
}

/// The FMU at `src` with the outputs `outputs` declared to depend directly on the input `input`.
fn with_feedthrough(src: &Path, dst: &Path, outputs: &[&str], input: &str) {
    rewrite_zip(src, dst, |name, data| {
        if name != "modelDescription.xml" {
            return Some(data);
        }
        let mut md = ModelDescription::from_xml(std::str::from_utf8(&data).unwrap()).unwrap();
        let index = |n: &str| md.variables().iter().position(|v| v.name == n).unwrap() + 1;
        let (outs, inp): (Vec<usize>, usize) = (outputs.iter().map(|o| index(o)).collect(), index(input));
        for u in &mut md.model_structure.outputs.as_mut().unwrap().unknowns {
            if outs.contains(&u.index) {
                u.dependencies = Some(inp.to_string());
            }
        }
        Some(md.to_xml().unwrap().into_bytes())
    });
}

/// A system whose connections close a loop through declared direct feedthrough ran with exit 0
/// and no warning: the master never read the declared dependencies. It is refused now, or
/// iterated with `--algebraic-loops iterate`.
#[test]
fn an_algebraic_loop_through_declared_feedthrough_is_refused_or_iterated() {
    let dir = tempfile::tempdir().unwrap();
    with_feedthrough(&packaged("ChatterController.fmu"), &dir.path().join("ChatterController.fmu"), &["u"], "y");
    with_feedthrough(&packaged("MillingPlant.fmu"), &dir.path().join("MillingPlant.fmu"), &["x"], "u");
    let ssd = dir.path().join("Loop.ssd");
    std::fs::write(&ssd, ssp::read_ssd_from_ssp(&closed_loop()).unwrap()).unwrap();
    let out = dir.path().join("r.csv");
    let base = |c: &mut std::process::Command| {
        c.arg("run")
            .arg(&ssd)
            .arg("--fmu-dir")
            .arg(dir.path())
            .args(["--stop-time", "0.001", "--quiet", "-o"])
            .arg(&out);
    };
    let mut c = cosim();
    base(&mut c);
    let (ok, _, err) = run(&mut c);
    assert!(!ok, "the loop ran");
    assert!(err.contains("algebraic loop") && err.contains("--algebraic-loops iterate"), "{err}");
    assert!(err.contains("controller.u → plant.u") && err.contains("plant.x → controller.y"), "{err}");
    assert!(!out.exists());
    let mut c = cosim();
    base(&mut c);
    let (ok, _, err) = run(c.args(["--algebraic-loops", "iterate"]));
    assert!(ok, "{err}");
    // one feedthrough only: no cycle, runs as before
    std::fs::copy(packaged("MillingPlant.fmu"), dir.path().join("MillingPlant.fmu")).unwrap();
    let mut c = cosim();
    base(&mut c);
    let (ok, _, err) = run(&mut c);
    assert!(ok, "{err}");
}
