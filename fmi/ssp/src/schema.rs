//! Serde mirror of the parts of the SSP 1.0 schemas this crate reads and
//! writes (`SystemStructureDescription.xsd`, `SystemStructureCommon.xsd`,
//! `SystemStructureParameterValues.xsd`).
//!
//! Attributes are `@`-renamed fields. Element names differ by direction:
//! quick-xml's deserializer matches *local* names (so any prefix, or a
//! default namespace, reads), while the serializer writes the name as given,
//! so writing uses the standard prefixes `ssd:`, `ssc:`, `ssv:`. Namespaces
//! themselves are checked by the streaming pre-scan ([`crate::prescan`]).
//! Numbers stay text here; [`crate::read`] converts them with messages that
//! say which attribute of which element is wrong.

use serde::{Deserialize, Serialize};

/// An element this crate recognises but does not support (its content is skipped).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Unsupported {}

/// An element without attributes or content (`<ssc:Integer/>`).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Empty {}

/// `ssd:SystemStructureDescription`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Ssd {
    #[serde(rename = "@xmlns:ssd", skip_deserializing, skip_serializing_if = "String::is_empty")]
    pub xmlns_ssd: String,
    #[serde(rename = "@xmlns:ssc", skip_deserializing, skip_serializing_if = "String::is_empty")]
    pub xmlns_ssc: String,
    #[serde(rename = "@xmlns:ssv", skip_deserializing, skip_serializing_if = "String::is_empty")]
    pub xmlns_ssv: String,
    #[serde(rename = "@version", default)]
    pub version: Option<String>,
    #[serde(rename = "@name", default)]
    pub name: Option<String>,
    #[serde(rename = "@generationTool", default, skip_serializing_if = "Option::is_none")]
    pub generation_tool: Option<String>,
    #[serde(rename(serialize = "ssd:System", deserialize = "System"), default)]
    pub system: Option<System>,
    #[serde(
        rename(serialize = "ssd:DefaultExperiment", deserialize = "DefaultExperiment"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub default_experiment: Option<DefaultExperiment>,
}

/// `ssd:System`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct System {
    #[serde(rename = "@name", default)]
    pub name: Option<String>,
    #[serde(rename = "@description", default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    #[serde(
        rename(serialize = "ssd:ParameterBindings", deserialize = "ParameterBindings"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub parameter_bindings: Option<ParameterBindings>,
    #[serde(
        rename(serialize = "ssd:Elements", deserialize = "Elements"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub elements: Option<Elements>,
    #[serde(
        rename(serialize = "ssd:Connections", deserialize = "Connections"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub connections: Option<Connections>,
}

/// `ssd:Elements`: components, nested systems and signal dictionary references, in document order.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Elements {
    #[serde(rename = "$value", default)]
    pub items: Vec<Element>,
}

/// One child of `ssd:Elements`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) enum Element {
    #[serde(rename(serialize = "ssd:Component", deserialize = "Component"))]
    Component(Component),
    #[serde(rename(serialize = "ssd:System", deserialize = "System"))]
    System(Unsupported),
    #[serde(rename(serialize = "ssd:SignalDictionaryReference", deserialize = "SignalDictionaryReference"))]
    SignalDictionaryReference(Unsupported),
}

/// `ssd:Component`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Component {
    #[serde(rename = "@name", default)]
    pub name: Option<String>,
    #[serde(rename = "@type", default, skip_serializing_if = "Option::is_none")]
    pub r#type: Option<String>,
    #[serde(rename = "@source", default)]
    pub source: Option<String>,
    #[serde(rename = "@implementation", default, skip_serializing_if = "Option::is_none")]
    pub implementation: Option<String>,
    #[serde(rename = "@description", default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    #[serde(
        rename(serialize = "ssd:Connectors", deserialize = "Connectors"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub connectors: Option<Connectors>,
    #[serde(
        rename(serialize = "ssd:ParameterBindings", deserialize = "ParameterBindings"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub parameter_bindings: Option<ParameterBindings>,
}

/// `ssd:Connectors`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Connectors {
    #[serde(rename(serialize = "ssd:Connector", deserialize = "Connector"), default)]
    pub connector: Vec<Connector>,
}

/// `ssd:Connector` with its optional type element.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Connector {
    #[serde(rename = "@name", default)]
    pub name: Option<String>,
    #[serde(rename = "@kind", default)]
    pub kind: Option<String>,
    #[serde(rename(serialize = "ssc:Real", deserialize = "Real"), default, skip_serializing_if = "Option::is_none")]
    pub real: Option<RealType>,
    #[serde(
        rename(serialize = "ssc:Integer", deserialize = "Integer"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub integer: Option<Empty>,
    #[serde(
        rename(serialize = "ssc:Boolean", deserialize = "Boolean"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub boolean: Option<Empty>,
    #[serde(
        rename(serialize = "ssc:String", deserialize = "String"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub string: Option<Empty>,
    #[serde(
        rename(serialize = "ssc:Enumeration", deserialize = "Enumeration"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub enumeration: Option<EnumerationType>,
}

/// `ssc:Real` (connector type).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct RealType {
    #[serde(rename = "@unit", default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
}

/// `ssc:Enumeration` (connector type).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct EnumerationType {
    #[serde(rename = "@name", default)]
    pub name: Option<String>,
}

/// `ssd:Connections`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Connections {
    #[serde(rename(serialize = "ssd:Connection", deserialize = "Connection"), default)]
    pub connection: Vec<Connection>,
}

