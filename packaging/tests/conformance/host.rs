//! The host side of the conformance test: one product's real cdylib loaded with `libloading`,
//! its 34 `fmi2*` functions resolved by name, a logger that records messages per instance,
//! and the variables the hostile-call table needs, picked from the product's own description.

use fmi2_abi::fn_types::*;
use fmi2_abi::*;
use model_description::{Causality, ModelDescription, ScalarType, ScalarVariable, VarKind, Variability};
use packaging::{PRODUCTS, target_dir};
use std::ffi::{CStr, CString, c_char, c_void};
use std::sync::Mutex;

pub type GetDirectionalDerivativeTYPE = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *const fmi2ValueReference,
    usize,
    *const fmi2Real,
    *mut fmi2Real,
) -> fmi2Status;
pub type SetRealInputDerivativesTYPE = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *const fmi2Integer,
    *const fmi2Real,
) -> fmi2Status;
pub type GetRealOutputDerivativesTYPE = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *const fmi2Integer,
    *mut fmi2Real,
) -> fmi2Status;
pub type GetIntegerStatusTYPE = unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Integer) -> fmi2Status;
pub type GetStringStatusTYPE = unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2String) -> fmi2Status;

macro_rules! api {
    ($($field:ident: $name:literal as $ty:ty),* $(,)?) => {
        /// The FMI 2.0 functions of one loaded library.
        #[allow(non_snake_case)]
        pub struct Api { $(pub $field: $ty),* }
        impl Api {
            fn resolve(lib: &libloading::Library, id: &str) -> Api {
                Api { $(
                    // SAFETY: the symbol is the FMI 2.0 function of that name, whose C signature is
                    // `$ty`; the library is never unloaded (`LIBRARIES`).
                    $field: *unsafe { lib.get::<$ty>(concat!($name, "\0").as_bytes()) }
                        .unwrap_or_else(|e| panic!("{id}: {} not exported: {e}", $name)),
                )* }
            }
        }
    };
}

api! {
    set_debug_logging: "fmi2SetDebugLogging" as fmi2SetDebugLoggingTYPE,
    instantiate: "fmi2Instantiate" as fmi2InstantiateTYPE,
    free_instance: "fmi2FreeInstance" as fmi2FreeInstanceTYPE,
    setup_experiment: "fmi2SetupExperiment" as fmi2SetupExperimentTYPE,
    enter_initialization_mode: "fmi2EnterInitializationMode" as fmi2EnterInitializationModeTYPE,
    exit_initialization_mode: "fmi2ExitInitializationMode" as fmi2ExitInitializationModeTYPE,
    terminate: "fmi2Terminate" as fmi2TerminateTYPE,
    reset: "fmi2Reset" as fmi2ResetTYPE,
    get_real: "fmi2GetReal" as fmi2GetRealTYPE,
    get_integer: "fmi2GetInteger" as fmi2GetIntegerTYPE,
    get_boolean: "fmi2GetBoolean" as fmi2GetBooleanTYPE,
    get_string: "fmi2GetString" as fmi2GetStringTYPE,
    set_real: "fmi2SetReal" as fmi2SetRealTYPE,
    set_integer: "fmi2SetInteger" as fmi2SetIntegerTYPE,
    set_boolean: "fmi2SetBoolean" as fmi2SetBooleanTYPE,
    set_string: "fmi2SetString" as fmi2SetStringTYPE,
    get_fmu_state: "fmi2GetFMUstate" as fmi2GetFMUstateTYPE,
    set_fmu_state: "fmi2SetFMUstate" as fmi2SetFMUstateTYPE,
    free_fmu_state: "fmi2FreeFMUstate" as fmi2FreeFMUstateTYPE,
    serialized_size: "fmi2SerializedFMUstateSize" as fmi2SerializedFMUstateSizeTYPE,
    serialize: "fmi2SerializeFMUstate" as fmi2SerializeFMUstateTYPE,
    deserialize: "fmi2DeSerializeFMUstate" as fmi2DeSerializeFMUstateTYPE,
    get_directional_derivative: "fmi2GetDirectionalDerivative" as GetDirectionalDerivativeTYPE,
    set_real_input_derivatives: "fmi2SetRealInputDerivatives" as SetRealInputDerivativesTYPE,
    get_real_output_derivatives: "fmi2GetRealOutputDerivatives" as GetRealOutputDerivativesTYPE,
    do_step: "fmi2DoStep" as fmi2DoStepTYPE,
    cancel_step: "fmi2CancelStep" as fmi2CancelStepTYPE,
    get_status: "fmi2GetStatus" as fmi2GetStatusTYPE,
    get_real_status: "fmi2GetRealStatus" as fmi2GetRealStatusTYPE,
    get_integer_status: "fmi2GetIntegerStatus" as GetIntegerStatusTYPE,
    get_boolean_status: "fmi2GetBooleanStatus" as fmi2GetBooleanStatusTYPE,
    get_string_status: "fmi2GetStringStatus" as GetStringStatusTYPE,
}

