//! # sliding-fuzzy-control: seed 003, DSMC with interval type-2 fuzzy compensation
//!
//! The core of Paul & Morales-Menendez (2019), *"Chatter mitigation in milling process using
//! discrete time sliding mode control with type 2-fuzzy logic system"*, with no FMI in it:
//!
//! * [`tool`]: the decoupled two-axis tool of Table 1 (Eqs. 4 and 14) with the averaged,
//!   delayed-difference cubic cutting force of Eqs. 5–6 (coefficients from the φ-integral of
//!   [`milling_process::directional::cubic_average`]), the active vibration damper (AVD) with
//!   viscous + Coulomb (tanh) friction (Eq. 13), and the harmonic forcing at 650 rad/s;
//! * [`linear`]: the exact zero-order-hold discretisation of one axis (augmented matrix
//!   exponential) with its slow reference;
//! * [`fuzzy`]: Gaussian membership-function grids, the type-1 fuzzy system, the interval type-2
//!   system with the seed's closed-form type reduction (Eq. 25) and Karnik–Mendel as an option;
//! * [`controller`]: the per-axis controllers `dpid` (Eq. 62), `dsmc` (Eqs. 35–38), `dsmc_t1`
//!   and `dsmc_t2` (Eqs. 26–31 with the dead-zone learning law), two channels (x and y);
//! * [`closed_loop`]: tool and controller coupled at the sample period, the loop the study runs.
//!
//! ## Why a dedicated plant and not the milling-process / machine-structure SSP
//!
//! The seed's cutting force (Eq. 5) is the *revolution-averaged* force of half-immersion
//! up-milling, a polynomial in the delayed differences `Δx = x(t) − x(t−τ)`, `Δy`, acting on a
//! decoupled x/y oscillator; [`milling_process`] computes the *instantaneous* tooth-by-tooth
//! force (time-periodic coefficients), a different model whose average only is Eq. 5. The AVD
//! with friction (Eqs. 9–14) has no counterpart in the project either. So the plant is
//! dedicated, and it reuses the project's φ-integral ([`milling_process::directional::cubic_average`],
//! tested there against Eq. 6 to 1e-12) for its coefficients rather than retyping Eq. 6.
//!
//! Units: SI inside (m, m/s, N, s); the study reports positions in mm as the paper does.

pub mod closed_loop;
pub mod controller;
pub mod fuzzy;
pub mod linear;
pub mod tool;

pub use closed_loop::{LoopRecord, simulate};
pub use controller::{AxisGains, ControlMode, ControllerOutputs, SlidingFuzzy, SlidingFuzzyParams};
pub use fuzzy::{Reduction, T1System, T2System};
pub use tool::{ToolInputs, ToolOutputs, ToolParams, ToolPlant};

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
}

/// Check that `v` is finite, else an input error naming it.
pub(crate) fn finite(name: &str, v: f64) -> Result<f64, SlidingFuzzyError> {
    if v.is_finite() { Ok(v) } else { Err(SlidingFuzzyError::Input(format!("{name} = {v} is not finite"))) }
}
