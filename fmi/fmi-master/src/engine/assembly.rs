//! Assembly: from a [`SystemFile`] and a [`RunConfig`] to initialized
//! instances, every check done before any FMU code runs where possible.
//!
//! 1. Open every component's FMU (each run opens its own copies: runs on
//!    different threads share nothing).
//! 2. Check the SSD's declared connectors against the FMUs (exist, declared
//!    type and kind agree), and every connection (both ends exist, start is
//!    an output, end an input, same type, each input driven once); resolve
//!    them into [`Route`]s between [`Ports`].
//! 3. Resolve the time grid, the stepping order and sequence, the recorded
//!    variables, and the parameter assignments — component bindings, then
//!    system bindings, then `--set` (later wins), each type-checked.
//!    An FMU that declares a work bound (`WorkBound` vendor annotation of the export layer)
//!    is refused here if one communication step would cost it more internal steps than it
//!    accepts per `fmi2DoStep`, with the parameter value this run gives it; FMUs without the
//!    annotation run as before.
//! 4. Instantiate with the GUID of the XML, `fmi2SetupExperiment(start,
//!    stop)`, apply the assignments, enter and exit initialization mode.
//!    Instances already created are closed if a later step fails.

use crate::engine::config::{AlgebraicLoops, RunConfig, Timing};
use crate::engine::loops;
use crate::engine::ports::{Api, Component, Components, Ports, Probe, Route, api_of};
use crate::error::{SetupError, SimError};
use crate::import::{Fmu, Instance};
use crate::overrides;
use crate::system::SystemFile;
use model_description::{Causality, ModelDescription, ScalarType, ScalarVariable, Value};
use ssp::{ConnectorKind, ConnectorType, Order, SystemDescription};

/// An assembled, initialized system (inputs not yet consistent at t0).
pub(crate) struct Assembled {
    pub comps: Components,
    pub order: Order,
    pub sequence: Vec<usize>,
    pub timing: Timing,
    pub probes: Vec<Probe>,
    pub record_names: Vec<String>,
    /// The connections close an algebraic loop (and the run iterates it).
    pub algebraic_loop: bool,
}

/// An unknown variable of `comp`, with "did you mean" suggestions.
pub(crate) fn unknown_variable(context: &str, comp: &str, fmu: &Fmu, name: &str) -> SetupError {
    SetupError::UnknownVariable {
        context: context.to_string(),
        component: comp.to_string(),
        fmu: fmu.name().to_string(),
        name: name.to_string(),
        suggestion: overrides::suggest(name, fmu.model_description().variables().iter().map(|v| v.name.as_str())),
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

fn type_label(v: &ScalarVariable) -> String {
    match &v.kind {
        model_description::VarKind::Enumeration(e) => format!("Enumeration {}", e.declared_type),
        _ => format!("{:?}", v.scalar_type()),
    }
}

/// Declared connectors must exist in the FMU, with the declared type and kind.
fn check_connectors(desc: &SystemDescription, fmus: &[Fmu]) -> Result<(), SetupError> {
    for (c, fmu) in desc.components.iter().zip(fmus) {
        let md = fmu.model_description();
        for k in &c.connectors {
            let v = md
                .variable(&k.name)
                .ok_or_else(|| unknown_variable(&format!("connector {}.{}", c.name, k.name), &c.name, fmu, &k.name))?;
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
                        type_label(v),
                        fmu.name()
                    )));
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
                )));
            }
        }
    }
    Ok(())
}

