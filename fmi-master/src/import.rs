//! The importer: opens an FMI 2.0 Co-Simulation `.fmu` and wraps its C API
//! in the safe types [`Fmu`] and [`Instance`].
//!
//! **This is the only module of the master with `unsafe` code.** Everything
//! that crosses into the FMU's shared library happens here; every `unsafe`
//! block says why it is sound.
//!
//! * [`Fmu::open`] extracts the archive safely into its own temporary
//!   directory ([`crate::unzip`]), parses `modelDescription.xml`, requires
//!   `<CoSimulation>`, loads `binaries/linux64/<modelIdentifier>.so` with
//!   `RTLD_NOW | RTLD_LOCAL` (unresolved symbols fail here, not mid-run), and
//!   resolves every FMI 2.0 function the master calls.
//! * [`Fmu::instantiate`] passes the GUID from the XML, the resource location
//!   as a `file:///…/resources` URI and callbacks whose logger is the C shim
//!   `csrc/logger_shim.c` (FMI's logger is variadic; the shim formats with
//!   `vsnprintf` and forwards to [`log_sink`]). Each instance keeps its own
//!   log ring buffer, quoted by every error.
//! * [`Instance`] methods return `Result<_, FmuError>`; `fmi2Discard`,
//!   `fmi2Error`, `fmi2Fatal` and `fmi2Pending` are errors naming the call,
//!   the time and the FMU's recent log lines. Dropping an instance terminates
//!   it if it was initialized and frees it (not after `fmi2Fatal`, when FMI
//!   forbids further calls). The library stays loaded, and the extracted
//!   directory stays on disk, until the last instance of the FMU is gone.
#![allow(unsafe_code)]

use crate::error::{FmuError, LogExcerpt};
use fmi2_abi::fn_types::*;
use fmi2_abi::*;
use model_description::ModelDescription;
use std::collections::VecDeque;
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::path::Path;
use std::ptr::NonNull;
use std::sync::{Arc, Mutex};

/// The platform directory under `binaries/` this build loads.
pub const PLATFORM: &str = "linux64";

/// How many log lines an instance keeps.
const LOG_CAPACITY: usize = 200;
/// How many of them an error quotes.
const LOG_QUOTED: usize = 20;

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
    get_types_platform: fmi2GetTypesPlatformTYPE,
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

/// A loaded library and the directory it was extracted to. Field order is
/// drop order: the library is unloaded before the directory is removed.
struct Loaded {
    api: Api,
    _library: libloading::Library,
    dir: tempfile::TempDir,
}

/// An opened FMU: its description, its extracted files and its loaded binary.
///
/// Cheap to share: instances keep the library alive through an `Arc`.
pub struct Fmu {
    name: String,
    md: ModelDescription,
    loaded: Arc<Loaded>,
}

impl std::fmt::Debug for Fmu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fmu").field("name", &self.name).field("model", &self.md.model_name).finish()
    }
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

/// Read and parse the `modelDescription.xml` of an `.fmu` without extracting
/// or loading anything (for `cosim info`).
pub fn read_model_description(path: &Path) -> Result<ModelDescription, FmuError> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let bytes = crate::unzip::read_entry(path, "modelDescription.xml")?.ok_or_else(|| FmuError::Description {
        fmu: name.clone(),
        message: "no modelDescription.xml in the archive".into(),
    })?;
    let xml = String::from_utf8(bytes).map_err(|_| FmuError::Description {
        fmu: name.clone(),
        message: "modelDescription.xml is not UTF-8".into(),
    })?;
    ModelDescription::from_xml(&xml).map_err(|e| FmuError::Description { fmu: name, message: e.to_string() })
}

fn available_platforms(dir: &Path) -> String {
    let mut v: Vec<String> = std::fs::read_dir(dir.join("binaries"))
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .filter(|e| e.path().is_dir())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    if v.is_empty() { "no binaries at all".into() } else { v.join(", ") }
}

