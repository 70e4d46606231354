//! # force-control: seed 004, adaptive model-following force control with a FROH
//!
//! The core of *"Adaptive model-following force control of milling with fractional-order
//! holds"* (seed 004), with no FMI in it:
//!
//! * [`plant`]: the milling force plant `K_p/((τ_s s + 1)(τ_c s + 1))` with a piecewise-constant
//!   depth of cut, integrated exactly for a piecewise-linear feed command;
//! * [`froh`]: the fractional-order hold of gain β, its exact discretisation by an augmented
//!   matrix exponential, the pulse transfer function, its zeros and the non-minimum-phase
//!   boundary in β;
//! * [`rls`]: recursive least squares with forgetting;
//! * [`mrac`]: the indirect model-following RST controller with the FROH reference model, the
//!   FROH ramp generated between samples, and the sample clock;
//! * [`closed_loop`]: plant and controller coupled at communication steps `T/M`, the loop the
//!   studies run and the FMUs reproduce;
//! * [`poly`]: polynomial products, roots and the Diophantine equation.
//!
//! Units: force in N, feed rate in mm/s, depth in mm, time in s (the paper's).

pub mod closed_loop;
pub mod froh;
pub mod mrac;
pub mod plant;
pub mod poly;
pub mod rls;

pub use closed_loop::{LoopSample, simulate};
pub use froh::{DiscreteTf, RampPropagator, StateSpace};
pub use mrac::{FrohMrac, MracOutputs, MracParams, Rst};
pub use plant::{DepthProfile, ForcePlant, ForcePlantInputs, ForcePlantOutputs, ForcePlantParams};
pub use rls::Rls;

/// What can go wrong in this crate.
#[derive(Debug, thiserror::Error)]
pub enum ForceControlError {
    /// A parameter out of range.
    #[error("invalid parameter: {0}")]
    Params(String),
    /// An input out of range (NaN, infinite, non-positive step).
    #[error("invalid input: {0}")]
    Input(String),
    /// A malformed model.
    #[error("invalid model: {0}")]
    Model(String),
    /// The controller design has no solution.
    #[error("design failed: {0}")]
    Design(String),
}
