//! # study-kit: what every study of the seed papers shares
//!
//! The studies themselves live in one crate per seed (`seed000` … `seed004`) and run from the
//! one `chatter` command; this crate holds what they have in common, with no seed in it:
//!
//! | module | holds |
//! |---|---|
//! | [`cases`] | a study as independent cases: plan (manifest), run any subset anywhere (shards, Slurm arrays, Dask), collect; re-runs complete only what is missing |
//! | [`batch_cases`] | the one case study of a fixed list of runs plus a report ([`batch_cases::RunBatch`], [`batch_cases::Batch`]) |
//! | [`fmu_params`] | parameter sets named as the FMUs name them: text, SSP and typed values resolved through an adapter's table; overrides for the master |
//! | [`growth`] | growth or decay of a recorded response (the time-domain side of every stability check) |
//! | [`optim`] | the shared optimisers: particle swarm ([`optim::pso`], seed 000) and the binary genetic algorithm ([`optim::ga`], seed 001), seeded, parallel over the population |
//! | [`output`] | CSV and PNG of several lobe diagrams on common axes |
//! | [`figures`] | line plots and heat maps on a common colour scale |

pub mod batch_cases;
pub mod cases;
mod error;
pub mod figures;
pub mod fmu_params;
pub mod growth;
pub mod optim;
pub mod output;

pub use error::StudyError;