/// Check every connection and resolve it into a route between output and input ports.
fn wire(
    desc: &SystemDescription,
    fmus: &[Fmu],
    names: &[String],
    outputs: &mut [Ports],
    inputs: &mut [Ports],
) -> Result<(Vec<Route>, Vec<loops::Edge>), SetupError> {
    let mut routes = Vec::new();
    let mut edges = Vec::new();
    let mut driven = std::collections::HashSet::new();
    // by name, not a search per connection: linear in the size of a (hostile) SSD
    let by_name: std::collections::HashMap<&str, usize> =
        names.iter().enumerate().map(|(i, n)| (n.as_str(), i)).collect();
    for conn in &desc.connections {
        let label = format!("connection {}", conn.label());
        let (Some(se), Some(ee)) = (&conn.start_element, &conn.end_element) else {
            return Err(SetupError::Invalid(format!(
                "{label}: connections to the system's own connectors are not supported (flat systems only)"
            )));
        };
        let find = |e: &str| {
            by_name.get(e).copied().ok_or_else(|| SetupError::UnknownComponent {
                name: format!("{e}' in {label} '"),
                known: names.join(", "),
            })
        };
        let (s, e) = (find(se)?, find(ee)?);
        let (smd, emd): (&ModelDescription, &ModelDescription) =
            (fmus[s].model_description(), fmus[e].model_description());
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
            )));
        }
        if ev.causality != Causality::Input {
            return Err(SetupError::Causality(format!(
                "{label}: the end {ee}.{} must be an input, it is {:?}",
                ev.name, ev.causality
            )));
        }
        let enumeration = |v: &ScalarVariable| v.scalar_type() == ScalarType::Enumeration;
        let api = match (api_of(sv), api_of(ev)) {
            (Some(a), Some(b)) if a == b && enumeration(sv) == enumeration(ev) => a,
            _ => {
                return Err(SetupError::TypeMismatch(format!(
                    "{label}: {se}.{} is {} but {ee}.{} is {}",
                    sv.name,
                    type_label(sv),
                    ev.name,
                    type_label(ev)
                )));
            }
        };
        if conn.linear.is_some() && api != Api::Real {
            return Err(SetupError::TypeMismatch(format!("{label}: a linear transformation needs Real variables")));
        }
        if conn.linear.is_none() {
            check_units(&label, (se, sv, smd), (ee, ev, emd))?;
        }
        if !driven.insert((e, ev.value_reference, api as u8)) {
            return Err(SetupError::Invalid(format!(
                "{label}: {ee}.{} is already driven by another connection",
                ev.name
            )));
        }
        let src_slot = outputs[s].slot(api, sv.value_reference);
        let dst_slot = inputs[e].slot(api, ev.value_reference);
        routes.push(Route { src: s, src_slot, dst: e, dst_slot, api, linear: conn.linear });
        edges.push(((s, sv.value_reference), (e, ev.value_reference)));
    }
    Ok((routes, edges))
}

/// A direct connection passes the number unchanged, so both ends must mean the same unit: the
/// same name, or names whose definitions (the FMUs' `UnitDefinitions`, else the unit registry)
/// have the same base-unit exponents, factor and offset. An end without a unit is not checked
/// (nothing declared to check against). A connection with a `LinearTransformation` converts on
/// purpose and is not checked either.
fn check_units(
    label: &str,
    (se, sv, smd): (&str, &ScalarVariable, &ModelDescription),
    (ee, ev, emd): (&str, &ScalarVariable, &ModelDescription),
) -> Result<(), SetupError> {
    let (Some(us), Some(ue)) = (sv.unit(), ev.unit()) else { return Ok(()) };
    if us == ue {
        return Ok(());
    }
    let (ms, me) = (smd.unit_meaning(us), emd.unit_meaning(ue));
    let hint = match (ms, me) {
        (Some((xs, fs, os)), Some((xe, fe, oe))) if xs == xe => {
            let same = |a: f64, b: f64| (a - b).abs() <= 1e-12 * a.abs().max(b.abs());
            if same(fs, fe) && same(os, oe) {
                return Ok(());
            }
            if os == 0.0 && oe == 0.0 {
                format!(
                    " (same dimension: add <ssc:LinearTransformation factor=\"{}\"/> to the connection to convert)",
                    fs / fe
                )
            } else {
                " (same dimension, different offset: convert with a LinearTransformation)".to_string()
            }
        }
        (Some(_), Some(_)) => " (different physical dimensions)".to_string(),
        _ => " (a unit without a definition cannot be checked; connect variables with the same unit)".to_string(),
    };
    Err(SetupError::Unit(format!("{label}: {se}.{} is in {us} but {ee}.{} is in {ue}{hint}", sv.name, ev.name)))
}

