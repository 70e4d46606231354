//! A fitted structure beyond ModalStructure's four mode parameters, through the FMU's own code
//! path: six modes fitted from a noisy tap test go into a modal table (`structure_ssv`), the
//! packaged `ModalStructure.fmu` reads it, and a sine sweep through the FMU (its sinusoidal
//! disturbance force, one run per frequency in the Rust master, steady-state amplitude and phase
//! by least squares over whole periods) gives the fitted FRF within 1 %. Needs the packaged FMUs
//! (`cargo run --release -p packaging`).

use fmi_master::{Override, Progress, Recorder, RunConfig, Simulation, SystemFile};
use machine::Machine;
use machine::frf_fit::synth::{TapTest, tap_test};
use machine::frf_fit::{FitOptions, fit};
use model_description::Value;
use num_complex::Complex64;
use std::f64::consts::PI;

/// The FMU's steady-state response `x/F` along `axis` to a unit sine force along `axis` at `f`.
fn sine_response(table: &std::path::Path, step: f64, f: f64, axis: usize) -> Complex64 {
    let fmu = machine::workflow::fmu_dir().join("ModalStructure.fmu");
    assert!(fmu.exists(), "{}: run `cargo run --release -p packaging` first", fmu.display());
    let sys = SystemFile::open(&fmu, None).unwrap();
    let c = "ModalStructure";
    let o = |n: &str, v: Value| Override::typed(format!("{c}.{n}"), v);
    let settle = 0.25;
    let periods = (0.05 * f).ceil();
    let stop = ((settle + periods / f) / step).ceil() * step;
    let out = ["tool_x", "tool_y"][axis];
    let cfg = RunConfig {
        start: Some(0.0),
        stop: Some(stop),
        step: Some(step),
        overrides: vec![
            o("modal_table", Value::String(table.display().to_string())),
            o("internal_step", Value::Real(step)),
            o("disturbance.noise", Value::Boolean(false)),
            o("disturbance.drift", Value::Boolean(false)),
            o("disturbance.sine_amplitude", Value::Real(1.0)),
            o("disturbance.sine_frequency", Value::Real(f)),
            o("disturbance.direction_angle", Value::Real(axis as f64 * PI / 2.0)),
        ],
        record: Some(vec![out.to_string()]),
        ..RunConfig::default()
    };
    let mut sim = Simulation::new(&sys, &cfg).unwrap();
    let mut rec = Recorder::default();
    sim.run(&mut rec, Progress::Off).unwrap();
    let x = rec.column(out).unwrap_or_else(|| panic!("{:?}", rec.names));
    // x = a sin(ωt) + b cos(ωt) over the last whole periods: H = a + i b
    let w = 2.0 * PI * f;
    let (mut ss, mut cc, mut sc, mut xs, mut xc) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (t, x) in rec.time.iter().zip(&x) {
        if *t >= settle {
            let (s, c) = (w * t).sin_cos();
            (ss, cc, sc, xs, xc) = (ss + s * s, cc + c * c, sc + s * c, xs + x * s, xc + x * c);
        }
    }
    let det = ss * cc - sc * sc;
    Complex64::new((xs * cc - xc * sc) / det, (xc * ss - xs * sc) / det)
}

#[test]
fn six_fitted_modes_through_the_fmu_give_the_fitted_frf() {
    let truth =
        Machine::from_file(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/six_modes.toml")).unwrap();
    let frf = tap_test(&truth, &TapTest::default()).unwrap();
    let f = fit(&frf, &FitOptions { band_hz: Some((200.0, 4000.0)), ..Default::default() }).unwrap();
    assert_eq!(f.modes.len(), 6, "{}", f.report(&frf));
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("modal_table.csv");
    let (ssv, text) = machine::fmus::structure_ssv(&f.modes, false, "fitted", &table).unwrap();
    std::fs::write(&table, text.expect("six modes go through a modal table")).unwrap();
    assert!(ssv.contains("modal_table") && ssv.contains(&table.display().to_string()), "{ssv}");
    let fitted = Machine { modes: f.modes.clone(), ..truth.clone() };
    let step = 1e-5 / 2.0; // 40 steps per period of 3200 Hz, as structure_ssv chooses
    for (fr, axis) in [(600.0, 0), (1100.0, 0), (2600.0, 0), (900.0, 0), (650.0, 1), (1500.0, 1), (3200.0, 1)] {
        let fmu = sine_response(&table, step, fr, axis);
        let model = fitted.receptance(2.0 * PI * fr)[(axis, axis)];
        let e = (fmu - model).norm() / model.norm();
        assert!(e < 0.01, "{fr} Hz axis {axis}: FMU {fmu} vs fitted {model} ({:.3} %)", e * 100.0);
    }
}
