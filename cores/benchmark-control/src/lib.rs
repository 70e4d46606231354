//! Seed 000's Table 8 benchmark controllers (Section 5.7: the Ozsoy et al. benchmark), designed
//! on the plant + actuator model and delivered as `LinearController` parameter sets.
//!
//! * [`ss`]: state-space systems, the closed loop of a generalised plant, the controller as a
//!   `LinearController` parameter set.
//! * [`riccati`]: the CARE by the matrix sign function, by the Hamiltonian eigenvectors and by
//!   Newton–Kleinman; Lyapunov; LQR and the steady-state Kalman filter.
//! * [`norm`]: the H∞ norm by the Hamiltonian bisection (Boyd–Balakrishnan–Bruinsma–Steinbuch)
//!   and a frequency sweep.
//! * [`synthesis`]: the two-Riccati H∞ synthesis (Doyle–Glover–Khargonekar–Francis) with
//!   γ-iteration: the central full-order controller.
//! * [`plant`]: the design model (mode + inertial actuator, normalised), the weights, the
//!   generalised plants of the H∞ and μ designs.
//! * [`designs`]: DVF, VPA, LQR with a Kalman observer, H∞ mixed sensitivity; [`mu_design`]:
//!   μ-synthesis by D–K iteration.
//!
//! The crate is a core: plain types, `thiserror` errors, no FMI.

pub mod designs;
pub mod mu_design;
pub mod norm;
pub mod plant;
pub mod riccati;
pub mod ss;
pub mod synthesis;

/// Errors of the designs.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// A parameter or a dimension is out of range; the message says which.
    #[error("invalid design parameter: {0}")]
    Invalid(String),
    /// A Riccati or Lyapunov equation has no (stabilising) solution.
    #[error("Riccati: {0}")]
    Riccati(String),
    /// No controller achieves the requested H∞ level (or the iteration failed).
    #[error("H∞ synthesis: {0}")]
    Synthesis(String),
}
