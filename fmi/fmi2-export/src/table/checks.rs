//! The checks every FMU adapter runs on its [`Table`](super::Table) (feature `checks`; call
//! them from the adapter's tests). Each returns `Err` with a message naming the variable.
//!
//! * [`description_matches_table`]: the generated `modelDescription.xml`, parsed back, holds
//!   exactly the table's variables with their attributes and start values, and the generated
//!   per-step path agrees with the rows ([`direct_paths_match_rows`]).
//! * [`parameter_round_trips`]: every parameter set to a distinct value through the instance
//!   API (the code path of `fmi2Set*`) arrives in the core's parameter struct, and nothing else
//!   changes.
//! * [`assignments_round_trip`]: a parameter set → `(name, value)` pairs → store → parameter
//!   set is the identity.
//! * [`parameter_coverage`]: every leaf field of the serialized parameter struct is written by
//!   some row, so a field cannot be added to the core without its row.
//! * [`work_bound_matches_internal_steps`]: the work bound declared in the description is the
//!   model's own cost of a step.
//! * [`non_finite_inputs_are_refused`]: every Real input refuses NaN and ±Inf with a message
//!   naming it, and the instance steps on.
//! * [`corrupted_states_after_steps`]: [`corrupted_states_never_panic_or_hang`] on a state
//!   reached by stepping with every Real input at a given value.
//!
//! * [`start_values_are_the_defaults`]: the start values read back are the default parameters.
//! * [`work_is`]: what the adapter says a step costs ([`Work`]) is what the model counts.
//! * [`parameter_extremes_are_safe`], [`tunable_parameters_take_effect`]: the hostile audit's
//!   per-parameter values, and tunable parameters honoured between steps ([`extremes`]).
//!
//! [`adapter_tests!`](crate::adapter_tests!) runs them all as the tests of one adapter. The
//! helpers in [`instances`] (re-exported here: [`vr`], [`ready`], [`ready_with`],
//! [`initializing`], [`real`], [`set_real`], [`stepped`], [`Quiet`]) give instances to the
//! adapter's own tests.

use super::{Attrs, ChoiceType, Row, Table, TableModel};
use crate::instance::Instance;
use crate::model::{Environment, Values};
use model_description::{Causality, ModelDescription, ScalarType, Value, Variability};
use serde::Serialize;
use std::collections::BTreeMap;

pub mod extremes;
pub mod instances;
mod suite;
pub use extremes::*;
pub use instances::*;
pub use suite::*;

/// A value of a row that differs from `current` and stays inside the row's bounds.
pub fn distinct_value(attrs: &Attrs, choice: Option<&ChoiceType>, current: &Value) -> Value {
    let (lo, hi) = attrs.bounds.unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
    match current {
        Value::Real(d) => {
            let mut c = if *d == 0.0 { 1e-3 * hi.min(1.0) } else { d * 1.001 };
            if !(lo..=hi).contains(&c) || c.to_bits() == d.to_bits() {
                c = if *d == 0.0 { 1e-3 * lo.max(-1.0) } else { d * 0.999 };
            }
            Value::Real(c)
        }
        Value::Integer(i) => match choice {
            Some(t) => Value::Integer(*i % t.items.len() as i32 + 1),
            None if f64::from(*i) < hi => Value::Integer(i + 1),
            None => Value::Integer(i - 1),
        },
        Value::Boolean(b) => Value::Boolean(!b),
        Value::String(s) => Value::String(format!("{s}x")),
    }
}

fn same(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Real(x), Value::Real(y)) => (x - y).abs() <= 1e-12 * x.abs().max(y.abs()),
        (a, b) => a == b,
    }
}

/// A row as the XML should show it: attributes, type, enumeration, causality, start.
type Expected<'a> = (&'a Attrs, ScalarType, Option<&'a ChoiceType>, Causality, Option<Value>);

