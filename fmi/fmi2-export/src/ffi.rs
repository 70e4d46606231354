//! The C boundary: every `fmi2*` entry point, generic over the model.
//!
//! This is the only module of the layer with `unsafe` code. Every function has
//! the same shape: null check → pointer/length checks → panic boundary →
//! state check → safe body in [`crate::instance`] → status. A panic becomes
//! `fmi2Fatal` (null from `fmi2Instantiate`) and a message through the host's
//! logger; it never unwinds into the host.
//!
//! The `export_fmi2!` macro (see the crate docs) defines the `#[no_mangle]`
//! symbols in the model's cdylib, each forwarding to the function of the same
//! name here.
//!
//! Ownership: `fmi2Instantiate` returns `Box::into_raw` of a [`Component`];
//! `fmi2FreeInstance` takes it back (null tolerated). FMU states are boxed
//! [`Snapshot`]s owned by the instance that made them (`fmi2GetFMUstate`,
//! `fmi2DeSerializeFMUstate`): the component keeps the addresses of its live states, a state
//! handle is used only if it is one of them (it is never read otherwise, so a junk pointer, a
//! freed state, a state of another instance or of another FMU is `fmi2Error` without touching
//! its memory), `fmi2FreeFMUstate` frees one and `fmi2FreeInstance` frees those left.
//! Components and states start with a magic number derived from the model (the address of its
//! description, unique per model in a process) and the handle's kind, checked on every call: a component of another FMU or a state passed as a component is `fmi2Error`,
//! not undefined behaviour (a pointer to unmapped memory cannot be detected). Strings returned by
//! `fmi2GetString` live in the component until the next `fmi2GetString` call.

#![allow(clippy::missing_safety_doc, missing_docs)]

use crate::instance::{CallError, CallResult, Instance, LogLevel, LogSink, Snapshot, State, mask, resource_path};
use crate::model::{Environment, Fmi2Model};
use fmi2_abi::*;
use model_description::{ScalarType, Value};
use std::ffi::{CStr, CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::ptr;

/// The object behind an `fmi2Component`.
#[repr(C)]
pub struct Component<M: Fmi2Model> {
    /// [`component_magic`] of `M` while alive (first field: read before anything else).
    magic: u64,
    inst: Instance<M>,
    /// Addresses of the live [`BoxedState`]s this instance made (see the module docs).
    states: Vec<usize>,
    strings: Vec<CString>,
    scratch: Vec<Value>,
}

/// The object behind an `fmi2FMUstate`.
#[repr(C)]
struct BoxedState<M: Fmi2Model> {
    /// [`state_magic`] of `M` (first field).
    magic: u64,
    snap: Snapshot<M>,
}

/// The magic number of a `kind` of handle of `M`: the kind's hash with the address of `M`'s
/// model description, which is unique to each model (each FMU binary, each model type) in a
/// process. Computed on every call, so it must be cheap: one load and two operations (the hash
/// of the GUID it replaced cost about 80 ns per call).
fn magic_of<M: Fmi2Model>(kind: u64) -> u64 {
    kind ^ (std::ptr::from_ref(M::description()) as usize as u64).rotate_left(17)
}

/// Kind hashes of the two handles (FNV-1a of a fixed text, at compile time).
const COMPONENT_KIND: u64 = fnv1a64_const(b"fmi2-export component ");
const STATE_KIND: u64 = fnv1a64_const(b"fmi2-export state ");

/// [`crate::model::fnv1a64`] at compile time.
const fn fnv1a64_const(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut i = 0;
    while i < bytes.len() {
        h = (h ^ bytes[i] as u64).wrapping_mul(0x0100_0000_01b3);
        i += 1;
    }
    h
}

/// Magic number of a live component of `M`.
fn component_magic<M: Fmi2Model>() -> u64 {
    magic_of::<M>(COMPONENT_KIND)
}

/// Magic number of an FMU state of `M`.
fn state_magic<M: Fmi2Model>() -> u64 {
    magic_of::<M>(STATE_KIND)
}

/// A new boxed FMU state, owned by (registered in) `owner`.
fn new_state<M: Fmi2Model>(owner: &mut Vec<usize>, snap: Snapshot<M>) -> fmi2FMUstate {
    let s = Box::into_raw(Box::new(BoxedState { magic: state_magic::<M>(), snap }));
    owner.push(s as usize);
    s as fmi2FMUstate
}

/// The snapshot behind a state handle of this instance (`owned`: its live states).
///
/// # Safety
/// Every address in `owned` is a live `BoxedState<M>` (the component's registry); the returned
/// reference must not outlive it.
unsafe fn state_ref<'a, M: Fmi2Model>(owned: &[usize], call: &str, s: fmi2FMUstate) -> CallResult<&'a mut Snapshot<M>> {
    if s.is_null() {
        return Err(CallError::Error(format!("{call}: FMUstate is NULL")));
    }
    if !owned.contains(&(s as usize)) {
        return Err(CallError::Error(format!(
            "{call}: FMUstate {s:p} is not a live state of this instance of {} (made by fmi2GetFMUstate or \
             fmi2DeSerializeFMUstate on it and not freed): a freed state, a state of another instance or FMU, \
             or not a state",
            M::description().model_name
        )));
    }
    // SAFETY: registered states are live `BoxedState<M>`s; the magic number is a second check.
    if unsafe { (s as *const u64).read_unaligned() } != state_magic::<M>() {
        return Err(CallError::Error(format!(
            "{call}: FMUstate {s:p} is not a state of this FMU ({}): wrong magic number",
            M::description().model_name
        )));
    }
    // SAFETY: the magic number says this is a live `BoxedState<M>`.
    Ok(unsafe { &mut (*(s as *mut BoxedState<M>)).snap })
}

/// Sends messages to the host's `fmi2CallbackLogger` with a fixed `"%s"` format.
struct HostSink {
    logger: fmi2CallbackLogger,
    env: fmi2ComponentEnvironment,
    name: CString,
}

// SAFETY: the environment pointer is the host's and only passed back to the
// host's logger; FMI allows an instance to be used from any thread, one at a time.
unsafe impl Send for HostSink {}

fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', "")).unwrap_or_default()
}