/// The stepping order and the Gauss–Seidel sequence (component indices).
fn sequence(cfg: &RunConfig, desc: &SystemDescription, names: &[String]) -> Result<(Order, Vec<usize>), SetupError> {
    let order = cfg.order.or(desc.master.order).unwrap_or_default();
    let seq_names = cfg.sequence.clone().unwrap_or_else(|| desc.master.sequence.clone());
    if seq_names.is_empty() {
        return Ok((order, (0..names.len()).collect()));
    }
    let mut seq = Vec::new();
    for n in &seq_names {
        let i = names.iter().position(|c| c == n).ok_or_else(|| SetupError::UnknownComponent {
            name: format!("{n}' in the stepping sequence '"),
            known: names.join(", "),
        })?;
        if seq.contains(&i) {
            return Err(SetupError::Invalid(format!("component {n} appears twice in the sequence")));
        }
        seq.push(i);
    }
    if seq.len() != names.len() {
        return Err(SetupError::Invalid(format!(
            "the stepping sequence ({}) must name every component ({})",
            seq_names.join(" "),
            names.join(" ")
        )));
    }
    Ok((order, seq))
}

/// The recorded variables (`--record`, else every output) as probes into `recorded`, and their column names.
fn probes(
    cfg: &RunConfig,
    fmus: &[Fmu],
    names: &[String],
    single: bool,
    recorded: &mut [Ports],
) -> Result<(Vec<Probe>, Vec<String>), SetupError> {
    let (mut probes, mut columns): (Vec<Probe>, Vec<String>) = (Vec::new(), Vec::new());
    let display = |c: usize, v: &str| if single { v.to_string() } else { format!("{}.{v}", names[c]) };
    match &cfg.record {
        Some(list) => {
            for target in list {
                let (c, vname) = resolve_target(names, single, target, "--record")?;
                let v = fmus[c]
                    .model_description()
                    .variable(vname)
                    .ok_or_else(|| unknown_variable("--record", &names[c], &fmus[c], vname))?;
                let api = api_of(v).ok_or_else(|| {
                    SetupError::TypeMismatch(format!("--record {target}: String variables cannot be recorded"))
                })?;
                let probe = (c, api, recorded[c].slot(api, v.value_reference));
                if probes.contains(&probe) {
                    // two columns of one name: `--record plant.x,plant.x`
                    return Err(SetupError::Value(format!(
                        "--record: {} is named twice (as '{target}'); record each variable once",
                        display(c, vname)
                    )));
                }
                probes.push(probe);
                columns.push(display(c, vname));
            }
        }
        None => {
            for (c, fmu) in fmus.iter().enumerate() {
                for v in fmu.model_description().variables() {
                    if v.causality == Causality::Output
                        && let Some(api) = api_of(v)
                    {
                        probes.push((c, api, recorded[c].slot(api, v.value_reference)));
                        columns.push(display(c, &v.name));
                    }
                }
            }
        }
    }
    Ok((probes, columns))
}

type Assignments = Vec<Vec<(ScalarVariable, Value)>>;

