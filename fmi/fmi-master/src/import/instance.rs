//! [`Instance`]: the safe co-simulation slave. It keeps the FMI 2.0 state
//! machine on the master's side (a call the current state does not allow is
//! an [`FmuError::State`] and never reaches the FMU), turns every status
//! other than `fmi2OK`/`fmi2Warning` into an [`FmuError::Call`] naming the
//! instance, the call, the time and the FMU's recent log lines, and closes
//! the instance on drop (terminate if initialized, then free; nothing after
//! `fmi2Fatal`, when FMI forbids further calls).

use crate::error::FmuError;
use crate::import::ffi::RawInstance;
use crate::import::log::LOG_QUOTED;
use fmi2_abi::{fmi2Error, fmi2Fatal, fmi2OK, fmi2Status, fmi2Warning, status_name};
use std::ffi::CString;

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
    raw: RawInstance,
    phase: Phase,
    time: f64,
    name: String,
    model: String,
}

impl std::fmt::Debug for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Instance").field("name", &self.name).field("model", &self.model).finish()
    }
}

const GET_OK: [Phase; 5] =
    [Phase::Instantiated, Phase::Initialization, Phase::Stepping, Phase::Terminated, Phase::Error];
const SET_OK: [Phase; 3] = [Phase::Instantiated, Phase::Initialization, Phase::Stepping];

