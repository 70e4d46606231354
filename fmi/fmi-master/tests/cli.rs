//! The `cosim` command line on a third-party FMU: the pythonfmu-built
//! `Lag.fmu` (see `tests/fixtures/pythonfmu/Lag.py`; pythonfmu 0.6 from
//! PyPI, built offline on the test machine), alone and as a two-component
//! SSP system; and every malformed input giving a clear error and a
//! non-zero exit. Each case runs the binary in its own process.

mod common;

use common::{build_pythonfmu, cosim, libpython, rewrite_zip, run};
use std::io::Write;
use std::path::{Path, PathBuf};

fn lag(dir: &Path) -> PathBuf {
    build_pythonfmu("Lag", dir)
}

/// Two Lag components, a.y → b.u, as an SSD (`conn` replaces the connection's connector names).
fn two_lags_ssd(start: &str, end: &str) -> String {
    format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
  xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon"
  xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="TwoLags">
  <ssd:System name="TwoLags">
    <ssd:Elements>
      <ssd:Component name="a" source="resources/Lag.fmu">
        <ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>
          <ssv:ParameterSet version="1.0" name="a"><ssv:Parameters>
            <ssv:Parameter name="tau"><ssv:Real value="0.2"/></ssv:Parameter>
            <ssv:Parameter name="u"><ssv:Real value="1"/></ssv:Parameter>
          </ssv:Parameters></ssv:ParameterSet>
        </ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>
      </ssd:Component>
      <ssd:Component name="b" source="resources/Lag.fmu"/>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="a" startConnector="{start}" endElement="b" endConnector="{end}"/>
    </ssd:Connections>
    <ssd:ParameterBindings><ssd:ParameterBinding prefix="b."><ssd:ParameterValues>
      <ssv:ParameterSet version="1.0" name="sys"><ssv:Parameters>
        <ssv:Parameter name="tau"><ssv:Real value="0.1"/></ssv:Parameter>
      </ssv:Parameters></ssv:ParameterSet>
    </ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="1"/>
</ssd:SystemStructureDescription>
"#
    )
}

fn two_lags_ssp(dir: &Path, start: &str, end: &str) -> PathBuf {
    let fmu = lag(dir);
    let ssp = dir.join("TwoLags.ssp");
    fmi_master::write_ssp_archive(&ssp, &two_lags_ssd(start, end), &[("Lag.fmu", &fmu)]).unwrap();
    ssp
}

fn lag_step(y: f64, k: f64, u: f64, h: f64, tau: f64) -> f64 {
    // Exactly the Python expression `y += (k*u - y) * h / tau`.
    y + (k * u - y) * h / tau
}

#[test]
fn two_pythonfmu_lags_from_an_ssp_follow_gauss_seidel_and_jacobi_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let ssp = two_lags_ssp(dir.path(), "y", "u");
    let h = 0.01;
    for (order, seq) in [("gauss-seidel", "a,b"), ("gauss-seidel", "b,a"), ("jacobi", "a,b")] {
        let csv = dir.path().join(format!("{order}-{}.csv", seq.replace(',', "")));
        let (ok, _out, err) = run(cosim()
            .arg("run")
            .arg(&ssp)
            .arg("--preload")
            .arg(libpython())
            .args(["--step", "0.01", "--order", order, "--sequence", seq, "--record", "a.y,b.y,b.u", "-o"])
            .arg(&csv));
        assert!(ok, "{order} {seq}: {err}");
        let t = fmi_master::csv::read_csv(&csv).unwrap();
        assert_eq!(t.names, vec!["time", "a.y", "b.y", "b.u"]);
        // Reference recurrences. a: tau 0.2, u 1 (SSP bindings); b: tau 0.1 (system binding with prefix "b.").
        let (mut ya, mut yb) = (0.0f64, 0.0f64);
        for n in 0..100 {
            let ya_old = ya;
            ya = lag_step(ya, 1.0, 1.0, h, 0.2);
            let ub = match (order, seq) {
                ("gauss-seidel", "a,b") => ya, // b sees a at t_{n+1}
                _ => ya_old,                   // b first, or Jacobi: a at t_n
            };
            yb = lag_step(yb, 1.0, ub, h, 0.1);
            assert_eq!(t.columns[0][n + 1].to_bits(), ((n + 1) as f64 * h).to_bits(), "time is t0 + n·h");
            assert_eq!(t.columns[1][n + 1].to_bits(), ya.to_bits(), "{order} {seq} a.y at step {n}");
            assert_eq!(t.columns[2][n + 1].to_bits(), yb.to_bits(), "{order} {seq} b.y at step {n}");
        }
    }
}

#[test]
fn zip_with_a_parent_dir_entry_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let evil = dir.path().join("Evil.fmu");
    let mut z = zip::ZipWriter::new(std::fs::File::create(&evil).unwrap());
    z.start_file("modelDescription.xml", zip::write::SimpleFileOptions::default()).unwrap();
    z.write_all(b"<fmiModelDescription/>").unwrap();
    z.start_file("../escaped.txt", zip::write::SimpleFileOptions::default()).unwrap();
    z.write_all(b"pwned").unwrap();
    z.finish().unwrap();
    let (ok, _, err) = run(cosim().arg("run").arg(&evil).args(["--stop-time", "1", "--step", "0.1"]));
    assert!(!ok);
    assert!(err.contains("unsafe entry '../escaped.txt'") && err.contains("'..' component"), "{err}");
    assert!(!dir.path().parent().unwrap().join("escaped.txt").exists());
}