impl LogSink for HostSink {
    fn emit(&mut self, level: LogLevel, category: &str, message: &str) {
        let Some(logger) = self.logger else { return };
        let status = match level {
            LogLevel::Info => fmi2OK,
            LogLevel::Warning => fmi2Warning,
            LogLevel::Discard => fmi2Discard,
            LogLevel::Error => fmi2Error,
            LogLevel::Fatal => fmi2Fatal,
        };
        let category = to_cstring(category);
        let message = to_cstring(message);
        // SAFETY: the host gave us this logger; all strings are valid, NUL-terminated
        // and outlive the call; the format is the constant "%s" with one string argument.
        unsafe { logger(self.env, self.name.as_ptr(), status, category.as_ptr(), c"%s".as_ptr(), message.as_ptr()) };
    }
}

fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".into()
    }
}

/// Borrow a C string; null is `None`.
///
/// # Safety
/// `s` is null or a valid NUL-terminated string that outlives `'a`.
unsafe fn opt_str<'a>(s: *const c_char) -> Option<&'a str> {
    if s.is_null() {
        None
    } else {
        // SAFETY: non-null and NUL-terminated by the caller's contract.
        unsafe { CStr::from_ptr(s) }.to_str().ok()
    }
}

/// `(ptr, n)` as a slice: `(null, 0)` is empty, `(null, n > 0)` an error.
///
/// # Safety
/// A non-null `p` points to `n` valid `T`s for `'a`.
unsafe fn slice<'a, T>(call: &str, what: &str, p: *const T, n: usize) -> CallResult<&'a [T]> {
    if n == 0 {
        Ok(&[])
    } else if p.is_null() {
        Err(CallError::Error(format!("{call}: {what} is NULL but its length is {n}")))
    } else {
        // SAFETY: non-null, and the caller guarantees n elements.
        Ok(unsafe { std::slice::from_raw_parts(p, n) })
    }
}

