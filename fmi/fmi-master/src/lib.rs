//! # fmi-master — an FMI 2.0 Co-Simulation master with SSP 1.0 system files
//!
//! * [`import`]: safe import of any FMI 2.0 CS `.fmu` (its `ffi` and
//!   `process` modules are the only code with `unsafe`; the FMI logger's variadic callback is a
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
//!
//! The `cosim` binary is the command-line front end.
#![deny(unsafe_code)]

pub mod csv;
pub mod engine;
pub mod error;
pub mod import;
pub mod observer;
pub mod overrides;
pub mod plot;
pub mod progress;
pub mod spectrum;
pub mod system;

pub use engine::{RunConfig, RunStats, Simulation};
pub use error::{FmuError, SetupError, SimError};
pub use observer::{NoObserver, Observer, Recorder};
pub use overrides::{Override, OverrideValue};
pub use progress::Progress;
pub use ssp;
pub use ssp::write_ssp_archive;
pub use system::SystemFile;
