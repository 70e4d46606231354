//! Parameter bindings: `ssd:ParameterBindings` of components and of the
//! system, with values inline (`ssd:ParameterValues/ssv:ParameterSet`) or in
//! a referenced `.ssv` file (`source`), names prefixed by the binding's
//! `prefix`. One binding may give each parameter one value only; several
//! bindings are applied in document order (a later one wins).

use crate::error::{SspError, invalid};
use crate::model::{ParamValue, Parameter};
use crate::number::num;
use crate::prescan::{SSV_ROOT, deserialize};
use crate::schema;
use std::collections::HashMap;

/// Reads a binding's `source` file (a path relative to the SSD), as text.
pub type SourceReader<'a> = &'a dyn Fn(&str) -> Result<String, SspError>;

/// The MIME type of SSP parameter sets, the only binding type supported.
const PARAMETER_SET_TYPE: &str = "application/x-ssp-parameter-set";

fn parse_value(child: &schema::ParameterChild, full: &str, file: &str) -> Result<Option<ParamValue>, SspError> {
    use schema::ParameterChild as C;
    let what = format!("parameter {full}");
    let need = |v: &Option<String>| -> Result<String, SspError> {
        v.clone().ok_or_else(|| invalid(file, format!("{what}: no value attribute")))
    };
    Ok(Some(match child {
        C::Real(r) => {
            let v = need(&r.value)?;
            let x = v.trim().parse::<f64>().map_err(|_| invalid(file, format!("{what}: '{v}' is not a number")))?;
            ParamValue::Real(x, r.unit.clone())
        }
        C::Integer(i) => {
            let v = need(&i.value)?;
            ParamValue::Integer(
                v.trim().parse().map_err(|_| invalid(file, format!("{what}: '{v}' is not an integer")))?,
            )
        }
        C::Boolean(b) => {
            let v = need(&b.value)?;
            ParamValue::Boolean(match v.trim() {
                "true" | "1" => true,
                "false" | "0" => false,
                _ => return Err(invalid(file, format!("{what}: '{v}' is not a boolean"))),
            })
        }
        C::String(s) => ParamValue::String(need(&s.value)?),
        C::Enumeration(e) => ParamValue::Enumeration(need(&e.value)?),
        C::Binary(_) => return Err(invalid(file, format!("{what}: unsupported value type ssv:Binary"))),
        C::Annotations(_) => return Ok(None),
    }))
}

/// The parameters of one `ssv:ParameterSet`, names prefixed.
fn read_set(set: &schema::ParameterSet, prefix: &str, file: &str) -> Result<Vec<Parameter>, SspError> {
    let mut out = Vec::new();
    for p in set.parameters.iter().flat_map(|ps| &ps.parameter) {
        let name = p.name.as_deref().ok_or_else(|| invalid(file, "ssv:Parameter without a name"))?;
        let full = format!("{prefix}{name}");
        let mut values = Vec::new();
        for c in &p.children {
            values.extend(parse_value(c, &full, file)?);
        }
        match values.len() {
            0 => return Err(invalid(file, format!("parameter {full} has no value element"))),
            1 => out.push(Parameter { name: full, value: values.remove(0) }),
            n => {
                let list: Vec<String> = values.iter().map(ToString::to_string).collect();
                return Err(invalid(
                    file,
                    format!(
                        "parameter {full} has {n} value elements ({}); give one value per parameter",
                        list.join(", ")
                    ),
                ));
            }
        }
    }
    Ok(out)
}

/// Parse an `.ssv` file (root `ssv:ParameterSet`); names prefixed with `prefix`.
pub fn parse_ssv(xml: &str, file: &str, prefix: &str) -> Result<Vec<Parameter>, SspError> {
    let set: schema::ParameterSet = deserialize(xml, file, SSV_ROOT)?;
    read_set(&set, prefix, file)
}

