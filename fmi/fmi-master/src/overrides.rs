//! Overrides and value conversion: parsing `--set component.variable=value`
//! ([`Override`]), converting typed text and SSP parameter values into values
//! of a variable's type (checked against the FMU's `modelDescription.xml`,
//! enumeration items by name or number), whether a variable may be set, and
//! "did you mean" suggestions for unknown names.

use crate::error::SetupError;
use model_description::{Causality, ModelDescription, ScalarType, ScalarVariable, Value, Variability};
use ssp::ParamValue;

/// One override of a parameter or input start value, not yet resolved against a system:
/// `--set target=value` from a command line, or a typed value from a program.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// `component.variable` (or a bare variable name for a one-component system).
    pub target: String,
    /// The value.
    pub value: OverrideValue,
}

/// The value of an [`Override`].
#[derive(Clone, Debug, PartialEq)]
pub enum OverrideValue {
    /// As typed on a command line; converted to the variable's type (enumeration items by name).
    Text(String),
    /// A typed value (e.g. from an FMU adapter's `parameter_assignments`), checked against the
    /// variable's type like an SSP parameter binding.
    Typed(Value),
}

impl std::fmt::Display for OverrideValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OverrideValue::Text(t) => f.write_str(t),
            OverrideValue::Typed(Value::Real(x)) => write!(f, "{x:e}"),
            OverrideValue::Typed(Value::Integer(i)) => write!(f, "{i}"),
            OverrideValue::Typed(Value::Boolean(b)) => write!(f, "{b}"),
            OverrideValue::Typed(Value::String(s)) => f.write_str(s),
        }
    }
}

impl Override {
    /// An override as typed on a command line.
    pub fn text(target: impl Into<String>, value: impl Into<String>) -> Override {
        Override { target: target.into(), value: OverrideValue::Text(value.into()) }
    }

    /// A typed override.
    pub fn typed(target: impl Into<String>, value: Value) -> Override {
        Override { target: target.into(), value: OverrideValue::Typed(value) }
    }

    /// The value converted to the type of `v` (of the FMU described by `md`).
    pub fn value_for(&self, md: &ModelDescription, v: &ScalarVariable, context: &str) -> Result<Value, SetupError> {
        match &self.value {
            OverrideValue::Text(t) => parse_value(md, v, t, context),
            OverrideValue::Typed(x) => {
                let p = match x {
                    Value::Real(r) => ParamValue::Real(*r, None),
                    Value::Integer(i) => ParamValue::Integer(*i),
                    Value::Boolean(b) => ParamValue::Boolean(*b),
                    Value::String(s) => ParamValue::String(s.clone()),
                };
                ssp_value(md, v, &p, context)
            }
        }
    }
}

impl std::str::FromStr for Override {
    type Err = SetupError;
    fn from_str(s: &str) -> Result<Self, SetupError> {
        parse_set(s)
    }
}

/// Parse `component.variable=value`.
pub fn parse_set(s: &str) -> Result<Override, SetupError> {
    let Some((target, value)) = s.split_once('=') else {
        return Err(SetupError::Value(format!("--set {s}: expected component.variable=value")));
    };
    let target = target.trim();
    if target.is_empty() {
        return Err(SetupError::Value(format!("--set {s}: the variable name is empty")));
    }
    if target.starts_with('.') || target.ends_with('.') {
        return Err(SetupError::Value(format!("--set {s}: '{target}' is not a variable name")));
    }
    if value.trim().is_empty() {
        return Err(SetupError::Value(format!("--set {s}: the value is empty")));
    }
    Ok(Override::text(target, value.trim()))
}

fn type_name(v: &ScalarVariable) -> &'static str {
    match v.scalar_type() {
        ScalarType::Real => "Real",
        ScalarType::Integer => "Integer",
        ScalarType::Boolean => "Boolean",
        ScalarType::String => "String",
        ScalarType::Enumeration => "Enumeration",
    }
}

/// May the master set this variable before initialization?
pub fn check_settable(v: &ScalarVariable, context: &str) -> Result<(), SetupError> {
    let ok = matches!(v.causality, Causality::Parameter | Causality::Input) && v.variability != Variability::Constant;
    if ok {
        Ok(())
    } else {
        Err(SetupError::Causality(format!(
            "{context}: '{}' cannot be set: it is a {:?} {:?} variable (only parameters and inputs can be set)",
            v.name, v.variability, v.causality
        )))
    }
}

