//! **All `unsafe` code of the import side.** Everything that crosses into an
//! FMU's shared library happens here, behind small safe functions; every
//! `unsafe` block says why it is sound.
//!
//! * [`Loaded::open`]: `dlopen` with `RTLD_NOW | RTLD_LOCAL` (unresolved
//!   symbols fail here, not mid-run), resolution of every FMI 2.0 function
//!   (all must be exported, FMI 2.0 §2.1.1), the `fmi2GetVersion` check.
//! * [`preload_global`]: a library loaded `RTLD_GLOBAL` for good (libpython).
//! * [`RawInstance`]: one `fmi2Component` and thin wrappers of the calls the
//!   master makes, each returning the raw `fmi2Status`. A raw instance is
//!   freed exactly once; after [`RawInstance::free`] or
//!   [`RawInstance::abandon`] every call answers `fmi2Error` without
//!   touching the FMU. The state rules of FMI live in the safe
//!   [`super::instance`] layer.
//! * The logger: FMI's logger is variadic, so `csrc/logger_shim.c` formats
//!   with `vsnprintf` and forwards to [`log_sink`], which appends to the
//!   instance's [`LogState`].

use crate::error::{FmuError, LogExcerpt};
use crate::import::log::{LOG_QUOTED, LogState};
use fmi2_abi::fn_types::*;
use fmi2_abi::*;
use std::ffi::{CStr, c_char, c_int, c_void};
use std::path::Path;
use std::ptr::NonNull;
use std::sync::Arc;

unsafe extern "C" {
    // Implemented in csrc/logger_shim.c.
    fn fmi_master_logger(
        env: fmi2ComponentEnvironment,
        instance_name: fmi2String,
        status: fmi2Status,
        category: fmi2String,
        message: fmi2String,
        ...
    );
    fn fmi_master_calloc(nobj: usize, size: usize) -> *mut c_void;
    fn fmi_master_free(obj: *mut c_void);
}

/// The FMI 2.0 functions the master calls, resolved from the library.
struct Api {
    get_version: fmi2GetVersionTYPE,
    set_debug_logging: fmi2SetDebugLoggingTYPE,
    instantiate: fmi2InstantiateTYPE,
    free_instance: fmi2FreeInstanceTYPE,
    setup_experiment: fmi2SetupExperimentTYPE,
    enter_initialization_mode: fmi2EnterInitializationModeTYPE,
    exit_initialization_mode: fmi2ExitInitializationModeTYPE,
    terminate: fmi2TerminateTYPE,
    reset: fmi2ResetTYPE,
    get_real: fmi2GetRealTYPE,
    get_integer: fmi2GetIntegerTYPE,
    get_boolean: fmi2GetBooleanTYPE,
    get_string: fmi2GetStringTYPE,
    set_real: fmi2SetRealTYPE,
    set_integer: fmi2SetIntegerTYPE,
    set_boolean: fmi2SetBooleanTYPE,
    set_string: fmi2SetStringTYPE,
    do_step: fmi2DoStepTYPE,
}

/// Functions every FMI 2.0 co-simulation FMU exports that the master does
/// not call; only their presence is checked.
const PRESENT_ONLY: [&str; 16] = [
    "fmi2GetTypesPlatform",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
];

fn resolve(lib: &libloading::Library, fmu: &str) -> Result<Api, FmuError> {
    let mut missing = Vec::new();
    macro_rules! api {
        ($($field:ident: $name:literal as $ty:ty),* $(,)?) => {{
            $(
                // SAFETY: the symbol, if present, is the FMI 2.0 function of
                // that name, whose C signature is `$ty` (fmi2FunctionTypes.h,
                // mirrored in fmi2-abi). The copied pointer is only used while
                // `lib` is loaded: Api and Library live and die together in `Loaded`.
                let $field = match unsafe { lib.get::<$ty>(concat!($name, "\0").as_bytes()) } {
                    Ok(s) => Some(*s),
                    Err(_) => {
                        missing.push($name);
                        None
                    }
                };
            )*
            for name in PRESENT_ONLY {
                let bytes = format!("{name}\0");
                // SAFETY: only the symbol's presence is checked; the pointer is
                // never called or kept (`*const c_void` is not a function type).
                if unsafe { lib.get::<*const c_void>(bytes.as_bytes()) }.is_err() {
                    missing.push(name);
                }
            }
            if !missing.is_empty() {
                return Err(FmuError::MissingSymbols { fmu: fmu.to_string(), missing: missing.join(", ") });
            }
            Api { $($field: $field.expect("a missing symbol returned above")),* }
        }};
    }
    Ok(api! {
        get_version: "fmi2GetVersion" as fmi2GetVersionTYPE,
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
        do_step: "fmi2DoStep" as fmi2DoStepTYPE,
    })
}

