//! # machine: your own machine, described once
//!
//! A machine file ([`machine`], TOML, schema version 1) holds the cutter, the modes of the
//! tool-point receptance in x and y, the material, the cut and optionally an actuator and a
//! controller; quantities carry their units ([`units`]) and implausible magnitudes are refused
//! with the unit they probably meant ([`read`]). Every analysis reads the same [`Machine`]:
//!
//! | module | holds |
//! |---|---|
//! | [`machine`] | the schema, reading and checking, writing a machine file back |
//! | [`units`] | quantities with units: parsing, dimensions, SI |
//! | [`read`] | the TOML reader that names the field and the fix in every error |
//! | [`models`] | the machine as the stability core's models (modes, cutter, receptance, the closed loop) |
//! | [`lobes`] | open-loop lobes by zero-order, multi-frequency and the time-periodic model (converged by default), where they disagree and which to trust |
//! | [`closed`] | closed-loop lobes of a controller on the machine, with the saturation-limited depth |
//! | [`tune`] | the seed's PSO tuning on the machine: its closed loop, its saturation check, the SSV of the result |
//! | [`workflow`] | the workflow as functions the `chatter` command and the Python package both call: summary, controller choice, validation through the FMUs |
//! | [`fmus`] | the machine as FMUs: parameter sets, its SSP, the time-domain check through the FMUs |

pub mod closed;
pub mod fmus;
pub mod frf;
pub mod frf_fit;
pub mod lobes;
pub mod machine;
pub mod models;
mod parse;
pub mod read;
pub mod tune;
pub mod units;
pub mod workflow;

pub use machine::Machine;
pub use read::MachineError;
