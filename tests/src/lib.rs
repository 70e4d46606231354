//! End-to-end test helpers: where the packaged FMUs are, and short
//! closed-loop runs of the shipped system through the `fmi-master` library.
//!
//! The FMUs are built by `cargo run --release -p packaging` (which
//! `tests/run_all.sh` runs before `cargo test`) into `target/fmu/`
//! (`$CARGO_TARGET_DIR/fmu` if that is set). Every helper fails with a
//! message saying so when they are missing.

use fmi_master::Override;
use fmi_master::ssp::Order;
use fmi_master::{Progress, Recorder, RunConfig, Simulation, SystemFile};
use std::path::{Path, PathBuf};

/// The workspace root.
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("tests/ sits in the workspace").to_path_buf()
}

/// The project's packaged FMUs (the fixtures of these tests): where they are, and one of them.
pub use packaging::{fmu_dir, packaged};

/// The shipped closed-loop system `target/fmu/ClosedLoop.ssp`.
pub fn closed_loop_ssp() -> SystemFile {
    SystemFile::open(&packaged("ClosedLoop.ssp"), None).expect("opening ClosedLoop.ssp")
}

/// The embedded scenario (`fmi-master/scenarios/ClosedLoop.ssd`) with the FMUs of `target/fmu`.
pub fn closed_loop_embedded() -> SystemFile {
    packaged("MillingPlant.fmu");
    packaged("ChatterController.fmu");
    SystemFile::from_text(packaging::CLOSED_LOOP_SSD, "packaging/scenarios/ClosedLoop.ssd", &fmu_dir())
        .expect("opening the embedded ClosedLoop.ssd")
}

/// `component.variable=value` overrides.
pub fn sets(list: &[&str]) -> Vec<Override> {
    list.iter().map(|s| s.parse().expect("valid --set syntax")).collect()
}

/// Options of a short closed-loop run.
#[derive(Clone, Debug)]
pub struct Short<'a> {
    /// Stop time [s].
    pub stop: f64,
    /// `--set` overrides.
    pub set: &'a [&'a str],
    /// Recorded variables.
    pub record: &'a [&'a str],
    /// Stepping order (None: the system's, Gauss–Seidel controller → plant).
    pub order: Option<Order>,
}

/// Run `sys` for a short time and keep every step.
pub fn run_short(sys: &SystemFile, o: &Short<'_>) -> Result<Recorder, fmi_master::SimError> {
    let cfg = RunConfig {
        stop: Some(o.stop),
        overrides: sets(o.set),
        record: Some(o.record.iter().map(|s| s.to_string()).collect()),
        order: o.order,
        ..RunConfig::default()
    };
    let mut sim = Simulation::new(sys, &cfg)?;
    let mut rec = Recorder::default();
    sim.run(&mut rec, Progress::Off)?;
    Ok(rec)
}

/// Root mean square of a signal.
pub fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}
