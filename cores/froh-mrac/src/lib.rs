//! # froh-mrac: seed 004, adaptive model-following force control with a FROH
//!
//! The controller of *"Adaptive model-following force control of milling with fractional-order
//! holds"* (seed 004), with no FMI in it; the plant and the hold discretisation are
//! [`milling_force_plant`]:
//!
//! * [`rls`]: recursive least squares with forgetting;
//! * [`mrac`]: the indirect model-following RST controller with the FROH reference model, the
//!   FROH ramp generated between samples, and the sample clock;
//! * [`closed_loop`]: plant and controller coupled at communication steps `T/M`, the loop the
//!   studies run and the FMUs reproduce.
//!
//! Units: force in N, feed rate in mm/s, depth in mm, time in s (the paper's).

pub mod closed_loop;
pub mod mrac;
pub mod rls;

pub use closed_loop::{LoopSample, simulate};
pub use milling_force_plant::ForceError;
pub use mrac::{FrohMrac, MracOutputs, MracParams, Rst};
pub use rls::Rls;