/// The generated description, parsed back from XML, holds exactly the table's variables.
pub fn description_matches_table<M: TableModel>() -> Result<(), String> {
    let md = M::description();
    let xml = md.to_xml().map_err(|e| e.to_string())?;
    let parsed = ModelDescription::from_xml(&xml).map_err(|e| e.to_string())?;
    let t = M::table();
    let defaults = M::Params::default();
    let inputs = M::Inputs::default();
    let mut expected: Vec<Expected<'_>> = Vec::new();
    for r in &t.vars.inputs {
        expected.push((&r.attrs, r.ty, r.choice.as_ref(), Causality::Input, Some(r.get(&inputs))));
    }
    for r in &t.vars.outputs {
        expected.push((&r.attrs, r.ty, r.choice.as_ref(), Causality::Output, None));
    }
    for r in &t.vars.parameters {
        expected.push((&r.attrs, r.ty, r.choice.as_ref(), Causality::Parameter, Some(r.get(&defaults))));
    }
    if parsed.variables().len() != expected.len() {
        return Err(format!("{} variables in the XML, {} rows in the table", parsed.variables().len(), expected.len()));
    }
    for ((a, ty, choice, c, start), v) in expected.into_iter().zip(parsed.variables()) {
        let what = |field: &str| format!("{}: {field} differs between the table and the XML", a.name);
        if v.name != a.name {
            return Err(format!("XML has {} where the table has {}", v.name, a.name));
        }
        if v.value_reference != a.vr {
            return Err(what("value reference"));
        }
        if v.scalar_type() != ty {
            return Err(what("type"));
        }
        if v.causality != c {
            return Err(what("causality"));
        }
        let variability = match (c, ty) {
            (Causality::Parameter, _) if a.tunable => Variability::Tunable,
            (Causality::Parameter, _) => Variability::Fixed,
            (_, ScalarType::Real) if !a.discrete => Variability::Continuous,
            _ => Variability::Discrete,
        };
        if v.variability != variability {
            return Err(what("variability"));
        }
        if v.unit().unwrap_or("") != a.unit {
            return Err(what("unit"));
        }
        let (lo, hi) = v.range();
        let bounds = match ty {
            // integer bounds are stored as integers
            ScalarType::Integer | ScalarType::Enumeration => a.bounds.map(|(l, h)| (l as i32 as f64, h as i32 as f64)),
            _ => a.bounds,
        };
        if (lo, hi) != (bounds.map(|b| b.0), bounds.map(|b| b.1)) {
            return Err(what("bounds"));
        }
        if v.description.as_deref().unwrap_or("") != a.description {
            return Err(what("description"));
        }
        if v.start_value() != start {
            return Err(format!("{}: XML start {:?}, table start {start:?}", a.name, v.start_value()));
        }
        if let Some(t) = choice {
            let items = parsed.enumeration_items(t.name);
            let names: Vec<&str> = items.iter().map(|(n, _)| n.as_str()).collect();
            let expected: Vec<&str> = t.items.iter().map(|(n, _)| *n).collect();
            if names != expected || items.iter().enumerate().any(|(i, (_, k))| *k != i as i32 + 1) {
                return Err(format!("{}: enumeration items {names:?} in the XML, {expected:?} in the table", a.name));
            }
        }
    }
    // every output is listed in ModelStructure with an empty dependency list (no feedthrough)
    let unknowns = parsed.model_structure.outputs.as_ref().map(|o| o.unknowns.as_slice()).unwrap_or(&[]);
    let outputs: Vec<usize> = parsed
        .variables()
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Output)
        .map(|(i, _)| i + 1)
        .collect();
    if unknowns.iter().map(|u| u.index).collect::<Vec<_>>() != outputs
        || unknowns.iter().any(|u| u.dependencies.as_deref() != Some(""))
    {
        return Err(format!(
            "ModelStructure/Outputs {unknowns:?} does not list the outputs {outputs:?} without dependencies"
        ));
    }
    direct_paths_match_rows::<M>()
}

/// The per-step path generated by `variables!` ([`super::Direct`], run by `read_inputs` and
/// `write_outputs`) moves what the rows' own `get`/`set` move: with every input at a distinct
/// value in the store, `read_inputs` gives the struct that setting each row gives; with every
/// output field at a distinct value, `write_outputs` gives the store that getting each row
/// gives (value references, fields and types all checked at once).
pub fn direct_paths_match_rows<M: TableModel>() -> Result<(), String> {
    let t = M::table();
    let mut v = Values::from_description(M::description());
    let start = M::Inputs::default();
    for r in &t.vars.inputs {
        v.set(r.attrs.vr, &distinct_value(&r.attrs, r.choice.as_ref(), &r.get(&start)));
    }
    let fast = t.read_inputs(&v)?;
    let mut reference = M::Inputs::default();
    for r in &t.vars.inputs {
        r.set(&mut reference, &v.get(r.ty.api_type(), r.attrs.vr))?;
    }
    for r in &t.vars.inputs {
        if r.get(&fast) != r.get(&reference) {
            return Err(format!(
                "input {}: read_inputs gives {:?}, the row {:?}",
                r.attrs.name,
                r.get(&fast),
                r.get(&reference)
            ));
        }
    }
    let mut o = M::Outputs::default();
    for r in &t.vars.outputs {
        let x = distinct_value(&r.attrs, r.choice.as_ref(), &r.get(&o));
        r.set(&mut o, &x)?;
    }
    let mut fast = Values::from_description(M::description());
    t.write_outputs(&o, &mut fast);
    let mut reference = Values::from_description(M::description());
    for r in &t.vars.outputs {
        reference.set(r.attrs.vr, &r.get(&o));
    }
    for r in &t.vars.outputs {
        let (a, b) = (fast.get(r.ty.api_type(), r.attrs.vr), reference.get(r.ty.api_type(), r.attrs.vr));
        if a != b {
            return Err(format!("output {}: write_outputs stores {a:?}, the row {b:?}", r.attrs.name));
        }
    }
    if fast != reference {
        return Err("write_outputs changed a variable that is not an output".into());
    }
    Ok(())
}

