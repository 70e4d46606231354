//! The safe core of an FMU instance: state machine, variable access rules,
//! time keeping and state snapshots. The C boundary ([`crate::ffi`]) only
//! converts pointers to slices and strings and calls these methods.

use crate::model::{
    Environment, Fmi2Model, MAX_INTERNAL_STEPS_PER_CALL, MAX_VALUE_REFERENCE, ModelLog, Severity, StepError, Values,
    fnv1a64,
};
use model_description::{
    Causality, Initial, ModelDescription, ScalarType, ScalarVariable, Value, ValueReference, Variability,
};
use serde::{Deserialize, Serialize};

/// FMI 2.0 co-simulation states (FMI 2.0.4, section 4.2.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum State {
    /// After `fmi2Instantiate` / `fmi2Reset`.
    Instantiated,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    InitializationMode,
    /// Ready for `fmi2DoStep`.
    StepComplete,
    /// A step returned `fmi2Discard`.
    StepFailed,
    /// After `fmi2Terminate`.
    Terminated,
    /// After an `fmi2Error`.
    Error,
    /// After an `fmi2Fatal`: only `fmi2FreeInstance` is allowed.
    Fatal,
}

impl State {
    /// Every state.
    pub const ALL: [State; 7] = [
        State::Instantiated,
        State::InitializationMode,
        State::StepComplete,
        State::StepFailed,
        State::Terminated,
        State::Error,
        State::Fatal,
    ];
}

/// Bit masks of the states in which each call is allowed (the Reference FMUs' `MASK_*`).
pub mod mask {
    use super::State;
    /// Bit of a state.
    pub const fn bit(s: State) -> u32 {
        1 << (s as u32)
    }
    const I: u32 = bit(State::Instantiated);
    const IM: u32 = bit(State::InitializationMode);
    const SC: u32 = bit(State::StepComplete);
    const SF: u32 = bit(State::StepFailed);
    const T: u32 = bit(State::Terminated);
    const E: u32 = bit(State::Error);
    /// `fmi2SetDebugLogging`, `fmi2Reset`, FMU-state functions.
    pub const ANY_BUT_FATAL: u32 = I | IM | SC | SF | T | E;
    /// `fmi2SetupExperiment`, `fmi2EnterInitializationMode`.
    pub const SETUP: u32 = I;
    /// `fmi2ExitInitializationMode`.
    pub const EXIT_INIT: u32 = IM;
    /// `fmi2Terminate`.
    pub const TERMINATE: u32 = SC | SF;
    /// `fmi2Get*`.
    pub const GET: u32 = IM | SC | SF | T | E;
    /// `fmi2Set*`.
    pub const SET: u32 = I | IM | SC;
    /// `fmi2DoStep`.
    pub const DO_STEP: u32 = SC;
    /// `fmi2GetStatus` family.
    pub const STATUS: u32 = SC | SF | T;
    /// `fmi2SetRealInputDerivatives`.
    pub const SET_DER: u32 = I | IM | SC;
    /// `fmi2GetRealOutputDerivatives`.
    pub const GET_DER: u32 = SC | SF | T | E;
}

/// Result of a call, mapped to `fmi2Status` at the boundary.
#[derive(Clone, Debug, PartialEq)]
pub enum CallError {
    /// `fmi2Discard` with a message.
    Discard(String),
    /// `fmi2Error` with a message.
    Error(String),
}

impl CallError {
    fn error(msg: impl Into<String>) -> Self {
        CallError::Error(msg.into())
    }
}

/// Result type of instance calls.
pub type CallResult<T> = Result<T, CallError>;

/// Log categories declared by every model of this layer.
pub const LOG_CATEGORIES: [(&str, &str); 6] = [
    ("logEvents", "Informational messages: state changes, parameter changes, model events"),
    ("logStatusWarning", "Messages with status fmi2Warning"),
    ("logStatusDiscard", "Messages with status fmi2Discard"),
    ("logStatusError", "Messages with status fmi2Error"),
    ("logStatusFatal", "Messages with status fmi2Fatal"),
    ("logAll", "All messages"),
];

/// Severity of a message passed to the host (maps to `fmi2Status`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LogLevel {
    /// `fmi2OK`, category `logEvents`.
    Info,
    /// `fmi2Warning`.
    Warning,
    /// `fmi2Discard`.
    Discard,
    /// `fmi2Error`.
    Error,
    /// `fmi2Fatal`.
    Fatal,
}

