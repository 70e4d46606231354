//! # tool-xy: seed 003's plant, a two-axis tool with the averaged cubic law and a damper
//!
//! The plant of Paul & Morales-Menendez (2019) with no FMI in it ([`tool`]): the decoupled
//! two-axis tool of Table 1 (Eqs. 4 and 14) with the averaged, delayed-difference cubic cutting
//! force of Eqs. 5–6 (coefficients from the φ-integral of
//! [`milling_process::directional::cubic_average`]), the active vibration damper (AVD) with
//! viscous + Coulomb (tanh) friction (Eq. 13), and the harmonic forcing at 650 rad/s. The
//! controllers of the paper are `sliding-fuzzy-control`.
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
//! Units: SI inside (m, m/s, N, s).

pub mod tool;

pub use tool::{ToolInputs, ToolOutputs, ToolParams, ToolPlant};

/// What can go wrong in the tool model.
#[derive(Debug, thiserror::Error)]
pub enum ToolError {
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
pub(crate) fn finite(name: &str, v: f64) -> Result<f64, ToolError> {
    if v.is_finite() { Ok(v) } else { Err(ToolError::Input(format!("{name} = {v} is not finite"))) }
}
