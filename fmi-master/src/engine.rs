//! The run engine: fixed-step co-simulation of a system of FMUs.
//!
//! ## Life cycle
//! 1. Open every component's FMU (each run opens its own copies: runs on
//!    different threads share nothing), check every connection (both ends
//!    exist, start is an output, end an input, same type, declared SSD
//!    connector types agree with the FMU), instantiate with the GUID of the
//!    XML, `fmi2SetupExperiment(start, stop)`.
//! 2. Apply parameters, in this order (later wins): the component's SSP
//!    bindings, the system's SSP bindings, the command line's `--set`.
//!    Each value is type-checked against the variable (and enumeration items
//!    may be given by name).
//! 3. `fmi2EnterInitializationMode`, `fmi2ExitInitializationMode` for each
//!    component; then every connected output is read and every connected
//!    input set, so all inputs are consistent at `t0`.
//! 4. Steps `n = 0 … N−1` from `tₙ = t0 + n·h` (computed, never
//!    accumulated) to `tₙ₊₁`:
//!    * **Gauss–Seidel** (default): for each component in the sequence, set
//!      its inputs from the latest values of the outputs they are connected
//!      to, `fmi2DoStep(tₙ, h)`, read its outputs. A component later in the
//!      sequence sees outputs at `tₙ₊₁` of the ones before it and at `tₙ` of
//!      the ones after. For the closed loop the sequence is
//!      `controller plant`: read the plant's output at `tₙ` → set the
//!      controller's input → step the controller → read its command → set
//!      the plant's input → step the plant → read the plant's output at `tₙ₊₁`.
//!    * **Jacobi**: set every input from the outputs at `tₙ`, step every
//!      component, read every output.
//! 5. Recorded variables are sampled at `t0` and every `k` steps (the
//!    output interval divided by `h`, which must be an integer) and at the
//!    last step, and handed to an [`Observer`] (e.g. the streaming CSV
//!    writer): memory does not grow with the run length.
//! 6. On success and on any failure, every instance is terminated (if it
//!    was initialized) and freed when the simulation is dropped
//!    ([`Instance`]'s `Drop`), and all
//!    temporary directories are removed; the observer is finished (flushed)
//!    in both cases.

use crate::error::{SetupError, SimError};
use crate::import::{Fmu, Instance};
use crate::params::{self, Override};
use crate::ssp::{ConnectorKind, ConnectorType, Linear, Order};
use crate::system::SystemFile;
use model_description::{Causality, ModelDescription, ScalarType, ScalarVariable, Value};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Options of one run. `None` fields come from the system description
/// (SSD `DefaultExperiment` and this master's annotation), else from the
/// FMU's `DefaultExperiment` for a single-FMU run.
#[derive(Clone, Debug, Default)]
pub struct RunConfig {
    /// Start time.
    pub start: Option<f64>,
    /// Stop time.
    pub stop: Option<f64>,
    /// Communication step.
    pub step: Option<f64>,
    /// Stepping order.
    pub order: Option<Order>,
    /// Gauss–Seidel sequence of component names.
    pub sequence: Option<Vec<String>>,
    /// `--set` overrides.
    pub overrides: Vec<Override>,
    /// Recorded variables (`component.variable`); None: all outputs.
    pub record: Option<Vec<String>>,
    /// Output interval (a multiple of the step); None: every step.
    pub output_interval: Option<f64>,
    /// Print the FMUs' log lines to stderr as they come.
    pub echo_fmu_log: bool,
}

/// Receives the recorded values.
pub trait Observer {
    /// Called once before the first sample with the column names.
    fn start(&mut self, names: &[String]) -> Result<(), SimError>;
    /// One row: time and the recorded values (integers and booleans as f64).
    fn sample(&mut self, t: f64, values: &[f64]) -> Result<(), SimError>;
    /// Called at the end of the run, also after a failure.
    fn finish(&mut self) -> Result<(), SimError>;
}