fn enum_items(md: &ModelDescription, v: &ScalarVariable) -> Vec<(String, i32)> {
    match &v.kind {
        model_description::VarKind::Enumeration(e) => md.enumeration_items(&e.declared_type),
        _ => Vec::new(),
    }
}

fn items_text(items: &[(String, i32)]) -> String {
    items.iter().map(|(n, i)| format!("{n} ({i})")).collect::<Vec<_>>().join(", ")
}

/// Convert text typed by the user into a value of the variable's type.
pub fn parse_value(md: &ModelDescription, v: &ScalarVariable, text: &str, context: &str) -> Result<Value, SetupError> {
    let t = text.trim();
    let bad = |what: &str| {
        let ty = type_name(v);
        let article = if ty.starts_with(['I', 'E']) { "an" } else { "a" };
        SetupError::Value(format!("{context}: '{}' is {article} {ty} variable; '{t}' is not {what}", v.name))
    };
    Ok(match v.scalar_type() {
        ScalarType::Real => {
            let x: f64 = t.parse().map_err(|_| bad("a number"))?;
            if !x.is_finite() {
                return Err(bad("a finite number"));
            }
            Value::Real(x)
        }
        ScalarType::Integer => Value::Integer(t.parse().map_err(|_| bad("an integer"))?),
        ScalarType::Boolean => Value::Boolean(match t {
            "true" | "1" | "on" => true,
            "false" | "0" | "off" => false,
            _ => return Err(bad("a boolean (true/false)")),
        }),
        ScalarType::String => Value::String(text.to_string()),
        ScalarType::Enumeration => {
            let items = enum_items(md, v);
            if let Some((_, i)) = items.iter().find(|(n, _)| n == t) {
                Value::Integer(*i)
            } else if let Ok(i) = t.parse::<i32>()
                && items.iter().any(|(_, k)| *k == i)
            {
                Value::Integer(i)
            } else {
                return Err(SetupError::Value(format!(
                    "{context}: '{t}' is not an item of enumeration '{}'; its items are: {}",
                    v.name,
                    items_text(&items)
                )));
            }
        }
    })
}

/// Convert an SSP parameter value into a value of the variable's type.
pub fn ssp_value(
    md: &ModelDescription,
    v: &ScalarVariable,
    p: &ParamValue,
    context: &str,
) -> Result<Value, SetupError> {
    let mismatch = || {
        SetupError::TypeMismatch(format!(
            "{context}: parameter value {p:?} does not fit '{}', a {} variable",
            v.name,
            type_name(v)
        ))
    };
    Ok(match (v.scalar_type(), p) {
        (ScalarType::Real, ParamValue::Real(x, _)) => Value::Real(*x),
        (ScalarType::Real, ParamValue::Integer(i)) => Value::Real(f64::from(*i)),
        (ScalarType::Integer, ParamValue::Integer(i)) => Value::Integer(*i),
        (ScalarType::Boolean, ParamValue::Boolean(b)) => Value::Boolean(*b),
        (ScalarType::String, ParamValue::String(s)) => Value::String(s.clone()),
        (ScalarType::Enumeration, ParamValue::Enumeration(s)) => parse_value(md, v, s, context)?,
        (ScalarType::Enumeration, ParamValue::Integer(i)) => parse_value(md, v, &i.to_string(), context)?,
        _ => return Err(mismatch()),
    })
}

