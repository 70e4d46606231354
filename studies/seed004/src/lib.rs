//! # seed004: the study of seed 004 (FROH model-following force control)
//!
//! The command line is the `chatter` crate (`chatter --help`).
//!
//! | module | holds |
//! |---|---|
//! | [`froh`] | the FROH zero locus, the non-minimum-phase boundary in β, and the J(β) sweep of the adaptive loop for three chip-lag readings |

pub mod froh;
