//! The master refuses, before instantiating, a communication step that costs an FMU more
//! internal steps per `fmi2DoStep` than the FMU's declared work bound (the `WorkBound` vendor
//! annotation of the export layer), with a message naming the component, the FMU, the step, the
//! limit and the largest acceptable step; FMUs without the annotation run as before (the FMU
//! itself refuses the call). `cosim run MillingPlant.fmu --stop-time 1e6 --step 1e6` used to
//! hang inside the FMU.

mod common;

use common::{cosim, packaged, rewrite_zip, run};
use std::time::Instant;

#[test]
fn a_step_beyond_the_declared_bound_is_refused_before_instantiation() {
    let tmp = tempfile::tempdir().unwrap();
    let started = Instant::now();
    let (ok, out, err) = run(cosim()
        .env("TMPDIR", tmp.path())
        .arg("run")
        .arg(packaged("MillingPlant.fmu"))
        .args(["--stop-time", "1e6", "--step", "1e6", "--quiet", "-o"])
        .arg(tmp.path().join("out.csv")));
    assert!(!ok, "{out}");
    assert!(started.elapsed().as_secs_f64() < 10.0, "took {:?}", started.elapsed());
    for part in [
        "component MillingPlant (MillingPlant.fmu)",
        "a communication step of 1000000 s costs 1.000e11 internal steps",
        "(internal_step = 0.00001 s)",
        "more than the 1e7 per fmi2DoStep the FMU declares",
        "use a step of at most 9.999988e1 s",
    ] {
        assert!(err.contains(part), "missing {part:?} in: {err}");
    }
    assert!(!err.contains("fmi2DoStep returned"), "refused by the master, not by the FMU: {err}");
    let left: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().flatten().map(|e| e.file_name()).collect();
    assert!(left.iter().all(|n| n.to_string_lossy().starts_with("out.csv")), "left behind: {left:?}");
}

#[test]
fn the_bound_uses_the_internal_step_this_run_sets() {
    // 1 s at the default 10 µs grid is 1e5 internal steps; at the smallest grid, 1e8
    let tmp = tempfile::tempdir().unwrap();
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(packaged("ClosedLoop.ssp"))
        .args(["--stop-time", "1", "--step", "1", "--set", "plant.internal_step=1e-8", "--quiet", "-o"])
        .arg(tmp.path().join("out.csv")));
    assert!(!ok);
    assert!(
        err.contains("component plant (MillingPlant.fmu)") && err.contains("(internal_step = 0.00000001 s)"),
        "{err}"
    );
    // the controller's bound: Ts = 1e-9 makes a 0.1 s step 1e8 samples
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(packaged("ClosedLoop.ssp"))
        .args(["--stop-time", "0.1", "--step", "0.1", "--set", "controller.Ts=1e-9", "--quiet", "-o"])
        .arg(tmp.path().join("out2.csv")));
    assert!(!ok);
    assert!(err.contains("component controller (ChatterController.fmu)") && err.contains("Ts = 0.000000001"), "{err}");
}

#[test]
fn an_fmu_without_the_annotation_runs_as_before_and_refuses_the_step_itself() {
    let tmp = tempfile::tempdir().unwrap();
    let plain = tmp.path().join("MillingPlant.fmu");
    rewrite_zip(&packaged("MillingPlant.fmu"), &plain, |name, data| {
        if name != "modelDescription.xml" {
            return Some(data);
        }
        let xml = String::from_utf8(data).unwrap();
        let (a, b) = (xml.find("<VendorAnnotations>").unwrap(), xml.find("</VendorAnnotations>").unwrap());
        Some(format!("{}{}", &xml[..a], &xml[b + "</VendorAnnotations>".len()..]).into_bytes())
    });
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&plain)
        .args(["--stop-time", "1e6", "--step", "1e6", "--quiet", "-o"])
        .arg(tmp.path().join("out.csv")));
    assert!(!ok);
    assert!(!err.contains("the FMU declares"), "no annotation, no check by the master: {err}");
    assert!(err.contains("fmi2DoStep returned fmi2Error") && err.contains("internal steps"), "{err}");
    // and an ordinary run of the same FMU is fine
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&plain)
        .args(["--stop-time", "0.01", "--step", "1e-3", "--quiet", "-o"])
        .arg(tmp.path().join("ok.csv")));
    assert!(ok, "{err}");
}

#[test]
fn info_states_the_work_bound() {
    let (ok, out, err) = run(cosim().arg("info").arg(packaged("MillingPlant.fmu")));
    assert!(ok, "{err}");
    assert!(
        out.contains("work bound: at most 1e7 internal steps per fmi2DoStep, a step h costs h / internal_step + 2"),
        "{out}"
    );
}
