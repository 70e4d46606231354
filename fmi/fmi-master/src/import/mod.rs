//! The importer: opens an FMI 2.0 Co-Simulation `.fmu` and wraps its C API
//! in the safe types [`Fmu`] and [`Instance`].
//!
//! * [`fmu`] (safe): extraction, `modelDescription.xml`, platform lookup,
//!   instantiation ([`Fmu`], [`read_model_description`], [`file_uri`]).
//! * [`instance`] (safe): the FMI state machine and status checks ([`Instance`]).
//! * [`log`] (safe): the per-instance log ring buffer quoted by errors.
//! * `ffi`: **the `unsafe` code of the calls into FMUs** — loading
//!   the library, resolving the FMI functions, the raw calls and the logger
//!   callback (with the C shim `csrc/logger_shim.c`, since FMI's logger is
//!   variadic).
//! * [`process`]: the only other module with `unsafe` code — what happens
//!   when the process ends without destructors (an FMU's `exit()`, a
//!   signal): scratch directories removed, a run in progress reported as
//!   failed ([`process::ScratchDir`], [`process::install_exit_guard`],
//!   [`process::install_signal_cleanup`]).
//!
//! Each instance keeps its own log; the library stays loaded, and the
//! extracted directory on disk, until the last instance of the FMU is gone.

#[allow(unsafe_code)]
mod ffi;
pub mod fmu;
pub mod instance;
pub(crate) mod log;
#[allow(unsafe_code)]
pub mod process;

pub use ffi::preload_global;
pub use fmu::{Fmu, LIBRARY_EXTENSION, MAX_MODEL_DESCRIPTION_BYTES, PLATFORM, file_uri, read_model_description};
pub use instance::Instance;