/// An observer that keeps nothing.
pub struct NoObserver;
impl Observer for NoObserver {
    fn start(&mut self, _: &[String]) -> Result<(), SimError> {
        Ok(())
    }
    fn sample(&mut self, _: f64, _: &[f64]) -> Result<(), SimError> {
        Ok(())
    }
    fn finish(&mut self) -> Result<(), SimError> {
        Ok(())
    }
}

/// An observer that keeps every sample in memory (short runs, tests).
#[derive(Clone, Debug, Default)]
pub struct Recorder {
    /// Column names (without `time`).
    pub names: Vec<String>,
    /// Sample times.
    pub time: Vec<f64>,
    /// One row of values per sample time.
    pub rows: Vec<Vec<f64>>,
}

impl Recorder {
    /// The column of the recorded variable `name` (e.g. `plant.x`).
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.names.iter().position(|n| n == name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }
}

impl Observer for Recorder {
    fn start(&mut self, names: &[String]) -> Result<(), SimError> {
        self.names = names.to_vec();
        Ok(())
    }
    fn sample(&mut self, t: f64, values: &[f64]) -> Result<(), SimError> {
        self.time.push(t);
        self.rows.push(values.to_vec());
        Ok(())
    }
    fn finish(&mut self) -> Result<(), SimError> {
        Ok(())
    }
}

/// Progress display.
#[derive(Clone, Debug, Default)]
pub enum Progress {
    /// None.
    #[default]
    Off,
    /// A bar on stderr if it is a terminal, shown once the run has taken 1 s.
    Auto,
    /// Increment this (shared) bar by the number of steps taken.
    Shared(indicatif::ProgressBar),
}

/// Statistics of a finished run.
#[derive(Clone, Copy, Debug)]
pub struct RunStats {
    /// Steps taken.
    pub steps: u64,
    /// Wall time of the stepping loop.
    pub wall: Duration,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Api {
    Real,
    Integer,
    Boolean,
}

fn api_of(v: &ScalarVariable) -> Option<Api> {
    match v.scalar_type().api_type() {
        ScalarType::Real => Some(Api::Real),
        ScalarType::Integer => Some(Api::Integer),
        ScalarType::Boolean => Some(Api::Boolean),
        _ => None,
    }
}

/// Variables of one component read or written together in one FMI call per type.
#[derive(Default)]
struct Ports {
    real_vrs: Vec<u32>,
    real: Vec<f64>,
    int_vrs: Vec<u32>,
    int: Vec<i32>,
    bool_vrs: Vec<u32>,
    boolean: Vec<bool>,
}

impl Ports {
    /// Slot of (api, vr), added if new.
    fn slot(&mut self, api: Api, vr: u32) -> usize {
        let (vrs, len) = match api {
            Api::Real => (&mut self.real_vrs, self.real.len()),
            Api::Integer => (&mut self.int_vrs, self.int.len()),
            Api::Boolean => (&mut self.bool_vrs, self.boolean.len()),
        };
        if let Some(i) = vrs.iter().position(|&v| v == vr) {
            return i;
        }
        vrs.push(vr);
        match api {
            Api::Real => self.real.push(0.0),
            Api::Integer => self.int.push(0),
            Api::Boolean => self.boolean.push(false),
        }
        len
    }

    fn read(&mut self, inst: &mut Instance) -> Result<(), SimError> {
        if !self.real_vrs.is_empty() {
            inst.get_real(&self.real_vrs, &mut self.real)?;
        }
        if !self.int_vrs.is_empty() {
            inst.get_integer(&self.int_vrs, &mut self.int)?;
        }
        if !self.bool_vrs.is_empty() {
            inst.get_boolean(&self.bool_vrs, &mut self.boolean)?;
        }
        Ok(())
    }

    fn write(&self, inst: &mut Instance) -> Result<(), SimError> {
        if !self.real_vrs.is_empty() {
            inst.set_real(&self.real_vrs, &self.real)?;
        }
        if !self.int_vrs.is_empty() {
            inst.set_integer(&self.int_vrs, &self.int)?;
        }
        if !self.bool_vrs.is_empty() {
            inst.set_boolean(&self.bool_vrs, &self.boolean)?;
        }
        Ok(())
    }

