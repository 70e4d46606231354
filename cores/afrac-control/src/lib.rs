//! # afrac-control: seed 001, adjustable fractional-order adaptive control (AFrAC)
//!
//! The controller of *"Adjustable fractional order adaptive control on single-delay
//! regenerative machining chatter"* (Wan, Zhang, French 2015) as plain Rust types, with no
//! FMI in it. It measures the tool displacement and velocity of the turning process and
//! commands the spindle speed and the feed:
//!
//! * [`delay_model`]: the reference delay model `ẏ = Ay + By(t − T)`, `Q₀` by Newton
//!   (`e^{(A+Q₀)T}Q₀ = B`), `P` by the Lyapunov equation, and why `ε + Q∗ε` removes the delay;
//! * [`memory`]: the convolution `Q∗ε` on the sample grid (trapezoidal rule);
//! * [`oustaloup`]: the band-limited fractional integrators `1/s^β` (β > 1 too), Table 3
//!   rebuilt, their exact sampled realisation;
//! * [`schedule`]: fixed β and the stepwise schedule of Eq. 30 / Table 5, bumpless switching;
//! * [`controller`]: the adaptation laws (20)–(21) for the feed and the spindle speed,
//!   integrated by `I^β`, and the sample loop.
//!
//! Units: displacement in mm, time in s, speed in rpm, feed in mm/rev.

pub mod controller;
pub mod delay_model;
pub mod memory;
pub mod oustaloup;
pub mod schedule;

pub use controller::{Afrac, AfracOutputs, AfracParams};
pub use delay_model::DelayModel;
pub use oustaloup::{Band, Integrator, Oustaloup};
pub use schedule::{BetaMode, Schedule};

/// What can go wrong in this crate.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AfracError {
    /// A parameter out of range.
    #[error("invalid parameter: {0}")]
    Params(String),
    /// An input out of range (NaN, infinite); the sample was not taken.
    #[error("invalid input: {0}")]
    Input(String),
    /// The design (Q₀, P) has no solution.
    #[error("design failed: {0}")]
    Design(String),
}