/// The causality-input Real variables of `M`: (name, value reference).
pub(crate) fn real_inputs<M: crate::Fmi2Model>() -> Vec<(String, u32)> {
    M::description()
        .variables()
        .iter()
        .filter(|v| v.causality == Causality::Input && v.scalar_type() == ScalarType::Real)
        .map(|v| (v.name.clone(), v.value_reference))
        .collect()
}

/// Every Real input of `M` discards NaN, +Inf and −Inf (`fmi2Discard` with a message naming the
/// input; the input keeps its previous value) and the instance takes a step of `h` afterwards.
/// Errs when `M` has no Real input.
pub fn non_finite_inputs_are_refused<M: crate::Fmi2Model>(h: f64) -> Result<(), String> {
    let inputs = real_inputs::<M>();
    if inputs.is_empty() {
        return Err("no Real input to check".into());
    }
    for (name, vr) in inputs {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut inst = ready::<M>();
            let mut before = Vec::new();
            inst.get("fmi2GetReal", ScalarType::Real, &[vr], &mut before).map_err(|e| format!("{name}: {e:?}"))?;
            match inst.set("fmi2SetReal", ScalarType::Real, &[vr], &[Value::Real(bad)]) {
                Err(crate::instance::CallError::Discard(m)) if m.contains(name.as_str()) => {}
                other => return Err(format!("{name} = {bad}: {other:?} (expected fmi2Discard naming it)")),
            }
            let mut after = Vec::new();
            inst.get("fmi2GetReal", ScalarType::Real, &[vr], &mut after).map_err(|e| format!("{name}: {e:?}"))?;
            if before != after {
                return Err(format!("{name} = {bad} was discarded but the input changed: {before:?} -> {after:?}"));
            }
            inst.do_step(0.0, h).map_err(|e| format!("a step after discarding {name} = {bad}: {e:?}"))?;
        }
    }
    Ok(())
}

/// [`corrupted_states_never_panic_or_hang`] on the state of [`stepped`]`(input, steps, h)` (so
/// the state holds history, not only start values).
pub fn corrupted_states_after_steps<M: crate::Fmi2Model>(
    input: f64,
    steps: usize,
    h: f64,
    seed: u64,
    tries: usize,
) -> (usize, usize) {
    let bytes = stepped::<M>(input, steps, h).snapshot().serialize().expect("a serializable state");
    corrupted_states_never_panic_or_hang::<M>(&bytes, seed, tries, ready::<M>, h)
}

/// Build the model through the instance API with `sets` applied before initialization.
fn initialized<M: TableModel>(sets: &[(&Row<M::Params>, Value)]) -> Result<M::Params, String> {
    let mut inst = Instance::<M>::new(Environment::default(), false, Box::new(Quiet));
    for (row, value) in sets {
        inst.set("fmi2Set", row.ty.api_type(), &[row.attrs.vr], std::slice::from_ref(value))
            .map_err(|e| format!("setting {} = {value:?}: {e:?}", row.attrs.name))?;
    }
    inst.setup_experiment(0.0, None).map_err(|e| format!("{e:?}"))?;
    inst.enter_initialization().map_err(|e| format!("{e:?}"))?;
    inst.exit_initialization().map_err(|e| format!("initialization: {e:?}"))?;
    Ok(inst.model().ok_or("no model after initialization")?.parameters().clone())
}

