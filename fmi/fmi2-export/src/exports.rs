// The FMI 2.0 Co-Simulation entry points of one model.
//
// This file is not compiled on its own: `build.rs` wraps it into the
// `export_fmi2!` macro, which places it in a module of the model's cdylib with
// `Model` = the model type and `use ::fmi2_export::abi::*`. cbindgen parses the
// same file to write the C header that the C header check compiles against the
// official FMI 2.0 headers. Keep one function per entry point, each a single
// forward to `::fmi2_export::ffi`.

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const fmi2Char {
    ::fmi2_export::ffi::get_types_platform()
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const fmi2Char {
    ::fmi2_export::ffi::get_version()
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(c: fmi2Component, loggingOn: fmi2Boolean, nCategories: usize, categories: *const fmi2String) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::set_debug_logging::<Model>(c, loggingOn, nCategories, categories) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(instanceName: fmi2String, fmuType: fmi2Type, fmuGUID: fmi2String, fmuResourceLocation: fmi2String, functions: *const fmi2CallbackFunctions, visible: fmi2Boolean, loggingOn: fmi2Boolean) -> fmi2Component {
    unsafe { ::fmi2_export::ffi::instantiate::<Model>(instanceName, fmuType, fmuGUID, fmuResourceLocation, functions, visible, loggingOn) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    unsafe { ::fmi2_export::ffi::free_instance::<Model>(c) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(c: fmi2Component, toleranceDefined: fmi2Boolean, tolerance: fmi2Real, startTime: fmi2Real, stopTimeDefined: fmi2Boolean, stopTime: fmi2Real) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::setup_experiment::<Model>(c, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::enter_initialization_mode::<Model>(c) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::exit_initialization_mode::<Model>(c) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::terminate::<Model>(c) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::reset::<Model>(c) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(c: fmi2Component, vr: *const fmi2ValueReference, nvr: usize, value: *mut fmi2Real) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_real::<Model>(c, vr, nvr, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetInteger(c: fmi2Component, vr: *const fmi2ValueReference, nvr: usize, value: *mut fmi2Integer) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_integer::<Model>(c, vr, nvr, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBoolean(c: fmi2Component, vr: *const fmi2ValueReference, nvr: usize, value: *mut fmi2Boolean) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_boolean::<Model>(c, vr, nvr, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetString(c: fmi2Component, vr: *const fmi2ValueReference, nvr: usize, value: *mut fmi2String) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_string::<Model>(c, vr, nvr, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(c: fmi2Component, vr: *const fmi2ValueReference, nvr: usize, value: *const fmi2Real) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::set_real::<Model>(c, vr, nvr, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetInteger(c: fmi2Component, vr: *const fmi2ValueReference, nvr: usize, value: *const fmi2Integer) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::set_integer::<Model>(c, vr, nvr, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetBoolean(c: fmi2Component, vr: *const fmi2ValueReference, nvr: usize, value: *const fmi2Boolean) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::set_boolean::<Model>(c, vr, nvr, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetString(c: fmi2Component, vr: *const fmi2ValueReference, nvr: usize, value: *const fmi2String) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::set_string::<Model>(c, vr, nvr, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_fmu_state::<Model>(c, FMUstate) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::set_fmu_state::<Model>(c, FMUstate) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::free_fmu_state::<Model>(c, FMUstate) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(c: fmi2Component, FMUstate: fmi2FMUstate, size: *mut usize) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::serialized_fmu_state_size::<Model>(c, FMUstate, size) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate, serializedState: *mut fmi2Byte, size: usize) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::serialize_fmu_state::<Model>(c, FMUstate, serializedState, size) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(c: fmi2Component, serializedState: *const fmi2Byte, size: usize, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::deserialize_fmu_state::<Model>(c, serializedState, size, FMUstate) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(c: fmi2Component, vUnknown_ref: *const fmi2ValueReference, nUnknown: usize, vKnown_ref: *const fmi2ValueReference, nKnown: usize, dvKnown: *const fmi2Real, dvUnknown: *mut fmi2Real) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_directional_derivative::<Model>(c, vUnknown_ref, nUnknown, vKnown_ref, nKnown, dvKnown, dvUnknown) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(c: fmi2Component, vr: *const fmi2ValueReference, nvr: usize, order: *const fmi2Integer, value: *const fmi2Real) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::set_real_input_derivatives::<Model>(c, vr, nvr, order, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(c: fmi2Component, vr: *const fmi2ValueReference, nvr: usize, order: *const fmi2Integer, value: *mut fmi2Real) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_real_output_derivatives::<Model>(c, vr, nvr, order, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(c: fmi2Component, currentCommunicationPoint: fmi2Real, communicationStepSize: fmi2Real, noSetFMUStatePriorToCurrentPoint: fmi2Boolean) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::do_step::<Model>(c, currentCommunicationPoint, communicationStepSize, noSetFMUStatePriorToCurrentPoint) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::cancel_step::<Model>(c) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(c: fmi2Component, s: fmi2StatusKind, value: *mut fmi2Status) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_status::<Model>(c, s, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(c: fmi2Component, s: fmi2StatusKind, value: *mut fmi2Real) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_real_status::<Model>(c, s, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(c: fmi2Component, s: fmi2StatusKind, value: *mut fmi2Integer) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_integer_status::<Model>(c, s, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(c: fmi2Component, s: fmi2StatusKind, value: *mut fmi2Boolean) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_boolean_status::<Model>(c, s, value) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(c: fmi2Component, s: fmi2StatusKind, value: *mut fmi2String) -> fmi2Status {
    unsafe { ::fmi2_export::ffi::get_string_status::<Model>(c, s, value) }
}