#[test]
fn fmu_without_a_linux64_binary_names_the_platforms_it_has() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = lag(dir.path());
    let stripped = dir.path().join("Lag.fmu.stripped");
    rewrite_zip(&fmu, &stripped, |name, data| (!name.starts_with("binaries/linux64/")).then_some(data));
    let renamed = dir.path().join("NoLinux.fmu");
    std::fs::rename(&stripped, &renamed).unwrap();
    let (ok, _, err) = run(cosim().arg("run").arg(&renamed).args(["--stop-time", "1", "--step", "0.1"]));
    assert!(!ok);
    assert!(err.contains("FMU NoLinux.fmu has no binary for linux64; it has: win64"), "{err}");
}

#[test]
fn connection_to_a_missing_variable_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let ssp = two_lags_ssp(dir.path(), "yy", "u");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&ssp)
        .arg("--preload")
        .arg(libpython())
        .args(["--step", "0.1", "-o"])
        .arg(dir.path().join("x.csv")));
    assert!(!ok);
    assert!(
        err.contains("connection a.yy → b.u: component 'a' (Lag.fmu) has no variable 'yy' (did you mean y"),
        "{err}"
    );
}

#[test]
fn connection_between_different_types_is_a_type_mismatch() {
    let dir = tempfile::tempdir().unwrap();
    let ssp = two_lags_ssp(dir.path(), "steps", "u");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&ssp)
        .arg("--preload")
        .arg(libpython())
        .args(["--step", "0.1", "-o"])
        .arg(dir.path().join("x.csv")));
    assert!(!ok);
    assert!(err.contains("type mismatch: connection a.steps → b.u: a.steps is Integer but b.u is Real"), "{err}");
}

#[test]
fn non_numeric_set_value_and_unknown_names_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let ssp = two_lags_ssp(dir.path(), "y", "u");
    let csv = dir.path().join("x.csv");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&ssp)
        .arg("--preload")
        .arg(libpython())
        .args(["--step", "0.1", "--set", "a.tau=fast", "-o"])
        .arg(&csv));
    assert!(!ok);
    assert!(err.contains("--set a.tau=fast: 'tau' is a Real variable; 'fast' is not a number"), "{err}");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&ssp)
        .arg("--preload")
        .arg(libpython())
        .args(["--step", "0.1", "--set", "c.tau=1", "-o"])
        .arg(&csv));
    assert!(!ok);
    assert!(err.contains("unknown component 'c'") && err.contains("the system has: a, b"), "{err}");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&ssp)
        .arg("--preload")
        .arg(libpython())
        .args(["--step", "0.1", "--set", "a.y=1", "-o"])
        .arg(&csv));
    assert!(!ok);
    assert!(err.contains("'y' cannot be set"), "{err}");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&ssp)
        .arg("--preload")
        .arg(libpython())
        .args(["--step", "0.1", "--set", "a.tau", "-o"])
        .arg(&csv));
    assert!(!ok);
    assert!(err.contains("expected component.variable=value"), "{err}");
    let (ok, _, err) =
        run(cosim().arg("run").arg(&ssp).arg("--preload").arg(libpython()).args(["--step", "0.3", "-o"]).arg(&csv));
    assert!(!ok);
    assert!(err.contains("not a whole number of steps"), "{err}");
}

#[test]
fn runtime_failure_names_fmu_call_time_and_log_and_keeps_the_csv() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = lag(dir.path());
    let csv = dir.path().join("fail.csv");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&fmu)
        .arg("--preload")
        .arg(libpython())
        .args([
            "--stop-time",
            "1",
            "--step",
            "0.01",
            "--set",
            "fail_at=0.5",
            "--set",
            "label=probe",
            "--record",
            "y",
            "-o",
        ])
        .arg(&csv));
    assert!(!ok);
    assert!(err.contains("FMU instance 'Lag' (Lag): fmi2DoStep returned fmi2Fatal at t = 0.5 s"), "{err}");
    assert!(err.contains("lag 'probe': deliberate failure at t=0.500"), "the FMU's log must be quoted: {err}");
    let t = fmi_master::csv::read_csv(&csv).unwrap();
    assert_eq!(t.columns[0].len(), 51, "rows for t = 0 … 0.5 were flushed");
    approx::assert_abs_diff_eq!(*t.columns[0].last().unwrap(), 0.5, epsilon = 1e-12);
}

#[test]
fn pythonfmu_without_its_runtime_fails_to_load_with_a_hint() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = lag(dir.path());
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&fmu)
        .args(["--stop-time", "1", "--step", "0.1", "-o"])
        .arg(dir.path().join("x.csv")));
    assert!(!ok);
    assert!(err.contains("cannot load") && err.contains("undefined symbol") && err.contains("--preload"), "{err}");
}

#[test]
fn info_describes_an_fmu_and_a_system() {
    let dir = tempfile::tempdir().unwrap();
    let ssp = two_lags_ssp(dir.path(), "y", "u");
    let (ok, out, err) = run(cosim().arg("info").arg(dir.path().join("Lag.fmu")));
    assert!(ok, "{err}");
    assert!(out.contains("generated by PythonFMU") && out.contains("tau"), "{out}");
    let (ok, out, err) = run(cosim().arg("info").arg(&ssp));
    assert!(ok, "{err}");
    assert!(out.contains("connection a.y → b.u") && out.contains("system parameter b.tau = 0.1"), "{out}");
}
