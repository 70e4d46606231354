//! # turning-process: seed 001's single-delay regenerative turning process
//!
//! The plant of *"Adjustable fractional order adaptive control on single-delay regenerative
//! machining chatter"* (Wan, Zhang, French 2015, Eqs. 3–5) as plain Rust types, with no FMI in
//! it: a one-degree-of-freedom tool structure cut by a power-law chip force whose chip is the
//! surface left one revolution earlier. Spindle speed and feed are inputs (the controller
//! changes both); the regenerative delay is found by angle in the surface history of
//! `milling-process` ([`milling_process::history`], one copy for milling and turning), so it is
//! exact at varying speed.
//!
//! | module | holds |
//! |---|---|
//! | [`params`] | [`TurningParams`] (the paper's Table 2 and the documented readings of the missing constants) |
//! | [`process`] | [`TurningProcess`]: RK4 on a fixed internal grid, chip, loss of contact, disturbance pulse |
//! | [`stability`] | the exact stability limit of the linearised single-delay equation (5) |
//!
//! Units: displacement in mm, time in s, speed in rpm, feed in mm/rev (the paper's).
//!
//! ```
//! use turning_process::{TurningInputs, TurningParams, TurningProcess};
//! let p = TurningParams::default();
//! let mut plant = TurningProcess::new(&p).unwrap();
//! for _ in 0..2000 {
//!     plant.step(1e-4, &TurningInputs::default()).unwrap();
//! }
//! // one revolution at 450 rpm
//! assert!((plant.outputs().delay - 60.0 / 450.0).abs() < 1e-9);
//! ```

pub mod params;
pub mod process;
pub mod stability;

pub use params::TurningParams;
pub use process::{TurningInputs, TurningOutputs, TurningProcess};
pub use stability::{StabilityLimit, stability_limit};

/// What can go wrong in this crate.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TurningError {
    /// A parameter out of range.
    #[error("invalid parameter: {0}")]
    Params(String),
    /// An input out of range (NaN, infinite, too slow, negative feed, non-positive step); the
    /// step was not taken.
    #[error("invalid input: {0}")]
    Input(String),
    /// The state left any physical range.
    #[error("the turning process diverged at t = {t} s")]
    Diverged {
        /// Time [s].
        t: f64,
    },
}
