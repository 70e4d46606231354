//! # ChatterController.fmu
//!
//! The C-ABI cdylib of the chatter controllers (off, PID, FOPID, ADRC-FOPID):
//! the control laws and the variable table live in [`chatter_control::fmu`];
//! this crate only exports them through the shared FMI 2.0 layer. Its library
//! name `ChatterController` is the FMU's `modelIdentifier` and the file name
//! under `binaries/linux64/`.
#![allow(non_snake_case)]

fmi2_export::export_fmi2!(chatter_control::fmu::ChatterController);
