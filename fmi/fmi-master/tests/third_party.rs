//! The master runs an FMU this project did not write: a co-simulation FMU
//! built on the test machine by the PyPI package **pythonfmu** (0.6, its
//! prebuilt C++ FMI 2.0 binary `binaries/linux64/<id>.so` plus a Python
//! class, `tests/fixtures/pythonfmu/Lag.py`), offline.
//!
//! pythonfmu binaries use libpython symbols without linking libpython (they
//! expect to be loaded by a Python host such as FMPy), so the master is told
//! to preload the venv's libpython (`--preload`, `import::preload_global`).

mod common;

use fmi_master::import::{Fmu, preload_global};
use std::sync::Mutex;

/// pythonfmu FMUs share one embedded interpreter per process: run them one at a time.
static PYTHON: Mutex<()> = Mutex::new(());

fn lag_fmu(dir: &std::path::Path) -> std::path::PathBuf {
    common::build_pythonfmu("Lag", dir)
}

#[test]
fn pythonfmu_lag_runs_in_the_importer_and_matches_the_recurrence() {
    let _g = PYTHON.lock().unwrap_or_else(|p| p.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let path = lag_fmu(dir.path());
    preload_global(&common::libpython()).unwrap();
    let fmu = Fmu::open(&path).unwrap();
    let md = fmu.model_description();
    assert_eq!(md.model_identifier(), Some("Lag"));
    assert_eq!(md.generation_tool.as_deref().map(|s| s.starts_with("PythonFMU")), Some(true), "not a pythonfmu FMU?");
    let vr = |n: &str| md.variable(n).unwrap().value_reference;
    let (tau, k, u, y, steps, label) = (vr("tau"), vr("k"), vr("u"), vr("y"), vr("steps"), vr("label"));
    let mut inst = fmu.instantiate("lag", false, false).unwrap();
    inst.setup_experiment(0.0, Some(1.0)).unwrap();
    inst.set_real(&[tau, k], &[0.25, 2.0]).unwrap();
    inst.set_string(&[label], &["from-rust"]).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    inst.set_real(&[u], &[1.0]).unwrap();
    let h = 0.01;
    let mut expect = 0.0f64;
    for n in 0..100 {
        let t = n as f64 * h;
        inst.do_step(t, h).unwrap();
        expect += (2.0 * 1.0 - expect) * h / 0.25;
        let mut out = [0.0];
        inst.get_real(&[y], &mut out).unwrap();
        assert_eq!(out[0].to_bits(), expect.to_bits(), "step {n}: {} vs {expect}", out[0]);
    }
    let mut n = [0];
    inst.get_integer(&[steps], &mut n).unwrap();
    assert_eq!(n[0], 100);
    assert_eq!(inst.get_string(&[label]).unwrap(), vec!["from-rust".to_string()]);
    // Analytic check of the model itself: y(1) ≈ 2(1 - e^{-4}) (Euler error ~ h).
    let mut out = [0.0];
    inst.get_real(&[y], &mut out).unwrap();
    assert!((out[0] - 2.0 * (1.0 - (-4.0f64).exp())).abs() < 0.02, "{}", out[0]);
    assert!((inst.time() - 1.0).abs() < 1e-12);
}

#[test]
fn pythonfmu_runtime_error_names_the_call_time_and_log() {
    let _g = PYTHON.lock().unwrap_or_else(|p| p.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let path = lag_fmu(dir.path());
    preload_global(&common::libpython()).unwrap();
    let fmu = Fmu::open(&path).unwrap();
    let md = fmu.model_description();
    let fail_at = md.variable("fail_at").unwrap().value_reference;
    let mut inst = fmu.instantiate("failing-lag", true, false).unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    inst.set_real(&[fail_at], &[0.5]).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    let h = 0.1;
    let mut err = None;
    for n in 0..10 {
        if let Err(e) = inst.do_step(n as f64 * h, h) {
            err = Some((n, e));
            break;
        }
    }
    let (n, e) = err.expect("the FMU should fail at t = 0.5");
    assert_eq!(n, 5);
    let msg = e.to_string();
    assert!(msg.contains("failing-lag") && msg.contains("fmi2DoStep") && msg.contains("t = 0.5"), "{msg}");
    // pythonfmu turns a Python exception into fmi2Fatal.
    assert!(msg.contains("fmi2Fatal"), "{msg}");
    assert!(msg.contains("deliberate failure at t=0.500"), "the FMU's own log must be quoted: {msg}");
    // Dropping the failed instance must not crash (free without terminate).
    drop(inst);
}