/// Load a shared library with `RTLD_NOW | RTLD_GLOBAL` and keep it loaded for
/// the life of the process, so that FMUs loaded later can resolve symbols
/// from it. Needed for FMUs that expect their host to provide a runtime, such
/// as those built by `pythonfmu`, whose binary uses `libpython` symbols
/// without linking it (FMPy works because it *is* a Python process).
pub fn preload_global(path: &Path) -> Result<(), FmuError> {
    // SAFETY: loading a library runs its initializers; the user names the
    // library explicitly for this purpose (e.g. libpython), exactly as
    // LD_PRELOAD would. It is never unloaded (forgotten below), so no
    // symbol from it can dangle.
    let lib = unsafe {
        libloading::os::unix::Library::open(
            Some(path),
            libloading::os::unix::RTLD_NOW | libloading::os::unix::RTLD_GLOBAL,
        )
    }
    .map_err(|e| FmuError::Load {
        fmu: "(preload)".into(),
        path: path.to_path_buf(),
        message: e.to_string(),
        hint: String::new(),
    })?;
    std::mem::forget(lib);
    Ok(())
}

/// A loaded FMU binary with its resolved functions, and the directory the
/// FMU was extracted to. Field order is drop order: the library is unloaded
/// before the directory is removed.
pub(crate) struct Loaded {
    api: Api,
    _library: libloading::Library,
    dir: super::process::ScratchDir,
}

impl Loaded {
    /// Load the binary `so` of the FMU `fmu` (extracted into `dir`), resolve
    /// its functions and check that it reports FMI 2.0.
    pub(crate) fn open(so: &Path, dir: super::process::ScratchDir, fmu: &str) -> Result<Loaded, FmuError> {
        // SAFETY: loading runs the library's initializers. The file is the
        // FMU's own binary, which the user asked to run; FMI binaries are
        // meant to be loaded into a host like this. RTLD_NOW makes missing
        // symbols fail here rather than abort the process at a later call.
        let library = unsafe {
            libloading::os::unix::Library::open(
                Some(so),
                libloading::os::unix::RTLD_NOW | libloading::os::unix::RTLD_LOCAL,
            )
        }
        .map_err(|e| {
            let message = e.to_string();
            let hint = if message.contains("undefined symbol: Py") || message.contains("undefined symbol: _Py") {
                "\n  hint: this binary expects its host to provide the Python runtime (a pythonfmu FMU); \
                 pass --preload <path to libpython3.x.so> to load it first"
                    .to_string()
            } else {
                String::new()
            };
            FmuError::Load { fmu: fmu.to_string(), path: so.to_path_buf(), message, hint }
        })?;
        let library = libloading::Library::from(library);
        let api = resolve(&library, fmu)?;
        // SAFETY: fmi2GetVersion takes no arguments and returns a pointer to a
        // static NUL-terminated string (FMI 2.0 §2.1.4); checked for NULL.
        let version = unsafe {
            let p = (api.get_version)();
            if p.is_null() { String::from("(null)") } else { CStr::from_ptr(p).to_string_lossy().into_owned() }
        };
        if !version.starts_with("2.") {
            return Err(FmuError::Version { fmu: fmu.to_string(), version });
        }
        Ok(Loaded { api, _library: library, dir })
    }

    /// The extraction directory.
    pub(crate) fn dir(&self) -> &Path {
        self.dir.path()
    }
}

/// Signature of the Rust function the C shim forwards formatted messages to.
type SinkFn = unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

/// The component environment handed to the FMU. `#[repr(C)]` with the sink
/// first: the C shim reads `sink` through `struct fmi_master_log_env`.
#[repr(C)]
struct LogEnv {
    sink: SinkFn,
    state: LogState,
}