    fn get(&self, api: Api, i: usize) -> f64 {
        match api {
            Api::Real => self.real[i],
            Api::Integer => f64::from(self.int[i]),
            Api::Boolean => f64::from(u8::from(self.boolean[i])),
        }
    }
}

struct Comp {
    name: String,
    // Field order is drop order: the instance goes before the FMU handle
    // (the library itself stays loaded until both are gone).
    inst: Instance,
    fmu: Fmu,
    outputs: Ports,
    inputs: Ports,
    recorded: Ports,
    /// Connections ending here.
    incoming: Vec<usize>,
}

/// The components, closing every instance before any library is unloaded
/// (see `Instance::close`): on success and on every failure path.
struct CompList(Vec<Comp>);

impl std::ops::Deref for CompList {
    type Target = Vec<Comp>;
    fn deref(&self) -> &Vec<Comp> {
        &self.0
    }
}

impl std::ops::DerefMut for CompList {
    fn deref_mut(&mut self) -> &mut Vec<Comp> {
        &mut self.0
    }
}

impl Drop for CompList {
    fn drop(&mut self) {
        for c in self.0.iter_mut() {
            c.inst.close();
        }
    }
}

struct Conn {
    src: usize,
    src_slot: usize,
    dst: usize,
    dst_slot: usize,
    api: Api,
    linear: Option<Linear>,
}

/// A system ready to run: FMUs loaded, connections checked, instances initialized.
pub struct Simulation {
    comps: CompList,
    conns: Vec<Conn>,
    sequence: Vec<usize>,
    order: Order,
    start: f64,
    step: f64,
    n_steps: u64,
    sample_every: u64,
    record: Vec<(usize, Api, usize)>,
    record_names: Vec<String>,
}

fn unknown_variable(context: &str, comp: &str, fmu: &Fmu, name: &str) -> SetupError {
    SetupError::UnknownVariable {
        context: context.to_string(),
        component: comp.to_string(),
        fmu: fmu.name().to_string(),
        name: name.to_string(),
        suggestion: params::suggest(name, fmu.model_description().variables().iter().map(|v| v.name.as_str())),
    }
}

/// Resolve `component.variable` (or a bare name in a one-component system).
fn resolve_target<'a>(
    names: &'a [String],
    single: bool,
    target: &'a str,
    context: &str,
) -> Result<(usize, &'a str), SetupError> {
    if let Some((c, v)) = target.split_once('.')
        && let Some(i) = names.iter().position(|n| n == c)
    {
        return Ok((i, v));
    }
    if single {
        return Ok((0, target));
    }
    let c = target.split_once('.').map(|(c, _)| c).unwrap_or(target);
    Err(SetupError::UnknownComponent { name: format!("{c}' in {context} '{target}"), known: names.join(", ") })
}

fn set_value(inst: &mut Instance, v: &ScalarVariable, value: &Value) -> Result<(), SimError> {
    let vr = [v.value_reference];
    match value {
        Value::Real(x) => inst.set_real(&vr, &[*x])?,
        Value::Integer(i) => inst.set_integer(&vr, &[*i])?,
        Value::Boolean(b) => inst.set_boolean(&vr, &[*b])?,
        Value::String(s) => inst.set_string(&vr, &[s.as_str()])?,
    }
    Ok(())
}

fn type_label(md: &ModelDescription, v: &ScalarVariable) -> String {
    match &v.kind {
        model_description::VarKind::Enumeration(e) => {
            let _ = md;
            format!("Enumeration {}", e.declared_type)
        }
        _ => format!("{:?}", v.scalar_type()),
    }
}