impl Fmu {
    /// Open an `.fmu`: extract, parse, check, load and resolve.
    pub fn open(path: &Path) -> Result<Fmu, FmuError> {
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "?".into());
        if !path.is_file() {
            return Err(FmuError::Io {
                context: "cannot open FMU",
                path: path.to_path_buf(),
                source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
            });
        }
        let dir = tempfile::Builder::new().prefix("fmi-master-").tempdir().map_err(|source| FmuError::Io {
            context: "cannot create a temporary directory for",
            path: path.to_path_buf(),
            source,
        })?;
        crate::unzip::extract(path, dir.path())?;
        let xml_path = dir.path().join("modelDescription.xml");
        let xml = std::fs::read_to_string(&xml_path).map_err(|e| FmuError::Description {
            fmu: name.clone(),
            message: format!("cannot read modelDescription.xml: {e}"),
        })?;
        let md = ModelDescription::from_xml(&xml)
            .map_err(|e| FmuError::Description { fmu: name.clone(), message: e.to_string() })?;
        if !md.fmi_version.starts_with("2.") {
            return Err(FmuError::Description {
                fmu: name,
                message: format!("fmiVersion is \"{}\"; this master imports FMI 2.0", md.fmi_version),
            });
        }
        let Some(id) = md.model_identifier().map(str::to_owned) else {
            return Err(FmuError::NotCoSimulation { fmu: name });
        };
        let so = dir.path().join("binaries").join(PLATFORM).join(format!("{id}.so"));
        if !so.is_file() {
            return Err(FmuError::MissingBinary {
                fmu: name,
                platform: PLATFORM,
                available: available_platforms(dir.path()),
            });
        }
        // SAFETY: loading runs the library's initializers. The file is the
        // FMU's own binary, which the user asked to run; FMI binaries are
        // meant to be loaded into a host like this. RTLD_NOW makes missing
        // symbols fail here rather than abort the process at a later call.
        let library = unsafe {
            libloading::os::unix::Library::open(
                Some(&so),
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
            FmuError::Load { fmu: name.clone(), path: so.clone(), message, hint }
        })?;
        let library = libloading::Library::from(library);
        let api = resolve(&library, &name)?;
        // SAFETY: fmi2GetVersion takes no arguments and returns a pointer to a
        // static NUL-terminated string (FMI 2.0 §2.1.4); checked for NULL.
        let version = unsafe {
            let p = (api.get_version)();
            if p.is_null() { String::from("(null)") } else { CStr::from_ptr(p).to_string_lossy().into_owned() }
        };
        if !version.starts_with("2.") {
            return Err(FmuError::Version { fmu: name, version });
        }
        // SAFETY: as above, a static string; only checked for information.
        let _platform = unsafe {
            let p = (api.get_types_platform)();
            if p.is_null() { String::new() } else { CStr::from_ptr(p).to_string_lossy().into_owned() }
        };
        Ok(Fmu { name, md, loaded: Arc::new(Loaded { api, _library: library, dir }) })
    }

    /// The FMU's file name (used in messages).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The parsed `modelDescription.xml`.
    pub fn model_description(&self) -> &ModelDescription {
        &self.md
    }

    /// The extraction directory (exists as long as the FMU or an instance does).
    pub fn directory(&self) -> &Path {
        self.loaded.dir.path()
    }

    /// The `file:///…/resources` URI passed to `fmi2Instantiate`.
    pub fn resource_uri(&self) -> String {
        file_uri(&self.loaded.dir.path().join("resources"))
    }

    /// Instantiate a co-simulation slave named `instance_name`.
    ///
    /// `logging_on` is passed to `fmi2Instantiate` (FMUs still report
    /// warnings and errors through the logger when it is off, if they
    /// follow the standard's advice). With `echo`, log lines are also
    /// printed to stderr as they arrive.
    pub fn instantiate(&self, instance_name: &str, logging_on: bool, echo: bool) -> Result<Instance, FmuError> {
        let model = self.md.model_identifier().unwrap_or_default().to_string();
        let arg = |what: &str, s: &str| {
            CString::new(s).map_err(|_| FmuError::Argument {
                instance: instance_name.to_string(),
                call: "fmi2Instantiate",
                message: format!("{what} contains a NUL byte"),
            })
        };
        let c_name = arg("the instance name", instance_name)?;
        let c_guid = arg("the GUID", &self.md.guid)?;
        let c_res = arg("the resource location", &self.resource_uri())?;
        let log = Box::new(LogEnv {
            sink: log_sink,
            state: LogState { lines: Mutex::new(VecDeque::new()), echo, instance: instance_name.to_string() },
        });
        let env: *const LogEnv = &*log;
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: Some(fmi_master_logger),
            allocateMemory: Some(fmi_master_calloc),
            freeMemory: Some(fmi_master_free),
            stepFinished: None,
            componentEnvironment: env as *mut c_void,
        });
        let api = &self.loaded.api;
        // SAFETY: all string arguments are valid NUL-terminated C strings that
        // outlive the call (FMI requires the FMU to copy them). `callbacks`
        // is boxed and kept in the returned Instance until after
        // fmi2FreeInstance, since FMUs may keep the pointer (pythonfmu does);
        // its environment points to the boxed LogEnv kept alongside.
        let comp = unsafe {
            (api.instantiate)(
                c_name.as_ptr(),
                fmi2CoSimulation,
                c_guid.as_ptr(),
                c_res.as_ptr(),
                &*callbacks,
                fmi2False,
                if logging_on { fmi2True } else { fmi2False },
            )
        };
        let Some(comp) = NonNull::new(comp) else {
            return Err(FmuError::Instantiate {
                instance: instance_name.to_string(),
                model,
                log: log.state.excerpt(LOG_QUOTED),
            });
        };
        Ok(Instance {
            comp,
            phase: Phase::Instantiated,
            time: 0.0,
            name: instance_name.to_string(),
            model,
            log,
            _callbacks: callbacks,
            loaded: Arc::clone(&self.loaded),
        })
    }
}

