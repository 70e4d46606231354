//! FMI 2.0 Co-Simulation export layer (work in progress: the C ABI lands next).
pub mod model;
pub use model::*;
pub use model_description;