/// One product: its description, its loaded library and its functions.
pub struct Fmu {
    pub id: String,
    pub md: &'static ModelDescription,
    pub api: Api,
}

/// The loaded libraries, never unloaded: their one-time statics (descriptions, tables) stay
/// reachable, so the valgrind run of this test reports only real leaks; and the functions in
/// [`Api`] stay valid for the life of the process.
static LIBRARIES: Mutex<Vec<libloading::Library>> = Mutex::new(Vec::new());

/// Every product of `PRODUCTS`: the linux64 binary shipped in its FMU, extracted into
/// `target/conformance/linux64/` and loaded.
pub fn load_all() -> Vec<Fmu> {
    PRODUCTS
        .iter()
        .map(|p| {
            let md = (p.description)();
            let id = md.model_identifier().expect("co-simulation product").to_string();
            let path = crate::common::packaged_binary(&id, "linux64", &target_dir().join("conformance"))
                .unwrap_or_else(|| panic!("{id}.fmu has no linux64 binary"));
            // SAFETY: our own FMU library; its initialisers only set up Rust statics.
            let lib = unsafe { libloading::Library::new(&path) }.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let api = Api::resolve(&lib, &id);
            LIBRARIES.lock().unwrap().push(lib);
            Fmu { id, md, api }
        })
        .collect()
}

/// Messages received by the logger: (instance name, status, message).
static LOG: Mutex<Vec<(String, fmi2Status, String)>> = Mutex::new(Vec::new());

/// A logger with the fixed arguments the export layer uses (`"%s"` + one string). The FMI
/// logger is variadic and stable Rust cannot define variadic functions; on the x86_64 and
/// aarch64 System V ABIs a call through the variadic pointer passes these arguments exactly as
/// a non-variadic call does. A message in another format is recorded as the format itself.
unsafe extern "C" fn logger_fixed(
    _env: *mut c_void,
    name: fmi2String,
    status: fmi2Status,
    _category: fmi2String,
    fmt: fmi2String,
    arg: *const c_char,
) {
    let s = |p: *const c_char| {
        if p.is_null() { String::new() } else { unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned() }
    };
    let text = if s(fmt) == "%s" { s(arg) } else { s(fmt) };
    LOG.lock().unwrap().push((s(name), status, text));
}

pub fn callbacks() -> fmi2CallbackFunctions {
    type Fixed = unsafe extern "C" fn(*mut c_void, fmi2String, fmi2Status, fmi2String, fmi2String, *const c_char);
    // SAFETY: see `logger_fixed`.
    let logger: fmi2CallbackLogger = Some(unsafe {
        std::mem::transmute::<
            Fixed,
            unsafe extern "C" fn(*mut c_void, fmi2String, fmi2Status, fmi2String, fmi2String, ...),
        >(logger_fixed as Fixed)
    });
    fmi2CallbackFunctions {
        logger,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    }
}

/// Did instance `name` log a warning or worse with a non-empty message?
pub fn refusal_logged(name: &str) -> bool {
    LOG.lock().unwrap().iter().any(|m| m.0 == name && m.1 >= fmi2Discard && !m.2.is_empty())
}

/// Number of error messages of instance `name`.
pub fn errors_logged(name: &str) -> usize {
    LOG.lock().unwrap().iter().filter(|m| m.0 == name && m.1 == fmi2Error).count()
}

/// The last message of instance `name`.
pub fn last_message(name: &str) -> String {
    LOG.lock().unwrap().iter().rev().find(|m| m.0 == name).map(|m| m.2.clone()).unwrap_or_default()
}

impl Fmu {
    pub fn guid(&self) -> CString {
        CString::new(self.md.guid.clone()).unwrap()
    }