/// `file:///` URI of an absolute path, percent-encoding what RFC 3986 requires.
pub fn file_uri(path: &Path) -> String {
    let abs = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().map(|d| d.join(path)).unwrap_or_else(|_| path.to_path_buf())
    };
    let mut s = String::from("file://");
    for b in abs.to_string_lossy().bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'.' | b'_' | b'~' => s.push(b as char),
            _ => s.push_str(&format!("%{b:02X}")),
        }
    }
    s
}

fn resolve(lib: &libloading::Library, fmu: &str) -> Result<Api, FmuError> {
    let mut missing = Vec::new();
    macro_rules! sym {
        ($name:literal, $ty:ty) => {{
            // SAFETY: the symbol, if present, is the FMI 2.0 function of that
            // name, whose C signature is `$ty` (fmi2FunctionTypes.h, mirrored
            // in fmi2-abi). The copied pointer is only used while `lib` is
            // loaded: Api and Library live and die together in `Loaded`.
            match unsafe { lib.get::<$ty>(concat!($name, "\0").as_bytes()) } {
                Ok(s) => Some(*s),
                Err(_) => {
                    missing.push($name);
                    None
                }
            }
        }};
    }
    let get_version = sym!("fmi2GetVersion", fmi2GetVersionTYPE);
    let get_types_platform = sym!("fmi2GetTypesPlatform", fmi2GetTypesPlatformTYPE);
    let set_debug_logging = sym!("fmi2SetDebugLogging", fmi2SetDebugLoggingTYPE);
    let instantiate = sym!("fmi2Instantiate", fmi2InstantiateTYPE);
    let free_instance = sym!("fmi2FreeInstance", fmi2FreeInstanceTYPE);
    let setup_experiment = sym!("fmi2SetupExperiment", fmi2SetupExperimentTYPE);
    let enter_initialization_mode = sym!("fmi2EnterInitializationMode", fmi2EnterInitializationModeTYPE);
    let exit_initialization_mode = sym!("fmi2ExitInitializationMode", fmi2ExitInitializationModeTYPE);
    let terminate = sym!("fmi2Terminate", fmi2TerminateTYPE);
    let reset = sym!("fmi2Reset", fmi2ResetTYPE);
    let get_real = sym!("fmi2GetReal", fmi2GetRealTYPE);
    let get_integer = sym!("fmi2GetInteger", fmi2GetIntegerTYPE);
    let get_boolean = sym!("fmi2GetBoolean", fmi2GetBooleanTYPE);
    let get_string = sym!("fmi2GetString", fmi2GetStringTYPE);
    let set_real = sym!("fmi2SetReal", fmi2SetRealTYPE);
    let set_integer = sym!("fmi2SetInteger", fmi2SetIntegerTYPE);
    let set_boolean = sym!("fmi2SetBoolean", fmi2SetBooleanTYPE);
    let set_string = sym!("fmi2SetString", fmi2SetStringTYPE);
    let do_step = sym!("fmi2DoStep", fmi2DoStepTYPE);
    // The remaining co-simulation functions must exist too (FMI 2.0 §2.1.1:
    // every function is exported, even if a capability flag says it is not
    // supported); the master does not call them.
    for name in [
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
    ] {
        let mut bytes = name.as_bytes().to_vec();
        bytes.push(0);
        // SAFETY: only the symbol's presence is checked; the pointer is
        // never called or kept (`*const c_void` is not a function type).
        if unsafe { lib.get::<*const c_void>(&bytes) }.is_err() {
            missing.push(name);
        }
    }
    if !missing.is_empty() {
        return Err(FmuError::MissingSymbols { fmu: fmu.to_string(), missing: missing.join(", ") });
    }
    // All required symbols are present here (a None would have been reported as missing).
    Ok(Api {
        get_version: get_version.expect("checked"),
        get_types_platform: get_types_platform.expect("checked"),
        set_debug_logging: set_debug_logging.expect("checked"),
        instantiate: instantiate.expect("checked"),
        free_instance: free_instance.expect("checked"),
        setup_experiment: setup_experiment.expect("checked"),
        enter_initialization_mode: enter_initialization_mode.expect("checked"),
        exit_initialization_mode: exit_initialization_mode.expect("checked"),
        terminate: terminate.expect("checked"),
        reset: reset.expect("checked"),
        get_real: get_real.expect("checked"),
        get_integer: get_integer.expect("checked"),
        get_boolean: get_boolean.expect("checked"),
        get_string: get_string.expect("checked"),
        set_real: set_real.expect("checked"),
        set_integer: set_integer.expect("checked"),
        set_boolean: set_boolean.expect("checked"),
        set_string: set_string.expect("checked"),
        do_step: do_step.expect("checked"),
    })
}

