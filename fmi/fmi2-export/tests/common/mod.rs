//! A minimal model used only by the export layer's tests (never shipped), and
//! a host side that calls the exported C functions in-process.
#![allow(dead_code, missing_docs, clippy::type_complexity)]

use fmi2_export::abi::*;
use fmi2_export::model_description::{
    Causality as C, ModelBuilder, ModelDescription, ScalarVariable as V, Variability as Va,
};
use fmi2_export::{Environment, Fmi2Model, ModelLog, Severity, StepError, Values};
use serde::{Deserialize, Serialize};
use std::cell::Cell;
use std::ffi::{CStr, CString, c_char, c_void};
use std::sync::{Mutex, OnceLock};

pub mod vr {
    pub const K: u32 = 0;
    pub const GAIN: u32 = 1;
    pub const U: u32 = 2;
    pub const X: u32 = 3;
    pub const V: u32 = 4;
    pub const X0: u32 = 5;
    pub const PANIC_AT: u32 = 6;
    pub const STEPS: u32 = 0; // Integer
    pub const MODE: u32 = 1; // Integer (enumeration)
    pub const POSITIVE: u32 = 0; // Boolean
    pub const DAMPED: u32 = 1; // Boolean parameter
    pub const LABEL: u32 = 0; // String
}

/// Undamped (or damped) oscillator ẍ = −k·x − c·ẋ + gain·u, symplectic Euler at 1 ms substeps.
#[derive(Clone, Serialize, Deserialize)]
pub struct Oscillator {
    x: f64,
    v: f64,
    k: f64,
    c: f64,
    steps: i32,
    #[serde(skip)]
    alive: Alive,
}

thread_local! {
    static LIVE: Cell<i64> = const { Cell::new(0) };
}

/// Oscillators made (initialized, cloned into a state, deserialized) minus those dropped, on
/// this thread: what a test that frees everything it made expects back at its start value.
pub fn live_models() -> i64 {
    LIVE.with(Cell::get)
}

/// Counts its oscillator in [`live_models`] while it exists.
struct Alive;
impl Alive {
    fn new() -> Self {
        LIVE.with(|n| n.set(n.get() + 1));
        Alive
    }
}
impl Default for Alive {
    /// A deserialized oscillator (serde skips the field) counts too.
    fn default() -> Self {
        Alive::new()
    }
}
impl Clone for Alive {
    fn clone(&self) -> Self {
        Alive::new()
    }
}
impl Drop for Alive {
    fn drop(&mut self) {
        LIVE.with(|n| n.set(n.get() - 1));
    }
}

impl Fmi2Model for Oscillator {
    fn description() -> &'static ModelDescription {
        static MD: OnceLock<ModelDescription> = OnceLock::new();
        MD.get_or_init(|| {
            let b = ModelBuilder::new("Oscillator", "Oscillator")
                .description("test model of the export layer")
                .unit("m", [0, 1, 0, 0, 0, 0, 0, 0])
                .unit("N/m", [1, 0, -2, 0, 0, 0, 0, 0])
                .enumeration("Mode", "integration mode", &[("euler", "symplectic Euler"), ("frozen", "no motion")])
                .default_experiment(0.0, 1.0, 1e-3)
                .var(V::real("k", vr::K, C::Parameter, Va::Fixed).start(4.0).bounds(0.0, 1e6).unit_of("N/m"))
                .var(V::real("gain", vr::GAIN, C::Parameter, Va::Tunable).start(1.0))
                .var(V::real("u", vr::U, C::Input, Va::Continuous).start(0.0))
                .var(V::real("x", vr::X, C::Output, Va::Continuous).unit_of("m").depends_on(&[]))
                .var(V::real("v", vr::V, C::Output, Va::Continuous).depends_on(&[]))
                .var(V::real("x0", vr::X0, C::Parameter, Va::Fixed).start(1.0).unit_of("m"))
                .var(V::real("panic_at", vr::PANIC_AT, C::Parameter, Va::Tunable).start(-1.0))
                .var(V::integer("steps", vr::STEPS, C::Output, Va::Discrete).depends_on(&[]))
                .var(V::enumeration("mode", vr::MODE, C::Parameter, Va::Fixed, "Mode").start(1))
                .var(V::boolean("positive", vr::POSITIVE, C::Output, Va::Discrete).depends_on(&[]))
                .var(V::boolean("damped", vr::DAMPED, C::Parameter, Va::Fixed).start(false))
                .var(V::string("label", vr::LABEL, C::Parameter, Va::Fixed).start("osc"));
            fmi2_export::with_log_categories(b).build().expect("valid test model")
        })
    }

    fn initialize(values: &Values, _env: &Environment) -> Result<Self, String> {
        if values.string(vr::LABEL) == "invalid" {
            return Err("label \"invalid\" is refused by the test model".into());
        }
        Ok(Oscillator {
            x: values.real(vr::X0),
            v: 0.0,
            k: values.real(vr::K),
            c: if values.boolean(vr::DAMPED) { 0.5 } else { 0.0 },
            steps: 0,
            alive: Alive::new(),
        })
    }

    fn update_outputs(&self, values: &mut Values) {
        values.set_real(vr::X, self.x);
        values.set_real(vr::V, self.v);
        values.set_integer(vr::STEPS, self.steps);
        values.set_boolean(vr::POSITIVE, self.x > 0.0);
    }

    fn do_step(&mut self, values: &mut Values, t: f64, h: f64, log: &mut dyn ModelLog) -> Result<(), StepError> {
        let panic_at = values.real(vr::PANIC_AT);
        if panic_at >= 0.0 && t >= panic_at {
            panic!("injected panic at t = {t}");
        }
        if h > 0.5 {
            return Err(StepError::Discard(format!("step {h} too large for the test model")));
        }
        if values.integer(vr::MODE) == 1 {
            let n = (h / 1e-3).round().max(1.0) as usize;
            let dt = h / n as f64;
            let f = values.real(vr::GAIN) * values.real(vr::U);
            for _ in 0..n {
                self.v += dt * (-self.k * self.x - self.c * self.v + f);
                self.x += dt * self.v;
            }
        }
        self.steps += 1;
        if self.steps == 1 {
            log.log(Severity::Info, "first step done");
        }
        self.update_outputs(values);
        Ok(())
    }

    fn internal_steps(&self, h: f64) -> f64 {
        (h / 1e-3).round().max(1.0)
    }
}

