//! # sliding-fuzzy-control: seed 003, DSMC with interval type-2 fuzzy compensation
//!
//! The core of Paul & Morales-Menendez (2019), *"Chatter mitigation in milling process using
//! discrete time sliding mode control with type 2-fuzzy logic system"*, with no FMI in it; the
//! plant (the two-axis tool with the cubic law and the damper) is [`tool_xy`]:
//!
//! * [`linear`]: the exact zero-order-hold discretisation of one axis (augmented matrix
//!   exponential) with its slow reference;
//! * [`fuzzy`]: Gaussian membership-function grids, the type-1 fuzzy system, the interval type-2
//!   system with the seed's closed-form type reduction (Eq. 25) and Karnik–Mendel as an option;
//! * [`params`]: the parameters, with the readings of the nominal model (`A_dis`, unknown in
//!   Eq. 22) and of the computation delay;
//! * [`controller`]: the per-axis controllers `dpid` (Eq. 62), `dsmc` (Eqs. 35–38), `dsmc_t1`
//!   and `dsmc_t2` (Eqs. 26–31 with the dead-zone learning law), two channels (x and y);
//! * [`closed_loop`]: tool and controller coupled at the sample period, the loop the study runs.
//!
//! Units: SI inside (m, m/s, N, s); the study reports positions in mm as the paper does.

pub mod closed_loop;
pub mod controller;
pub mod fuzzy;
pub mod linear;
pub mod params;

pub use closed_loop::{LoopRecord, simulate, simulate_coupled};
pub use controller::{ControllerOutputs, SlidingFuzzy};
pub use fuzzy::{Reduction, T1System, T2System};
pub use params::{AxisGains, ControlMode, NominalModel, SlidingFuzzyParams};
pub use tool_xy::{ToolError, ToolInputs, ToolOutputs, ToolParams, ToolPlant};

/// What can go wrong in this crate.
#[derive(Debug, thiserror::Error)]
pub enum SlidingFuzzyError {
    /// A parameter out of range.
    #[error("invalid parameter: {0}")]
    Params(String),
    /// An input out of range (NaN, infinite, non-positive step).
    #[error("invalid input: {0}")]
    Input(String),
    /// A state that cannot be continued (non-finite after a step).
    #[error("invalid state: {0}")]
    State(String),
    /// An error of the tool model (the closed loop's plant).
    #[error(transparent)]
    Tool(#[from] ToolError),
}

/// Check that `v` is finite, else an input error naming it.
pub(crate) fn finite(name: &str, v: f64) -> Result<f64, SlidingFuzzyError> {
    if v.is_finite() { Ok(v) } else { Err(SlidingFuzzyError::Input(format!("{name} = {v} is not finite"))) }
}