// ---------------------------------------------------------------------------
// Logging

/// Signature of the Rust function the C shim forwards formatted messages to.
type SinkFn = unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

/// The component environment handed to the FMU. `#[repr(C)]` with the sink
/// first: the C shim reads `sink` through `struct fmi_master_log_env`.
#[repr(C)]
struct LogEnv {
    sink: SinkFn,
    state: LogState,
}

struct LogState {
    lines: Mutex<VecDeque<String>>,
    echo: bool,
    instance: String,
}

impl LogState {
    fn push(&self, line: String) {
        if self.echo {
            eprintln!("[{}] {line}", self.instance);
        }
        let mut q = self.lines.lock().unwrap_or_else(|p| p.into_inner());
        if q.len() == LOG_CAPACITY {
            q.pop_front();
        }
        q.push_back(line);
    }

    fn excerpt(&self, n: usize) -> LogExcerpt {
        let q = self.lines.lock().unwrap_or_else(|p| p.into_inner());
        LogExcerpt(q.iter().skip(q.len().saturating_sub(n)).cloned().collect())
    }

    fn all(&self) -> Vec<String> {
        self.lines.lock().unwrap_or_else(|p| p.into_inner()).iter().cloned().collect()
    }
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

// ---------------------------------------------------------------------------
// Instances

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    Instantiated,
    Initialization,
    Stepping,
    Terminated,
    /// After `fmi2Error`: only get, reset and free are allowed.
    Error,
    /// After `fmi2Fatal`: no further call is allowed, not even free.
    Fatal,
    /// Freed (or leaked after `fmi2Fatal`): nothing more.
    Freed,
}

/// A co-simulation slave. All methods check the returned status; the
/// instance is terminated (if initialized) and freed on drop.
pub struct Instance {
    comp: NonNull<c_void>,
    phase: Phase,
    time: f64,
    name: String,
    model: String,
    // Both must outlive fmi2FreeInstance (see Drop).
    log: Box<LogEnv>,
    _callbacks: Box<fmi2CallbackFunctions>,
    loaded: Arc<Loaded>,
}

impl std::fmt::Debug for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Instance").field("name", &self.name).field("model", &self.model).finish()
    }
}

impl Instance {
    /// The instance name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The last time reached (start time, then the end of the last step).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// All log lines kept so far (the last 200).
    pub fn log_lines(&self) -> Vec<String> {
        self.log.state.all()
    }

    fn api(&self) -> &Api {
        &self.loaded.api
    }

    fn check(&mut self, call: &'static str, status: fmi2Status, time: f64) -> Result<(), FmuError> {
        match status {
            s if s == fmi2OK || s == fmi2Warning => Ok(()),
            s => {
                self.phase = if s == fmi2Fatal {
                    Phase::Fatal
                } else if s == fmi2Error {
                    Phase::Error
                } else {
                    // Discard / Pending / invalid: the FMU cannot go on as asked;
                    // it may still be terminated and freed.
                    self.phase
                };
                Err(FmuError::Call {
                    instance: self.name.clone(),
                    model: self.model.clone(),
                    call,
                    status: status_name(s),
                    time,
                    log: self.log.state.excerpt(LOG_QUOTED),
                })
            }
        }
    }