/// Parameter assignments per component, in the order applied (later wins).
fn assignments(
    desc: &SystemDescription,
    cfg: &RunConfig,
    fmus: &[Fmu],
    names: &[String],
    single: bool,
) -> Result<Assignments, SetupError> {
    let mut out: Assignments = vec![Vec::new(); fmus.len()];
    let mut assign =
        |i: usize,
         vname: &str,
         ctx: &str,
         value: &dyn Fn(&ModelDescription, &ScalarVariable) -> Result<Value, SetupError>| {
            let md = fmus[i].model_description();
            let v = md.variable(vname).ok_or_else(|| unknown_variable(ctx, &names[i], &fmus[i], vname))?;
            overrides::check_settable(v, ctx)?;
            out[i].push((v.clone(), value(md, v)?));
            Ok::<(), SetupError>(())
        };
    for (i, c) in desc.components.iter().enumerate() {
        let ctx = format!("parameter binding of {}", c.name);
        for p in &c.parameters {
            let what = format!("{ctx}: {}", p.name);
            assign(i, &p.name, &ctx, &|md, v| overrides::ssp_value(md, v, &p.value, &what))?;
        }
    }
    for p in &desc.parameters {
        let ctx = "system parameter binding";
        let (i, vname) = resolve_target(names, single, &p.name, ctx)?;
        let what = format!("{ctx}: {}", p.name);
        assign(i, vname, ctx, &|md, v| overrides::ssp_value(md, v, &p.value, &what))?;
    }
    let mut set_once = std::collections::HashMap::new();
    for o in &cfg.overrides {
        let ctx = format!("--set {}={}", o.target, o.value);
        let (i, vname) = resolve_target(names, single, &o.target, "--set")?;
        // the same duplicate in an SSD binding is refused (ssp::bindings): so is it among the
        // `--set`s of a command line (typed overrides compose programmatically: later wins)
        if matches!(o.value, overrides::OverrideValue::Text(_))
            && let Some(first) = set_once.insert((i, vname.to_string()), ctx.clone())
        {
            return Err(SetupError::Value(format!(
                "{ctx}: {}.{vname} is already set by {first}; set each variable once",
                names[i]
            )));
        }
        assign(i, vname, &ctx, &|md, v| o.value_for(md, v, &ctx))?;
    }
    Ok(out)
}