impl LogLevel {
    /// The category a message of this level is filed under.
    pub fn category(self) -> &'static str {
        match self {
            LogLevel::Info => "logEvents",
            LogLevel::Warning => "logStatusWarning",
            LogLevel::Discard => "logStatusDiscard",
            LogLevel::Error => "logStatusError",
            LogLevel::Fatal => "logStatusFatal",
        }
    }
}

/// Where an instance sends its messages (the host logger at the boundary, a
/// vector in tests).
pub trait LogSink: Send {
    /// Deliver a message.
    fn emit(&mut self, level: LogLevel, category: &str, message: &str);
}

/// Time keeping without drift: while the master keeps the same step size, the
/// time is `base + n·h`, not a running sum.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Clock {
    base: f64,
    h: f64,
    n: u64,
}

impl Clock {
    fn new(t0: f64) -> Self {
        Clock { base: t0, h: 0.0, n: 0 }
    }
    /// Current time.
    pub fn now(&self) -> f64 {
        self.base + self.n as f64 * self.h
    }
    /// The step the model takes for a requested `h`, and whether it continues the current step
    /// size: the current step size when `h` equals it within [`approx_eq`] (masters that count
    /// time in integers, such as libcosim's nanoseconds, pass `t_{n+1} − t_n` in doubles, which
    /// wanders by an ulp from step to step), so the model integrates exactly the steps the clock
    /// counts.
    fn step_for(&self, h: f64) -> (f64, bool) {
        if self.n > 0 && approx_eq(h, self.h) { (self.h, true) } else { (h, false) }
    }
    /// After a step of [`step_for`](Self::step_for)`(h)`.
    fn advance_by(&mut self, (h, same): (f64, bool)) {
        if same {
            self.n += 1;
        } else {
            self.base = self.now();
            self.h = h;
            self.n = 1;
        }
    }
}

/// Time comparison used for communication points: 1e-12 absolute plus 1e-9 relative.
pub fn approx_eq(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 + 1e-9 * a.abs().max(b.abs())
}

/// Everything that a saved FMU state holds.
#[derive(Clone, Serialize, Deserialize)]
#[serde(bound = "M: Fmi2Model")]
pub struct Snapshot<M: Fmi2Model> {
    state: State,
    values: Values,
    model: Option<M>,
    clock: Clock,
    start_time: f64,
    stop_time: Option<f64>,
    dirty: bool,
}

const SNAPSHOT_MAGIC: &[u8; 8] = b"CHFMUST\0";
/// Version of the serialized state format; version 1 had no version field and no checksum.
const SNAPSHOT_VERSION: u32 = 2;

/// (API type, value reference) → position in the model description's variable list: one dense
/// table per API type indexed by the value reference (at most [`MAX_VALUE_REFERENCE`]), so a
/// lookup in `fmi2Get*`/`fmi2Set*` is one bounds-checked load instead of hashing.
struct VarIndex([Vec<u32>; 4]);

impl VarIndex {
    const NONE: u32 = u32::MAX;

    fn slot(ty: ScalarType) -> Option<usize> {
        match ty {
            ScalarType::Real => Some(0),
            ScalarType::Integer => Some(1),
            ScalarType::Boolean => Some(2),
            ScalarType::String => Some(3),
            ScalarType::Enumeration => None,
        }
    }

    fn new(md: &ModelDescription) -> Self {
        let mut t: [Vec<u32>; 4] = Default::default();
        for (i, v) in md.variables().iter().enumerate() {
            let vr = v.value_reference as usize;
            // larger references are refused by `Values::from_description`
            if let (Some(s), true) = (Self::slot(v.scalar_type().api_type()), vr <= MAX_VALUE_REFERENCE as usize) {
                if t[s].len() <= vr {
                    t[s].resize(vr + 1, Self::NONE);
                }
                t[s][vr] = i as u32;
            }
        }
        VarIndex(t)
    }

    fn get(&self, ty: ScalarType, vr: ValueReference) -> Option<usize> {
        let i = *self.0[Self::slot(ty)?].get(vr as usize)?;
        (i != Self::NONE).then_some(i as usize)
    }
}

/// What `fmi2SetReal` checks of one Real variable, derived once from the description by the
/// rules of [`Instance::check_value`]: the states in which it may be set ([`settable_in`]) and
/// its range (±∞ where it has none). The per-step set accepts a finite value in range in one of
/// those states with a few comparisons; anything else goes to `check_value`, which says why.
#[derive(Clone, Copy, Debug)]
struct RealCheck {
    states: u32,
    lo: f64,
    hi: f64,
    /// A tunable parameter (a set after initialization asks the model to [retune](Fmi2Model::retune)).
    tunable: bool,
}

