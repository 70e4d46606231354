//! # seed003: the study of seed 003 (Paul & Morales-Menendez 2019, DSMC with type-2 fuzzy compensation)
//!
//! The command line is the `chatter` crate (`chatter --help`).
//!
//! | module | holds |
//! |---|---|
//! | [`dsmc`] | Table 2 (none, DSMC, D-PID, DSMC-T1, DSMC-T2) on the two-axis tool with the cubic law and the damper: MSE and reductions per axis |
//! | [`readings`] | the same rows under every reading of what the paper leaves open (the model of `A_dis`, T, the force limit, the computation delay): ranking and reductions |

pub mod dsmc;
pub mod readings;
