//! # fmi-master — an FMI 2.0 Co-Simulation master with SSP 1.0 system files
//!
//! * [`import`]: safe import of any FMI 2.0 CS `.fmu` (the only module with
//!   `unsafe` code; the FMI logger's variadic callback is a small C shim).
//! * [`unzip`]: archive extraction that rejects absolute paths, `..` and links.
//! * [`ssp`]: SSP 1.0 `SystemStructure.ssd` reader and writer, `.ssp` archives.
//! * [`system`], [`engine`]: assembling a system (connections and parameters
//!   type-checked against each `modelDescription.xml`) and running it at a
//!   fixed communication step in Gauss–Seidel or Jacobi order.
//! * [`csv`]: streaming results (FMPy's CSV convention); [`spectrum`],
//!   [`plot`]: amplitude spectra and PNG plots; [`mainjob`]: the seed
//!   paper's nominal scenario (Table 5, Figures 6–7) over controllers and
//!   noise seeds, in parallel.
//!
//! The `cosim` binary is the command-line front end.
#![deny(unsafe_code)]

pub mod csv;
pub mod engine;
pub mod error;
pub mod import;
pub mod mainjob;
pub mod params;
pub mod plot;
pub mod spectrum;
pub mod ssp;
pub mod system;
pub mod unzip;

pub use engine::{NoObserver, Observer, Progress, Recorder, RunConfig, RunStats, Simulation};
pub use error::{FmuError, SetupError, SimError};
pub use ssp::write_ssp_archive;
pub use system::SystemFile;

/// The repository's closed-loop system description (plant + controller),
/// `fmi-master/scenarios/ClosedLoop.ssd`: the embedded default scenario and
/// the `SystemStructure.ssd` of `target/fmu/ClosedLoop.ssp`.
pub const CLOSED_LOOP_SSD: &str = include_str!("../scenarios/ClosedLoop.ssd");
