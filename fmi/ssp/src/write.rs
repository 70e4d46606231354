//! Writing an SSD: the model becomes [`crate::schema`] values, which
//! quick-xml's serializer writes with the standard prefixes (`ssd:`, `ssc:`,
//! `ssv:` declared on the root; this master's annotation element declares
//! its own namespace). Numbers are written in the shortest form that reads
//! back to the same double (`1e-5`, `30.0`), valid as `xs:double`. The
//! output validates against the SSP 1.0 XSD (checked with the schema files
//! FMPy ships, `tests/python/test_ssd_schema.py`).

use crate::bindings::write_bindings;
use crate::error::SspError;
use crate::model::{ConnectorType, SystemDescription};
use crate::names::{ANNOTATION_TYPE, NS_MASTER, NS_SSC, NS_SSD, NS_SSV};
use crate::number::num;
use crate::schema;
use serde::Serialize;

fn connector(k: &crate::model::Connector) -> schema::Connector {
    let mut c =
        schema::Connector { name: Some(k.name.clone()), kind: Some(k.kind.as_str().into()), ..Default::default() };
    match &k.ty {
        None => {}
        Some(ConnectorType::Real(unit)) => c.real = Some(schema::RealType { unit: unit.clone() }),
        Some(ConnectorType::Integer) => c.integer = Some(schema::Empty {}),
        Some(ConnectorType::Boolean) => c.boolean = Some(schema::Empty {}),
        Some(ConnectorType::String) => c.string = Some(schema::Empty {}),
        Some(ConnectorType::Enumeration(n)) => c.enumeration = Some(schema::EnumerationType { name: Some(n.clone()) }),
    }
    c
}

fn component(c: &crate::model::ComponentDesc) -> schema::Component {
    schema::Component {
        name: Some(c.name.clone()),
        r#type: Some("application/x-fmu-sharedlibrary".into()),
        source: Some(c.source.clone()),
        implementation: c.implementation.clone(),
        description: c.description.clone(),
        connectors: (!c.connectors.is_empty())
            .then(|| schema::Connectors { connector: c.connectors.iter().map(connector).collect() }),
        parameter_bindings: write_bindings(&c.parameters, &format!("{} parameters", c.name)),
    }
}

fn connection(c: &crate::model::Connection) -> schema::Connection {
    schema::Connection {
        start_element: c.start_element.clone(),
        start_connector: Some(c.start_connector.clone()),
        end_element: c.end_element.clone(),
        end_connector: Some(c.end_connector.clone()),
        linear: c
            .linear
            .map(|l| schema::LinearTransformation { factor: Some(num(l.factor)), offset: Some(num(l.offset)) }),
        ..Default::default()
    }
}

fn default_experiment(d: &SystemDescription) -> Option<schema::DefaultExperiment> {
    let m = &d.master;
    if d.start_time.is_none() && d.stop_time.is_none() && m.is_empty() {
        return None;
    }
    let settings = schema::MasterSettings {
        xmlns_master: NS_MASTER.into(),
        step_size: m.step_size.map(num),
        order: m.order.map(|o| o.as_str().into()),
        sequence: (!m.sequence.is_empty()).then(|| m.sequence.join(" ")),
    };
    Some(schema::DefaultExperiment {
        start_time: d.start_time.map(num),
        stop_time: d.stop_time.map(num),
        annotations: (!m.is_empty()).then(|| schema::Annotations {
            annotation: vec![schema::Annotation { r#type: Some(ANNOTATION_TYPE.into()), settings: vec![settings] }],
        }),
    })
}

fn document(d: &SystemDescription) -> schema::Ssd {
    schema::Ssd {
        xmlns_ssd: NS_SSD.into(),
        xmlns_ssc: NS_SSC.into(),
        xmlns_ssv: NS_SSV.into(),
        version: Some("1.0".into()),
        name: Some(d.name.clone()),
        generation_tool: d.generation_tool.clone(),
        system: Some(schema::System {
            name: Some(d.system_name.clone()),
            description: d.description.clone(),
            parameter_bindings: write_bindings(&d.parameters, "system parameters"),
            elements: (!d.components.is_empty()).then(|| schema::Elements {
                items: d.components.iter().map(|c| schema::Element::Component(component(c))).collect(),
            }),
            connections: (!d.connections.is_empty())
                .then(|| schema::Connections { connection: d.connections.iter().map(connection).collect() }),
        }),
        default_experiment: default_experiment(d),
    }
}

impl SystemDescription {
    /// Render as a standard `SystemStructure.ssd` (SSP 1.0, UTF-8, with XML declaration).
    pub fn to_xml(&self) -> Result<String, SspError> {
        to_xml(self)
    }
}

fn to_xml(d: &SystemDescription) -> Result<String, SspError> {
    let err = |e: quick_xml::SeError| SspError::Write { name: d.name.clone(), message: e.to_string() };
    let mut body = String::new();
    let mut ser =
        quick_xml::se::Serializer::with_root(&mut body, Some("ssd:SystemStructureDescription")).map_err(err)?;
    ser.indent(' ', 2);
    document(d).serialize(ser).map_err(err)?;
    Ok(format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{body}\n"))
}
