//! # FMI 2.0 C ABI types
//!
//! The types of `fmi2TypesPlatform.h` and `fmi2FunctionTypes.h` (FMI 2.0.4),
//! written by hand so that the project builds without libclang (the `fmi-sys`
//! crate generates the same with bindgen). Their agreement with the official
//! headers is checked by compiling a C file that includes both the official
//! headers and the cbindgen-generated header of our exporter
//! (`packaging` tests, `c_header_check`): any mismatch fails that build.
//!
//! Used by the exporter (`fmi2-export`) and the importer (`fmi-master`).
#![allow(non_camel_case_types, non_upper_case_globals, non_snake_case)]

use std::ffi::{c_char, c_int, c_uint, c_void};

/// `fmi2Component`: the instance handle.
pub type fmi2Component = *mut c_void;
/// `fmi2ComponentEnvironment`: the host's pointer passed back to callbacks.
pub type fmi2ComponentEnvironment = *mut c_void;
/// `fmi2FMUstate`: an opaque saved state.
pub type fmi2FMUstate = *mut c_void;
/// `fmi2ValueReference`.
pub type fmi2ValueReference = c_uint;
/// `fmi2Real`.
pub type fmi2Real = f64;
/// `fmi2Integer`.
pub type fmi2Integer = c_int;
/// `fmi2Boolean` (`fmi2True` = 1, `fmi2False` = 0).
pub type fmi2Boolean = c_int;
/// `fmi2Char`.
pub type fmi2Char = c_char;
/// `fmi2String`.
pub type fmi2String = *const fmi2Char;
/// `fmi2Byte`.
pub type fmi2Byte = c_char;

/// `fmi2True`.
pub const fmi2True: fmi2Boolean = 1;
/// `fmi2False`.
pub const fmi2False: fmi2Boolean = 0;

/// `fmi2Status` (a C enum, `int`-sized).
pub type fmi2Status = c_int;
/// `fmi2OK`
pub const fmi2OK: fmi2Status = 0;
/// `fmi2Warning`
pub const fmi2Warning: fmi2Status = 1;
/// `fmi2Discard`
pub const fmi2Discard: fmi2Status = 2;
/// `fmi2Error`
pub const fmi2Error: fmi2Status = 3;
/// `fmi2Fatal`
pub const fmi2Fatal: fmi2Status = 4;
/// `fmi2Pending`
pub const fmi2Pending: fmi2Status = 5;

/// `fmi2Type`.
pub type fmi2Type = c_int;
/// `fmi2ModelExchange`
pub const fmi2ModelExchange: fmi2Type = 0;
/// `fmi2CoSimulation`
pub const fmi2CoSimulation: fmi2Type = 1;

/// `fmi2StatusKind`.
pub type fmi2StatusKind = c_int;
/// `fmi2DoStepStatus`
pub const fmi2DoStepStatus: fmi2StatusKind = 0;
/// `fmi2PendingStatus`
pub const fmi2PendingStatus: fmi2StatusKind = 1;
/// `fmi2LastSuccessfulTime`
pub const fmi2LastSuccessfulTime: fmi2StatusKind = 2;
/// `fmi2Terminated`
pub const fmi2Terminated: fmi2StatusKind = 3;

/// `fmi2CallbackLogger`: `printf`-style, variadic.
pub type fmi2CallbackLogger = Option<
    unsafe extern "C" fn(
        env: fmi2ComponentEnvironment,
        instance_name: fmi2String,
        status: fmi2Status,
        category: fmi2String,
        message: fmi2String,
        ...
    ),
>;
/// `fmi2CallbackAllocateMemory`.
pub type fmi2CallbackAllocateMemory = Option<unsafe extern "C" fn(nobj: usize, size: usize) -> *mut c_void>;
/// `fmi2CallbackFreeMemory`.
pub type fmi2CallbackFreeMemory = Option<unsafe extern "C" fn(obj: *mut c_void)>;
/// `fmi2StepFinished`.
pub type fmi2StepFinished = Option<unsafe extern "C" fn(env: fmi2ComponentEnvironment, status: fmi2Status)>;

/// `fmi2CallbackFunctions`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct fmi2CallbackFunctions {
    /// Logger (may be null: then nothing is logged).
    pub logger: fmi2CallbackLogger,
    /// Allocator (unused by our FMUs: `canNotUseMemoryManagementFunctions="true"`).
    pub allocateMemory: fmi2CallbackAllocateMemory,
    /// Deallocator (unused by our FMUs).
    pub freeMemory: fmi2CallbackFreeMemory,
    /// Asynchronous step callback (unused: `canRunAsynchronuously="false"`).
    pub stepFinished: fmi2StepFinished,
    /// Passed back as the first argument of the callbacks.
    pub componentEnvironment: fmi2ComponentEnvironment,
}

