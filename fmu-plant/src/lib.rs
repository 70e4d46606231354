//! # MillingPlant.fmu
//!
//! The C-ABI cdylib of the milling plant: the physics and the variable table
//! live in [`milling_plant::fmu`]; this crate only exports them through the
//! shared FMI 2.0 layer. Its library name `MillingPlant` is the FMU's
//! `modelIdentifier` and the file name under `binaries/linux64/`.
#![allow(non_snake_case)]

fmi2_export::export_fmi2!(milling_plant::fmu::MillingPlant);