    fn require(&self, call: &'static str, ok: &[Phase]) -> Result<(), FmuError> {
        if ok.contains(&self.phase) {
            return Ok(());
        }
        let state = match self.phase {
            Phase::Instantiated => "before initialization",
            Phase::Initialization => "in initialization mode",
            Phase::Stepping => "after initialization",
            Phase::Terminated => "after fmi2Terminate",
            Phase::Error => "after the FMU reported fmi2Error",
            Phase::Fatal => "after the FMU reported fmi2Fatal",
            Phase::Freed => "after the instance was freed",
        };
        Err(FmuError::State { instance: self.name.clone(), call, state })
    }

    fn lengths(&self, call: &'static str, a: usize, b: usize) -> Result<(), FmuError> {
        if a == b {
            Ok(())
        } else {
            Err(FmuError::Argument {
                instance: self.name.clone(),
                call,
                message: format!("{a} value references but {b} values"),
            })
        }
    }

    /// `fmi2SetDebugLogging(loggingOn, all categories)`.
    pub fn set_debug_logging(&mut self, on: bool) -> Result<(), FmuError> {
        self.require("fmi2SetDebugLogging", &[Phase::Instantiated, Phase::Initialization, Phase::Stepping])?;
        // SAFETY: comp is a live instance of this library; zero categories
        // with a NULL array is the documented "all categories" form.
        let s = unsafe {
            (self.api().set_debug_logging)(
                self.comp.as_ptr(),
                if on { fmi2True } else { fmi2False },
                0,
                std::ptr::null(),
            )
        };
        self.check("fmi2SetDebugLogging", s, self.time)
    }

