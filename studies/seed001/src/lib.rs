//! # seed001: the studies of seed 001 (Wan, Zhang, French 2015, AFrAC)
//!
//! The command line is the `chatter` crate (`chatter --help`).
//!
//! | module | holds |
//! |---|---|
//! | [`afrac`] | AFrAC on the turning process with the cores: open loop, fixed β, the Table 5 schedule; settling times, speed and feed excursions, window work; the switch-time GA (Table 4) |
//! | [`afrac_fmu`] | the same loop through `Afrac.ssp` (TurningProcess + AfracController FMUs) in the Rust master |

pub mod afrac;
pub mod afrac_fmu;
