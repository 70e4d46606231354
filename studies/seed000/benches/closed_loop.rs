//! Closed-loop throughput: MillingPlant + ChatterController through the FMI
//! C API at a 10 µs communication step, in the Rust master and in FMPy.
//!
//! ```text
//! cargo run --release -p packaging            # target/fmu/*.fmu, ClosedLoop.ssp
//! cargo bench -p seed000 --bench closed_loop
//! ```
//!
//! For each controller structure: the Rust master's steps per second
//! (`Simulation::run` on the shipped `ClosedLoop.ssp`, Gauss–Seidel
//! controller → plant, nothing recorded, best of 3 runs of 1 s = 100 000
//! steps), then the same loop in Python on FMPy's `FMU2Slave`
//! (`tests/python/fmpy_closed_loop.py --bench`, same FMUs, same call
//! sequence, best of 3 runs of 20 000 steps) and the ratio. Single-threaded
//! both. Then the Rust master's cost per step with the plant's exact integrator
//! (default) and with its RK4 reference (`plant.integrator=reference`), and the ratio. Needs the venv `.venv` with FMPy (or `FMI_MASTER_VENV`); environment
//! variables `BENCH_RUST_STEPS`, `BENCH_FMPY_STEPS` change the lengths.

use fmi_master::{NoObserver, Progress, RunConfig, Simulation, SystemFile};
use std::path::{Path, PathBuf};
use std::process::Command;

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn rust_steps_per_s(ssp: &Path, structure: &str, steps: u64) -> f64 {
    rust_steps_per_s_with(ssp, structure, "exact", steps)
}

/// The Rust master's steps per second with the plant's `integrator` (`exact`, `reference`).
fn rust_steps_per_s_with(ssp: &Path, structure: &str, integrator: &str, steps: u64) -> f64 {
    let sys = SystemFile::open(ssp, None).expect("opening ClosedLoop.ssp");
    let mut best = 0.0f64;
    for _ in 0..3 {
        let cfg = RunConfig {
            stop: Some(steps as f64 * 1e-5),
            step: Some(1e-5),
            overrides: vec![
                format!("controller.structure={structure}").parse().unwrap(),
                format!("plant.integrator={integrator}").parse().unwrap(),
            ],
            record: Some(Vec::new()),
            ..RunConfig::default()
        };
        let mut sim = Simulation::new(&sys, &cfg).expect("loading the closed loop");
        let stats = sim.run(&mut NoObserver, Progress::Off).expect("closed-loop run");
        best = best.max(stats.steps as f64 / stats.wall.as_secs_f64());
    }
    best
}

fn fmpy_steps_per_s(root: &Path, ssp: &Path, structure: &str, steps: u64) -> Result<f64, String> {
    let venv = std::env::var_os("FMI_MASTER_VENV").map(PathBuf::from).unwrap_or_else(|| root.join(".venv"));
    let python = venv.join("bin/python");
    if !python.exists() {
        return Err(format!(
            "{} missing (python3 -m venv .venv && .venv/bin/pip install -r tests/python/requirements.txt)",
            python.display()
        ));
    }
    let out = Command::new(&python)
        .arg(root.join("tests/python/fmpy_closed_loop.py"))
        .arg(ssp)
        .args(["--bench", "--steps", &steps.to_string(), "--set", &format!("controller.structure={structure}")])
        .output()
        .map_err(|e| format!("running {}: {e}", python.display()))?;
    if !out.status.success() {
        return Err(format!("FMPy loop failed:\n{}", String::from_utf8_lossy(&out.stderr)));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    // {"steps": N, "steps_per_s": X, ...}
    let key = "\"steps_per_s\": ";
    let at = text.find(key).ok_or_else(|| format!("unexpected output: {text}"))? + key.len();
    let end = text[at..].find([',', '}']).map(|e| at + e).unwrap_or(text.len());
    text[at..end].trim().parse().map_err(|e| format!("parsing '{}': {e}", &text[at..end]))
}

fn main() {
    // `cargo bench` passes --bench; `cargo test --benches` passes nothing special: run quickly then.
    let quick = !std::env::args().any(|a| a == "--bench");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let ssp = packaging::fmu_dir().join("ClosedLoop.ssp");
    if !ssp.is_file() {
        eprintln!("{} is missing: run `cargo run --release -p packaging` first", ssp.display());
        std::process::exit(1);
    }
    let (rust_n, py_n) =
        if quick { (1000, 200) } else { (env_u64("BENCH_RUST_STEPS", 100_000), env_u64("BENCH_FMPY_STEPS", 20_000)) };
    println!("closed-loop throughput, 10 µs step, {} (single thread each)", ssp.display());
    println!("| controller | Rust master [steps/s] | FMPy loop [steps/s] | ratio Rust/FMPy |");
    println!("|---|---|---|---|");
    let mut failed = false;
    for s in ["off", "pid", "fopid", "adrc_fopid"] {
        let r = rust_steps_per_s(&ssp, s, rust_n);
        match fmpy_steps_per_s(&root, &ssp, s, py_n) {
            Ok(p) => println!("| {s} | {r:.0} | {p:.0} | {:.1} |", r / p),
            Err(e) => {
                println!("| {s} | {r:.0} | (failed) | — |");
                eprintln!("{e}");
                failed = true;
            }
        }
    }
    // the plant's exact integrator (default) against its RK4 reference, same run, same master
    println!();
    println!("closed loop through the C API, Rust master: plant integrator exact vs reference (best of 3 each)");
    println!("| controller | exact [µs/step] | reference [µs/step] | ratio reference/exact |");
    println!("|---|---|---|---|");
    for s in ["off", "pid", "fopid", "adrc_fopid"] {
        let fast = rust_steps_per_s_with(&ssp, s, "exact", rust_n);
        let slow = rust_steps_per_s_with(&ssp, s, "reference", rust_n);
        println!("| {s} | {:.3} | {:.3} | {:.2} |", 1e6 / fast, 1e6 / slow, fast / slow);
    }
    if failed {
        std::process::exit(1);
    }
}