impl RealCheck {
    /// Undeclared value references: settable in no state.
    const NONE: RealCheck = RealCheck { states: 0, lo: f64::NAN, hi: f64::NAN, tunable: false };

    /// One entry per Real value reference (dense, like [`VarIndex`]).
    fn table(md: &ModelDescription) -> Vec<RealCheck> {
        let mut t = Vec::new();
        for v in md.variables() {
            let vr = v.value_reference as usize;
            if v.scalar_type().api_type() != ScalarType::Real || vr > MAX_VALUE_REFERENCE as usize {
                continue;
            }
            if t.len() <= vr {
                t.resize(vr + 1, RealCheck::NONE);
            }
            let states = State::ALL.iter().filter(|&&s| settable_in(s, v)).fold(0, |m, &s| m | mask::bit(s));
            let (lo, hi) = v.range();
            let tunable = v.causality == Causality::Parameter && v.variability == Variability::Tunable;
            t[vr] = RealCheck { states, lo: lo.unwrap_or(f64::NEG_INFINITY), hi: hi.unwrap_or(f64::INFINITY), tunable };
        }
        t
    }

    /// Does `check_value` accept `x` in a state of bit `state`? (`false` may still be accepted
    /// there: the caller then asks it.)
    #[inline]
    fn accepts(&self, state: u32, x: f64) -> bool {
        self.states & state != 0 && x.is_finite() && x >= self.lo && x <= self.hi
    }
}

/// May `v` be set in state `state`? (FMI 2.0.4, Table 4.2.4 / 2.2.7.)
fn settable_in(state: State, v: &ScalarVariable) -> bool {
    if v.variability == Variability::Constant {
        return false;
    }
    let init = v.effective_initial();
    match state {
        State::Instantiated => {
            v.causality == Causality::Input || matches!(init, Some(Initial::Exact | Initial::Approx))
        }
        State::InitializationMode => v.causality == Causality::Input || init == Some(Initial::Exact),
        State::StepComplete => {
            v.causality == Causality::Input
                || (v.causality == Causality::Parameter && v.variability == Variability::Tunable)
        }
        _ => false,
    }
}

/// One FMU instance.
pub struct Instance<M: Fmi2Model> {
    md: &'static ModelDescription,
    index: VarIndex,
    /// The per-step checks of `fmi2SetReal`, by value reference.
    real_checks: Vec<RealCheck>,
    /// The Real outputs (value reference, position in the description), checked finite after
    /// every step and after initialization ([`Instance::check_outputs`]).
    real_outputs: Vec<(ValueReference, usize)>,
    /// Current state.
    pub state: State,
    env: Environment,
    values: Values,
    model: Option<M>,
    clock: Clock,
    start_time: f64,
    stop_time: Option<f64>,
    /// Parameters or inputs changed since the model was last built (initialization mode).
    dirty: bool,
    /// A tunable parameter changed since the last step: the model retunes before the next one.
    retune: bool,
    debug_categories: Vec<bool>,
    sink: Box<dyn LogSink>,
    /// The message of the `fmi2Error` that put the instance in [`State::Error`].
    error_cause: Option<String>,
}

struct StepLog<'a> {
    sink: &'a mut dyn LogSink,
    info_on: bool,
    warn_on: bool,
}

impl ModelLog for StepLog<'_> {
    fn log(&mut self, severity: Severity, message: &str) {
        match severity {
            Severity::Info if self.info_on => self.sink.emit(LogLevel::Info, "logEvents", message),
            Severity::Warning if self.warn_on => self.sink.emit(LogLevel::Warning, "logStatusWarning", message),
            _ => {}
        }
    }
}

impl<M: Fmi2Model> Instance<M> {
    /// A new instance with start values.
    pub fn new(env: Environment, logging_on: bool, sink: Box<dyn LogSink>) -> Self {
        let md = M::description();
        let index = VarIndex::new(md);
        Instance {
            md,
            index,
            real_checks: RealCheck::table(md),
            real_outputs: md
                .variables()
                .iter()
                .enumerate()
                .filter(|(_, v)| v.causality == Causality::Output && v.scalar_type() == ScalarType::Real)
                .map(|(i, v)| (v.value_reference, i))
                .collect(),
            state: State::Instantiated,
            env,
            values: Values::from_description(md),
            model: None,
            clock: Clock::new(0.0),
            start_time: 0.0,
            stop_time: None,
            dirty: true,
            retune: false,
            debug_categories: vec![logging_on; LOG_CATEGORIES.len()],
            sink,
            error_cause: None,
        }
    }

    /// The model, once built (after initialization, or on a `get` during it).
    pub fn model(&self) -> Option<&M> {
        self.model.as_ref()
    }

