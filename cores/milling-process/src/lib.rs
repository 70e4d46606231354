//! # milling-process
//!
//! The regenerative milling process alone, in two axes, free of FFI types: the physics of
//! `MillingProcess.fmu`. Inputs are the tool and the workpiece displacement at the cutting
//! point (the process uses their difference), the spindle speed and the feed per tooth;
//! outputs the cutting force on the tool (and its opposite on the workpiece), the largest chip,
//! the regenerative delay and the tool angle.
//!
//! ```
//! use milling_process::{Process, ProcessInputs, ProcessParams};
//! let mut p = Process::new(&ProcessParams::default()).unwrap();
//! for _ in 0..1000 {
//!     p.step(1e-5, &ProcessInputs::default()).unwrap();
//! }
//! // tooth-passing delay at 2000 rpm, 4 teeth: 7.5 ms
//! assert!((p.outputs().delay - 7.5e-3).abs() < 1e-9);
//! ```
//!
//! | module | holds |
//! |---|---|
//! | [`params`] | [`ProcessParams`], conventions, the three force laws |
//! | [`process`] | [`Process`]: chip, engagement, loss of contact, multiple regeneration |
//! | [`history`] | the angle-indexed surface history (shared with `milling-plant`) |
//! | [`directional`] | the averaged directional matrix (lobes) and seed 003's Eq. 6 |

pub mod directional;
pub mod history;
pub mod params;
pub mod process;

pub use params::{Coefficients, ForceLaw, MillingMode, ProcessParams};
pub use process::{Process, ProcessError, ProcessInputs, ProcessOutputs};