    /// `fmi2SetupExperiment` (no tolerance; stop time if given).
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), FmuError> {
        self.require("fmi2SetupExperiment", &[Phase::Instantiated])?;
        // SAFETY: comp is a live instance; plain value arguments.
        let s = unsafe {
            (self.api().setup_experiment)(
                self.comp.as_ptr(),
                fmi2False,
                0.0,
                start,
                if stop.is_some() { fmi2True } else { fmi2False },
                stop.unwrap_or(0.0),
            )
        };
        self.time = start;
        self.check("fmi2SetupExperiment", s, start)
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization_mode(&mut self) -> Result<(), FmuError> {
        self.require("fmi2EnterInitializationMode", &[Phase::Instantiated])?;
        // SAFETY: comp is a live instance.
        let s = unsafe { (self.api().enter_initialization_mode)(self.comp.as_ptr()) };
        self.phase = Phase::Initialization;
        self.check("fmi2EnterInitializationMode", s, self.time)
    }

    /// `fmi2ExitInitializationMode`.
    pub fn exit_initialization_mode(&mut self) -> Result<(), FmuError> {
        self.require("fmi2ExitInitializationMode", &[Phase::Initialization])?;
        // SAFETY: comp is a live instance.
        let s = unsafe { (self.api().exit_initialization_mode)(self.comp.as_ptr()) };
        self.phase = Phase::Stepping;
        self.check("fmi2ExitInitializationMode", s, self.time)
    }

    /// `fmi2DoStep(t, h, noSetFMUStatePriorToCurrentPoint = true)`.
    #[inline]
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), FmuError> {
        if self.phase != Phase::Stepping {
            self.require("fmi2DoStep", &[Phase::Stepping])?;
        }
        // SAFETY: comp is a live instance; plain value arguments.
        let s = unsafe { (self.api().do_step)(self.comp.as_ptr(), t, h, fmi2True) };
        if s == fmi2OK {
            self.time = t + h;
            return Ok(());
        }
        self.check("fmi2DoStep", s, t)?;
        self.time = t + h;
        Ok(())
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> Result<(), FmuError> {
        self.require("fmi2Terminate", &[Phase::Initialization, Phase::Stepping])?;
        // SAFETY: comp is a live instance.
        let s = unsafe { (self.api().terminate)(self.comp.as_ptr()) };
        self.phase = Phase::Terminated;
        self.check("fmi2Terminate", s, self.time)
    }

    /// `fmi2Reset`: back to the instantiated state.
    pub fn reset(&mut self) -> Result<(), FmuError> {
        self.require(
            "fmi2Reset",
            &[Phase::Instantiated, Phase::Initialization, Phase::Stepping, Phase::Terminated, Phase::Error],
        )?;
        // SAFETY: comp is a live instance.
        let s = unsafe { (self.api().reset)(self.comp.as_ptr()) };
        self.phase = Phase::Instantiated;
        self.check("fmi2Reset", s, self.time)
    }

    const GET_OK: [Phase; 5] =
        [Phase::Instantiated, Phase::Initialization, Phase::Stepping, Phase::Terminated, Phase::Error];
    const SET_OK: [Phase; 3] = [Phase::Instantiated, Phase::Initialization, Phase::Stepping];

    /// `fmi2GetReal`.
    #[inline]
    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), FmuError> {
        self.lengths("fmi2GetReal", vrs.len(), out.len())?;
        self.require("fmi2GetReal", &Self::GET_OK)?;
        // SAFETY: vrs and out are valid for vrs.len() elements (checked equal).
        let s = unsafe { (self.api().get_real)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
        if s == fmi2OK { Ok(()) } else { self.check("fmi2GetReal", s, self.time) }
    }

    /// `fmi2SetReal`.
    #[inline]
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), FmuError> {
        self.lengths("fmi2SetReal", vrs.len(), values.len())?;
        self.require("fmi2SetReal", &Self::SET_OK)?;
        // SAFETY: both slices are valid for vrs.len() elements (checked equal).
        let s = unsafe { (self.api().set_real)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), values.as_ptr()) };
        if s == fmi2OK { Ok(()) } else { self.check("fmi2SetReal", s, self.time) }
    }

    /// `fmi2GetInteger` (also for enumerations).
    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> Result<(), FmuError> {
        self.lengths("fmi2GetInteger", vrs.len(), out.len())?;
        self.require("fmi2GetInteger", &Self::GET_OK)?;
        // SAFETY: both slices are valid for vrs.len() elements (checked equal).
        let s = unsafe { (self.api().get_integer)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
        self.check("fmi2GetInteger", s, self.time)
    }

    /// `fmi2SetInteger` (also for enumerations).
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<(), FmuError> {
        self.lengths("fmi2SetInteger", vrs.len(), values.len())?;
        self.require("fmi2SetInteger", &Self::SET_OK)?;
        // SAFETY: both slices are valid for vrs.len() elements (checked equal).
        let s = unsafe { (self.api().set_integer)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), values.as_ptr()) };
        self.check("fmi2SetInteger", s, self.time)
    }

    /// `fmi2GetBoolean`.
    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> Result<(), FmuError> {
        self.lengths("fmi2GetBoolean", vrs.len(), out.len())?;
        self.require("fmi2GetBoolean", &Self::GET_OK)?;
        let mut raw = vec![fmi2False; vrs.len()];
        // SAFETY: vrs and raw are valid for vrs.len() elements.
        let s = unsafe { (self.api().get_boolean)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), raw.as_mut_ptr()) };
        self.check("fmi2GetBoolean", s, self.time)?;
        for (o, r) in out.iter_mut().zip(raw) {
            *o = r != fmi2False;
        }
        Ok(())
    }

    /// `fmi2SetBoolean`.
    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<(), FmuError> {
        self.lengths("fmi2SetBoolean", vrs.len(), values.len())?;
        self.require("fmi2SetBoolean", &Self::SET_OK)?;
        let raw: Vec<fmi2Boolean> = values.iter().map(|&b| if b { fmi2True } else { fmi2False }).collect();
        // SAFETY: vrs and raw are valid for vrs.len() elements.
        let s = unsafe { (self.api().set_boolean)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), raw.as_ptr()) };
        self.check("fmi2SetBoolean", s, self.time)
    }

    /// `fmi2GetString` (copied out immediately: FMU strings are only valid until the next call).
    pub fn get_string(&mut self, vrs: &[u32]) -> Result<Vec<String>, FmuError> {
        self.require("fmi2GetString", &Self::GET_OK)?;
        let mut raw: Vec<fmi2String> = vec![std::ptr::null(); vrs.len()];
        // SAFETY: vrs and raw are valid for vrs.len() elements.
        let s = unsafe { (self.api().get_string)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), raw.as_mut_ptr()) };
        self.check("fmi2GetString", s, self.time)?;
        Ok(raw
            .into_iter()
            .map(|p| {
                if p.is_null() {
                    String::new()
                } else {
                    // SAFETY: the FMU returned OK, so each non-null pointer is a
                    // NUL-terminated string valid until the next call on it; we
                    // copy it before any other call.
                    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
                }
            })
            .collect())
    }

    /// `fmi2SetString`.
    pub fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> Result<(), FmuError> {
        self.lengths("fmi2SetString", vrs.len(), values.len())?;
        self.require("fmi2SetString", &Self::SET_OK)?;
        let owned: Vec<CString> =
            values.iter().map(|v| CString::new(*v)).collect::<Result<_, _>>().map_err(|_| FmuError::Argument {
                instance: self.name.clone(),
                call: "fmi2SetString",
                message: "a string value contains a NUL byte".into(),
            })?;
        let ptrs: Vec<fmi2String> = owned.iter().map(|c| c.as_ptr()).collect();
        // SAFETY: vrs and ptrs are valid for vrs.len() elements; each pointer is
        // a NUL-terminated string alive (in `owned`) for the whole call.
        let s = unsafe { (self.api().set_string)(self.comp.as_ptr(), vrs.as_ptr(), vrs.len(), ptrs.as_ptr()) };
        self.check("fmi2SetString", s, self.time)
    }
}