/// All parameters of the bindings `b` (of a component or the system), in document order.
pub(crate) fn read_bindings(
    b: Option<&schema::ParameterBindings>,
    file: &str,
    read_source: Option<SourceReader<'_>>,
) -> Result<Vec<Parameter>, SspError> {
    let mut out = Vec::new();
    for binding in b.iter().flat_map(|b| &b.binding) {
        let prefix = binding.prefix.as_deref().unwrap_or("");
        if let Some(t) = binding.r#type.as_deref()
            && t != PARAMETER_SET_TYPE
        {
            return Err(invalid(file, format!("parameter binding of unsupported type {t}")));
        }
        if binding.mapping.is_some() {
            return Err(invalid(file, "ssd:ParameterMapping is not supported by this master"));
        }
        let mut params = Vec::new();
        if let Some(src) = binding.source.as_deref() {
            let read = read_source.ok_or_else(|| {
                invalid(
                    file,
                    format!("parameter binding refers to {src}, but this SSD has no location to read it from"),
                )
            })?;
            params.extend(parse_ssv(&read(src)?, src, prefix)?);
        }
        for set in binding.values.iter().flat_map(|v| &v.sets) {
            params.extend(read_set(set, prefix, file)?);
        }
        let mut seen = HashMap::with_capacity(params.len());
        for p in &params {
            if let Some(q) = seen.insert(p.name.as_str(), &p.value) {
                return Err(invalid(
                    file,
                    format!("parameter {} is given two values in one parameter binding ({q} and {})", p.name, p.value),
                ));
            }
        }
        out.extend(params);
    }
    Ok(out)
}

fn write_value(v: &ParamValue) -> schema::ParameterChild {
    use schema::ParameterChild as C;
    let value = |s: String| schema::Value { value: Some(s) };
    match v {
        ParamValue::Real(x, unit) => C::Real(schema::RealValue { value: Some(num(*x)), unit: unit.clone() }),
        ParamValue::Integer(i) => C::Integer(value(i.to_string())),
        ParamValue::Boolean(b) => C::Boolean(value(b.to_string())),
        ParamValue::String(s) => C::String(value(s.clone())),
        ParamValue::Enumeration(s) => C::Enumeration(value(s.clone())),
    }
}

/// A standalone `.ssv` file (root `ssv:ParameterSet` named `name`) holding `params` (a name
/// given twice keeps its last value); [`parse_ssv`] reads it back.
pub fn ssv_xml(name: &str, params: &[Parameter]) -> Result<String, SspError> {
    let err = |e: quick_xml::SeError| SspError::Write { name: name.to_string(), message: e.to_string() };
    let Some(mut b) = write_bindings(params, name) else {
        return Err(SspError::Write {
            name: name.to_string(),
            message: "a parameter set needs at least one parameter".into(),
        });
    };
    let set = b.binding.remove(0).values.map(|v| v.sets).unwrap_or_default().remove(0);
    let mut body = String::new();
    let mut ser = quick_xml::se::Serializer::with_root(&mut body, Some("ssv:ParameterSet")).map_err(err)?;
    ser.indent(' ', 2);
    serde::Serialize::serialize(&set, ser).map_err(err)?;
    let body =
        body.replacen("<ssv:ParameterSet", &format!("<ssv:ParameterSet xmlns:ssv=\"{}\"", crate::names::NS_SSV), 1);
    Ok(format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{body}\n"))
}

/// One inline binding with one parameter set named `set_name` (None if there
/// are no parameters). A name given twice keeps its last value, which is the
/// value the list means (later wins), so the written binding stays valid.
pub(crate) fn write_bindings(params: &[Parameter], set_name: &str) -> Option<schema::ParameterBindings> {
    if params.is_empty() {
        return None;
    }
    let last: HashMap<&str, usize> = params.iter().enumerate().map(|(i, p)| (p.name.as_str(), i)).collect();
    let parameter = params
        .iter()
        .enumerate()
        .filter(|(i, p)| last[p.name.as_str()] == *i)
        .map(|(_, p)| schema::Parameter { name: Some(p.name.clone()), children: vec![write_value(&p.value)] })
        .collect();
    Some(schema::ParameterBindings {
        binding: vec![schema::ParameterBinding {
            values: Some(schema::ParameterValues {
                sets: vec![schema::ParameterSet {
                    version: Some("1.0".into()),
                    name: Some(set_name.to_string()),
                    parameters: Some(schema::Parameters { parameter }),
                }],
            }),
            ..Default::default()
        }],
    })
}

#[cfg(test)]
mod ssv_tests {
    use super::*;

    #[test]
    fn a_written_parameter_set_reads_back() {
        let params = vec![
            Parameter { name: "pid.kp".into(), value: ParamValue::Real(1.5e5, None) },
            Parameter { name: "structure".into(), value: ParamValue::Integer(2) },
            Parameter { name: "fractional.method".into(), value: ParamValue::Enumeration("oustaloup".into()) },
        ];
        let xml = ssv_xml("tuned_pid", &params).unwrap();
        assert!(xml.contains("name=\"tuned_pid\""), "{xml}");
        assert_eq!(parse_ssv(&xml, "tuned_pid.ssv", "").unwrap(), params);
        assert!(ssv_xml("empty", &[]).is_err());
    }
}
