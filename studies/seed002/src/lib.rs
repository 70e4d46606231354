//! # seed002: the studies of seed 002 (fixed-structure delayed output feedback, AMB spindle)
//!
//! The command line is the `chatter` crate (`chatter --help`).
//!
//! | module | holds |
//! |---|---|
//! | [`spindle`] | seed 002 end to end on the FMUs (`Spindle.ssp`: MillingProcess + SpindleStructure + LinearController): closed-loop tool FRFs, growth/decay around the SD boundary, the seed 002 SD presets |
//! | [`presets`] | the Section 6 cases as named presets of `chatter sd-lobes` (`seed002-6.1`, `-6.1-closed`, `-6.2`) |
//! | [`multistart`] | Table II n_c = 4 from many independent initial controllers (structured and random), the distribution of a_p,max |
//! | [`synth`] | the robust synthesis (Sections 4–6): §6.1's static structured gain and Table II's n_c = 0, 2, 4 controllers by D–K iteration with bisection on ā_p, SD box checks, SSP parameter sets |

pub mod multistart;
pub mod presets;
pub mod spindle;
pub mod synth;