/// `ssd:Connection`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Connection {
    #[serde(rename = "@startElement", default, skip_serializing_if = "Option::is_none")]
    pub start_element: Option<String>,
    #[serde(rename = "@startConnector", default)]
    pub start_connector: Option<String>,
    #[serde(rename = "@endElement", default, skip_serializing_if = "Option::is_none")]
    pub end_element: Option<String>,
    #[serde(rename = "@endConnector", default)]
    pub end_connector: Option<String>,
    #[serde(
        rename(serialize = "ssc:LinearTransformation", deserialize = "LinearTransformation"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub linear: Option<LinearTransformation>,
    #[serde(rename = "BooleanMappingTransformation", default, skip_serializing)]
    pub boolean_mapping: Option<Unsupported>,
    #[serde(rename = "IntegerMappingTransformation", default, skip_serializing)]
    pub integer_mapping: Option<Unsupported>,
    #[serde(rename = "EnumerationMappingTransformation", default, skip_serializing)]
    pub enumeration_mapping: Option<Unsupported>,
}

/// `ssc:LinearTransformation`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct LinearTransformation {
    #[serde(rename = "@factor", default, skip_serializing_if = "Option::is_none")]
    pub factor: Option<String>,
    #[serde(rename = "@offset", default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<String>,
}

/// `ssd:ParameterBindings`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct ParameterBindings {
    #[serde(rename(serialize = "ssd:ParameterBinding", deserialize = "ParameterBinding"), default)]
    pub binding: Vec<ParameterBinding>,
}

/// `ssd:ParameterBinding`: values inline or in a `source` file, names prefixed by `prefix`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct ParameterBinding {
    #[serde(rename = "@type", default, skip_serializing_if = "Option::is_none")]
    pub r#type: Option<String>,
    #[serde(rename = "@source", default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    #[serde(rename = "@prefix", default, skip_serializing_if = "Option::is_none")]
    pub prefix: Option<String>,
    #[serde(
        rename(serialize = "ssd:ParameterValues", deserialize = "ParameterValues"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub values: Option<ParameterValues>,
    #[serde(rename = "ParameterMapping", default, skip_serializing)]
    pub mapping: Option<Unsupported>,
}

/// `ssd:ParameterValues`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct ParameterValues {
    #[serde(rename(serialize = "ssv:ParameterSet", deserialize = "ParameterSet"), default)]
    pub sets: Vec<ParameterSet>,
}

/// `ssv:ParameterSet` (inline, or the root of an `.ssv` file).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct ParameterSet {
    #[serde(rename = "@version", default)]
    pub version: Option<String>,
    #[serde(rename = "@name", default)]
    pub name: Option<String>,
    #[serde(
        rename(serialize = "ssv:Parameters", deserialize = "Parameters"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub parameters: Option<Parameters>,
}

/// `ssv:Parameters`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Parameters {
    #[serde(rename(serialize = "ssv:Parameter", deserialize = "Parameter"), default)]
    pub parameter: Vec<Parameter>,
}

/// `ssv:Parameter`: a name and (exactly one, checked when reading) value element.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Parameter {
    #[serde(rename = "@name", default)]
    pub name: Option<String>,
    #[serde(rename = "$value", default)]
    pub children: Vec<ParameterChild>,
}

/// A child of `ssv:Parameter`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) enum ParameterChild {
    #[serde(rename(serialize = "ssv:Real", deserialize = "Real"))]
    Real(RealValue),
    #[serde(rename(serialize = "ssv:Integer", deserialize = "Integer"))]
    Integer(Value),
    #[serde(rename(serialize = "ssv:Boolean", deserialize = "Boolean"))]
    Boolean(Value),
    #[serde(rename(serialize = "ssv:String", deserialize = "String"))]
    String(Value),
    #[serde(rename(serialize = "ssv:Enumeration", deserialize = "Enumeration"))]
    Enumeration(Value),
    #[serde(rename(serialize = "ssv:Binary", deserialize = "Binary"))]
    Binary(Unsupported),
    #[serde(rename(serialize = "ssv:Annotations", deserialize = "Annotations"))]
    Annotations(Unsupported),
}

/// `ssv:Real value unit`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct RealValue {
    #[serde(rename = "@value", default)]
    pub value: Option<String>,
    #[serde(rename = "@unit", default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
}

/// `ssv:Integer|Boolean|String|Enumeration value`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Value {
    #[serde(rename = "@value", default)]
    pub value: Option<String>,
}

/// `ssd:DefaultExperiment`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct DefaultExperiment {
    #[serde(rename = "@startTime", default, skip_serializing_if = "Option::is_none")]
    pub start_time: Option<String>,
    #[serde(rename = "@stopTime", default, skip_serializing_if = "Option::is_none")]
    pub stop_time: Option<String>,
    #[serde(
        rename(serialize = "ssd:Annotations", deserialize = "Annotations"),
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub annotations: Option<Annotations>,
}

/// `ssd:Annotations`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Annotations {
    #[serde(rename(serialize = "ssc:Annotation", deserialize = "Annotation"), default)]
    pub annotation: Vec<Annotation>,
}

/// `ssc:Annotation`: this master reads only its own type (see [`crate::names::ANNOTATION_TYPE`]).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Annotation {
    #[serde(rename = "@type", default)]
    pub r#type: Option<String>,
    #[serde(rename(serialize = "master:Settings", deserialize = "Settings"), default)]
    pub settings: Vec<MasterSettings>,
}

/// `master:Settings` inside this master's annotation.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct MasterSettings {
    #[serde(rename = "@xmlns:master", skip_deserializing, skip_serializing_if = "String::is_empty")]
    pub xmlns_master: String,
    #[serde(rename = "@stepSize", default, skip_serializing_if = "Option::is_none")]
    pub step_size: Option<String>,
    #[serde(rename = "@order", default, skip_serializing_if = "Option::is_none")]
    pub order: Option<String>,
    #[serde(rename = "@sequence", default, skip_serializing_if = "Option::is_none")]
    pub sequence: Option<String>,
}
