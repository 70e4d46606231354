//! # milling-force-plant: seed 004's plant and its discretisation under a fractional-order hold
//!
//! The plant of *"Adaptive model-following force control of milling with fractional-order
//! holds"* (seed 004), with no FMI in it:
//!
//! * [`plant`]: the milling force plant `K_p/((τ_s s + 1)(τ_c s + 1))` with a piecewise-constant
//!   depth of cut, integrated exactly for a piecewise-linear feed command;
//! * [`froh`]: the fractional-order hold of gain β, its exact discretisation by an augmented
//!   matrix exponential, the pulse transfer function, its zeros and the non-minimum-phase
//!   boundary in β;
//! * [`poly`]: polynomial products, roots and the Diophantine equation.
//!
//! The controller (RLS, model-following RST, the closed loop) is `froh-mrac`.
//!
//! Units: force in N, feed rate in mm/s, depth in mm, time in s (the paper's).

pub mod froh;
pub mod plant;
pub mod poly;

pub use froh::{DiscreteTf, RampPropagator, StateSpace};
pub use plant::{DepthProfile, ForcePlant, ForcePlantInputs, ForcePlantOutputs, ForcePlantParams};

/// What can go wrong in the plant, the hold discretisation and the controller built on them.
#[derive(Debug, thiserror::Error)]
pub enum ForceError {
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