/// Mutable version of [`slice`].
///
/// # Safety
/// A non-null `p` points to `n` writable `T`s for `'a`, not aliased.
unsafe fn slice_mut<'a, T>(call: &str, what: &str, p: *mut T, n: usize) -> CallResult<&'a mut [T]> {
    if n == 0 {
        Ok(&mut [])
    } else if p.is_null() {
        Err(CallError::Error(format!("{call}: {what} is NULL but its length is {n}")))
    } else {
        // SAFETY: non-null, and the caller guarantees n writable elements.
        Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
    }
}

/// Run `body` on the instance behind `c` if `call` is allowed in its state,
/// inside the panic boundary, and map the outcome to an `fmi2Status`.
///
/// # Safety
/// `c` is null or a pointer returned by [`instantiate`] for the same `M` and not yet freed.
unsafe fn with<M: Fmi2Model>(
    c: fmi2Component,
    call: &str,
    allowed: u32,
    body: impl FnOnce(&mut Component<M>) -> CallResult<fmi2Status>,
) -> fmi2Status {
    if c.is_null() {
        return fmi2Error;
    }
    // SAFETY: by contract `c` points to at least 8 readable bytes; a foreign or freed
    // component is refused (there is no logger to tell: the host's is in the component).
    if unsafe { (c as *const u64).read_unaligned() } != component_magic::<M>() {
        return fmi2Error;
    }
    // SAFETY: the magic number says `c` is a live component of `M`, used by one thread at a time.
    let comp = unsafe { &mut *(c as *mut Component<M>) };
    if comp.inst.state == State::Fatal {
        return fmi2Fatal;
    }
    let result = catch_unwind(AssertUnwindSafe(|| {
        comp.inst.check_state(call, allowed)?;
        body(comp)
    }));
    match result {
        Ok(Ok(status)) => status,
        Ok(Err(CallError::Discard(m))) => {
            comp.inst.log(LogLevel::Discard, &m);
            fmi2Discard
        }
        Ok(Err(CallError::Error(m))) => {
            comp.inst.log(LogLevel::Error, &m);
            comp.inst.enter_error(&m);
            fmi2Error
        }
        Err(p) => {
            // A panic may have left the instance inconsistent: only free is allowed now.
            let m = format!("{call}: internal error (panic): {}", panic_message(p.as_ref()));
            let _ = catch_unwind(AssertUnwindSafe(|| comp.inst.log(LogLevel::Fatal, &m)));
            comp.inst.state = State::Fatal;
            fmi2Fatal
        }
    }
}

pub fn get_types_platform() -> *const c_char {
    c"default".as_ptr()
}

pub fn get_version() -> *const c_char {
    c"2.0".as_ptr()
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn instantiate<M: Fmi2Model>(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    guid: fmi2String,
    resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    // FMI 2.0: `functions` is a required argument. Without it there is no logger to say why, so
    // the refusal is the NULL result alone.
    if functions.is_null() {
        return ptr::null_mut();
    }
    let r = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: `functions` is non-null and points to the host's callback struct.
        let cb = Some(unsafe { *functions });
        // SAFETY: the host passes NUL-terminated strings or null.
        let name = unsafe { opt_str(instance_name) };
        let mut sink = HostSink {
            logger: cb.and_then(|c| c.logger),
            env: cb.map_or(ptr::null_mut(), |c| c.componentEnvironment),
            name: to_cstring(name.unwrap_or("")),
        };
        let mut fail = |m: String| {
            sink.emit(LogLevel::Error, "logStatusError", &format!("fmi2Instantiate: {m}"));
            ptr::null_mut::<std::ffi::c_void>()
        };
        let Some(name) = name else {
            return fail("instanceName is NULL or not UTF-8".into());
        };
        if fmu_type != fmi2CoSimulation {
            return fail(format!("fmuType {fmu_type} is not supported: this FMU only implements Co-Simulation"));
        }
        let expected = &M::description().guid;
        // SAFETY: as above.
        match unsafe { opt_str(guid) } {
            Some(g) if g == expected => {}
            Some(g) => return fail(format!("Wrong GUID {g}; expected {expected}")),
            None => return fail("fmuGUID is NULL".into()),
        }
        // SAFETY: as above.
        let resources = unsafe { opt_str(resource_location) }.and_then(resource_path);
        let env = Environment { instance_name: name.to_string(), resources };
        let inst = Instance::<M>::new(env, logging_on != fmi2False, Box::new(sink));
        let comp = Box::new(Component {
            magic: component_magic::<M>(),
            inst,
            states: Vec::new(),
            strings: Vec::new(),
            scratch: Vec::new(),
        });
        Box::into_raw(comp) as fmi2Component
    }));
    r.unwrap_or(ptr::null_mut())
}