/// Function-pointer types of every FMI 2.0 Co-Simulation entry point, for importers.
#[allow(missing_docs)]
pub mod fn_types {
    use super::*;
    pub type fmi2GetTypesPlatformTYPE = unsafe extern "C" fn() -> *const c_char;
    pub type fmi2GetVersionTYPE = unsafe extern "C" fn() -> *const c_char;
    pub type fmi2SetDebugLoggingTYPE =
        unsafe extern "C" fn(fmi2Component, fmi2Boolean, usize, *const fmi2String) -> fmi2Status;
    pub type fmi2InstantiateTYPE = unsafe extern "C" fn(
        fmi2String,
        fmi2Type,
        fmi2String,
        fmi2String,
        *const fmi2CallbackFunctions,
        fmi2Boolean,
        fmi2Boolean,
    ) -> fmi2Component;
    pub type fmi2FreeInstanceTYPE = unsafe extern "C" fn(fmi2Component);
    pub type fmi2SetupExperimentTYPE =
        unsafe extern "C" fn(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean, fmi2Real) -> fmi2Status;
    pub type fmi2EnterInitializationModeTYPE = unsafe extern "C" fn(fmi2Component) -> fmi2Status;
    pub type fmi2ExitInitializationModeTYPE = unsafe extern "C" fn(fmi2Component) -> fmi2Status;
    pub type fmi2TerminateTYPE = unsafe extern "C" fn(fmi2Component) -> fmi2Status;
    pub type fmi2ResetTYPE = unsafe extern "C" fn(fmi2Component) -> fmi2Status;
    pub type fmi2GetRealTYPE =
        unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Real) -> fmi2Status;
    pub type fmi2GetIntegerTYPE =
        unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Integer) -> fmi2Status;
    pub type fmi2GetBooleanTYPE =
        unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Boolean) -> fmi2Status;
    pub type fmi2GetStringTYPE =
        unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2String) -> fmi2Status;
    pub type fmi2SetRealTYPE =
        unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Real) -> fmi2Status;
    pub type fmi2SetIntegerTYPE =
        unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Integer) -> fmi2Status;
    pub type fmi2SetBooleanTYPE =
        unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Boolean) -> fmi2Status;
    pub type fmi2SetStringTYPE =
        unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2String) -> fmi2Status;
    pub type fmi2GetFMUstateTYPE = unsafe extern "C" fn(fmi2Component, *mut fmi2FMUstate) -> fmi2Status;
    pub type fmi2SetFMUstateTYPE = unsafe extern "C" fn(fmi2Component, fmi2FMUstate) -> fmi2Status;
    pub type fmi2FreeFMUstateTYPE = unsafe extern "C" fn(fmi2Component, *mut fmi2FMUstate) -> fmi2Status;
    pub type fmi2SerializedFMUstateSizeTYPE =
        unsafe extern "C" fn(fmi2Component, fmi2FMUstate, *mut usize) -> fmi2Status;
    pub type fmi2SerializeFMUstateTYPE =
        unsafe extern "C" fn(fmi2Component, fmi2FMUstate, *mut fmi2Byte, usize) -> fmi2Status;
    pub type fmi2DeSerializeFMUstateTYPE =
        unsafe extern "C" fn(fmi2Component, *const fmi2Byte, usize, *mut fmi2FMUstate) -> fmi2Status;
    pub type fmi2DoStepTYPE = unsafe extern "C" fn(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean) -> fmi2Status;
    pub type fmi2CancelStepTYPE = unsafe extern "C" fn(fmi2Component) -> fmi2Status;
    pub type fmi2GetStatusTYPE = unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Status) -> fmi2Status;
    pub type fmi2GetRealStatusTYPE = unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Real) -> fmi2Status;
    pub type fmi2GetBooleanStatusTYPE =
        unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Boolean) -> fmi2Status;
}

/// A human-readable name of a status value.
pub fn status_name(s: fmi2Status) -> &'static str {
    match s {
        fmi2OK => "fmi2OK",
        fmi2Warning => "fmi2Warning",
        fmi2Discard => "fmi2Discard",
        fmi2Error => "fmi2Error",
        fmi2Fatal => "fmi2Fatal",
        fmi2Pending => "fmi2Pending",
        _ => "invalid fmi2Status",
    }
}
