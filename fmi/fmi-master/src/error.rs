//! Error types of the master.
//!
//! [`FmuError`] is what loading an FMU and calling it can fail with: every
//! failed FMI call names the instance, the call, the simulation time and
//! quotes the FMU's own recent log lines. [`SetupError`] covers a system
//! that cannot be assembled (unknown component or variable, type mismatch,
//! bad `--set` value, missing FMU). [`SimError`] is the union the run engine
//! returns. I/O errors are part of the message and not also a `source()`, so
//! an error chain printed with `{:#}` states each cause once.

use std::fmt;
use std::path::PathBuf;

/// The last log lines of an FMU instance, quoted in errors.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LogExcerpt(pub Vec<String>);

impl fmt::Display for LogExcerpt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return write!(f, "\n  (the FMU logged nothing)");
        }
        write!(f, "\n  the FMU's log:")?;
        for l in &self.0 {
            write!(f, "\n    {l}")?;
        }
        Ok(())
    }
}

/// Errors from opening an FMU and from calls into it.
#[derive(Debug, thiserror::Error)]
pub enum FmuError {
    /// File-system error.
    #[error("{context} {}: {error}", path.display())]
    Io {
        /// What was being done.
        context: &'static str,
        /// The path involved.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// The archive is not a readable zip, has an unsafe entry, or exceeds the extraction limits.
    #[error(transparent)]
    Archive(#[from] fmi_archive::ArchiveError),
    /// `modelDescription.xml` missing or unparsable.
    #[error("FMU {fmu}: {message}")]
    Description {
        /// FMU file name.
        fmu: String,
        /// What is wrong.
        message: String,
    },
    /// The FMU has no co-simulation interface.
    #[error("FMU {fmu} does not support co-simulation (its modelDescription.xml has no <CoSimulation> element)")]
    NotCoSimulation {
        /// FMU file name.
        fmu: String,
    },
    /// No shared library for this platform.
    #[error("FMU {fmu} has no binary for {platform}; it has: {available}")]
    MissingBinary {
        /// FMU file name.
        fmu: String,
        /// The platform we need (the host's, e.g. `linux64`).
        platform: &'static str,
        /// Platforms the archive has binaries for.
        available: String,
    },
    /// `dlopen` failed.
    #[error("FMU {fmu}: cannot load {}: {message}{hint}", path.display())]
    Load {
        /// FMU file name.
        fmu: String,
        /// The shared library.
        path: PathBuf,
        /// The loader's message.
        message: String,
        /// A hint for known cases (e.g. pythonfmu needs libpython).
        hint: String,
    },
    /// Required FMI functions are not exported.
    #[error("FMU {fmu}: the binary does not export the FMI 2.0 function(s) {missing}")]
    MissingSymbols {
        /// FMU file name.
        fmu: String,
        /// Missing function names.
        missing: String,
    },
    /// The binary reports another FMI version than the XML.
    #[error("FMU {fmu}: the binary reports FMI version '{version}', expected 2.0")]
    Version {
        /// FMU file name.
        fmu: String,
        /// What `fmi2GetVersion` returned.
        version: String,
    },
    /// `fmi2Instantiate` returned NULL (wrong GUID, bad resources, ...).
    #[error("FMU {model}: fmi2Instantiate of instance '{instance}' failed (returned NULL){log}")]
    Instantiate {
        /// Instance name.
        instance: String,
        /// Model identifier.
        model: String,
        /// The FMU's log.
        log: LogExcerpt,
    },
    /// An FMI call returned Discard, Error, Fatal or Pending.
    #[error("FMU instance '{instance}' ({model}): {call} returned {status} at t = {time} s{log}")]
    Call {
        /// Instance name.
        instance: String,
        /// Model identifier.
        model: String,
        /// The FMI function.
        call: &'static str,
        /// The status name (`fmi2Error`, ...).
        status: &'static str,
        /// Simulation time of the call (the communication point for `fmi2DoStep`).
        time: f64,
        /// The FMU's recent log lines.
        log: LogExcerpt,
    },
    /// A call the instance cannot accept in its current state (caught by the master).
    #[error("FMU instance '{instance}': {call} is not allowed {state}")]
    State {
        /// Instance name.
        instance: String,
        /// The FMI function.
        call: &'static str,
        /// Description of the current state.
        state: &'static str,
    },
    /// Invalid arguments given by the master's caller.
    #[error("FMU instance '{instance}': {call}: {message}")]
    Argument {
        /// Instance name.
        instance: String,
        /// The FMI function.
        call: &'static str,
        /// What is wrong.
        message: String,
    },
}

/// Errors while assembling a system (before any step is taken).
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    /// A component name that the system does not have.
    #[error("unknown component '{name}' (the system has: {known})")]
    UnknownComponent {
        /// The name given.
        name: String,
        /// The component names of the system.
        known: String,
    },
    /// A variable name the FMU does not declare.
    #[error("{context}: component '{component}' ({fmu}) has no variable '{name}'{suggestion}")]
    UnknownVariable {
        /// Where the name was used (a connection, `--set`, `--record`...).
        context: String,
        /// Component name.
        component: String,
        /// FMU file name.
        fmu: String,
        /// The name given.
        name: String,
        /// ", did you mean …?" or empty.
        suggestion: String,
    },
    /// Connected or assigned types do not agree.
    #[error("type mismatch: {0}")]
    TypeMismatch(String),
    /// A connection between variables of different units, without a conversion.
    #[error("unit mismatch: {0}")]
    Unit(String),
    /// A variable used against its causality (e.g. a connection into an output).
    #[error("{0}")]
    Causality(String),
    /// A `--set` or parameter value that cannot be used.
    #[error("{0}")]
    Value(String),
    /// A component's FMU file does not exist.
    #[error("component {component}: FMU '{source_uri}' not found (looked at {looked_at}){hint}")]
    MissingFmu {
        /// Component name.
        component: String,
        /// Its `source` in the system description.
        source_uri: String,
        /// The paths tried.
        looked_at: String,
        /// What to do about it, or empty.
        hint: String,
    },
    /// The communication step costs an FMU more internal steps per `fmi2DoStep` than its
    /// declared work bound (`WorkBound` vendor annotation) allows: refused before instantiating.
    #[error(
        "component {component} ({fmu}): a communication step of {step} s costs {cost:.3e} internal steps \
         ({parameter} = {internal_step} s), more than the {limit:e} per fmi2DoStep the FMU declares \
         (WorkBound in its modelDescription.xml); use a step of at most {max_step:.6e} s"
    )]
    StepTooCostly {
        /// Component name.
        component: String,
        /// FMU file name.
        fmu: String,
        /// The communication step.
        step: f64,
        /// The internal-step parameter.
        parameter: String,
        /// Its value in this run.
        internal_step: f64,
        /// Internal steps one call would cost.
        cost: f64,
        /// The declared limit per call.
        limit: f64,
        /// The largest step within the limit.
        max_step: f64,
    },
    /// Anything else about the system description.
    #[error("{0}")]
    Invalid(String),
}