fmi2_export::export_fmi2!(crate::common::Oscillator);
pub use __fmi2_exports as api;

/// Messages received by the test logger: (env tag, instance, status, category, message).
pub static LOG: Mutex<Vec<(usize, String, i32, String, String)>> = Mutex::new(Vec::new());

/// A logger with the fixed arguments the export layer uses (`"%s"` + one
/// string). The FMI logger type is variadic and stable Rust cannot define
/// variadic functions; on the x86_64 and aarch64 System V ABIs a call through
/// the variadic pointer passes these arguments exactly as a non-variadic call.
unsafe extern "C" fn test_logger_fixed(
    env: *mut c_void,
    name: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    fmt: fmi2String,
    arg: *const c_char,
) {
    let s = |p: *const c_char| {
        if p.is_null() { String::new() } else { unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned() }
    };
    assert_eq!(s(fmt), "%s", "the export layer must use a fixed %s format");
    LOG.lock().unwrap().push((env as usize, s(name), status, s(category), s(arg)));
}

pub fn callbacks(env_tag: usize) -> fmi2CallbackFunctions {
    type Fixed = unsafe extern "C" fn(*mut c_void, fmi2String, fmi2Status, fmi2String, fmi2String, *const c_char);
    // SAFETY: see `test_logger_fixed`.
    let logger: fmi2CallbackLogger = Some(unsafe {
        std::mem::transmute::<
            Fixed,
            unsafe extern "C" fn(*mut c_void, fmi2String, fmi2Status, fmi2String, fmi2String, ...),
        >(test_logger_fixed as Fixed)
    });
    fmi2CallbackFunctions {
        logger,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: env_tag as *mut c_void,
    }
}

/// Messages logged so far for instance `name`.
pub fn messages(name: &str) -> Vec<(i32, String, String)> {
    LOG.lock().unwrap().iter().filter(|m| m.1 == name).map(|m| (m.2, m.3.clone(), m.4.clone())).collect()
}

pub fn guid() -> CString {
    CString::new(Oscillator::description().guid.clone()).unwrap()
}

/// Instantiate with the test logger; `name` must be unique per test for `messages`.
pub fn instantiate(name: &str, cb: &fmi2CallbackFunctions) -> fmi2Component {
    let n = CString::new(name).unwrap();
    let g = guid();
    unsafe {
        api::fmi2Instantiate(n.as_ptr(), fmi2CoSimulation, g.as_ptr(), c"file:///tmp/res%20dir".as_ptr(), cb, 0, 0)
    }
}

/// Instantiate, set up at t0 = 0 and initialize.
pub fn ready(name: &str, cb: &fmi2CallbackFunctions) -> fmi2Component {
    let c = instantiate(name, cb);
    assert!(!c.is_null());
    unsafe {
        assert_eq!(api::fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
        assert_eq!(api::fmi2EnterInitializationMode(c), fmi2OK);
        assert_eq!(api::fmi2ExitInitializationMode(c), fmi2OK);
    }
    c
}

pub fn get_real(c: fmi2Component, vr: u32) -> (fmi2Status, f64) {
    let mut v = f64::NAN;
    let s = unsafe { api::fmi2GetReal(c, &vr, 1, &mut v) };
    (s, v)
}

pub fn set_real(c: fmi2Component, vr: u32, v: f64) -> fmi2Status {
    unsafe { api::fmi2SetReal(c, &vr, 1, &v) }
}