/// The closest names to `name` among `candidates` (for "did you mean" hints).
pub fn suggest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> String {
    let mut scored: Vec<(usize, &str)> = candidates.map(|c| (edit_distance(name, c), c)).collect();
    scored.sort();
    let close: Vec<&str> =
        scored.iter().filter(|(d, _)| *d <= 3.max(name.len() / 3)).take(3).map(|(_, c)| *c).collect();
    if close.is_empty() { String::new() } else { format!(" (did you mean {}?)", close.join(", ")) }
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != *cb)).min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use model_description::{Causality as C, ModelBuilder, ScalarVariable as V, Variability as Va};

    fn md() -> ModelDescription {
        ModelBuilder::new("M", "M")
            .enumeration("Structure", "s", &[("off", ""), ("pid", ""), ("adrc_fopid", "")])
            .var(V::real("spindle_speed", 0, C::Input, Va::Continuous).start(2000.0))
            .var(V::integer("seed", 1, C::Parameter, Va::Fixed).start(1))
            .var(V::boolean("noise", 2, C::Parameter, Va::Fixed).start(true))
            .var(V::enumeration("structure", 3, C::Parameter, Va::Fixed, "Structure").start(1))
            .var(V::real("x", 4, C::Output, Va::Continuous).depends_on(&[]))
            .var(V::string("label", 5, C::Parameter, Va::Fixed).start("a"))
            .build()
            .unwrap()
    }

    #[test]
    fn set_syntax_is_checked() {
        assert_eq!(parse_set("plant.spindle_speed=1500").unwrap(), Override::text("plant.spindle_speed", "1500"));
        assert_eq!(parse_set("plant.cutting.kt = 7.6e8").unwrap().target, "plant.cutting.kt");
        for bad in ["plant.spindle_speed", "=3", "plant.x=", ".x=1", "plant.=1"] {
            let e = parse_set(bad).unwrap_err().to_string();
            assert!(e.starts_with("--set "), "{bad}: {e}");
        }
    }

    #[test]
    fn values_are_type_checked() {
        let md = md();
        let v = |n: &str| md.variable(n).unwrap();
        assert_eq!(parse_value(&md, v("spindle_speed"), "1500", "--set").unwrap(), Value::Real(1500.0));
        let e = parse_value(&md, v("spindle_speed"), "fast", "--set plant.spindle_speed=fast").unwrap_err().to_string();
        assert_eq!(e, "--set plant.spindle_speed=fast: 'spindle_speed' is a Real variable; 'fast' is not a number");
        assert!(parse_value(&md, v("spindle_speed"), "inf", "c").is_err());
        assert!(parse_value(&md, v("spindle_speed"), "NaN", "c").is_err());
        assert_eq!(parse_value(&md, v("seed"), "7", "c").unwrap(), Value::Integer(7));
        assert!(parse_value(&md, v("seed"), "7.5", "c").unwrap_err().to_string().contains("not an integer"));
        assert_eq!(parse_value(&md, v("noise"), "false", "c").unwrap(), Value::Boolean(false));
        assert!(parse_value(&md, v("noise"), "maybe", "c").is_err());
        assert_eq!(parse_value(&md, v("structure"), "adrc_fopid", "c").unwrap(), Value::Integer(3));
        assert_eq!(parse_value(&md, v("structure"), "2", "c").unwrap(), Value::Integer(2));
        let e = parse_value(&md, v("structure"), "lqr", "c").unwrap_err().to_string();
        assert!(e.contains("off (1), pid (2), adrc_fopid (3)"), "{e}");
        assert!(parse_value(&md, v("structure"), "9", "c").is_err());
        assert_eq!(parse_value(&md, v("label"), "x y", "c").unwrap(), Value::String("x y".into()));
    }

    #[test]
    fn only_parameters_and_inputs_are_settable() {
        let md = md();
        assert!(check_settable(md.variable("spindle_speed").unwrap(), "c").is_ok());
        assert!(check_settable(md.variable("seed").unwrap(), "c").is_ok());
        let e = check_settable(md.variable("x").unwrap(), "--set plant.x=1").unwrap_err().to_string();
        assert!(e.contains("'x' cannot be set"), "{e}");
    }

    #[test]
    fn ssp_values_must_match_the_variable_type() {
        let md = md();
        let v = |n: &str| md.variable(n).unwrap();
        assert_eq!(ssp_value(&md, v("spindle_speed"), &ParamValue::Real(1.0, None), "c").unwrap(), Value::Real(1.0));
        assert_eq!(
            ssp_value(&md, v("structure"), &ParamValue::Enumeration("pid".into()), "c").unwrap(),
            Value::Integer(2)
        );
        let e = ssp_value(&md, v("seed"), &ParamValue::Real(1.5, None), "c").unwrap_err();
        assert!(matches!(e, SetupError::TypeMismatch(_)), "{e}");
        assert!(ssp_value(&md, v("noise"), &ParamValue::String("yes".into()), "c").is_err());
    }

    #[test]
    fn suggestions_find_near_names() {
        let names = ["spindle_speed", "seed", "x", "depth"];
        assert_eq!(suggest("spindle_sped", names.iter().copied()), " (did you mean spindle_speed?)");
        assert_eq!(suggest("zzzzzzzzzzzzzz", names.iter().copied()), "");
    }
}
