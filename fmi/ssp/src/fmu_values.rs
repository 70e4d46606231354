//! FMU variable values as SSP parameters: the one conversion from a value in the FMU's own
//! terms (`model_description::Value`, enumerations by their integer) to an `ssv:` parameter.

use crate::model::{ParamValue, Parameter};
use model_description::{ModelDescription, Value, VarKind};

/// How enumeration values are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Enumerations {
    /// `ssv:Enumeration value="item"` (the SSP 1.0 form).
    ItemNames,
    /// `ssv:Integer value="2"`: the item's value, which some masters (libcosim) read where they
    /// refuse `ssv:Enumeration`.
    Integers,
}

/// One FMU variable assignment as an SSP parameter; reals are written without a unit attribute
/// (an SSP unit must be declared in a Units element, and the FMUs' values are SI).
pub fn fmu_parameter(
    md: &ModelDescription,
    name: &str,
    value: Value,
    enums: Enumerations,
) -> Result<Parameter, String> {
    let var = md.variable(name).ok_or_else(|| format!("{name}: not a variable of {}", md.model_name))?;
    let value = match (&var.kind, value) {
        (VarKind::Enumeration(e), Value::Integer(i)) => match enums {
            Enumerations::Integers => ParamValue::Integer(i),
            Enumerations::ItemNames => {
                let items = md.enumeration_items(&e.declared_type);
                let item = items.iter().find(|(_, v)| *v == i).ok_or_else(|| format!("{name} = {i}: no such item"))?;
                ParamValue::Enumeration(item.0.clone())
            }
        },
        (_, Value::Real(x)) => ParamValue::Real(x, None),
        (_, Value::Integer(i)) => ParamValue::Integer(i),
        (_, Value::Boolean(b)) => ParamValue::Boolean(b),
        (_, Value::String(s)) => ParamValue::String(s),
    };
    Ok(Parameter { name: name.to_string(), value })
}