/// Every parameter, set alone to a distinct value through the instance API, arrives in the
/// core's parameter struct, and every other parameter keeps its start value. `valid` gives the
/// value to use for rows where [`distinct_value`] would fail the model's own validation.
pub fn parameter_round_trips<M: TableModel>(valid: &[(&str, Value)]) -> Result<(), String> {
    let t = M::table();
    let defaults = initialized::<M>(&[])?;
    for row in &t.vars.parameters {
        let start = row.get(&defaults);
        let value = match valid.iter().find(|(n, _)| *n == row.attrs.name) {
            Some((_, v)) => v.clone(),
            None => distinct_value(&row.attrs, row.choice.as_ref(), &start),
        };
        if same(&value, &start) {
            return Err(format!("{}: no distinct value found (start {start:?})", row.attrs.name));
        }
        let p = initialized::<M>(&[(row, value.clone())])?;
        if !same(&row.get(&p), &value) {
            return Err(format!("{}: set {value:?}, the core's parameters hold {:?}", row.attrs.name, row.get(&p)));
        }
        for other in t.vars.parameters.iter().filter(|o| o.attrs.name != row.attrs.name) {
            if !same(&other.get(&p), &other.get(&defaults)) {
                return Err(format!("setting {} also changed {}", row.attrs.name, other.attrs.name));
            }
        }
    }
    Ok(())
}

/// `p` → [`super::Table::assignments`] → a store → [`super::Table::read_parameters`] gives `p`
/// back (compared row by row).
pub fn assignments_round_trip<M: TableModel>(p: &M::Params) -> Result<(), String> {
    let t = M::table();
    let mut values = Values::from_description(M::description());
    for (name, value) in t.assignments(p) {
        let row = t.parameter(&name).ok_or_else(|| format!("{name}: assigned but not a parameter row"))?;
        values.set(row.attrs.vr, &value);
    }
    rows_agree(t, p, &t.read_parameters(&values)?, "assigned", |_, a, b| same(a, b))
}

/// Every parameter row gives the same value in `p` and `back` (`agree`), else an error naming
/// the first that does not (`what` happened to `p`).
fn rows_agree<P, I, O>(
    t: &Table<P, I, O>,
    p: &P,
    back: &P,
    what: &str,
    agree: impl Fn(&Row<P>, &Value, &Value) -> bool,
) -> Result<(), String> {
    for row in &t.vars.parameters {
        if !agree(row, &row.get(back), &row.get(p)) {
            return Err(format!("{}: {what} {:?}, read back {:?}", row.attrs.name, row.get(p), row.get(back)));
        }
    }
    Ok(())
}

/// The start values of the description, read into the parameter struct, are `P::default()`:
/// every row the same value, bit for bit (computed rows, which go through the core's own
/// conversions, to 1e-12 relative).
pub fn start_values_are_the_defaults<M: TableModel>() -> Result<(), String> {
    let t = M::table();
    let back = t.read_parameters(&Values::from_description(M::description()))?;
    rows_agree(t, &M::Params::default(), &back, "default", |r, a, b| if r.computed { same(a, b) } else { a == b })
}

fn leaves(prefix: &str, v: &serde_json::Value, out: &mut BTreeMap<String, serde_json::Value>) {
    match v {
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                leaves(&if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") }, x, out);
            }
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                leaves(&format!("{prefix}[{i}]"), x, out);
            }
        }
        x => {
            out.insert(prefix.to_string(), x.clone());
        }
    }
}

/// Every leaf field of the serialized default parameter struct is changed by at least one
/// parameter row, and every row changes at least one field: a field added to the core without
/// a row, or a row that writes nothing, fails here with its path.
pub fn parameter_coverage<M>() -> Result<(), String>
where
    M: TableModel,
    M::Params: Serialize,
{
    let json = |p: &M::Params| serde_json::to_value(p).map_err(|e| e.to_string());
    let t = M::table();
    let defaults = M::Params::default();
    let mut base = BTreeMap::new();
    leaves("", &json(&defaults)?, &mut base);
    let mut touched = std::collections::BTreeSet::new();
    for row in &t.vars.parameters {
        let mut p = defaults.clone();
        let value = distinct_value(&row.attrs, row.choice.as_ref(), &row.get(&defaults));
        row.set(&mut p, &value)?;
        let mut now = BTreeMap::new();
        leaves("", &json(&p)?, &mut now);
        let changed: Vec<&String> = now.iter().filter(|(k, v)| base.get(*k) != Some(v)).map(|(k, _)| k).collect();
        if changed.is_empty() {
            return Err(format!("row {} changes no field of the parameter struct", row.attrs.name));
        }
        touched.extend(changed.into_iter().cloned());
    }
    let missing: Vec<&String> = base.keys().filter(|k| !touched.contains(*k)).collect();
    if !missing.is_empty() {
        return Err(format!("parameter fields without a row: {missing:?}"));
    }
    Ok(())
}

