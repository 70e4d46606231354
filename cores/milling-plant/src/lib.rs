//! # milling-plant
//!
//! The physics of `MillingPlant.fmu` (seed 000, Soufi et al., Section 3), free of FFI types:
//! a cantilever workpiece (first bending mode, optionally two higher modes), the mechanistic
//! regenerative cutting force with a variable, angle-tracked delay, an inertial actuator
//! saturated at ±27 N, stiffness drift and band-limited noise.
//!
//! ```
//! use milling_plant::{Plant, PlantInputs, PlantParams};
//! let p = PlantParams::default();
//! let mut plant = Plant::new(&p).unwrap();
//! plant.step(0.01, &PlantInputs::default()).unwrap();
//! assert!(plant.outputs().x.abs() < 1e-4);
//! // tooth-passing delay at 2000 rpm, 4 teeth: 7.5 ms
//! plant.step(0.01, &PlantInputs::default()).unwrap();
//! assert!((plant.outputs().delay - 7.5e-3).abs() < 1e-9);
//! ```
//!
//! | module | holds |
//! |---|---|
//! | [`params`] | [`PlantParams`], direction convention, directional factor, receptance, actuator response |
//! | [`plant`] | [`Plant`]: equations, the fixed grid, RK4 (reference) or the exact scheme |
//! | [`exact`] | exact discretisation of the linear dynamics (matrix exponential, φ-functions) |
//! | [`history`] | angle-indexed displacement history for the regenerative delay |
//! | [`noise`] | band-limited Gaussian noise on the fixed grid |

/// The band-limited noise lives in `machine-structure` (shared with the structure FMU).
pub use machine_structure::noise;
/// The angle-indexed history lives in `milling-process` (shared with the process FMU).
pub use milling_process::history;
pub mod exact;
pub mod params;
pub mod plant;
mod teeth;

pub use params::{CuttingModel, Integrator, MillingMode, Mode, PlantParams};
pub use plant::{Plant, PlantError, PlantInputs, PlantOutputs};