/// Receives every message the FMU logs, already formatted by the C shim.
///
/// # Safety
/// `env` must be the `LogEnv` pointer this module passed to
/// `fmi2Instantiate` (or NULL); the strings NULL or NUL-terminated.
unsafe extern "C" fn log_sink(
    env: *mut c_void,
    _instance: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    let text = |p: *const c_char| {
        if p.is_null() {
            String::new()
        } else {
            // SAFETY: a non-null pointer from the shim is a NUL-terminated
            // string valid for the duration of the logger call.
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    // Never unwind into C.
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let line = format!("{} [{}] {}", status_name(status), text(category), text(message));
        if env.is_null() {
            eprintln!("(FMU log without environment) {line}");
            return;
        }
        // SAFETY: a non-null env is the boxed LogEnv of a live instance: the
        // box outlives fmi2FreeInstance, after which the FMU may not log.
        let env = unsafe { &*(env as *const LogEnv) };
        env.state.push(line);
    }));
}

/// One `fmi2Component` of a loaded library (see the module documentation).
pub(crate) struct RawInstance {
    comp: NonNull<c_void>,
    /// False once freed or abandoned: then no call reaches the FMU.
    alive: bool,
    /// Scratch for `fmi2Boolean` conversions (no allocation per step).
    bools: Vec<fmi2Boolean>,
    // Both must outlive fmi2FreeInstance (Drop frees before fields drop).
    log: Box<LogEnv>,
    _callbacks: Box<fmi2CallbackFunctions>,
    loaded: Arc<Loaded>,
}

