//! Regression tests of "results lost on a crash" (hardening issue, item 5),
//! through `cosim run` on a small C FMU (`fixtures/c/crashy.c`, built with
//! gcc here) that segfaults, calls `exit(0)` or hangs at step 500 of 1000.
//! Before the fix the CSV was empty (not even the header), `exit(0)` made
//! `cosim` succeed, and the extraction directory stayed behind.

mod common;

use common::{cosim, run};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

const MD: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="Crashy" guid="{crashy-0001}" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="Crashy" canHandleVariableCommunicationStepSize="true"/>
  <DefaultExperiment startTime="0" stopTime="1" stepSize="0.001"/>
  <ModelVariables>
    <ScalarVariable name="x" valueReference="0" causality="output" variability="continuous"><Real/></ScalarVariable>
  </ModelVariables>
  <ModelStructure><Outputs><Unknown index="1"/></Outputs></ModelStructure>
</fmiModelDescription>
"#;

/// Build `Crashy.fmu` with behaviour `mode` (0 fine, 1 segfault, 2 exit(0), 3 hang) at step 500.
fn crashy(dir: &Path, mode: u32) -> PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/c/crashy.c");
    let so = dir.join("Crashy.so");
    let out = Command::new("gcc")
        .args(["-shared", "-fPIC", "-O1", &format!("-DMODE={mode}"), "-o"])
        .arg(&so)
        .arg(&src)
        .output()
        .expect("running gcc");
    assert!(out.status.success(), "gcc: {}", String::from_utf8_lossy(&out.stderr));
    let fmu = dir.join("Crashy.fmu");
    let mut zip = fmi_archive::ZipBuilder::new();
    zip.file("modelDescription.xml", MD, fmi_archive::Compression::Deflated)
        .directory("binaries")
        .directory("binaries/linux64")
        .file("binaries/linux64/Crashy.so", std::fs::read(&so).unwrap(), fmi_archive::Compression::Deflated);
    zip.write_to(&fmu).unwrap();
    fmu
}

struct Case {
    _dir: tempfile::TempDir,
    tmp: tempfile::TempDir,
    fmu: PathBuf,
    csv: PathBuf,
}

fn case(mode: u32) -> Case {
    let dir = tempfile::tempdir().unwrap();
    let fmu = crashy(dir.path(), mode);
    let csv = dir.path().join("out/r.csv");
    Case { tmp: tempfile::tempdir().unwrap(), fmu, csv, _dir: dir }
}

impl Case {
    fn command(&self) -> Command {
        let mut c = cosim();
        c.env("TMPDIR", self.tmp.path()).arg("run").arg(&self.fmu).args([
            "--stop-time",
            "1",
            "--step",
            "0.001",
            "-q",
            "-o",
        ]);
        c.arg(&self.csv);
        c
    }
    fn marker(&self) -> PathBuf {
        fmi_master::csv::incomplete_marker(&self.csv)
    }
    fn rows(&self) -> Vec<f64> {
        let text = std::fs::read_to_string(&self.csv).unwrap();
        assert!(text.starts_with("\"time\",\"x\"\n"), "the header is there: {:?}", &text[..text.len().min(40)]);
        let t = fmi_master::csv::read_csv(&self.csv).unwrap();
        t.column("x").unwrap().to_vec()
    }
    fn scratch_left(&self) -> Vec<String> {
        std::fs::read_dir(self.tmp.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect()
    }
}

#[test]
fn a_run_that_finishes_has_no_marker_and_leaves_no_scratch() {
    let c = case(0);
    let (ok, _, err) = run(&mut c.command());
    assert!(ok, "{err}");
    assert_eq!(c.rows().len(), 1001);
    assert!(!c.marker().exists());
    assert!(c.scratch_left().is_empty(), "{:?}", c.scratch_left());
}

#[test]
fn a_segfaulting_fmu_leaves_the_header_the_flushed_rows_and_the_marker() {
    let c = case(1);
    let out = c.command().output().unwrap();
    assert!(!out.status.success());
    let rows = c.rows();
    assert!(rows.len() as u64 >= fmi_master::csv::FLUSH_ROWS, "{} rows", rows.len());
    assert!(rows.len() <= 500);
    assert!(c.marker().is_file(), "the CSV is marked incomplete");
}

#[test]
fn an_fmu_calling_exit_0_makes_cosim_fail_and_cleans_up() {
    let c = case(2);
    let out = c.command().output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(fmi_master::import::process::EXIT_DURING_RUN), "{err}");
    assert!(err.contains("exit() called") && err.contains("results are incomplete"), "{err}");
    assert!(c.rows().len() as u64 >= fmi_master::csv::FLUSH_ROWS);
    assert!(c.marker().is_file());
    assert!(c.scratch_left().is_empty(), "extraction directory left: {:?}", c.scratch_left());
}

#[test]
fn sigterm_during_a_run_keeps_the_rows_and_cleans_up() {
    let c = case(3);
    let mut child = c.command().spawn().unwrap();
    let t0 = Instant::now();
    // Wait for the first flush by count (the FMU then hangs at step 500).
    while std::fs::read_to_string(&c.csv).map(|s| s.lines().count() as u64).unwrap_or(0) <= fmi_master::csv::FLUSH_ROWS
    {
        assert!(t0.elapsed() < Duration::from_secs(30), "the rows never arrived");
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    assert!(!c.scratch_left().is_empty(), "the FMU is extracted while it runs");
    let ok = Command::new("kill").arg("-TERM").arg(child.id().to_string()).status().unwrap().success();
    assert!(ok);
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(128 + 15));
    let rows = c.rows().len() as u64;
    assert!((fmi_master::csv::FLUSH_ROWS..=500).contains(&rows), "{rows} rows");
    assert!(c.marker().is_file());
    assert!(c.scratch_left().is_empty(), "extraction directory left: {:?}", c.scratch_left());
}