impl Simulation {
    /// Load and initialize the system.
    pub fn new(sys: &SystemFile, cfg: &RunConfig) -> Result<Simulation, SimError> {
        let desc = &sys.desc;
        if desc.components.is_empty() {
            return Err(SetupError::Invalid(format!("{}: the system has no components", sys.origin)).into());
        }
        // Open all FMUs first (no instance yet): structural errors come before any FMU code runs.
        let mut fmus = Vec::with_capacity(desc.components.len());
        for c in &desc.components {
            let path = sys.fmu_path(c)?;
            fmus.push(Fmu::open(&path)?);
        }
        let names: Vec<String> = desc.components.iter().map(|c| c.name.clone()).collect();
        // Declared connectors must exist in the FMU, with the declared type.
        for (c, fmu) in desc.components.iter().zip(&fmus) {
            let md = fmu.model_description();
            for k in &c.connectors {
                let v = md.variable(&k.name).ok_or_else(|| {
                    unknown_variable(&format!("connector {}.{}", c.name, k.name), &c.name, fmu, &k.name)
                })?;
                if let Some(t) = &k.ty {
                    let ok = matches!(
                        (t, v.scalar_type()),
                        (ConnectorType::Real(_), ScalarType::Real)
                            | (ConnectorType::Integer, ScalarType::Integer)
                            | (ConnectorType::Boolean, ScalarType::Boolean)
                            | (ConnectorType::String, ScalarType::String)
                            | (ConnectorType::Enumeration(_), ScalarType::Enumeration)
                    );
                    if !ok {
                        return Err(SetupError::TypeMismatch(format!(
                            "connector {}.{} is declared {t:?} in the SSD but is a {} variable in {}",
                            c.name,
                            k.name,
                            type_label(md, v),
                            fmu.name()
                        ))
                        .into());
                    }
                }
                let causality_ok = match k.kind {
                    ConnectorKind::Input => v.causality == Causality::Input,
                    ConnectorKind::Output => v.causality == Causality::Output,
                    ConnectorKind::Parameter => v.causality == Causality::Parameter,
                    ConnectorKind::CalculatedParameter => v.causality == Causality::CalculatedParameter,
                    ConnectorKind::Inout => true,
                };
                if !causality_ok {
                    return Err(SetupError::Causality(format!(
                        "connector {}.{} is declared kind=\"{}\" but the variable's causality is {:?}",
                        c.name,
                        k.name,
                        k.kind.as_str(),
                        v.causality
                    ))
                    .into());
                }
            }
        }
        // Connections.
        let mut outputs: Vec<Ports> = (0..fmus.len()).map(|_| Ports::default()).collect();
        let mut inputs: Vec<Ports> = (0..fmus.len()).map(|_| Ports::default()).collect();
        let mut conns = Vec::new();
        let mut driven = std::collections::HashSet::new();
        for conn in &desc.connections {
            let label = format!("connection {}", conn.label());
            let (Some(se), Some(ee)) = (&conn.start_element, &conn.end_element) else {
                return Err(SetupError::Invalid(format!(
                    "{label}: connections to the system's own connectors are not supported (flat systems only)"
                ))
                .into());
            };
            let find = |e: &str| {
                names.iter().position(|n| n == e).ok_or_else(|| SetupError::UnknownComponent {
                    name: format!("{e}' in {label} '"),
                    known: names.join(", "),
                })
            };
            let (s, e) = (find(se)?, find(ee)?);
            let smd = fmus[s].model_description();
            let emd = fmus[e].model_description();
            let sv = smd
                .variable(&conn.start_connector)
                .ok_or_else(|| unknown_variable(&label, se, &fmus[s], &conn.start_connector))?;
            let ev = emd
                .variable(&conn.end_connector)
                .ok_or_else(|| unknown_variable(&label, ee, &fmus[e], &conn.end_connector))?;
            if sv.causality != Causality::Output {
                return Err(SetupError::Causality(format!(
                    "{label}: the start {se}.{} must be an output, it is {:?}",
                    sv.name, sv.causality
                ))
                .into());
            }
            if ev.causality != Causality::Input {
                return Err(SetupError::Causality(format!(
                    "{label}: the end {ee}.{} must be an input, it is {:?}",
                    ev.name, ev.causality
                ))
                .into());
            }
            let (sa, ea) = (api_of(sv), api_of(ev));
            if sa.is_none()
                || sa != ea
                || (sv.scalar_type() == ScalarType::Enumeration) != (ev.scalar_type() == ScalarType::Enumeration)
            {
                return Err(SetupError::TypeMismatch(format!(
                    "{label}: {se}.{} is {} but {ee}.{} is {}",
                    sv.name,
                    type_label(smd, sv),
                    ev.name,
                    type_label(emd, ev)
                ))
                .into());
            }
            let api = sa.expect("checked");
            if conn.linear.is_some() && api != Api::Real {
                return Err(
                    SetupError::TypeMismatch(format!("{label}: a linear transformation needs Real variables")).into()
                );
            }
            if !driven.insert((e, ev.value_reference, api as u8)) {
                return Err(SetupError::Invalid(format!(
                    "{label}: {ee}.{} is already driven by another connection",
                    ev.name
                ))
                .into());
            }
            let src_slot = outputs[s].slot(api, sv.value_reference);
            let dst_slot = inputs[e].slot(api, ev.value_reference);
            conns.push(Conn { src: s, src_slot, dst: e, dst_slot, api, linear: conn.linear });
        }
        // Time settings.
        let single = sys.is_single_fmu();
        let fmu_default = if single { fmus[0].model_description().default_experiment.clone() } else { None };
        let start = cfg.start.or(desc.start_time).or(fmu_default.as_ref().and_then(|d| d.start_time)).unwrap_or(0.0);
        let stop = cfg.stop.or(desc.stop_time).or(fmu_default.as_ref().and_then(|d| d.stop_time)).ok_or_else(|| {
            SetupError::Invalid("no stop time: the system has no DefaultExperiment stopTime; pass --stop-time".into())
        })?;
        let step =
            cfg.step.or(desc.master.step_size).or(fmu_default.as_ref().and_then(|d| d.step_size)).ok_or_else(|| {
                SetupError::Invalid("no communication step in the system description; pass --step".into())
            })?;
        if !(step > 0.0 && step.is_finite()) {
            return Err(SetupError::Value(format!("the step must be positive and finite, not {step}")).into());
        }
        if stop.partial_cmp(&start) != Some(std::cmp::Ordering::Greater) {
            return Err(SetupError::Value(format!("the stop time {stop} must be after the start time {start}")).into());
        }
        let span = stop - start;
        let n_steps = (span / step).round();
        if (n_steps * step - span).abs() > 1e-9 * span.max(step) || n_steps < 1.0 {
            return Err(SetupError::Value(format!(
                "stop time − start time ({span}) is not a whole number of steps of {step}"
            ))
            .into());
        }
        let n_steps = n_steps as u64;
        let sample_every = match cfg.output_interval {
            None => 1,
            Some(dt) => {
                let k = (dt / step).round();
                if dt.is_nan() || dt <= 0.0 || k < 1.0 || (k * step - dt).abs() > 1e-9 * dt {
                    return Err(SetupError::Value(format!(
                        "the output interval {dt} must be a positive multiple of the step {step}"
                    ))
                    .into());
                }
                k as u64
            }
        };
        let order = cfg.order.or(desc.master.order).unwrap_or_default();
        let seq_names = cfg.sequence.clone().unwrap_or_else(|| desc.master.sequence.clone());
        let sequence = if seq_names.is_empty() {
            (0..fmus.len()).collect()
        } else {
            let mut seq = Vec::new();
            for n in &seq_names {
                let i = names.iter().position(|c| c == n).ok_or_else(|| SetupError::UnknownComponent {
                    name: format!("{n}' in the stepping sequence '"),
                    known: names.join(", "),
                })?;
                if seq.contains(&i) {
                    return Err(SetupError::Invalid(format!("component {n} appears twice in the sequence")).into());
                }
                seq.push(i);
            }
            if seq.len() != names.len() {
                return Err(SetupError::Invalid(format!(
                    "the stepping sequence ({}) must name every component ({})",
                    seq_names.join(" "),
                    names.join(" ")
                ))
                .into());
            }
            seq
        };
        // Recorded variables.
        let mut recorded: Vec<Ports> = (0..fmus.len()).map(|_| Ports::default()).collect();
        let mut record = Vec::new();
        let mut record_names = Vec::new();
        let display = |c: usize, v: &str| if single { v.to_string() } else { format!("{}.{v}", names[c]) };
        match &cfg.record {
            Some(list) => {
                for target in list {
                    let (c, vname) = resolve_target(&names, single, target, "--record")?;
                    let v = fmus[c]
                        .model_description()
                        .variable(vname)
                        .ok_or_else(|| unknown_variable("--record", &names[c], &fmus[c], vname))?;
                    let api = api_of(v).ok_or_else(|| {
                        SetupError::TypeMismatch(format!("--record {target}: String variables cannot be recorded"))
                    })?;
                    record.push((c, api, recorded[c].slot(api, v.value_reference)));
                    record_names.push(display(c, vname));
                }
            }
            None => {
                for (c, fmu) in fmus.iter().enumerate() {
                    for v in fmu.model_description().variables() {
                        if v.causality == Causality::Output
                            && let Some(api) = api_of(v)
                        {
                            record.push((c, api, recorded[c].slot(api, v.value_reference)));
                            record_names.push(display(c, &v.name));
                        }
                    }
                }
            }
        }
        // Parameter assignments, type-checked before any instance exists.
        let mut assignments: Vec<Vec<(&ScalarVariable, Value)>> = vec![Vec::new(); fmus.len()];
        for (i, c) in desc.components.iter().enumerate() {
            let md = fmus[i].model_description();
            for p in &c.parameters {
                let ctx = format!("parameter binding of {}", c.name);
                let v = md.variable(&p.name).ok_or_else(|| unknown_variable(&ctx, &c.name, &fmus[i], &p.name))?;
                params::check_settable(v, &ctx)?;
                assignments[i].push((v, params::ssp_value(md, v, &p.value, &format!("{ctx}: {}", p.name))?));
            }
        }
        for p in &desc.parameters {
            let ctx = "system parameter binding";
            let (i, vname) = resolve_target(&names, single, &p.name, ctx)?;
            let md = fmus[i].model_description();
            let v = md.variable(vname).ok_or_else(|| unknown_variable(ctx, &names[i], &fmus[i], vname))?;
            params::check_settable(v, ctx)?;
            assignments[i].push((v, params::ssp_value(md, v, &p.value, &format!("{ctx}: {}", p.name))?));
        }
        for o in &cfg.overrides {
            let ctx = format!("--set {}={}", o.target, o.value);
            let (i, vname) = resolve_target(&names, single, &o.target, "--set")?;
            let md = fmus[i].model_description();
            let v = md.variable(vname).ok_or_else(|| unknown_variable(&ctx, &names[i], &fmus[i], vname))?;
            params::check_settable(v, &ctx)?;
            assignments[i].push((v, params::parse_value(md, v, &o.value, &ctx)?));
        }
        // Instantiate and initialize. Instances already created are dropped
        // (terminated/freed) if a later one fails.
        let mut comps = CompList(Vec::with_capacity(fmus.len()));
        let mut owned: Vec<Vec<(ScalarVariable, Value)>> =
            assignments.into_iter().map(|a| a.into_iter().map(|(v, x)| (v.clone(), x)).collect()).collect();
        for (i, ((fmu, out), (inp, rec))) in
            fmus.into_iter().zip(outputs).zip(inputs.into_iter().zip(recorded)).enumerate()
        {
            let mut inst = fmu.instantiate(&names[i], true, cfg.echo_fmu_log)?;
            inst.setup_experiment(start, Some(stop))?;
            for (v, x) in std::mem::take(&mut owned[i]) {
                set_value(&mut inst, &v, &x)?;
            }
            comps.push(Comp {
                name: names[i].clone(),
                inst,
                fmu,
                outputs: out,
                inputs: inp,
                recorded: rec,
                incoming: Vec::new(),
            });
        }
        for (k, c) in conns.iter().enumerate() {
            comps[c.dst].incoming.push(k);
        }
        for c in comps.iter_mut() {
            c.inst.enter_initialization_mode()?;
        }
        for c in comps.iter_mut() {
            c.inst.exit_initialization_mode()?;
        }
        let mut sim =
            Simulation { comps, conns, sequence, order, start, step, n_steps, sample_every, record, record_names };
        // Consistent inputs at t0.
        for i in 0..sim.comps.len() {
            let c = &mut sim.comps[i];
            c.outputs.read(&mut c.inst)?;
        }
        for i in 0..sim.comps.len() {
            sim.set_inputs(i)?;
        }
        Ok(sim)
    }