    /// Instance name.
    pub fn name(&self) -> &str {
        &self.env.instance_name
    }

    fn category_on(&self, name: &str) -> bool {
        let all = self.debug_categories[LOG_CATEGORIES.len() - 1];
        all || LOG_CATEGORIES.iter().position(|(c, _)| *c == name).is_some_and(|i| self.debug_categories[i])
    }

    /// Log a message. Informational messages need their category enabled
    /// through `fmi2SetDebugLogging`; warnings, discards and errors are always
    /// reported, since the master has no other way to learn why a call failed.
    pub fn log(&mut self, level: LogLevel, message: &str) {
        if level == LogLevel::Info && !self.category_on(level.category()) {
            return;
        }
        self.sink.emit(level, level.category(), message);
    }

    /// Enter [`State::Error`] after a call answered `fmi2Error` with `message`. FMI 2.0
    /// §2.1.3: "The simulation cannot be continued with this FMU instance"; the ways out are
    /// `fmi2SetFMUstate` with a state stored before the error, `fmi2Reset` and
    /// `fmi2FreeInstance` (README "FMI conformance decisions").
    pub fn enter_error(&mut self, message: &str) {
        if self.state != State::Error || self.error_cause.is_none() {
            self.error_cause = Some(message.to_string());
        }
        self.state = State::Error;
    }

    /// Check that `call` is allowed in the current state.
    pub fn check_state(&self, call: &str, allowed: u32) -> CallResult<()> {
        if allowed & mask::bit(self.state) == 0 && self.state == State::Error {
            Err(CallError::error(format!(
                "{call}: not allowed after an fmi2Error ({}); FMI 2.0 (2.1.3): the simulation cannot be continued \
                 with this instance: restore a state stored before the error (fmi2SetFMUstate), fmi2Reset or \
                 fmi2FreeInstance",
                self.error_cause.as_deref().unwrap_or("a state stored in the error state was restored")
            )))
        } else if allowed & mask::bit(self.state) == 0 {
            Err(CallError::error(format!("{call}: not allowed in state {:?}", self.state)))
        } else {
            Ok(())
        }
    }