impl Instance {
    /// Wrap a freshly instantiated slave.
    pub(crate) fn new(raw: RawInstance, name: &str, model: &str) -> Instance {
        Instance { raw, phase: Phase::Instantiated, time: 0.0, name: name.to_string(), model: model.to_string() }
    }

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
        self.raw.log().all()
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
                    log: self.raw.log().excerpt(LOG_QUOTED),
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
        let s = self.raw.set_debug_logging(on);
        self.check("fmi2SetDebugLogging", s, self.time)
    }

    /// `fmi2SetupExperiment` (no tolerance; stop time if given).
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), FmuError> {
        self.require("fmi2SetupExperiment", &[Phase::Instantiated])?;
        let s = self.raw.setup_experiment(start, stop);
        self.time = start;
        self.check("fmi2SetupExperiment", s, start)
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization_mode(&mut self) -> Result<(), FmuError> {
        self.require("fmi2EnterInitializationMode", &[Phase::Instantiated])?;
        let s = self.raw.enter_initialization_mode();
        self.phase = Phase::Initialization;
        self.check("fmi2EnterInitializationMode", s, self.time)
    }

    /// `fmi2ExitInitializationMode`.
    pub fn exit_initialization_mode(&mut self) -> Result<(), FmuError> {
        self.require("fmi2ExitInitializationMode", &[Phase::Initialization])?;
        let s = self.raw.exit_initialization_mode();
        self.phase = Phase::Stepping;
        self.check("fmi2ExitInitializationMode", s, self.time)
    }

    /// `fmi2DoStep(t, h, noSetFMUStatePriorToCurrentPoint = true)`.
    #[inline]
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), FmuError> {
        if self.phase != Phase::Stepping {
            self.require("fmi2DoStep", &[Phase::Stepping])?;
        }
        let s = self.raw.do_step(t, h);
        if s == fmi2OK {
            self.time = t + h;
            return Ok(());
        }
        self.check("fmi2DoStep", s, t)?;
        self.time = t + h;
        Ok(())
    }

    /// One step of the stepping loop for one component: `fmi2SetReal(ins)` (skipped when
    /// empty), `fmi2DoStep(t, h)`, `fmi2GetReal(outs)` (skipped when empty), with the phase and
    /// the slice lengths checked once for the three calls; the first status other than
    /// `fmi2OK` stops the sequence and is reported as [`set_real`](Self::set_real),
    /// [`do_step`](Self::do_step) or [`get_real`](Self::get_real) report it.
    #[inline]
    pub fn step_reals(
        &mut self,
        (in_vrs, ins): (&[u32], &[f64]),
        t: f64,
        h: f64,
        (out_vrs, outs): (&[u32], &mut [f64]),
    ) -> Result<(), FmuError> {
        if self.phase != Phase::Stepping || in_vrs.len() != ins.len() || out_vrs.len() != outs.len() {
            if !in_vrs.is_empty() {
                self.set_real(in_vrs, ins)?;
            }
            self.do_step(t, h)?;
            return if out_vrs.is_empty() { Ok(()) } else { self.get_real(out_vrs, outs) };
        }
        if !in_vrs.is_empty() {
            let s = self.raw.set_real(in_vrs, ins);
            if s != fmi2OK {
                self.check("fmi2SetReal", s, self.time)?;
            }
        }
        self.do_step(t, h)?;
        if !out_vrs.is_empty() {
            let s = self.raw.get_real(out_vrs, outs);
            if s != fmi2OK {
                self.check("fmi2GetReal", s, self.time)?;
            }
        }
        Ok(())
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> Result<(), FmuError> {
        self.require("fmi2Terminate", &[Phase::Initialization, Phase::Stepping])?;
        let s = self.raw.terminate();
        self.phase = Phase::Terminated;
        self.check("fmi2Terminate", s, self.time)
    }

    /// `fmi2Reset`: back to the instantiated state.
    pub fn reset(&mut self) -> Result<(), FmuError> {
        self.require(
            "fmi2Reset",
            &[Phase::Instantiated, Phase::Initialization, Phase::Stepping, Phase::Terminated, Phase::Error],
        )?;
        let s = self.raw.reset();
        self.phase = Phase::Instantiated;
        self.check("fmi2Reset", s, self.time)
    }

    /// `fmi2GetReal`.
    #[inline]
    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), FmuError> {
        self.lengths("fmi2GetReal", vrs.len(), out.len())?;
        self.require("fmi2GetReal", &GET_OK)?;
        let s = self.raw.get_real(vrs, out);
        if s == fmi2OK { Ok(()) } else { self.check("fmi2GetReal", s, self.time) }
    }

    /// `fmi2SetReal`.
    #[inline]
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), FmuError> {
        self.lengths("fmi2SetReal", vrs.len(), values.len())?;
        self.require("fmi2SetReal", &SET_OK)?;
        let s = self.raw.set_real(vrs, values);
        if s == fmi2OK { Ok(()) } else { self.check("fmi2SetReal", s, self.time) }
    }

    /// `fmi2GetInteger` (also for enumerations).
    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> Result<(), FmuError> {
        self.lengths("fmi2GetInteger", vrs.len(), out.len())?;
        self.require("fmi2GetInteger", &GET_OK)?;
        let s = self.raw.get_integer(vrs, out);
        self.check("fmi2GetInteger", s, self.time)
    }

    /// `fmi2SetInteger` (also for enumerations).
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<(), FmuError> {
        self.lengths("fmi2SetInteger", vrs.len(), values.len())?;
        self.require("fmi2SetInteger", &SET_OK)?;
        let s = self.raw.set_integer(vrs, values);
        self.check("fmi2SetInteger", s, self.time)
    }

    /// `fmi2GetBoolean`.
    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> Result<(), FmuError> {
        self.lengths("fmi2GetBoolean", vrs.len(), out.len())?;
        self.require("fmi2GetBoolean", &GET_OK)?;
        let s = self.raw.get_boolean(vrs, out);
        self.check("fmi2GetBoolean", s, self.time)
    }

    /// `fmi2SetBoolean`.
    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<(), FmuError> {
        self.lengths("fmi2SetBoolean", vrs.len(), values.len())?;
        self.require("fmi2SetBoolean", &SET_OK)?;
        let s = self.raw.set_boolean(vrs, values);
        self.check("fmi2SetBoolean", s, self.time)
    }

    /// `fmi2GetString` (copied out immediately: FMU strings are only valid until the next call).
    pub fn get_string(&mut self, vrs: &[u32]) -> Result<Vec<String>, FmuError> {
        self.require("fmi2GetString", &GET_OK)?;
        let (s, values) = self.raw.get_string(vrs);
        self.check("fmi2GetString", s, self.time)?;
        Ok(values)
    }

    /// `fmi2SetString`.
    pub fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> Result<(), FmuError> {
        self.lengths("fmi2SetString", vrs.len(), values.len())?;
        self.require("fmi2SetString", &SET_OK)?;
        let owned: Vec<CString> =
            values.iter().map(|v| CString::new(*v)).collect::<Result<_, _>>().map_err(|_| FmuError::Argument {
                instance: self.name.clone(),
                call: "fmi2SetString",
                message: "a string value contains a NUL byte".into(),
            })?;
        let borrowed: Vec<&std::ffi::CStr> = owned.iter().map(CString::as_c_str).collect();
        let s = self.raw.set_string(vrs, &borrowed);
        self.check("fmi2SetString", s, self.time)
    }

    /// Terminate (if initialized) and free the instance now; later calls
    /// fail with a state error and dropping does nothing more. Systems close
    /// all their instances before any library is unloaded, because some
    /// FMUs share process-wide state between copies of their library
    /// (pythonfmu's embedded interpreter is finalized by the copy that
    /// started it).
    pub fn close(&mut self) {
        match self.phase {
            Phase::Freed => return,
            Phase::Fatal => self.raw.abandon(),
            Phase::Initialization | Phase::Stepping => {
                // The status is irrelevant on this path.
                let _ = self.raw.terminate();
                self.raw.free();
            }
            Phase::Instantiated | Phase::Terminated | Phase::Error => self.raw.free(),
        }
        self.phase = Phase::Freed;
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        self.close();
    }
}