/// Everything a simulation run can fail with.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// Loading or calling an FMU failed.
    #[error(transparent)]
    Fmu(#[from] FmuError),
    /// The system could not be assembled.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The system description could not be read.
    #[error(transparent)]
    Ssp(#[from] ssp::SspError),
    /// Writing results failed.
    #[error("writing {}: {error}", path.display())]
    Output {
        /// The output file.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// An output path that the run must not write (an input of the run, a directory, or a
    /// file another run is writing).
    #[error("output {}: {message}", path.display())]
    OutputRefused {
        /// The output file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// The fixed-point iteration of an algebraic loop did not converge.
    #[error("{0}")]
    AlgebraicLoop(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn call_errors_name_the_instance_the_call_the_time_and_quote_the_log() {
        let e = FmuError::Call {
            instance: "plant".into(),
            model: "MillingPlant".into(),
            call: "fmi2DoStep",
            status: "fmi2Error",
            time: 0.125,
            log: LogExcerpt(vec!["fmi2Error [logStatusError] state is not finite".into()]),
        };
        assert_eq!(
            e.to_string(),
            "FMU instance 'plant' (MillingPlant): fmi2DoStep returned fmi2Error at t = 0.125 s\n  \
             the FMU's log:\n    fmi2Error [logStatusError] state is not finite"
        );
        let e = FmuError::Instantiate { instance: "c".into(), model: "M".into(), log: LogExcerpt(Vec::new()) };
        assert_eq!(
            e.to_string(),
            "FMU M: fmi2Instantiate of instance 'c' failed (returned NULL)\n  (the FMU logged nothing)"
        );
    }

    #[test]
    fn setup_errors_say_what_and_where() {
        let e = SetupError::UnknownVariable {
            context: "connection plant.xx → controller.y".into(),
            component: "plant".into(),
            fmu: "MillingPlant.fmu".into(),
            name: "xx".into(),
            suggestion: " (did you mean x?)".into(),
        };
        assert_eq!(
            e.to_string(),
            "connection plant.xx → controller.y: component 'plant' (MillingPlant.fmu) has no variable 'xx' (did you mean x?)"
        );
        let e: SimError =
            FmuError::MissingBinary { fmu: "A.fmu".into(), platform: "linux64", available: "win64".into() }.into();
        assert_eq!(e.to_string(), "FMU A.fmu has no binary for linux64; it has: win64");
    }
}
