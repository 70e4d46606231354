//! Reading an SSD: the streaming pre-scan, quick-xml's serde deserializer
//! into [`crate::schema`], then the checked conversion into the model
//! ([`SystemDescription`]) with messages that name the file and the element.
//!
//! Supported: one flat `ssd:System` of FMU components (`ssd:Component` with
//! `name`, `source`, `type` and `implementation` CoSimulation), their
//! connectors with an optional `ssc:` type, connections with an optional
//! `ssc:LinearTransformation`, parameter bindings ([`crate::bindings`]) and
//! `ssd:DefaultExperiment` with this master's annotation. Refused with a clear
//! error: nested systems, signal dictionaries, parameter mappings, mapping
//! transformations, Model Exchange components.

use crate::bindings::{SourceReader, read_bindings};
use crate::error::{SspError, invalid};
use crate::model::{
    ComponentDesc, Connection, Connector, ConnectorKind, ConnectorType, Linear, MasterSettings, Order,
    SystemDescription,
};
use crate::names::ANNOTATION_TYPE;
use crate::number::{opt_f64, parse_f64};
use crate::prescan::{SSD_ROOT, deserialize};
use crate::schema;

fn connector_type(c: &schema::Connector) -> Option<ConnectorType> {
    if let Some(r) = &c.real {
        Some(ConnectorType::Real(r.unit.clone()))
    } else if c.integer.is_some() {
        Some(ConnectorType::Integer)
    } else if c.boolean.is_some() {
        Some(ConnectorType::Boolean)
    } else if c.string.is_some() {
        Some(ConnectorType::String)
    } else {
        c.enumeration.as_ref().map(|e| ConnectorType::Enumeration(e.name.clone().unwrap_or_default()))
    }
}

fn component(e: &schema::Component, file: &str, read: Option<SourceReader<'_>>) -> Result<ComponentDesc, SspError> {
    let name = e.name.clone().ok_or_else(|| invalid(file, "ssd:Component without a name"))?;
    if let Some(t) = e.r#type.as_deref()
        && t != "application/x-fmu-sharedlibrary"
    {
        return Err(invalid(file, format!("component {name}: type {t} is not an FMU")));
    }
    let source = e.source.clone().ok_or_else(|| invalid(file, format!("component {name} has no source")))?;
    if e.implementation.as_deref() == Some("ModelExchange") {
        return Err(invalid(
            file,
            format!("component {name}: implementation ModelExchange (this master runs CoSimulation)"),
        ));
    }
    let mut connectors = Vec::new();
    for c in e.connectors.iter().flat_map(|c| &c.connector) {
        let cname =
            c.name.clone().ok_or_else(|| invalid(file, format!("component {name}: connector without a name")))?;
        let kind = c
            .kind
            .as_deref()
            .and_then(ConnectorKind::parse)
            .ok_or_else(|| invalid(file, format!("connector {name}.{cname}: missing or unknown kind")))?;
        connectors.push(Connector { name: cname, kind, ty: connector_type(c) });
    }
    Ok(ComponentDesc {
        parameters: read_bindings(e.parameter_bindings.as_ref(), file, read)?,
        name,
        source,
        implementation: e.implementation.clone(),
        description: e.description.clone(),
        connectors,
    })
}

fn connection(c: &schema::Connection, file: &str) -> Result<Connection, SspError> {
    let req =
        |v: &Option<String>, a: &str| v.clone().ok_or_else(|| invalid(file, format!("ssd:Connection without {a}")));
    if c.boolean_mapping.is_some() || c.integer_mapping.is_some() || c.enumeration_mapping.is_some() {
        return Err(invalid(file, "mapping transformations on connections are not supported"));
    }
    let linear = match &c.linear {
        Some(t) => Some(Linear {
            factor: opt_f64(file, "factor", t.factor.as_deref())?.unwrap_or(1.0),
            offset: opt_f64(file, "offset", t.offset.as_deref())?.unwrap_or(0.0),
        }),
        None => None,
    };
    Ok(Connection {
        start_element: c.start_element.clone(),
        start_connector: req(&c.start_connector, "startConnector")?,
        end_element: c.end_element.clone(),
        end_connector: req(&c.end_connector, "endConnector")?,
        linear,
    })
}

