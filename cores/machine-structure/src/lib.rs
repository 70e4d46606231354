//! # machine-structure
//!
//! A machine structure as plain Rust types, free of FFI: the physics of `ModalStructure.fmu`
//! and `InertialActuator.fmu`.
//!
//! | module | holds |
//! |---|---|
//! | [`modal`] | [`ModalStructure`]: N modes with mode shapes at a tool and an actuator point, exact discretisation, RK4 reference, force disturbances and stiffness drift |
//! | [`actuator`] | [`InertialActuator`]: seed 000's inertial actuator `ż = Az + Bu`, `F = Cz + Du`, saturated command |
//! | [`noise`] | band-limited Gaussian force noise on a fixed grid (shared with `milling-plant`) |

pub mod actuator;
pub mod grid;
pub mod modal;
pub mod noise;

pub use actuator::{ActuatorError, ActuatorOutputs, ActuatorParams, InertialActuator};
pub use modal::{ModalParams, ModalStructure, StructureError, StructureInputs, StructureMode, StructureOutputs};