/// # Safety
/// `c` is null or a live component of model `M`; it is invalid afterwards.
pub unsafe fn free_instance<M: Fmi2Model>(c: fmi2Component) {
    // SAFETY: a non-null `c` points to at least 8 readable bytes; only a live component of `M`
    // (right magic number) is freed, anything else is ignored.
    if c.is_null() || unsafe { (c as *const u64).read_unaligned() } != component_magic::<M>() {
        return;
    }
    // SAFETY: `c` came from `Box::into_raw` in `instantiate::<M>`.
    let mut comp = unsafe { Box::from_raw(c as *mut Component<M>) };
    comp.magic = 0;
    for s in std::mem::take(&mut comp.states) {
        // SAFETY: registered states came from `Box::into_raw` in `new_state` and are freed once.
        let mut b = unsafe { Box::from_raw(s as *mut BoxedState<M>) };
        b.magic = 0;
        let _ = catch_unwind(AssertUnwindSafe(move || drop(b)));
    }
    let _ = catch_unwind(AssertUnwindSafe(move || drop(comp)));
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn set_debug_logging<M: Fmi2Model>(
    c: fmi2Component,
    on: fmi2Boolean,
    n: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    const CALL: &str = "fmi2SetDebugLogging";
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, CALL, mask::ANY_BUT_FATAL, |comp| {
            let ptrs = slice(CALL, "categories", categories, n)?;
            let mut names = Vec::with_capacity(n);
            for &p in ptrs {
                names.push(opt_str(p).ok_or_else(|| CallError::Error(format!("{CALL}: a category is NULL")))?);
            }
            comp.inst.set_debug_logging(on != fmi2False, &names)?;
            Ok(fmi2OK)
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn setup_experiment<M: Fmi2Model>(
    c: fmi2Component,
    tolerance_defined: fmi2Boolean,
    tolerance: fmi2Real,
    start: fmi2Real,
    stop_defined: fmi2Boolean,
    stop: fmi2Real,
) -> fmi2Status {
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, "fmi2SetupExperiment", mask::SETUP, |comp| {
            // the models step on fixed grids and use no tolerance, but a defined one must be a tolerance
            if tolerance_defined != fmi2False && !(tolerance.is_finite() && tolerance > 0.0) {
                return Err(CallError::Error(format!(
                    "fmi2SetupExperiment: tolerance {tolerance} is defined but not a finite positive number"
                )));
            }
            comp.inst.setup_experiment(start, (stop_defined != fmi2False).then_some(stop))?;
            Ok(fmi2OK)
        })
    }
}

macro_rules! simple_call {
    ($(#[$doc:meta])* $fn:ident, $name:literal, $mask:expr, $method:ident) => {
        $(#[$doc])*
        /// # Safety
        /// `c` is null or a live component of model `M`.
        pub unsafe fn $fn<M: Fmi2Model>(c: fmi2Component) -> fmi2Status {
            // SAFETY: forwarded contract.
            unsafe {
                with::<M>(c, $name, $mask, |comp| {
                    comp.inst.$method()?;
                    Ok(fmi2OK)
                })
            }
        }
    };
}

simple_call!(enter_initialization_mode, "fmi2EnterInitializationMode", mask::SETUP, enter_initialization);
simple_call!(exit_initialization_mode, "fmi2ExitInitializationMode", mask::EXIT_INIT, exit_initialization);
simple_call!(terminate, "fmi2Terminate", mask::TERMINATE, terminate);
simple_call!(reset, "fmi2Reset", mask::ANY_BUT_FATAL, reset);

macro_rules! getter {
    ($fn:ident, $name:literal, $cty:ty, $sty:expr, $pat:pat => $conv:expr) => {
        /// # Safety
        /// Arguments as in the FMI 2.0 standard.
        pub unsafe fn $fn<M: Fmi2Model>(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            n: usize,
            out: *mut $cty,
        ) -> fmi2Status {
            // SAFETY: forwarded contract.
            unsafe {
                with::<M>(c, $name, mask::GET, |comp| {
                    let vrs = slice($name, "vr", vr, n)?;
                    let out = slice_mut($name, "value", out, n)?;
                    let mut vals = std::mem::take(&mut comp.scratch);
                    let r = comp.inst.get($name, $sty, vrs, &mut vals);
                    if r.is_ok() {
                        for (o, v) in out.iter_mut().zip(&vals) {
                            if let $pat = v {
                                *o = $conv;
                            }
                        }
                    }
                    comp.scratch = vals;
                    r.map(|()| fmi2OK)
                })
            }
        }
    };
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn get_real<M: Fmi2Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    out: *mut fmi2Real,
) -> fmi2Status {
    const CALL: &str = "fmi2GetReal";
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, CALL, mask::GET, |comp| {
            let vrs = slice(CALL, "vr", vr, n)?;
            let out = slice_mut(CALL, "value", out, n)?;
            // straight into the host's array (the per-step call: no `Value` buffer)
            comp.inst.get_reals(CALL, vrs, out)?;
            Ok(fmi2OK)
        })
    }
}
getter!(get_integer, "fmi2GetInteger", fmi2Integer, ScalarType::Integer, Value::Integer(x) => *x);
getter!(get_boolean, "fmi2GetBoolean", fmi2Boolean, ScalarType::Boolean, Value::Boolean(x) => fmi2Boolean::from(*x));

/// # Safety
/// Arguments as in the FMI 2.0 standard. The returned strings stay valid until
/// the next `fmi2GetString` call on this instance.
pub unsafe fn get_string<M: Fmi2Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    out: *mut fmi2String,
) -> fmi2Status {
    const CALL: &str = "fmi2GetString";
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, CALL, mask::GET, |comp| {
            let vrs = slice(CALL, "vr", vr, n)?;
            let out = slice_mut(CALL, "value", out, n)?;
            let mut vals = Vec::with_capacity(n);
            comp.inst.get(CALL, ScalarType::String, vrs, &mut vals)?;
            comp.strings.clear();
            comp.strings.extend(vals.iter().map(|v| match v {
                Value::String(s) => to_cstring(s),
                _ => CString::default(),
            }));
            for (o, s) in out.iter_mut().zip(&comp.strings) {
                *o = s.as_ptr();
            }
            Ok(fmi2OK)
        })
    }
}

