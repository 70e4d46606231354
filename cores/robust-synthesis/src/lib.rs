//! Fixed-structure robust synthesis of delayed (Pyragas) output feedback for milling, as in
//! seed 002 (IJRNC 2015, Sections 4–5).
//!
//! * [`optim`]: the nonsmooth optimiser: BFGS with a weak Wolfe line search (Lewis & Overton,
//!   Math. Program. 141, 2013), then gradient sampling (Burke, Lewis & Overton, SIAM J. Optim.
//!   15, 2005): the HANSO scheme the seed uses. Seeded, reproducible.
//! * [`mu`]: the structured singular value's upper bound `inf_D σ̄(D N D⁻¹)` with full-block
//!   scalings for repeated complex scalars (and scalar ones for full blocks), its gradient.
//! * [`abscissa`]: the spectral abscissa of `ẋ = A₀x + B_d C_d x(t − τ)` by a Chebyshev
//!   (infinitesimal-generator, Breda–Maset–Vermiglio) discretisation of the delayed-output
//!   history, refined by Newton on the characteristic matrix, and its derivative.
//! * [`plant`]: seed 002's generalised plant (Eqs. 12–19) at a frequency, the controller
//!   parameterisations, the closed loop `N = F_l(P̃, K)` and the gradients w.r.t. the controller
//!   parameters.
//! * [`dk`]: the D–K iteration (D-step pointwise in frequency, K-step by HANSO on
//!   `sup_ω σ̄(DND⁻¹) + ρ·max(0, Ψ)`) and the bisection on the design depth `ā_p`.
//!
//! The crate is a core: plain types, `thiserror` errors, no FMI.

pub mod abscissa;
pub mod dk;
pub mod mu;
pub mod optim;
pub mod plant;

/// Errors of the synthesis.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SynthError {
    /// A parameter is out of range; the message says which.
    #[error("invalid parameter: {0}")]
    Invalid(String),
    /// A linear system was singular (the message says where).
    #[error("singular: {0}")]
    Singular(String),
    /// An eigenvalue computation did not converge.
    #[error("eigenvalues did not converge ({0})")]
    Eigen(String),
    /// An error of the stability crate.
    #[error(transparent)]
    Stability(#[from] delay_stability::StabilityError),
}
