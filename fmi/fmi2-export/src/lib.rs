//! # FMI 2.0 Co-Simulation export layer
//!
//! Write the physics and a variable table in safe Rust; get a standard-conformant
//! FMI 2.0 Co-Simulation C API. No Rust crate exports FMI 2.0 otherwise
//! (rust-fmi's exporter targets FMI 3.0).
//!
//! A model:
//! 1. declares its variables once with [`model_description::ModelBuilder`]
//!    (name, value reference, causality, variability, start, unit, bounds,
//!    enumeration types, output dependencies); the XML, `ModelStructure`, the
//!    GUID, start values and all get/set checks derive from that table;
//! 2. implements [`Fmi2Model`]: build from parameters, write outputs, step;
//! 3. is exported from a `cdylib` whose library name is its `modelIdentifier`:
//!
//! ```ignore
//! // fmu-mymodel/src/lib.rs, with [lib] name = "MyModel", crate-type = ["cdylib", "rlib"]
//! fmi2_export::export_fmi2!(my_model::MyModel);
//! ```
//!
//! The layer implements every FMI 2.0.4 common and co-simulation function:
//! a state machine per instance with an allowed-state mask per call,
//! pointer/length checks, the GUID and fmuType check at instantiation, a panic
//! boundary around every body (a panic is `fmi2Fatal`, never an abort of the
//! host), logging through the host's logger with a fixed `"%s"` format and the
//! categories of `fmi2SetDebugLogging`, FMI's rules on which variables may be
//! set in which state, NaN/Inf and range checks, drift-free communication
//! time, FMU state get/set/serialize with a versioned byte format, and honest
//! answers for the optional functions the capability flags declare absent.
//!
//! Layout: [`model`] (what a model implements, safe), [`instance`] (the
//! state machine and rules, safe), [`ffi`] (the only `unsafe` code: the C
//! boundary), [`abi`] (the C types, re-exported from `fmi2-abi`).
#![deny(unsafe_code)]

#[allow(unsafe_code)]
pub mod ffi;
pub mod instance;
pub mod model;
pub mod table;

pub use fmi2_abi as abi;
pub use instance::{LOG_CATEGORIES, approx_eq};
pub use model::*;
pub use model_description;
pub use model_kit;
pub use table::{Header, Scalar, Table, Variables};

/// Add the log categories that the export layer emits to a model's description.
pub fn with_log_categories(mut b: model_description::ModelBuilder) -> model_description::ModelBuilder {
    for (name, desc) in LOG_CATEGORIES {
        b = b.log_category(name, desc);
    }
    b
}

include!(concat!(env!("OUT_DIR"), "/export_macro.rs"));

/// The README's example of a model compiles (run as a doctest).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
