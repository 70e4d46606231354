//! # chatter-control
//!
//! The controllers of `ChatterController.fmu` (seed 000, Soufi et al., Section 4): classical
//! PID, fractional-order PID (FOPID, Eq. 28) and ADRC-FOPID (tracking differentiator +
//! extended state observer + FOPID), as plain Rust types with no FFI, and their linear
//! frequency responses for the stability-lobe and tuning tools.
//!
//! ```
//! use chatter_control::{Controller, ControllerParams, Structure};
//! let p = ControllerParams { structure: Structure::Fopid, ..ControllerParams::paper_table2() };
//! let mut c = Controller::new(&p).unwrap();
//! let out = c.sample(2e-6, 0.0); // y = 2 µm
//! assert!(out.u < 0.0 && out.u.abs() <= p.u_max);
//! // linear U/Y at 143 Hz, from the same discrete coefficients the sample() call uses
//! let h = p.frequency_response(2.0 * std::f64::consts::PI * 143.0);
//! assert!(h.norm() > p.fopid.kp);
//! ```
//!
//! One algorithm per module, its maths in the module documentation:
//!
//! | module | holds |
//! |---|---|
//! | [`params`] | [`ControllerParams`], the shipped defaults ([`params::DEFAULT_PARAMS`]), the Table 2 preset and its unit reading |
//! | [`controller`] | [`Controller::sample`] and the frequency responses (hold and delay conventions) |
//! | [`pid`] | discrete PID with anti-windup |
//! | [`fopid`] | FOPID from two fractional operators |
//! | [`fractional`] | `D^α` = exact integer part × GL or Oustaloup non-integer part |
//! | [`grunwald`] | short-memory Grünwald–Letnikov (ring buffer FIR, block-precomputed tail) |
//! | [`kernels`] | the GL window dot product and block tail sums (scalar definitions, AVX2, portable) |
//! | [`partitioned`] | the GL tail by uniformly partitioned FFT convolution (the default for L ≥ 63) |
//! | [`oustaloup`] | Oustaloup filter, Tustin with prewarping |
//! | [`eso`] | linear ESO, exact ZOH model + current observer with poles `e^{−ωo T}` |
//! | [`td`] | Han's tracking differentiator |

pub mod controller;
pub mod eso;
pub mod fopid;
pub mod fractional;
pub mod grunwald;
pub mod kernels;
pub mod oustaloup;
pub mod params;
pub mod partitioned;
pub mod pid;
pub mod td;

/// Checks of restored states: a configuration value must equal, bit for bit, the one the
/// parameters give; a state value must be finite.
pub(crate) mod restored {
    /// `what` if the configuration differs from the fresh one.
    pub fn same(what: &str, a: &[f64], fresh: &[f64]) -> Result<(), String> {
        let eq = a.len() == fresh.len() && a.iter().zip(fresh).all(|(x, y)| x.to_bits() == y.to_bits());
        if eq { Ok(()) } else { Err(format!("{what} does not match the parameters")) }
    }
    /// `what` if a state value is not finite.
    pub fn finite(what: &str, a: &[f64]) -> Result<(), String> {
        if a.iter().all(|x| x.is_finite()) { Ok(()) } else { Err(format!("{what} is not finite")) }
    }
}

pub use controller::{Controller, ControllerOutput, zoh};
pub use fopid::FopidGains;
pub use fractional::{FractionalMethod, FractionalParams};
pub use params::{AdrcParams, ControllerParams, Structure};
pub use pid::PidGains;