    /// `fmi2SetDebugLogging`.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> CallResult<()> {
        if categories.is_empty() {
            self.debug_categories.iter_mut().for_each(|c| *c = on);
            return Ok(());
        }
        for c in categories {
            match LOG_CATEGORIES.iter().position(|(n, _)| n == c) {
                Some(i) => self.debug_categories[i] = on,
                None => return Err(CallError::error(format!("fmi2SetDebugLogging: unknown log category \"{c}\""))),
            }
        }
        Ok(())
    }

    /// `fmi2SetupExperiment`.
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> CallResult<()> {
        if !start.is_finite() {
            return Err(CallError::error(format!("fmi2SetupExperiment: startTime {start} is not finite")));
        }
        if let Some(stop) = stop
            && (!stop.is_finite() || stop < start)
        {
            return Err(CallError::error(format!(
                "fmi2SetupExperiment: stopTime {stop} is not a finite time after startTime {start}"
            )));
        }
        self.start_time = start;
        self.stop_time = stop;
        self.clock = Clock::new(start);
        Ok(())
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization(&mut self) -> CallResult<()> {
        self.state = State::InitializationMode;
        Ok(())
    }

    fn build_model(&mut self) -> CallResult<()> {
        let model = M::initialize(&self.values, &self.env).map_err(CallError::Error)?;
        model.update_outputs(&mut self.values);
        self.check_outputs().map_err(|m| CallError::error(format!("initialization: {m}")))?;
        self.model = Some(model);
        self.dirty = false;
        Ok(())
    }

    /// Every Real output is finite: a model whose arithmetic overflowed (an input of 1e308, a
    /// diverging state) must not hand NaN or ±Inf to the master with `fmi2OK`. The error names
    /// the outputs and the inputs they were computed from.
    fn check_outputs(&self) -> Result<(), String> {
        let vars = self.md.variables();
        let bad: Vec<String> = self
            .real_outputs
            .iter()
            .filter(|&&(vr, _)| !self.values.real(vr).is_finite())
            .map(|&(vr, i)| format!("{} = {}", vars[i].name, self.values.real(vr)))
            .collect();
        if bad.is_empty() {
            return Ok(());
        }
        let inputs: Vec<String> = vars
            .iter()
            .filter(|v| v.causality == Causality::Input && v.scalar_type() == ScalarType::Real)
            .map(|v| format!("{} = {:e}", v.name, self.values.real(v.value_reference)))
            .collect();
        Err(format!(
            "non-finite output{} {} (the model's arithmetic overflowed; inputs {}); the instance cannot continue",
            if bad.len() > 1 { "s" } else { "" },
            bad.join(", "),
            if inputs.is_empty() { "none".to_string() } else { inputs.join(", ") }
        ))
    }

    /// `fmi2ExitInitializationMode`: builds the model from the parameters.
    pub fn exit_initialization(&mut self) -> CallResult<()> {
        if self.dirty || self.model.is_none() {
            self.build_model()?;
        }
        self.state = State::StepComplete;
        self.log(LogLevel::Info, &format!("initialized at t = {}", self.start_time));
        Ok(())
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> CallResult<()> {
        self.state = State::Terminated;
        Ok(())
    }

    /// `fmi2Reset`: back to start values, state Instantiated.
    pub fn reset(&mut self) -> CallResult<()> {
        self.values = Values::from_description(self.md);
        self.model = None;
        self.clock = Clock::new(0.0);
        self.start_time = 0.0;
        self.stop_time = None;
        self.dirty = true;
        self.retune = false;
        self.state = State::Instantiated;
        self.error_cause = None;
        Ok(())
    }

    /// Resolve a value reference of the given API type.
    fn lookup(&self, call: &str, ty: ScalarType, vr: ValueReference) -> CallResult<&'static ScalarVariable> {
        let md = self.md;
        self.index
            .get(ty, vr)
            .map(|i| &md.variables()[i])
            .ok_or_else(|| CallError::error(format!("{call}: unknown value reference {vr} for type {ty:?}")))
    }

    /// Before a get in initialization mode, calculated values must reflect the
    /// parameters set so far.
    fn refresh_for_get(&mut self) -> CallResult<()> {
        if self.state == State::InitializationMode && self.dirty {
            self.build_model()?;
        }
        Ok(())
    }

    /// Get values of one API type: `out` receives one value per reference.
    pub fn get(&mut self, call: &str, ty: ScalarType, vrs: &[ValueReference], out: &mut Vec<Value>) -> CallResult<()> {
        self.refresh_for_get()?;
        out.clear();
        for &vr in vrs {
            self.lookup(call, ty, vr)?;
            out.push(match ty {
                ScalarType::Real => Value::Real(self.values.real(vr)),
                ScalarType::Integer => Value::Integer(self.values.integer(vr)),
                ScalarType::Boolean => Value::Boolean(self.values.boolean(vr)),
                ScalarType::String => Value::String(self.values.string(vr).to_string()),
                ScalarType::Enumeration => unreachable!("enumerations are accessed as Integer"),
            });
        }
        Ok(())
    }

    /// [`get`](Self::get) of Real variables straight into `out` (no [`Value`]; every reference
    /// is looked up before any value is written): `fmi2GetReal`, once or twice per step.
    pub fn get_reals(&mut self, call: &str, vrs: &[ValueReference], out: &mut [f64]) -> CallResult<()> {
        self.refresh_for_get()?;
        for &vr in vrs {
            self.lookup(call, ScalarType::Real, vr)?;
        }
        for (&vr, o) in vrs.iter().zip(out) {
            *o = self.values.real(vr);
        }
        Ok(())
    }

    /// [`set`](Self::set) of Real values without the [`Value`] buffer: `fmi2SetReal`. The same
    /// checks, all before any value is stored.
    pub fn set_reals(&mut self, call: &str, vrs: &[ValueReference], vals: &[f64]) -> CallResult<()> {
        let state = mask::bit(self.state);
        for (&vr, &x) in vrs.iter().zip(vals) {
            // the precomputed check; what it does not accept, `check_value` decides and explains
            if !self.real_checks.get(vr as usize).is_some_and(|c| c.accepts(state, x)) {
                let v = self.lookup(call, ScalarType::Real, vr)?;
                self.check_value(call, v, &Value::Real(x))?;
            }
        }
        for (&vr, &x) in vrs.iter().zip(vals) {
            self.values.set_real(vr, x);
        }
        if matches!(self.state, State::Instantiated | State::InitializationMode) {
            self.dirty = true;
        } else if vrs.iter().any(|&vr| self.real_checks.get(vr as usize).is_some_and(|c| c.tunable)) {
            self.retune = true;
        }
        Ok(())
    }

    /// Check a value against a variable's declaration.
    fn check_value(&self, call: &str, v: &ScalarVariable, x: &Value) -> CallResult<()> {
        if !settable_in(self.state, v) {
            return Err(CallError::error(format!(
                "{call}: variable \"{}\" ({:?}, {:?}) cannot be set in state {:?}",
                v.name, v.causality, v.variability, self.state
            )));
        }
        let num = match x {
            Value::Real(r) => {
                if !r.is_finite() {
                    let msg = format!("{call}: value {r} for \"{}\" is not finite", v.name);
                    // An input that goes non-finite (a diverging neighbour) is discarded: nothing
                    // is stored, the instance keeps its previous input and stays usable, and the
                    // master decides (retry with a valid value, shorter step, or stop). A
                    // non-finite parameter is a configuration error.
                    return Err(if v.causality == Causality::Input {
                        CallError::Discard(format!("{msg}; the input keeps its previous value"))
                    } else {
                        CallError::error(msg)
                    });
                }
                Some(*r)
            }
            Value::Integer(i) => Some(f64::from(*i)),
            _ => None,
        };
        if let Some(x) = num {
            let (lo, hi) = v.range();
            if lo.is_some_and(|lo| x < lo) || hi.is_some_and(|hi| x > hi) {
                let hint = v
                    .unit()
                    .and_then(|u| {
                        model_description::units::slip_hint(u, x, lo.unwrap_or(f64::MIN), hi.unwrap_or(f64::MAX))
                    })
                    .map_or(String::new(), |h| format!("; {h}"));
                return Err(CallError::error(format!(
                    "{call}: value {x} for \"{}\" is outside [{}, {}]{hint}",
                    v.name,
                    lo.map_or("-inf".into(), |l| l.to_string()),
                    hi.map_or("inf".into(), |h| h.to_string()),
                )));
            }
        }
        if let (model_description::VarKind::Enumeration(e), Value::Integer(i)) = (&v.kind, x)
            && !self.md.enumeration_items(&e.declared_type).iter().any(|(_, val)| val == i)
        {
            return Err(CallError::error(format!(
                "{call}: {i} is not an item of enumeration {} for \"{}\"",
                e.declared_type, v.name
            )));
        }
        Ok(())
    }

    /// Set values of one API type. All values are checked before any is stored.
    pub fn set(&mut self, call: &str, ty: ScalarType, vrs: &[ValueReference], vals: &[Value]) -> CallResult<()> {
        for (&vr, x) in vrs.iter().zip(vals) {
            let v = self.lookup(call, ty, vr)?;
            self.check_value(call, v, x)?;
        }
        let mut tuned = false;
        for (&vr, x) in vrs.iter().zip(vals) {
            tuned |= self.lookup(call, ty, vr).is_ok_and(|v| v.causality == Causality::Parameter);
            match x {
                Value::Real(r) => self.values.set_real(vr, *r),
                Value::Integer(i) => self.values.set_integer(vr, *i),
                Value::Boolean(b) => self.values.set_boolean(vr, *b),
                Value::String(s) => self.values.set_string(vr, s),
            }
        }
        if matches!(self.state, State::Instantiated | State::InitializationMode) {
            self.dirty = true;
        } else if tuned {
            self.retune = true;
        }
        Ok(())
    }

    /// Current time.
    pub fn time(&self) -> f64 {
        self.clock.now()
    }

    /// `fmi2DoStep`.
    pub fn do_step(&mut self, t: f64, h: f64) -> CallResult<()> {
        let now = self.clock.now();
        if !t.is_finite() || !approx_eq(t, now) {
            return Err(CallError::error(format!(
                "fmi2DoStep: currentCommunicationPoint {t} does not match the instance time {now}"
            )));
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(CallError::error(format!("fmi2DoStep: communicationStepSize {h} must be positive and finite")));
        }
        if let Some(stop) = self.stop_time
            && now + h > stop
            && !approx_eq(now + h, stop)
        {
            return Err(CallError::error(format!("fmi2DoStep: step to {} passes the stop time {stop}", now + h)));
        }
        let info_on = self.category_on("logEvents");
        let warn_on = true;
        let Some(model) = self.model.as_mut() else {
            return Err(CallError::error("fmi2DoStep: model not initialized"));
        };
        let cost = model.internal_steps(h);
        if cost.is_nan() || cost > MAX_INTERNAL_STEPS_PER_CALL {
            return Err(CallError::error(format!(
                "fmi2DoStep: communicationStepSize {h} s needs {cost:e} internal steps, more than the limit of \
                 {MAX_INTERNAL_STEPS_PER_CALL:e} per call; split it into steps of at most {} s",
                h * MAX_INTERNAL_STEPS_PER_CALL / cost
            )));
        }
        if self.retune {
            model.retune(&self.values).map_err(|m| CallError::error(format!("fmi2DoStep at t = {now}: {m}")))?;
            self.retune = false;
        }
        let step = self.clock.step_for(h);
        let mut log = StepLog { sink: self.sink.as_mut(), info_on, warn_on };
        match model.do_step(&mut self.values, now, step.0, &mut log) {
            Ok(()) => {
                self.clock.advance_by(step);
                self.check_outputs().map_err(|m| CallError::error(format!("fmi2DoStep at t = {now}: {m}")))
            }
            Err(StepError::Discard(m)) => {
                self.state = State::StepFailed;
                Err(CallError::Discard(format!("fmi2DoStep at t = {now}: {m}")))
            }
            Err(StepError::Error(m)) => Err(CallError::error(format!("fmi2DoStep at t = {now}: {m}"))),
        }
    }

    /// Take a snapshot (`fmi2GetFMUstate`).
    pub fn snapshot(&self) -> Snapshot<M> {
        Snapshot {
            state: self.state,
            values: self.values.clone(),
            model: self.model.clone(),
            clock: self.clock,
            start_time: self.start_time,
            stop_time: self.stop_time,
            dirty: self.dirty,
        }
    }

    /// Overwrite `snap` with the current state, reusing its allocations.
    pub fn snapshot_into(&self, snap: &mut Snapshot<M>) {
        snap.state = self.state;
        snap.values.clone_from(&self.values);
        snap.model.clone_from(&self.model);
        snap.clock = self.clock;
        snap.start_time = self.start_time;
        snap.stop_time = self.stop_time;
        snap.dirty = self.dirty;
    }

    /// Restore a snapshot (`fmi2SetFMUstate`).
    pub fn restore(&mut self, snap: &Snapshot<M>) {
        self.state = snap.state;
        self.error_cause = None;
        self.values.clone_from(&snap.values);
        self.model.clone_from(&snap.model);
        self.clock = snap.clock;
        self.start_time = snap.start_time;
        self.stop_time = snap.stop_time;
        self.dirty = snap.dirty;
        // the restored values may hold other tunable parameters than the model was last tuned to
        self.retune = self.model.is_some();
    }
}

