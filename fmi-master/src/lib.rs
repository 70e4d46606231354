//! # fmi-master — an FMI 2.0 Co-Simulation master with SSP 1.0 system files
//!
//! * [`import`]: safe import of any FMI 2.0 CS `.fmu` (its `ffi` module is
//!   the only code with `unsafe`; the FMI logger's variadic callback is a
//!   small C shim).
//! * [`system`]: where a system comes from (`.ssp`, `.ssd`, SSD text, a
//!   single `.fmu`; the SSP layer is the [`ssp`] crate, archives go through
//!   `fmi-archive`) and where its FMUs are.
//! * [`engine`]: assembling a system (connections and parameters
//!   type-checked against each `modelDescription.xml`) and running it at a
//!   fixed communication step in Gauss–Seidel or Jacobi order;
//!   [`overrides`]: `--set` parsing and value conversion.
//! * [`observer`], [`progress`], [`csv`]: what a run reports to — observers,
//!   the progress display, streaming results (FMPy's CSV convention);
//!   [`spectrum`], [`plot`]: amplitude spectra and PNG plots.
//! * [`mainjob`]: the seed paper's nominal scenario (Table 5, Figures 6–7)
//!   over controllers and noise seeds, in parallel (to move to the studies crate).
//!
//! The `cosim` binary is the command-line front end.
#![deny(unsafe_code)]

pub mod csv;
pub mod engine;
pub mod error;
pub mod import;
pub mod mainjob;
pub mod observer;
pub mod overrides;
pub mod plot;
pub mod progress;
pub mod spectrum;
pub mod system;

/// Former name of [`overrides`], kept for callers not yet updated (`stability`).
#[doc(hidden)]
pub mod params {
    pub use crate::overrides::*;
}

pub use engine::{RunConfig, RunStats, Simulation};
pub use error::{FmuError, SetupError, SimError};
pub use observer::{NoObserver, Observer, Recorder};
pub use overrides::Override;
pub use progress::Progress;
pub use ssp;
pub use ssp::write_ssp_archive;
pub use system::SystemFile;

/// The repository's closed-loop system description (plant + controller),
/// `fmi-master/scenarios/ClosedLoop.ssd`: the embedded default scenario and
/// the `SystemStructure.ssd` of `target/fmu/ClosedLoop.ssp`.
pub const CLOSED_LOOP_SSD: &str = include_str!("../scenarios/ClosedLoop.ssd");

#[cfg(test)]
mod tests {
    use ssp::{ConnectorKind, SystemDescription};

    /// The embedded SSD is in the writer's canonical form; also writes
    /// `target/ssd-test/ClosedLoop.ssd` for `tests/python/test_ssd_schema.py`.
    #[test]
    fn the_embedded_closed_loop_is_canonical_and_complete() {
        let d = SystemDescription::from_xml(crate::CLOSED_LOOP_SSD, "ClosedLoop.ssd", None).unwrap();
        assert_eq!(
            d.to_xml().unwrap(),
            crate::CLOSED_LOOP_SSD,
            "scenarios/ClosedLoop.ssd is not in the writer's canonical form"
        );
        assert_eq!(d.components.len(), 2);
        assert!(d.components.iter().all(|c| c.source.starts_with("resources/") && c.source.ends_with(".fmu")));
        assert_eq!(d.connections.len(), 2, "the closed loop has one feedback and one command connection");
        // Every connection's end points are declared connectors of matching kinds.
        for c in &d.connections {
            let s = d.component(c.start_element.as_deref().unwrap()).unwrap();
            let e = d.component(c.end_element.as_deref().unwrap()).unwrap();
            let has = |k: &ssp::ComponentDesc, name: &str, kind| {
                k.connectors.iter().any(|x| x.name == name && x.kind == kind)
            };
            assert!(has(s, &c.start_connector, ConnectorKind::Output), "{}", c.label());
            assert!(has(e, &c.end_connector, ConnectorKind::Input), "{}", c.label());
        }
        assert!(d.master.step_size.is_some() && d.stop_time.is_some());
        let target = std::env::var_os("CARGO_TARGET_DIR")
            .map(std::path::PathBuf::from)
            .unwrap_or_else(|| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target"));
        let dir = target.join("ssd-test");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("ClosedLoop.ssd"), crate::CLOSED_LOOP_SSD).unwrap();
    }
}
