//! Parameter sets named as the FMUs name them.
//!
//! A study describes a machine or a controller with the FMU's own variable names (`--set
//! plant.workpiece.mass=32`, an SSP's parameter bindings) and computes with the core's typed
//! parameter struct. This module converts between the two through the adapter's one variable
//! table ([`fmi2_export::Table`]) and its `modelDescription.xml`, converting values exactly as
//! the master does for `--set` and SSP bindings ([`fmi_master::overrides`]), so the names,
//! types, bounds and enumeration items are those of the FMU, and a study's analysis and its FMU
//! runs always use one parameter set.

use crate::StudyError;
use fmi_master::overrides::{parse_value, ssp_value};
use fmi2_export::table::{Row, TableModel};
use model_description::{ModelDescription, ScalarType, ScalarVariable, Value};
use ssp::ParamValue;

fn check_bounds<S>(row: &Row<S>, v: &Value) -> Result<(), String> {
    let x = match v {
        Value::Real(x) => *x,
        Value::Integer(i) if row.ty == ScalarType::Integer => f64::from(*i),
        _ => return Ok(()),
    };
    match row.attrs.bounds {
        Some((lo, hi)) if !(lo..=hi).contains(&x) => {
            let hint = model_description::units::slip_hint(row.attrs.unit, x, lo, hi)
                .map_or(String::new(), |h| format!("; {h}"));
            Err(format!("{} = {x} is outside its bounds [{lo}, {hi}]{hint}", row.attrs.name))
        }
        _ => Ok(()),
    }
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

/// How a value for a variable is converted: as the master converts `--set` text, an SSP
/// binding or a typed override for that variable of the FMU's `modelDescription.xml`.
type Convert<'a> = &'a dyn Fn(&ModelDescription, &ScalarVariable) -> Result<Value, fmi_master::SetupError>;

/// Set the parameter or input `name` of `r` to the value `convert` gives for its variable,
/// within the row's bounds.
fn apply<M: TableModel>(
    r: &mut Resolved<M::Params, M::Inputs>,
    name: &str,
    convert: Convert<'_>,
) -> Result<(), String> {
    let (t, md) = (M::table(), M::description());
    let var = md.variable(name).ok_or_else(|| {
        let names =
            t.vars().parameters.iter().map(|r| r.attrs.name).chain(t.vars().inputs.iter().map(|r| r.attrs.name));
        format!(
            "{} has no parameter or input {name:?}{}",
            t.header.model_name,
            fmi_master::overrides::suggest(name, names)
        )
    })?;
    let value = convert(md, var).map_err(|e| e.to_string())?;
    if let Some(row) = t.parameter(name) {
        check_bounds(row, &value)?;
        row.set(&mut r.params, &value)
    } else if let Some(row) = t.vars().inputs.iter().find(|row| row.attrs.name == name) {
        check_bounds(row, &value)?;
        row.set(&mut r.inputs, &value)
    } else {
        Err(format!("{name} is an output of {}, not a parameter or input", t.header.model_name))
    }
}

/// `name=text` as on a command line (`--set`), checked against the variable's type and bounds.
pub fn apply_text<M: TableModel>(r: &mut Resolved<M::Params, M::Inputs>, name: &str, text: &str) -> Result<(), String> {
    apply::<M>(r, name, &|md, v| parse_value(md, v, text, &format!("{name}={text}")))
}

/// An SSP parameter binding.
pub fn apply_ssp<M: TableModel>(
    r: &mut Resolved<M::Params, M::Inputs>,
    name: &str,
    p: &ParamValue,
) -> Result<(), String> {
    apply::<M>(r, name, &|md, v| ssp_value(md, v, p, name))
}

/// A typed value (what [`fmi_master::Override::typed`] carries).
pub fn apply_value<M: TableModel>(r: &mut Resolved<M::Params, M::Inputs>, name: &str, x: &Value) -> Result<(), String> {
    let o = fmi_master::Override::typed(name, x.clone());
    apply::<M>(r, name, &|md, v| o.value_for(md, v, name))
}

/// The parameters and inputs of `component` in `sys`: the table's defaults, then the component's
/// SSP parameter bindings, the system's bindings that name it, and the `overrides` that target it
/// — the order in which the master applies them.
pub fn resolve<M: TableModel>(
    sys: &fmi_master::SystemFile,
    component: &str,
    overrides: &[fmi_master::Override],
) -> Result<Resolved<M::Params, M::Inputs>, StudyError> {
    let mut r = Resolved::default();
    let invalid = |e: String| StudyError::Invalid(format!("{component}: {e}"));
    let desc = &sys.desc;
    let c = desc
        .components
        .iter()
        .find(|c| c.name == component)
        .ok_or_else(|| StudyError::Invalid(format!("{}: no component {component}", sys.origin)))?;
    for p in &c.parameters {
        apply_ssp::<M>(&mut r, &p.name, &p.value).map_err(invalid)?;
    }
    let prefix = format!("{component}.");
    for p in &desc.parameters {
        if let Some(name) = p.name.strip_prefix(&prefix) {
            apply_ssp::<M>(&mut r, name, &p.value).map_err(invalid)?;
        }
    }
    for o in overrides {
        if let Some(name) = o.target.strip_prefix(&prefix) {
            match &o.value {
                fmi_master::OverrideValue::Text(text) => apply_text::<M>(&mut r, name, text),
                fmi_master::OverrideValue::Typed(v) => apply_value::<M>(&mut r, name, v),
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
    use fmu_plant::MillingPlant;
    use milling_plant::{CuttingModel, PlantInputs, PlantParams};

    #[test]
    fn names_types_bounds_and_items_are_the_fmus() {
        let mut r: Resolved<PlantParams, PlantInputs> = Resolved::default();
        apply_text::<MillingPlant>(&mut r, "workpiece.mass", "32.5").unwrap();
        apply_text::<MillingPlant>(&mut r, "cutting.model", "averaged").unwrap();
        apply_text::<MillingPlant>(&mut r, "spindle_speed", "1500").unwrap();
        apply_value::<MillingPlant>(&mut r, "cutting.teeth", &Value::Integer(3)).unwrap();
        apply_ssp::<MillingPlant>(&mut r, "disturbance.noise", &ParamValue::Boolean(false)).unwrap();
        assert_eq!(r.params.workpiece.first.mass.to_bits(), 32.5f64.to_bits());
        assert_eq!(r.params.cutting.model, CuttingModel::Averaged);
        assert_eq!(r.params.cutting.teeth, 3);
        assert!(!r.params.disturbance.noise);
        assert_eq!(r.inputs.spindle_speed_rpm.to_bits(), 1500f64.to_bits());
        let e = apply_text::<MillingPlant>(&mut r, "workpiece.mas", "1").unwrap_err();
        assert!(e.contains("no parameter or input \"workpiece.mas\"") && e.contains("workpiece.mass"), "{e}");
        let e = apply_text::<MillingPlant>(&mut r, "workpiece.damping_ratio", "1.5").unwrap_err();
        assert!(e.contains("outside its bounds"), "{e}");
        let e = apply_text::<MillingPlant>(&mut r, "cutting.model", "exact").unwrap_err();
        assert!(e.contains("time_domain") && e.contains("averaged"), "{e}");
        assert!(apply_text::<MillingPlant>(&mut r, "cutting.kt", "NaN").is_err());
        assert!(apply_value::<MillingPlant>(&mut r, "cutting.kt", &Value::Boolean(true)).is_err());
    }
}