impl RawInstance {
    /// `fmi2Instantiate` a co-simulation slave; on NULL, the lines the FMU logged.
    pub(crate) fn instantiate(
        loaded: &Arc<Loaded>,
        name: &CStr,
        guid: &CStr,
        resources: &CStr,
        logging_on: bool,
        log: LogState,
    ) -> Result<RawInstance, LogExcerpt> {
        let log = Box::new(LogEnv { sink: log_sink, state: log });
        let env: *const LogEnv = &*log;
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: Some(fmi_master_logger),
            allocateMemory: Some(fmi_master_calloc),
            freeMemory: Some(fmi_master_free),
            stepFinished: None,
            componentEnvironment: env as *mut c_void,
        });
        // SAFETY: all string arguments are valid NUL-terminated C strings that
        // outlive the call (FMI requires the FMU to copy them). `callbacks`
        // is boxed and kept in the returned instance until after
        // fmi2FreeInstance, since FMUs may keep the pointer (pythonfmu does);
        // its environment points to the boxed LogEnv kept alongside.
        let comp = unsafe {
            (loaded.api.instantiate)(
                name.as_ptr(),
                fmi2CoSimulation,
                guid.as_ptr(),
                resources.as_ptr(),
                &*callbacks,
                fmi2False,
                if logging_on { fmi2True } else { fmi2False },
            )
        };
        let Some(comp) = NonNull::new(comp) else { return Err(log.state.excerpt(LOG_QUOTED)) };
        Ok(RawInstance { comp, alive: true, bools: Vec::new(), log, _callbacks: callbacks, loaded: Arc::clone(loaded) })
    }

    /// The instance's log.
    pub(crate) fn log(&self) -> &LogState {
        &self.log.state
    }

    fn api(&self) -> &Api {
        &self.loaded.api
    }

    /// `fmi2SetDebugLogging(loggingOn, all categories)`.
    pub(crate) fn set_debug_logging(&mut self, on: bool) -> fmi2Status {
        if !self.alive {
            return fmi2Error;
        }
        // SAFETY: comp is a live instance of this library; zero categories
        // with a NULL array is the documented "all categories" form.
        unsafe {
            (self.api().set_debug_logging)(
                self.comp.as_ptr(),
                if on { fmi2True } else { fmi2False },
                0,
                std::ptr::null(),
            )
        }
    }

    /// `fmi2SetupExperiment` (no tolerance; the stop time if given).
    pub(crate) fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> fmi2Status {
        if !self.alive {
            return fmi2Error;
        }
        let (defined, stop) = (if stop.is_some() { fmi2True } else { fmi2False }, stop.unwrap_or(0.0));
        // SAFETY: comp is a live instance; plain value arguments.
        unsafe { (self.api().setup_experiment)(self.comp.as_ptr(), fmi2False, 0.0, start, defined, stop) }
    }

    /// `fmi2EnterInitializationMode`.
    pub(crate) fn enter_initialization_mode(&mut self) -> fmi2Status {
        // SAFETY: comp is a live instance (checked).
        if self.alive { unsafe { (self.api().enter_initialization_mode)(self.comp.as_ptr()) } } else { fmi2Error }
    }

    /// `fmi2ExitInitializationMode`.
    pub(crate) fn exit_initialization_mode(&mut self) -> fmi2Status {
        // SAFETY: comp is a live instance (checked).
        if self.alive { unsafe { (self.api().exit_initialization_mode)(self.comp.as_ptr()) } } else { fmi2Error }
    }

    /// `fmi2Terminate`.
    pub(crate) fn terminate(&mut self) -> fmi2Status {
        // SAFETY: comp is a live instance (checked).
        if self.alive { unsafe { (self.api().terminate)(self.comp.as_ptr()) } } else { fmi2Error }
    }

    /// `fmi2Reset`.
    pub(crate) fn reset(&mut self) -> fmi2Status {
        // SAFETY: comp is a live instance (checked).
        if self.alive { unsafe { (self.api().reset)(self.comp.as_ptr()) } } else { fmi2Error }
    }

    /// `fmi2DoStep(t, h, noSetFMUStatePriorToCurrentPoint = true)`.
    #[inline]
    pub(crate) fn do_step(&mut self, t: f64, h: f64) -> fmi2Status {
        // SAFETY: comp is a live instance (checked); plain value arguments.
        if self.alive { unsafe { (self.api().do_step)(self.comp.as_ptr(), t, h, fmi2True) } } else { fmi2Error }
    }

    /// `fmi2GetReal`; `vrs` and `out` must have the same length.
    #[inline]
    pub(crate) fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> fmi2Status {
        assert_eq!(vrs.len(), out.len(), "fmi2GetReal: value references and values differ in length");
        if !self.alive {
            return fmi2Error;
        }
        // SAFETY: vrs and out are valid for vrs.len() elements (asserted equal).
        unsafe { (self.api().get_real)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) }
    }

    /// `fmi2SetReal`; `vrs` and `values` must have the same length.
    #[inline]
    pub(crate) fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> fmi2Status {
        assert_eq!(vrs.len(), values.len(), "fmi2SetReal: value references and values differ in length");
        if !self.alive {
            return fmi2Error;
        }
        // SAFETY: both slices are valid for vrs.len() elements (asserted equal).
        unsafe { (self.api().set_real)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), values.as_ptr()) }
    }

    /// `fmi2GetInteger`; `vrs` and `out` must have the same length.
    pub(crate) fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> fmi2Status {
        assert_eq!(vrs.len(), out.len(), "fmi2GetInteger: value references and values differ in length");
        if !self.alive {
            return fmi2Error;
        }
        // SAFETY: both slices are valid for vrs.len() elements (asserted equal).
        unsafe { (self.api().get_integer)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) }
    }

    /// `fmi2SetInteger`; `vrs` and `values` must have the same length.
    pub(crate) fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> fmi2Status {
        assert_eq!(vrs.len(), values.len(), "fmi2SetInteger: value references and values differ in length");
        if !self.alive {
            return fmi2Error;
        }
        // SAFETY: both slices are valid for vrs.len() elements (asserted equal).
        unsafe { (self.api().set_integer)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), values.as_ptr()) }
    }

    /// `fmi2GetBoolean`; `vrs` and `out` must have the same length.
    pub(crate) fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> fmi2Status {
        assert_eq!(vrs.len(), out.len(), "fmi2GetBoolean: value references and values differ in length");
        if !self.alive {
            return fmi2Error;
        }
        self.bools.clear();
        self.bools.resize(vrs.len(), fmi2False);
        // SAFETY: vrs and the scratch buffer are valid for vrs.len() elements.
        let s = unsafe {
            (self.loaded.api.get_boolean)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), self.bools.as_mut_ptr())
        };
        for (o, r) in out.iter_mut().zip(&self.bools) {
            *o = *r != fmi2False;
        }
        s
    }

    /// `fmi2SetBoolean`; `vrs` and `values` must have the same length.
    pub(crate) fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> fmi2Status {
        assert_eq!(vrs.len(), values.len(), "fmi2SetBoolean: value references and values differ in length");
        if !self.alive {
            return fmi2Error;
        }
        self.bools.clear();
        self.bools.extend(values.iter().map(|&b| if b { fmi2True } else { fmi2False }));
        // SAFETY: vrs and the scratch buffer are valid for vrs.len() elements.
        unsafe { (self.loaded.api.set_boolean)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), self.bools.as_ptr()) }
    }

    /// `fmi2GetString`, copied out at once (FMU strings are only valid until the next call).
    pub(crate) fn get_string(&mut self, vrs: &[u32]) -> (fmi2Status, Vec<String>) {
        if !self.alive {
            return (fmi2Error, Vec::new());
        }
        let mut raw: Vec<fmi2String> = vec![std::ptr::null(); vrs.len()];
        // SAFETY: vrs and raw are valid for vrs.len() elements.
        let s = unsafe { (self.api().get_string)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), raw.as_mut_ptr()) };
        if s != fmi2OK && s != fmi2Warning {
            return (s, Vec::new());
        }
        let copy = |p: fmi2String| {
            if p.is_null() {
                String::new()
            } else {
                // SAFETY: the FMU returned OK, so each non-null pointer is a
                // NUL-terminated string valid until the next call on it; we
                // copy it before any other call.
                unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
            }
        };
        (s, raw.into_iter().map(copy).collect())
    }

    /// `fmi2SetString`; `vrs` and `values` must have the same length.
    pub(crate) fn set_string(&mut self, vrs: &[u32], values: &[&CStr]) -> fmi2Status {
        assert_eq!(vrs.len(), values.len(), "fmi2SetString: value references and values differ in length");
        if !self.alive {
            return fmi2Error;
        }
        let ptrs: Vec<fmi2String> = values.iter().map(|c| c.as_ptr()).collect();
        // SAFETY: vrs and ptrs are valid for vrs.len() elements; each pointer is
        // a NUL-terminated string alive (borrowed) for the whole call.
        unsafe { (self.api().set_string)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), ptrs.as_ptr()) }
    }

    /// `fmi2FreeInstance`, once; later calls do nothing.
    pub(crate) fn free(&mut self) {
        if self.alive {
            self.alive = false;
            // SAFETY: comp is live and freed exactly once (alive is now false);
            // the callbacks and log environment it may reference are fields
            // of self, dropped only after this; the library is kept by self.loaded.
            unsafe { (self.api().free_instance)(self.comp.as_ptr()) };
        }
    }

    /// After `fmi2Fatal` no function may be called, not even
    /// `fmi2FreeInstance`: the instance is leaked, and with it the library
    /// (unloading code that a live instance may still reference, e.g. through
    /// threads it started, is unsafe); the extracted files are removed all the same.
    pub(crate) fn abandon(&mut self) {
        if self.alive {
            self.alive = false;
            let _ = std::fs::remove_dir_all(self.loaded.dir());
            std::mem::forget(Arc::clone(&self.loaded));
        }
    }
}

impl Drop for RawInstance {
    fn drop(&mut self) {
        self.free();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_c_shim_formats_variadic_messages() {
        // Call the C logger as an FMU would, with printf arguments.
        let env = Box::new(LogEnv { sink: log_sink, state: LogState::new("shim", false) });
        let p = &*env as *const LogEnv as *mut c_void;
        let long = "x".repeat(3000);
        let c_long = std::ffi::CString::new(long.clone()).unwrap();
        // SAFETY: env is a live LogEnv; all strings are NUL-terminated and the
        // varargs match the format (an int, a string, a double).
        unsafe {
            fmi_master_logger(
                p,
                c"inst".as_ptr(),
                fmi2Error,
                c"logStatusError".as_ptr(),
                c"%d items in %s: %.2f".as_ptr(),
                3 as c_int,
                c"box".as_ptr(),
                1.5f64,
            );
            fmi_master_logger(p, c"inst".as_ptr(), fmi2Warning, c"cat".as_ptr(), c"%s".as_ptr(), c_long.as_ptr());
        }
        let lines = env.state.all();
        assert_eq!(lines[0], "fmi2Error [logStatusError] 3 items in box: 1.50");
        assert_eq!(lines[1], format!("fmi2Warning [cat] {long}"));
    }
}