impl Instance {
    /// Terminate (if initialized) and free the instance now; later calls
    /// fail with a state error and dropping does nothing more. Systems close
    /// all their instances before any library is unloaded, because some
    /// FMUs share process-wide state between copies of their library
    /// (pythonfmu's embedded interpreter is finalized by the copy that
    /// started it).
    pub fn close(&mut self) {
        match self.phase {
            Phase::Freed => return,
            Phase::Fatal => {
                // FMI 2.0: after fmi2Fatal no function may be called, not even
                // fmi2FreeInstance. The instance is leaked, and with it the
                // library (unloading code that a live instance may still
                // reference, e.g. through threads it started, is unsafe); the
                // extracted files are removed all the same.
                let _ = std::fs::remove_dir_all(self.loaded.dir.path());
                std::mem::forget(Arc::clone(&self.loaded));
                self.phase = Phase::Freed;
                return;
            }
            Phase::Initialization | Phase::Stepping => {
                // SAFETY: comp is a live instance in a state that allows
                // fmi2Terminate; the status is irrelevant on this path.
                let _ = unsafe { (self.api().terminate)(self.comp.as_ptr()) };
            }
            Phase::Instantiated | Phase::Terminated | Phase::Error => {}
        }
        // SAFETY: comp is live and freed exactly once (phase becomes Freed);
        // the callbacks and log environment it may reference are fields of
        // self, dropped only after this; the library is kept by self.loaded.
        unsafe { (self.api().free_instance)(self.comp.as_ptr()) };
        self.phase = Phase::Freed;
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        self.close();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_uris_are_percent_encoded() {
        assert_eq!(file_uri(Path::new("/tmp/a b/résources")), "file:///tmp/a%20b/r%C3%A9sources");
        assert_eq!(file_uri(Path::new("/x/y_z-1.0~")), "file:///x/y_z-1.0~");
    }

    #[test]
    fn log_ring_buffer_keeps_the_last_lines() {
        let s = LogState { lines: Mutex::new(VecDeque::new()), echo: false, instance: "i".into() };
        for i in 0..(LOG_CAPACITY + 5) {
            s.push(format!("line {i}"));
        }
        let all = s.all();
        assert_eq!(all.len(), LOG_CAPACITY);
        assert_eq!(all[0], "line 5");
        let ex = s.excerpt(3);
        assert_eq!(
            ex.0,
            vec![
                format!("line {}", LOG_CAPACITY + 2),
                format!("line {}", LOG_CAPACITY + 3),
                format!("line {}", LOG_CAPACITY + 4)
            ]
        );
    }

    #[test]
    fn the_c_shim_formats_variadic_messages() {
        // Call the C logger as an FMU would, with printf arguments.
        let env = Box::new(LogEnv {
            sink: log_sink,
            state: LogState { lines: Mutex::new(VecDeque::new()), echo: false, instance: "shim".into() },
        });
        let p = &*env as *const LogEnv as *mut c_void;
        let long = "x".repeat(3000);
        let c_long = CString::new(long.clone()).unwrap();
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