fn master_settings(annotations: Option<&schema::Annotations>, file: &str) -> Result<MasterSettings, SspError> {
    let mut m = MasterSettings::default();
    let ours = annotations.iter().flat_map(|a| &a.annotation).filter(|a| a.r#type.as_deref() == Some(ANNOTATION_TYPE));
    for s in ours.flat_map(|a| &a.settings) {
        if let Some(v) = &s.step_size {
            m.step_size = Some(parse_f64(file, "stepSize", v)?);
        }
        if let Some(v) = &s.order {
            m.order = Some(Order::parse(v).ok_or_else(|| invalid(file, format!("unknown order '{v}'")))?);
        }
        if let Some(v) = &s.sequence {
            m.sequence = v.split_whitespace().map(str::to_owned).collect();
        }
    }
    Ok(m)
}

impl SystemDescription {
    /// Parse an SSD document. `file` names it in errors; `read_source`
    /// reads `source=` files of parameter bindings relative to the SSD (None:
    /// such references are an error).
    pub fn from_xml(xml: &str, file: &str, read_source: Option<SourceReader<'_>>) -> Result<Self, SspError> {
        parse_ssd(xml, file, read_source)
    }
}

fn parse_ssd(xml: &str, file: &str, read_source: Option<SourceReader<'_>>) -> Result<SystemDescription, SspError> {
    let doc: schema::Ssd = deserialize(xml, file, SSD_ROOT)?;
    let version = doc.version.as_deref().unwrap_or("");
    if !version.starts_with("1.") {
        return Err(invalid(file, format!("SSD version '{version}' (this master reads SSP 1.x)")));
    }
    let system = doc.system.as_ref().ok_or_else(|| invalid(file, "no ssd:System element"))?;
    let mut components: Vec<ComponentDesc> = Vec::new();
    // names seen (a set: comparing each component with all before it made a 4 MB SSD of 37 500
    // components take 7.4 s, quadratic in their number)
    let mut names = std::collections::HashSet::new();
    for e in system.elements.iter().flat_map(|e| &e.items) {
        match e {
            schema::Element::Component(c) => {
                let c = component(c, file, read_source)?;
                if !names.insert(c.name.clone()) {
                    return Err(invalid(file, format!("two components are named {}", c.name)));
                }
                components.push(c);
            }
            schema::Element::System(_) => {
                return Err(invalid(file, "nested ssd:System elements are not supported by this master"));
            }
            schema::Element::SignalDictionaryReference(_) => {
                return Err(invalid(file, "signal dictionaries (ssd:SignalDictionaryReference) are not supported"));
            }
        }
    }
    let connections = system
        .connections
        .iter()
        .flat_map(|c| &c.connection)
        .map(|c| connection(c, file))
        .collect::<Result<Vec<_>, _>>()?;
    let parameters = read_bindings(system.parameter_bindings.as_ref(), file, read_source)?;
    let de = doc.default_experiment.as_ref();
    Ok(SystemDescription {
        name: doc.name.clone().unwrap_or_default(),
        generation_tool: doc.generation_tool.clone(),
        system_name: system.name.clone().unwrap_or_default(),
        description: system.description.clone(),
        components,
        connections,
        parameters,
        start_time: opt_f64(file, "startTime", de.and_then(|d| d.start_time.as_deref()))?,
        stop_time: opt_f64(file, "stopTime", de.and_then(|d| d.stop_time.as_deref()))?,
        master: master_settings(de.and_then(|d| d.annotations.as_ref()), file)?,
    })
}

#[cfg(test)]
mod tests {
    /// 37 500 components (a 3.6 MB SSD with 300 000 attributes, 8 per component) took 7.4 s in
    /// `cosim info`: each name was compared with every one before it. A duplicate is still
    /// refused.
    #[test]
    fn many_components_read_and_a_duplicate_name_is_refused() {
        let head = r#"<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0" name="x"><ssd:System name="s"><ssd:Elements>"#;
        let tail = "</ssd:Elements></ssd:System></ssd:SystemStructureDescription>";
        let comps: String =
            (0..37_500).map(|k| format!(r#"<ssd:Component name="c{k}" source="resources/X.fmu"/>"#)).collect();
        let d = crate::SystemDescription::from_xml(&format!("{head}{comps}{tail}"), "many.ssd", None).unwrap();
        assert_eq!(d.components.len(), 37_500);
        let twice = format!(r#"{head}{comps}<ssd:Component name="c7" source="resources/X.fmu"/>{tail}"#);
        let e = crate::SystemDescription::from_xml(&twice, "twice.ssd", None).unwrap_err().to_string();
        assert!(e.contains("two components are named c7"), "{e}");
    }
}