    /// A new instance named `name` (unique per row, so its messages can be told apart).
    pub fn instantiate(&self, name: &str, cb: &fmi2CallbackFunctions) -> fmi2Component {
        let n = CString::new(name).unwrap();
        let g = self.guid();
        // SAFETY: valid strings and callbacks that outlive the call.
        let c = unsafe { (self.api.instantiate)(n.as_ptr(), fmi2CoSimulation, g.as_ptr(), std::ptr::null(), cb, 0, 0) };
        assert!(!c.is_null(), "{}: instantiation failed: {}", self.id, last_message(name));
        c
    }

    /// Instantiated, set up at t0 = 0 without a stop time, and initialized.
    pub fn ready(&self, name: &str, cb: &fmi2CallbackFunctions) -> fmi2Component {
        let c = self.instantiate(name, cb);
        // SAFETY: a live component of this library.
        unsafe {
            assert_eq!((self.api.setup_experiment)(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK, "{}", self.id);
            assert_eq!((self.api.enter_initialization_mode)(c), fmi2OK, "{}", self.id);
            let s = (self.api.exit_initialization_mode)(c);
            assert_eq!(s, fmi2OK, "{}: default initialization failed: {}", self.id, last_message(name));
        }
        c
    }

    /// The serialized state of a fresh, initialized instance.
    pub fn state_bytes(&self, cb: &fmi2CallbackFunctions) -> Vec<fmi2Byte> {
        let c = self.ready(&format!("{}-bytes", self.id), cb);
        // SAFETY: a live component; buffers of the announced size.
        unsafe {
            let mut st: fmi2FMUstate = std::ptr::null_mut();
            assert_eq!((self.api.get_fmu_state)(c, &mut st), fmi2OK, "{}", self.id);
            let mut n = 0usize;
            assert_eq!((self.api.serialized_size)(c, st, &mut n), fmi2OK, "{}", self.id);
            let mut b = vec![0 as fmi2Byte; n];
            assert_eq!((self.api.serialize)(c, st, b.as_mut_ptr(), n), fmi2OK, "{}", self.id);
            (self.api.free_fmu_state)(c, &mut st);
            (self.api.free_instance)(c);
            b
        }
    }

    fn find(&self, ok: impl Fn(&ScalarVariable) -> bool) -> Option<&'static ScalarVariable> {
        self.md.variables().iter().find(|v| ok(v))
    }

    /// A variable of API type `ty` with causality `causality` (and variability, if given).
    pub fn var(
        &self,
        ty: ScalarType,
        causality: Causality,
        var: Option<Variability>,
    ) -> Option<&'static ScalarVariable> {
        self.find(|v| {
            v.scalar_type().api_type() == ty.api_type()
                && v.causality == causality
                && var.is_none_or(|x| x == v.variability)
        })
    }

    /// Any variable of API type `ty` (for get calls and null-array rows).
    pub fn any(&self, ty: ScalarType) -> Option<&'static ScalarVariable> {
        self.find(|v| v.scalar_type().api_type() == ty.api_type())
    }

    /// A value reference no variable of API type `ty` has.
    pub fn unknown_vr(&self, ty: ScalarType) -> fmi2ValueReference {
        let used = self.md.variables().iter().filter(|v| v.scalar_type().api_type() == ty.api_type());
        used.map(|v| v.value_reference).max().map_or(0, |m| m + 1000)
    }

    /// A Real parameter with a finite bound, settable before initialization, and a value
    /// outside that bound.
    pub fn out_of_range_real(&self) -> Option<(fmi2ValueReference, f64, String)> {
        self.md.variables().iter().find_map(|v| {
            let settable = v.causality == Causality::Parameter || v.causality == Causality::Input;
            if !settable || v.scalar_type() != ScalarType::Real {
                return None;
            }
            match v.range() {
                (_, Some(hi)) if hi.is_finite() && hi < 1e300 => {
                    Some((v.value_reference, hi + hi.abs().max(1.0), v.name.clone()))
                }
                (Some(lo), _) if lo.is_finite() && lo > -1e300 => {
                    Some((v.value_reference, lo - lo.abs().max(1.0), v.name.clone()))
                }
                _ => None,
            }
        })
    }

    /// An enumeration parameter or input and an integer that is none of its items.
    pub fn non_item(&self) -> Option<(fmi2ValueReference, i32)> {
        self.md.variables().iter().find_map(|v| match &v.kind {
            VarKind::Enumeration(e) if matches!(v.causality, Causality::Parameter | Causality::Input) => {
                let items = self.md.enumeration_items(&e.declared_type);
                Some((v.value_reference, items.iter().map(|i| i.1).max().unwrap_or(0) + 100))
            }
            _ => None,
        })
    }
}
