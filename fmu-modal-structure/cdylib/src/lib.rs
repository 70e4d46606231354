//! `ModalStructure.fmu`'s shared library: the 34 `fmi2*` functions of [`fmu_modal_structure::ModalStructure`]
//! through the shared export layer. Its library name `ModalStructure` is the FMU's
//! `modelIdentifier` and the file name under `binaries/<platform>/`.
#![allow(non_snake_case)]

fmi2_export::export_fmi2!(fmu_modal_structure::ModalStructure);