/// Refuse a step that costs an FMU more than its declared work bound (see the module docs).
fn check_work_bounds(fmus: &[Fmu], names: &[String], assignments: &Assignments, step: f64) -> Result<(), SetupError> {
    for (i, fmu) in fmus.iter().enumerate() {
        let md = fmu.model_description();
        let Some(w) = md.work_bound() else { continue };
        let parameter = &w.internal_step_parameter;
        // the value this run gives the parameter: the last assignment, else the start value
        let assigned = assignments[i].iter().rev().find(|(v, _)| &v.name == parameter).map(|(_, x)| x.clone());
        let internal_step = match assigned.or_else(|| md.variable(parameter).and_then(|v| v.start_value())) {
            Some(Value::Real(x)) => x,
            _ => {
                return Err(SetupError::Invalid(format!(
                    "component {} ({}): the work bound names {parameter}, which is not a Real parameter with a value",
                    names[i],
                    fmu.name()
                )));
            }
        };
        if w.exceeded(step, internal_step) {
            return Err(SetupError::StepTooCostly {
                component: names[i].clone(),
                fmu: fmu.name().to_string(),
                step,
                parameter: parameter.clone(),
                internal_step,
                cost: w.cost(step, internal_step),
                limit: w.max_internal_steps_per_call,
                // shown to 7 digits: shrunk by 1e-6 so that the rounded figure is still within the bound
                max_step: w.max_step(internal_step) * (1.0 - 1e-6),
            });
        }
    }
    Ok(())
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

/// Assemble the system (see the module documentation).
pub(crate) fn assemble(sys: &SystemFile, cfg: &RunConfig) -> Result<Assembled, SimError> {
    let desc = &sys.desc;
    if desc.components.is_empty() {
        return Err(SetupError::Invalid(format!("{}: the system has no components", sys.origin)).into());
    }
    // Open all FMUs first (no instance yet): structural errors come before any FMU code runs.
    let fmus =
        desc.components.iter().map(|c| Ok(Fmu::open(&sys.fmu_path(c)?)?)).collect::<Result<Vec<_>, SimError>>()?;
    let names: Vec<String> = desc.components.iter().map(|c| c.name.clone()).collect();
    let single = sys.is_single_fmu();
    check_connectors(desc, &fmus)?;
    let new_ports = || (0..fmus.len()).map(|_| Ports::default()).collect::<Vec<_>>();
    let (mut outputs, mut inputs, mut recorded) = (new_ports(), new_ports(), new_ports());
    let (routes, edges) = wire(desc, &fmus, &names, &mut outputs, &mut inputs)?;
    let algebraic_loop = loops::find(&fmus, &names, &edges);
    if let (Some(cycle), AlgebraicLoops::Refuse) = (&algebraic_loop, cfg.algebraic_loops) {
        return Err(loops::refusal(cycle).into());
    }
    let fmu_default = if single { fmus[0].model_description().default_experiment.clone() } else { None };
    let timing = Timing::resolve(cfg, desc, fmu_default.as_ref())?;
    let (order, sequence) = sequence(cfg, desc, &names)?;
    let (probes, record_names) = probes(cfg, &fmus, &names, single, &mut recorded)?;
    let mut assignments = assignments(desc, cfg, &fmus, &names, single)?;
    check_work_bounds(&fmus, &names, &assignments, timing.step)?;
    // Instantiate and initialize. Instances already created are closed
    // (terminated/freed) by `Components` if a later one fails.
    let mut comps = Components(Vec::with_capacity(fmus.len()));
    let ports = outputs.into_iter().zip(inputs).zip(recorded);
    for (i, (fmu, ((outputs, inputs), recorded))) in fmus.into_iter().zip(ports).enumerate() {
        let mut inst = fmu.instantiate(&names[i], true, cfg.echo_fmu_log)?;
        inst.setup_experiment(timing.start, Some(timing.stop))?;
        for (v, x) in std::mem::take(&mut assignments[i]) {
            set_value(&mut inst, &v, &x)?;
        }
        comps.push(Component { name: names[i].clone(), inst, fmu, outputs, inputs, recorded, incoming: Vec::new() });
    }
    for r in &routes {
        comps[r.dst].incoming.push(*r);
    }
    for c in comps.iter_mut() {
        c.inst.enter_initialization_mode()?;
    }
    for c in comps.iter_mut() {
        c.inst.exit_initialization_mode()?;
    }
    Ok(Assembled { comps, order, sequence, timing, probes, record_names, algebraic_loop: algebraic_loop.is_some() })
}

#[cfg(test)]
mod tests {
    use super::check_units;
    use model_description::{Causality, ModelBuilder, ModelDescription, ScalarVariable, Variability};

    const M: [i32; 8] = [0, 1, 0, 0, 0, 0, 0, 0];

    /// A description whose one output `y` is in `unit` (defined with `exps`, `factor`) or has no unit.
    fn md(unit: Option<(&str, [i32; 8], f64)>) -> ModelDescription {
        let mut b = ModelBuilder::new("M", "M");
        let mut y = ScalarVariable::real("y", 0, Causality::Output, Variability::Continuous).depends_on(&[]);
        if let Some((name, exps, factor)) = unit {
            b = b.unit_scaled(name, exps, factor);
            y = y.unit_of(name);
        }
        b.var(y).build().unwrap()
    }

    fn check(a: &ModelDescription, b: &ModelDescription) -> Result<(), String> {
        let (va, vb) = (a.variable("y").unwrap(), b.variable("y").unwrap());
        check_units("connection a.y → b.y", ("a", va, a), ("b", vb, b)).map_err(|e| e.to_string())
    }

    #[test]
    fn direct_connections_must_mean_the_same_unit() {
        let m = md(Some(("m", M, 1.0)));
        let mm = md(Some(("mm", M, 1e-3)));
        let metre = md(Some(("metre", M, 1.0)));
        let ms = md(Some(("m/s", [0, 1, -1, 0, 0, 0, 0, 0], 1.0)));
        let bare = md(None);
        assert_eq!(check(&m, &m), Ok(()));
        assert_eq!(check(&m, &metre), Ok(()), "same definition, another name");
        assert_eq!(check(&bare, &m), Ok(()), "nothing declared to check");
        let e = check(&mm, &m).unwrap_err();
        assert!(e.starts_with("unit mismatch: connection a.y → b.y: a.y is in mm but b.y is in m"), "{e}");
        assert!(e.contains("factor=\"0.001\""), "{e}");
        let e = check(&ms, &m).unwrap_err();
        assert!(e.contains("a.y is in m/s but b.y is in m (different physical dimensions)"), "{e}");
        // a unit the FMU does not define and the registry does not know
        let furlong = md(None);
        let mut f = furlong.clone();
        if let model_description::VarKind::Real(r) = &mut f.model_variables.variables[0].kind {
            r.unit = Some("furlong".into());
        }
        assert!(check(&f, &m).unwrap_err().contains("cannot be checked"));
    }
}