    /// Column names of the recorded variables (without `time`).
    pub fn record_names(&self) -> &[String] {
        &self.record_names
    }

    /// Number of communication steps.
    pub fn n_steps(&self) -> u64 {
        self.n_steps
    }

    /// The communication step.
    pub fn step(&self) -> f64 {
        self.step
    }

    /// The start time.
    pub fn start_time(&self) -> f64 {
        self.start
    }

    /// The stepping order in use.
    pub fn order(&self) -> Order {
        self.order
    }

    /// The Gauss–Seidel sequence (component names).
    pub fn sequence(&self) -> Vec<&str> {
        self.sequence.iter().map(|&i| self.comps[i].name.as_str()).collect()
    }

    /// Every component's FMU model identifier and instance name.
    pub fn components(&self) -> Vec<(&str, &str)> {
        self.comps
            .iter()
            .map(|c| (c.name.as_str(), c.fmu.model_description().model_identifier().unwrap_or("")))
            .collect()
    }

    /// Read a numeric variable (Real, Integer, Enumeration or Boolean) of a
    /// component now, as f64 (e.g. parameter values for reports: the plant's
    /// `cutting.teeth` is an Integer).
    pub fn get_number(&mut self, component: &str, variable: &str) -> Result<f64, SimError> {
        let i = self.comps.iter().position(|c| c.name == component).ok_or_else(|| SetupError::UnknownComponent {
            name: component.to_string(),
            known: self.comps.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", "),
        })?;
        let c = &mut self.comps[i];
        let v = c
            .fmu
            .model_description()
            .variable(variable)
            .ok_or_else(|| unknown_variable("get_number", &c.name, &c.fmu, variable))?;
        let vr = [v.value_reference];
        match api_of(v) {
            Some(Api::Real) => {
                let mut out = [0.0];
                c.inst.get_real(&vr, &mut out)?;
                Ok(out[0])
            }
            Some(Api::Integer) => {
                let mut out = [0];
                c.inst.get_integer(&vr, &mut out)?;
                Ok(f64::from(out[0]))
            }
            Some(Api::Boolean) => {
                let mut out = [false];
                c.inst.get_boolean(&vr, &mut out)?;
                Ok(f64::from(u8::from(out[0])))
            }
            None => {
                Err(SetupError::TypeMismatch(format!("{component}.{variable} is a String variable, not a number"))
                    .into())
            }
        }
    }

    /// Log lines an instance has kept (for reports).
    pub fn log_lines(&self, component: &str) -> Vec<String> {
        self.comps.iter().find(|c| c.name == component).map(|c| c.inst.log_lines()).unwrap_or_default()
    }

    #[inline]
    fn set_inputs(&mut self, i: usize) -> Result<(), SimError> {
        if self.comps[i].incoming.is_empty() {
            return Ok(());
        }
        for k in 0..self.comps[i].incoming.len() {
            let c = &self.conns[self.comps[i].incoming[k]];
            let src = &self.comps[c.src].outputs;
            match c.api {
                Api::Real => {
                    let mut x = src.real[c.src_slot];
                    if let Some(l) = c.linear {
                        x = l.factor * x + l.offset;
                    }
                    self.comps[i].inputs.real[c.dst_slot] = x;
                }
                Api::Integer => {
                    let x = src.int[c.src_slot];
                    self.comps[i].inputs.int[c.dst_slot] = x;
                }
                Api::Boolean => {
                    let x = src.boolean[c.src_slot];
                    self.comps[i].inputs.boolean[c.dst_slot] = x;
                }
            }
        }
        let c = &mut self.comps[i];
        c.inputs.write(&mut c.inst)
    }

    #[inline]
    fn step_component(&mut self, i: usize, t: f64) -> Result<(), SimError> {
        let h = self.step;
        let c = &mut self.comps[i];
        c.inst.do_step(t, h)?;
        c.outputs.read(&mut c.inst)
    }

    fn sample(&mut self, t: f64, row: &mut Vec<f64>, obs: &mut dyn Observer) -> Result<(), SimError> {
        for c in self.comps.iter_mut() {
            c.recorded.read(&mut c.inst)?;
        }
        row.clear();
        for &(c, api, slot) in &self.record {
            row.push(self.comps[c].recorded.get(api, slot));
        }
        obs.sample(t, row)
    }

    /// Run from the start to the stop time. The observer is finished (flushed)
    /// whether the run succeeds or fails.
    pub fn run(&mut self, obs: &mut dyn Observer, progress: Progress) -> Result<RunStats, SimError> {
        let r = self.run_inner(obs, progress);
        let f = obs.finish();
        let stats = r?;
        f?;
        Ok(stats)
    }

    fn run_inner(&mut self, obs: &mut dyn Observer, progress: Progress) -> Result<RunStats, SimError> {
        obs.start(&self.record_names)?;
        let mut row = Vec::with_capacity(self.record.len());
        self.sample(self.start, &mut row, obs)?;
        let began = Instant::now();
        let tty = matches!(progress, Progress::Auto) && std::io::stderr().is_terminal();
        let mut bar: Option<indicatif::ProgressBar> = None;
        let mut reported = 0u64;
        const CHUNK: u64 = 4096;
        let seq = self.sequence.clone();
        let all: Vec<usize> = (0..self.comps.len()).collect();
        for n in 0..self.n_steps {
            let t = self.start + n as f64 * self.step;
            match self.order {
                Order::GaussSeidel => {
                    for &i in &seq {
                        self.set_inputs(i)?;
                        self.step_component(i, t)?;
                    }
                }
                Order::Jacobi => {
                    for &i in &all {
                        self.set_inputs(i)?;
                    }
                    for &i in &all {
                        self.step_component(i, t)?;
                    }
                }
            }
            let done = n + 1;
            if done.is_multiple_of(self.sample_every) || done == self.n_steps {
                self.sample(self.start + done as f64 * self.step, &mut row, obs)?;
            }
            if done.is_multiple_of(CHUNK) || done == self.n_steps {
                match &progress {
                    Progress::Off => {}
                    Progress::Shared(b) => {
                        b.inc(done - reported);
                        reported = done;
                    }
                    Progress::Auto => {
                        if bar.is_none() && tty && began.elapsed() > Duration::from_secs(1) {
                            let b = indicatif::ProgressBar::new(self.n_steps);
                            b.set_style(
                                indicatif::ProgressStyle::with_template(
                                    "{elapsed_precise} [{bar:40}] {percent:>3}% {human_pos}/{human_len} steps, ETA {eta}",
                                )
                                .expect("valid template")
                                .progress_chars("=> "),
                            );
                            bar = Some(b);
                        }
                        if let Some(b) = &bar {
                            b.set_position(done);
                        }
                    }
                }
            }
        }
        if let Some(b) = bar {
            b.finish_and_clear();
        }
        Ok(RunStats { steps: self.n_steps, wall: began.elapsed() })
    }
}