macro_rules! setter {
    ($fn:ident, $name:literal, $cty:ty, $sty:expr, |$x:ident| $conv:expr) => {
        /// # Safety
        /// Arguments as in the FMI 2.0 standard.
        pub unsafe fn $fn<M: Fmi2Model>(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            n: usize,
            value: *const $cty,
        ) -> fmi2Status {
            // SAFETY: forwarded contract.
            unsafe {
                with::<M>(c, $name, mask::SET, |comp| {
                    let vrs = slice($name, "vr", vr, n)?;
                    let vals = slice($name, "value", value, n)?;
                    // the converted values go to the instance's scratch buffer: no allocation
                    // per call (numbers); all are checked by `set` before any is stored
                    let mut buf = std::mem::take(&mut comp.scratch);
                    buf.clear();
                    let mut r = Ok(());
                    for &$x in vals {
                        match $conv {
                            Ok(v) => buf.push(v),
                            Err(e) => {
                                r = Err(e);
                                break;
                            }
                        }
                    }
                    if r.is_ok() {
                        r = comp.inst.set($name, $sty, vrs, &buf);
                    }
                    buf.clear();
                    comp.scratch = buf;
                    r.map(|()| fmi2OK)
                })
            }
        }
    };
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn set_real<M: Fmi2Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    const CALL: &str = "fmi2SetReal";
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, CALL, mask::SET, |comp| {
            let vrs = slice(CALL, "vr", vr, n)?;
            let vals = slice(CALL, "value", value, n)?;
            // straight from the host's array (the per-step call: no `Value` buffer)
            comp.inst.set_reals(CALL, vrs, vals)?;
            Ok(fmi2OK)
        })
    }
}
setter!(set_integer, "fmi2SetInteger", fmi2Integer, ScalarType::Integer, |x| Ok(Value::Integer(x)));
setter!(set_boolean, "fmi2SetBoolean", fmi2Boolean, ScalarType::Boolean, |x| Ok(Value::Boolean(x != fmi2False)));
setter!(set_string, "fmi2SetString", fmi2String, ScalarType::String, |p| {
    // (inside the setter's unsafe block) the host passes NUL-terminated strings.
    opt_str(p)
        .map(|s| Value::String(s.to_string()))
        .ok_or_else(|| CallError::Error("fmi2SetString: a value is NULL or not UTF-8".into()))
});

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn do_step<M: Fmi2Model>(
    c: fmi2Component,
    t: fmi2Real,
    h: fmi2Real,
    _no_set_prior: fmi2Boolean,
) -> fmi2Status {
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, "fmi2DoStep", mask::DO_STEP, |comp| {
            comp.inst.do_step(t, h)?;
            Ok(fmi2OK)
        })
    }
}

