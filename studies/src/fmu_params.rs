//! Parameter sets named as the FMUs name them.
//!
//! A study describes a machine or a controller with the FMU's own variable names (`--set
//! plant.workpiece.mass=32`, an SSP's parameter bindings) and computes with the core's typed
//! parameter struct. This module converts between the two through the adapter's one variable
//! table ([`fmi2_export::Table`]), so the names, types, bounds and enumeration items are those
//! of the FMU, and a study's analysis and its FMU runs always use one parameter set.

use crate::StudyError;
use fmi2_export::Table;
use fmi2_export::table::Row;
use model_description::{ScalarType, Value};
use ssp::ParamValue;

/// Where a named value goes: a parameter or an input start value.
enum Target<'a, P, I> {
    Parameter(&'a Row<P>),
    Input(&'a Row<I>),
}

fn find<'a, P, I, O>(t: &'a Table<P, I, O>, name: &str) -> Option<Target<'a, P, I>> {
    t.vars
        .parameters
        .iter()
        .find(|r| r.attrs.name == name)
        .map(Target::Parameter)
        .or_else(|| t.vars.inputs.iter().find(|r| r.attrs.name == name).map(Target::Input))
}

/// Text as a value of a row's type (Real, Integer, Boolean, enumeration item by name or number).
fn parse<S>(row: &Row<S>, text: &str) -> Result<Value, String> {
    let text = text.trim();
    let bad = |what: &str| format!("{}: {text:?} is not {what}", row.attrs.name);
    let v = match row.ty {
        ScalarType::Real => {
            let x: f64 = text.parse().map_err(|_| bad("a number"))?;
            if !x.is_finite() {
                return Err(bad("a finite number"));
            }
            Value::Real(x)
        }
        ScalarType::Integer => Value::Integer(text.parse().map_err(|_| bad("an integer"))?),
        ScalarType::Boolean => Value::Boolean(match text {
            "true" | "1" => true,
            "false" | "0" => false,
            _ => return Err(bad("true or false")),
        }),
        ScalarType::String => Value::String(text.to_string()),
        ScalarType::Enumeration => {
            let items = &row.choice.as_ref().expect("enumeration rows carry their items").items;
            let i = match items.iter().position(|(n, _)| *n == text) {
                Some(i) => i as i32 + 1,
                None => text.parse::<i32>().ok().filter(|i| (1..=items.len() as i32).contains(i)).ok_or_else(|| {
                    bad(&format!("one of {}", items.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")))
                })?,
            };
            Value::Integer(i)
        }
    };
    check_bounds(row, &v)?;
    Ok(v)
}

fn check_bounds<S>(row: &Row<S>, v: &Value) -> Result<(), String> {
    let x = match v {
        Value::Real(x) => *x,
        Value::Integer(i) if row.ty == ScalarType::Integer => f64::from(*i),
        _ => return Ok(()),
    };
    match row.attrs.bounds {
        Some((lo, hi)) if !(lo..=hi).contains(&x) => {
            Err(format!("{} = {x} is outside its bounds [{lo}, {hi}]", row.attrs.name))
        }
        _ => Ok(()),
    }
}

/// An SSP parameter value as a value of a row's type.
fn from_ssp<S>(row: &Row<S>, p: &ParamValue) -> Result<Value, String> {
    match (row.ty, p) {
        (ScalarType::Real, ParamValue::Real(x, _)) => Ok(Value::Real(*x)),
        (ScalarType::Real, ParamValue::Integer(i)) => Ok(Value::Real(f64::from(*i))),
        (ScalarType::Integer, ParamValue::Integer(i)) => Ok(Value::Integer(*i)),
        (ScalarType::Boolean, ParamValue::Boolean(b)) => Ok(Value::Boolean(*b)),
        (ScalarType::String, ParamValue::String(s)) => Ok(Value::String(s.clone())),
        (ScalarType::Enumeration, ParamValue::Enumeration(s)) => parse(row, s),
        (ScalarType::Enumeration, ParamValue::Integer(i)) => parse(row, &i.to_string()),
        (_, p) => Err(format!("{}: the value {p} does not fit its type", row.attrs.name)),
    }
    .and_then(|v| check_bounds(row, &v).map(|()| v))
}

/// A core's parameters and input start values as an FMU component of a system sees them.
#[derive(Clone, Debug, PartialEq)]
pub struct Resolved<P, I> {
    /// The parameters.
    pub params: P,
    /// The input start values.
    pub inputs: I,
}

impl<P: Default, I: Default> Default for Resolved<P, I> {
    fn default() -> Self {
        Resolved { params: P::default(), inputs: I::default() }
    }
}

fn unknown<P, I, O>(t: &Table<P, I, O>, name: &str) -> String {
    let names = t.vars.parameters.iter().map(|r| r.attrs.name).chain(t.vars.inputs.iter().map(|r| r.attrs.name));
    format!("{} has no parameter or input {name:?}{}", t.header.model_name, fmi_master::overrides::suggest(name, names))
}

/// Set the parameter or input `name` of `r` from a value computed for its row.
fn apply<P, I, O>(
    t: &Table<P, I, O>,
    r: &mut Resolved<P, I>,
    name: &str,
    parse_p: impl FnOnce(&Row<P>) -> Result<Value, String>,
    parse_i: impl FnOnce(&Row<I>) -> Result<Value, String>,
) -> Result<(), String> {
    match find(t, name).ok_or_else(|| unknown(t, name))? {
        Target::Parameter(row) => row.set(&mut r.params, &parse_p(row)?),
        Target::Input(row) => row.set(&mut r.inputs, &parse_i(row)?),
    }
}

/// `name=text` as on a command line (`--set`), checked against the row's type and bounds.
pub fn apply_text<P, I, O>(t: &Table<P, I, O>, r: &mut Resolved<P, I>, name: &str, text: &str) -> Result<(), String> {
    apply(t, r, name, |row| parse(row, text), |row| parse(row, text))
}

/// An SSP parameter binding.
pub fn apply_ssp<P, I, O>(
    t: &Table<P, I, O>,
    r: &mut Resolved<P, I>,
    name: &str,
    v: &ParamValue,
) -> Result<(), String> {
    apply(t, r, name, |row| from_ssp(row, v), |row| from_ssp(row, v))
}

/// A typed value (what [`fmi_master::Override::typed`] carries).
pub fn apply_value<P, I, O>(t: &Table<P, I, O>, r: &mut Resolved<P, I>, name: &str, v: &Value) -> Result<(), String> {
    let checked = |ty: ScalarType, bounds: Result<(), String>| {
        let fits = matches!(
            (ty, v),
            (ScalarType::Real, Value::Real(_))
                | (ScalarType::Integer | ScalarType::Enumeration, Value::Integer(_))
                | (ScalarType::Boolean, Value::Boolean(_))
                | (ScalarType::String, Value::String(_))
        );
        if fits { bounds.map(|()| v.clone()) } else { Err(format!("{name}: {v:?} does not fit its type")) }
    };
    apply(t, r, name, |row| checked(row.ty, check_bounds(row, v)), |row| checked(row.ty, check_bounds(row, v)))
}

/// The parameters and inputs of `component` in `sys`: the table's defaults, then the component's
/// SSP parameter bindings, the system's bindings that name it, and the `overrides` that target it
/// — the order in which the master applies them.
pub fn resolve<P: Default, I: Default, O>(
    t: &Table<P, I, O>,
    sys: &fmi_master::SystemFile,
    component: &str,
    overrides: &[fmi_master::Override],
) -> Result<Resolved<P, I>, StudyError> {
    let mut r = Resolved::default();
    let invalid = |e: String| StudyError::Invalid(format!("{component}: {e}"));
    let desc = &sys.desc;
    let c = desc
        .components
        .iter()
        .find(|c| c.name == component)
        .ok_or_else(|| StudyError::Invalid(format!("{}: no component {component}", sys.origin)))?;
    for p in &c.parameters {
        apply_ssp(t, &mut r, &p.name, &p.value).map_err(invalid)?;
    }
    let prefix = format!("{component}.");
    for p in &desc.parameters {
        if let Some(name) = p.name.strip_prefix(&prefix) {
            apply_ssp(t, &mut r, name, &p.value).map_err(invalid)?;
        }
    }
    for o in overrides {
        if let Some(name) = o.target.strip_prefix(&prefix) {
            match &o.value {
                fmi_master::OverrideValue::Text(text) => apply_text(t, &mut r, name, text),
                fmi_master::OverrideValue::Typed(v) => apply_value(t, &mut r, name, v),
            }
            .map_err(invalid)?;
        }
    }
    Ok(r)
}

/// A parameter set as typed overrides of `component` (the adapter's `parameter_assignments`
/// prefixed with the component name).
pub fn overrides_of(component: &str, assignments: Vec<(String, Value)>) -> Vec<fmi_master::Override> {
    assignments.into_iter().map(|(name, v)| fmi_master::Override::typed(format!("{component}.{name}"), v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use fmu_plant::TABLE;
    use milling_plant::{CuttingModel, PlantInputs, PlantParams};

    #[test]
    fn names_types_bounds_and_items_are_the_fmus() {
        let mut r: Resolved<PlantParams, PlantInputs> = Resolved::default();
        apply_text(&TABLE, &mut r, "workpiece.mass", "32.5").unwrap();
        apply_text(&TABLE, &mut r, "cutting.model", "averaged").unwrap();
        apply_text(&TABLE, &mut r, "spindle_speed", "1500").unwrap();
        apply_value(&TABLE, &mut r, "cutting.teeth", &Value::Integer(3)).unwrap();
        apply_ssp(&TABLE, &mut r, "disturbance.noise", &ParamValue::Boolean(false)).unwrap();
        assert_eq!(r.params.workpiece.first.mass.to_bits(), 32.5f64.to_bits());
        assert_eq!(r.params.cutting.model, CuttingModel::Averaged);
        assert_eq!(r.params.cutting.teeth, 3);
        assert!(!r.params.disturbance.noise);
        assert_eq!(r.inputs.spindle_speed_rpm.to_bits(), 1500f64.to_bits());
        let e = apply_text(&TABLE, &mut r, "workpiece.mas", "1").unwrap_err();
        assert!(e.contains("no parameter or input \"workpiece.mas\"") && e.contains("workpiece.mass"), "{e}");
        let e = apply_text(&TABLE, &mut r, "workpiece.damping_ratio", "1.5").unwrap_err();
        assert!(e.contains("outside its bounds"), "{e}");
        assert!(apply_text(&TABLE, &mut r, "cutting.model", "exact").unwrap_err().contains("time_domain, averaged"));
        assert!(apply_text(&TABLE, &mut r, "cutting.kt", "NaN").is_err());
        assert!(apply_value(&TABLE, &mut r, "cutting.kt", &Value::Integer(3)).is_err());
    }
}