impl<M: Fmi2Model> Snapshot<M> {
    /// Versioned byte format: magic (8 bytes), format version (u32 LE), GUID length (u32 LE) and
    /// GUID, the postcard encoding of the snapshot, then the FNV-1a 64 checksum (u64 LE) of all
    /// the bytes before it.
    pub fn serialize(&self) -> CallResult<Vec<u8>> {
        let guid = M::description().guid.as_bytes();
        let mut out = Vec::with_capacity(64);
        out.extend_from_slice(SNAPSHOT_MAGIC);
        out.extend_from_slice(&SNAPSHOT_VERSION.to_le_bytes());
        out.extend_from_slice(&(guid.len() as u32).to_le_bytes());
        out.extend_from_slice(guid);
        let mut out =
            postcard::to_extend(self, out).map_err(|e| CallError::error(format!("fmi2SerializeFMUstate: {e}")))?;
        let sum = fnv1a64(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        Ok(out)
    }

    /// Parse bytes written by [`Snapshot::serialize`] and validate what they hold
    /// ([`Snapshot::validate`]); anything else is an error.
    pub fn deserialize(bytes: &[u8]) -> CallResult<Self> {
        let err = |m: &str| CallError::error(format!("fmi2DeSerializeFMUstate: {m}"));
        if bytes.starts_with(b"CHFMUST\x01") {
            return Err(err("state in format version 1 (an older build of this FMU); it cannot be read"));
        }
        let rest =
            bytes.strip_prefix(SNAPSHOT_MAGIC).ok_or_else(|| err("not a serialized state of this FMU (bad header)"))?;
        if rest.len() < 16 {
            return Err(err("truncated state"));
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        if fnv1a64(body).to_le_bytes() != sum {
            return Err(err("corrupted state (checksum mismatch)"));
        }
        let rest = &body[SNAPSHOT_MAGIC.len()..];
        let version = u32::from_le_bytes([rest[0], rest[1], rest[2], rest[3]]);
        if version != SNAPSHOT_VERSION {
            return Err(err(&format!("state format version {version}, this FMU reads {SNAPSHOT_VERSION}")));
        }
        let n = u32::from_le_bytes([rest[4], rest[5], rest[6], rest[7]]) as usize;
        let rest = &rest[8..];
        if rest.len() < n || &rest[..n] != M::description().guid.as_bytes() {
            return Err(err("state was saved by another model (GUID mismatch)"));
        }
        let (snap, tail) =
            postcard::take_from_bytes::<Self>(&rest[n..]).map_err(|e| err(&format!("corrupted state: {e}")))?;
        if !tail.is_empty() {
            return Err(err("trailing bytes after state"));
        }
        snap.validate().map_err(|m| err(&format!("invalid state: {m}")))?;
        Ok(snap)
    }

    /// Is this a state the instance can continue from? The variable store has the table's
    /// shape, every Real is finite, parameters and inputs are within their bounds and
    /// enumerations hold items, the times are finite, and the model accepts its own state
    /// ([`Fmi2Model::validate_state`]).
    pub fn validate(&self) -> Result<(), String> {
        let md = M::description();
        if !self.values.same_shape(md) {
            return Err("the variable store does not match the variable table".into());
        }
        for v in md.variables() {
            let x = self.values.get(v.scalar_type(), v.value_reference);
            let num = match x {
                Value::Real(r) if !r.is_finite() => return Err(format!("\"{}\" = {r} is not finite", v.name)),
                Value::Real(r) => r,
                Value::Integer(i) => f64::from(i),
                _ => continue,
            };
            let (lo, hi) = v.range();
            let bounded = matches!(v.causality, Causality::Parameter | Causality::Input);
            if bounded && (lo.is_some_and(|lo| num < lo) || hi.is_some_and(|hi| num > hi)) {
                return Err(format!("\"{}\" = {num} is outside its bounds", v.name));
            }
            if let model_description::VarKind::Enumeration(e) = &v.kind
                && !md
                    .enumeration_items(&e.declared_type)
                    .iter()
                    .any(|(_, val)| f64::from(*val).to_bits() == num.to_bits())
            {
                return Err(format!("\"{}\" = {num} is not an item of {}", v.name, e.declared_type));
            }
        }
        let c = &self.clock;
        if !(c.base.is_finite() && c.h.is_finite() && c.h >= 0.0 && c.now().is_finite() && self.start_time.is_finite())
        {
            return Err("the time is not finite".into());
        }
        if self.stop_time.is_some_and(|s| !(s.is_finite() && s >= self.start_time)) {
            return Err("the stop time is not a finite time after the start time".into());
        }
        match &self.model {
            Some(m) => m.validate_state(),
            None => Ok(()),
        }
    }
}

/// Decode an FMI resource location (`file:///path`, `file:/path` or
/// `file://localhost/path`, percent-encoded) into a local path.
pub fn resource_path(uri: &str) -> Option<std::path::PathBuf> {
    let rest = uri.strip_prefix("file:")?;
    let path = if let Some(r) = rest.strip_prefix("//") {
        // authority: empty or localhost
        let slash = r.find('/')?;
        let host = &r[..slash];
        if !(host.is_empty() || host.eq_ignore_ascii_case("localhost")) {
            return None;
        }
        &r[slash..]
    } else {
        rest
    };
    if !path.starts_with('/') {
        return None;
    }
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    let s = String::from_utf8(out).ok()?;
    Some(std::path::PathBuf::from(s))
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // exact time arithmetic is what is tested
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn resource_locations_are_decoded() {
        assert_eq!(resource_path("file:///tmp/a%20b/res"), Some(PathBuf::from("/tmp/a b/res")));
        assert_eq!(resource_path("file:/tmp/x"), Some(PathBuf::from("/tmp/x")));
        assert_eq!(resource_path("file://localhost/tmp/x"), Some(PathBuf::from("/tmp/x")));
        assert_eq!(resource_path("file://otherhost/tmp/x"), None);
        assert_eq!(resource_path("http://example.invalid/x"), None);
        assert_eq!(resource_path("file:///bad%zz"), None);
        assert_eq!(resource_path("file:///trailing%2"), Some(PathBuf::from("/trailing%2")));
    }

    #[test]
    fn clock_does_not_drift() {
        let mut c = Clock::new(0.0);
        let mut summed = 0.0;
        for _ in 0..3_000_000 {
            c.advance_by(c.step_for(1e-5));
            summed += 1e-5;
        }
        // one rounding of n·h, against the drift of a running sum
        assert_eq!(c.now(), 3_000_000.0 * 1e-5);
        assert!((c.now() - 30.0).abs() < 1e-14);
        assert!((summed - 30.0_f64).abs() > 1e-10);
        c.advance_by(c.step_for(0.5));
        assert_eq!(c.now(), 3_000_000.0 * 1e-5 + 0.5);
    }

    #[test]
    fn time_tolerance() {
        assert!(approx_eq(0.30000000000000004, 0.3));
        assert!(!approx_eq(0.3, 0.30001));
    }
}
