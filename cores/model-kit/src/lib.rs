//! # model-kit
//!
//! Building blocks shared by the physics and control cores of the workspace. Nothing here
//! knows about FMI: the cores depend on this crate, the FMU adapters translate.
//!
//! | item | what |
//! |---|---|
//! | [`Choice`], [`choice!`] | a parameter that takes one of a fixed list of named items (an FMI enumeration, a CLI keyword) |
//! | [`rem_two_pi`] | `x.rem_euclid(2π)` bit for bit without the software `fmod` (tool angles every step) |
//! | [`budget`] | the memory budget of one model instance, checked when a core is built |

pub mod angle;
pub mod budget;
pub mod choice;

pub use angle::rem_two_pi;
pub use choice::{Choice, parse_choice};