/// Replace the trailing checksum of a serialized FMU state, so that only the model's validation
/// can refuse the bytes.
pub fn reseal(bytes: &mut [u8]) {
    let n = bytes.len() - 8;
    let sum = crate::fnv1a64(&bytes[..n]);
    bytes[n..].copy_from_slice(&sum.to_le_bytes());
}

/// `tries` copies of the serialized state `bytes`, each with 3 bits flipped by a xorshift stream
/// from `seed` and resealed: every copy is refused by `Snapshot::deserialize`, or restored into a
/// `fresh()` instance whose next step of `h` neither panics nor takes 2 s. Returns (refused,
/// loaded).
pub fn corrupted_states_never_panic_or_hang<M: crate::Fmi2Model>(
    bytes: &[u8],
    seed: u64,
    tries: usize,
    fresh: impl Fn() -> Instance<M>,
    h: f64,
) -> (usize, usize) {
    let mut rng = seed;
    let (mut refused, mut loaded) = (0, 0);
    for _ in 0..tries {
        let mut bad = bytes.to_vec();
        for _ in 0..3 {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            let i = (rng % (bad.len() as u64 - 8)) as usize;
            bad[i] ^= 1 << (rng >> 60 & 7);
        }
        reseal(&mut bad);
        match crate::instance::Snapshot::<M>::deserialize(&bad) {
            Err(_) => refused += 1,
            Ok(snap) => {
                loaded += 1;
                let mut inst = fresh();
                inst.restore(&snap);
                let t = inst.time();
                let started = std::time::Instant::now();
                let _ = inst.do_step(t, h);
                assert!(started.elapsed().as_secs_f64() < 2.0, "a step of a restored corrupted state took over 2 s");
            }
        }
    }
    (refused, loaded)
}

/// The communication step sizes at which the work checks count a step's internal steps.
pub(crate) const STEP_SIZES: [f64; 5] = [1e-6, 1e-4, 1e-2, 1.0, 1e3];

/// The work bound declared in `M`'s description (if any) is the model's own
/// [`Fmi2Model::internal_steps`](crate::Fmi2Model::internal_steps): for the start value of its
/// internal-step parameter and for a second value inside the parameter's bounds, models built
/// from those values report the declared `h / p + extra` (to 1e-9 relative) for step sizes from
/// 1 µs to 1000 s, counted in the layer's internal steps (times
/// `MAX_INTERNAL_STEPS_PER_CALL / maxInternalStepsPerCall`, 1 unless the bound is
/// [scaled](super::Table::work_bound_scaled)). So a master that refuses a step by the annotation
/// refuses exactly what the layer refuses. Returns whether a bound is declared.
pub fn work_bound_matches_internal_steps<M: crate::Fmi2Model>() -> Result<bool, String> {
    let md = M::description();
    let Some(w) = md.work_bound() else { return Ok(false) };
    let v = md.variable(&w.internal_step_parameter).ok_or("the work bound names no variable")?;
    let Some(Value::Real(p0)) = v.start_value() else {
        return Err(format!("{}: no Real start value", v.name));
    };
    let (lo, hi) = v.range();
    // the annotation counts steps of p; the layer refuses beyond MAX_INTERNAL_STEPS_PER_CALL
    let per = crate::MAX_INTERNAL_STEPS_PER_CALL / w.max_internal_steps_per_call;
    let p1 = if hi.is_none_or(|hi| 2.0 * p0 <= hi) { 2.0 * p0 } else { (p0 + lo.unwrap_or(0.0)) / 2.0 };
    for p in [p0, p1] {
        let mut values = Values::from_description(md);
        values.set_real(v.value_reference, p);
        let model = M::initialize(&values, &Environment::default()).map_err(|e| format!("{} = {p}: {e}", v.name))?;
        for h in STEP_SIZES {
            let (declared, actual) = (per * w.cost(h, p), model.internal_steps(h));
            if (declared - actual).abs() > 1e-9 * actual.abs().max(1.0) {
                return Err(format!(
                    "{} = {p}, h = {h}: the description declares {declared} internal steps, the model counts {actual}",
                    v.name
                ));
            }
        }
    }
    Ok(true)
}