/// # Safety
/// `c` is null or a live component of model `M`.
pub unsafe fn cancel_step<M: Fmi2Model>(c: fmi2Component) -> fmi2Status {
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, "fmi2CancelStep", mask::ANY_BUT_FATAL, |_| {
            Err(CallError::Error(
                "fmi2CancelStep: steps are synchronous (canRunAsynchronuously=\"false\"); there is nothing to cancel"
                    .into(),
            ))
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn get_fmu_state<M: Fmi2Model>(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    const CALL: &str = "fmi2GetFMUstate";
    // SAFETY: forwarded contract; a non-null `*state` was returned by this FMU for model `M`.
    unsafe {
        with::<M>(c, CALL, mask::ANY_BUT_FATAL, |comp| {
            if state.is_null() {
                return Err(CallError::Error(format!("{CALL}: FMUstate pointer is NULL")));
            }
            if (*state).is_null() {
                *state = new_state(&mut comp.states, comp.inst.snapshot());
            } else {
                comp.inst.snapshot_into(state_ref::<M>(&comp.states, CALL, *state)?);
            }
            Ok(fmi2OK)
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn set_fmu_state<M: Fmi2Model>(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    // SAFETY: forwarded contract; `state` was returned by this FMU for model `M`.
    unsafe {
        with::<M>(c, "fmi2SetFMUstate", mask::ANY_BUT_FATAL, |comp| {
            comp.inst.restore(state_ref::<M>(&comp.states, "fmi2SetFMUstate", state)?);
            Ok(fmi2OK)
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn free_fmu_state<M: Fmi2Model>(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    // SAFETY: forwarded contract; a non-null `*state` came from `Box::into_raw` here.
    unsafe {
        with::<M>(c, "fmi2FreeFMUstate", mask::ANY_BUT_FATAL, |comp| {
            if !state.is_null() && !(*state).is_null() {
                state_ref::<M>(&comp.states, "fmi2FreeFMUstate", *state)?;
                comp.states.retain(|&s| s != *state as usize);
                let mut b = Box::from_raw(*state as *mut BoxedState<M>);
                b.magic = 0;
                drop(b);
                *state = ptr::null_mut();
            }
            Ok(fmi2OK)
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn serialized_fmu_state_size<M: Fmi2Model>(
    c: fmi2Component,
    state: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    const CALL: &str = "fmi2SerializedFMUstateSize";
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, CALL, mask::ANY_BUT_FATAL, |comp| {
            if size.is_null() {
                return Err(CallError::Error(format!("{CALL}: size is NULL")));
            }
            *size = state_ref::<M>(&comp.states, CALL, state)?.serialize()?.len();
            Ok(fmi2OK)
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn serialize_fmu_state<M: Fmi2Model>(
    c: fmi2Component,
    state: fmi2FMUstate,
    bytes: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    const CALL: &str = "fmi2SerializeFMUstate";
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, CALL, mask::ANY_BUT_FATAL, |comp| {
            let data = state_ref::<M>(&comp.states, CALL, state)?.serialize()?;
            if size < data.len() {
                return Err(CallError::Error(format!("{CALL}: buffer of {size} bytes is smaller than {}", data.len())));
            }
            let out = slice_mut(CALL, "serializedState", bytes as *mut u8, data.len())?;
            out.copy_from_slice(&data);
            Ok(fmi2OK)
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn deserialize_fmu_state<M: Fmi2Model>(
    c: fmi2Component,
    bytes: *const fmi2Byte,
    size: usize,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    const CALL: &str = "fmi2DeSerializeFMUstate";
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, CALL, mask::ANY_BUT_FATAL, |comp| {
            if state.is_null() {
                return Err(CallError::Error(format!("{CALL}: FMUstate pointer is NULL")));
            }
            let data = slice(CALL, "serializedState", bytes as *const u8, size)?;
            let snap = Snapshot::<M>::deserialize(data)?;
            if (*state).is_null() {
                *state = new_state(&mut comp.states, snap);
            } else {
                *state_ref::<M>(&comp.states, CALL, *state)? = snap;
            }
            Ok(fmi2OK)
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn get_directional_derivative<M: Fmi2Model>(
    c: fmi2Component,
    _vu: *const fmi2ValueReference,
    _nu: usize,
    _vk: *const fmi2ValueReference,
    _nk: usize,
    _dvk: *const fmi2Real,
    _dvu: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, "fmi2GetDirectionalDerivative", mask::ANY_BUT_FATAL, |_| {
            Err(CallError::Error(
                "fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative=\"false\")".into(),
            ))
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn set_real_input_derivatives<M: Fmi2Model>(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _n: usize,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, "fmi2SetRealInputDerivatives", mask::SET_DER, |_| {
            Err(CallError::Error(
                "fmi2SetRealInputDerivatives: inputs are held constant over a step (canInterpolateInputs=\"false\")"
                    .into(),
            ))
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn get_real_output_derivatives<M: Fmi2Model>(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _n: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, "fmi2GetRealOutputDerivatives", mask::GET_DER, |_| {
            Err(CallError::Error(
                "fmi2GetRealOutputDerivatives: no output derivatives (maxOutputDerivativeOrder=\"0\")".into(),
            ))
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn get_status<M: Fmi2Model>(c: fmi2Component, kind: fmi2StatusKind, value: *mut fmi2Status) -> fmi2Status {
    const CALL: &str = "fmi2GetStatus";
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, CALL, mask::STATUS, |_| {
            if value.is_null() {
                return Err(CallError::Error(format!("{CALL}: value is NULL")));
            }
            Err(CallError::Discard(format!(
                "{CALL}: status kind {kind} is only defined after fmi2DoStep returned fmi2Pending, which this FMU never does"
            )))
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn get_real_status<M: Fmi2Model>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    const CALL: &str = "fmi2GetRealStatus";
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, CALL, mask::STATUS, |comp| {
            if value.is_null() {
                return Err(CallError::Error(format!("{CALL}: value is NULL")));
            }
            if kind != fmi2LastSuccessfulTime {
                return Err(CallError::Discard(format!("{CALL}: status kind {kind} has no Real value")));
            }
            *value = comp.inst.time();
            Ok(fmi2OK)
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn get_integer_status<M: Fmi2Model>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, "fmi2GetIntegerStatus", mask::STATUS, |_| {
            Err(CallError::Discard(format!("fmi2GetIntegerStatus: status kind {kind} has no Integer value")))
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn get_boolean_status<M: Fmi2Model>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    const CALL: &str = "fmi2GetBooleanStatus";
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, CALL, mask::STATUS, |_| {
            if value.is_null() {
                return Err(CallError::Error(format!("{CALL}: value is NULL")));
            }
            if kind != fmi2Terminated {
                return Err(CallError::Discard(format!("{CALL}: status kind {kind} has no Boolean value")));
            }
            // The models of this layer never ask the master to terminate.
            *value = fmi2False;
            Ok(fmi2OK)
        })
    }
}

/// # Safety
/// Arguments as in the FMI 2.0 standard.
pub unsafe fn get_string_status<M: Fmi2Model>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    _value: *mut fmi2String,
) -> fmi2Status {
    // SAFETY: forwarded contract.
    unsafe {
        with::<M>(c, "fmi2GetStringStatus", mask::STATUS, |_| {
            Err(CallError::Discard(format!("fmi2GetStringStatus: status kind {kind} has no String value")))
        })
    }
}
