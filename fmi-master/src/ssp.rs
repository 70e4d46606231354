//! SSP 1.0 system structure descriptions: read and write `SystemStructure.ssd`
//! and `.ssp` archives.
//!
//! Read (namespace-aware, any prefixes): the root `ssd:SystemStructureDescription`,
//! its `ssd:System` with `ssd:Elements/ssd:Component` (`name`, `source`,
//! `implementation`), their `ssd:Connectors/ssd:Connector` (`name`, `kind`,
//! an optional `ssc:Real|Integer|Boolean|String|Enumeration` type), the
//! `ssd:Connections/ssd:Connection`s (`startElement`, `startConnector`,
//! `endElement`, `endConnector`, optional `ssc:LinearTransformation`), and
//! `ssd:ParameterBindings/ssd:ParameterBinding` on components and on the
//! system: inline `ssd:ParameterValues/ssv:ParameterSet/ssv:Parameters/ssv:Parameter`
//! with `ssv:Real|Integer|Boolean|String|Enumeration value=…`, or a `source`
//! `.ssv` file next to the SSD; a binding's `prefix` is prepended to the
//! names. `ssd:DefaultExperiment` (`startTime`, `stopTime`) is read, and
//! this master's own annotation on it ([`ANNOTATION_TYPE`]) carries the
//! communication step and the stepping order, which SSP 1.0 has no attribute
//! for. Nested systems and signal dictionaries are refused with a clear error.
//!
//! Write: [`SystemDescription::to_xml`] produces a standard SSD that
//! validates against the SSP 1.0 XSD (checked by `tests/python` with the
//! schema files FMPy ships), and [`write_ssp_archive`] packs it with FMUs
//! under `resources/`.

use quick_xml::events::Event;
use quick_xml::name::ResolveResult;
use std::io::Write;
use std::path::Path;

/// Namespace of `ssd:` elements.
pub const NS_SSD: &str = "http://ssp-standard.org/SSP1/SystemStructureDescription";
/// Namespace of `ssc:` elements.
pub const NS_SSC: &str = "http://ssp-standard.org/SSP1/SystemStructureCommon";
/// Namespace of `ssv:` elements.
pub const NS_SSV: &str = "http://ssp-standard.org/SSP1/SystemStructureParameterValues";
/// Type of this master's annotation (communication step, order).
pub const ANNOTATION_TYPE: &str = "org.chatter-fmu.master";
/// Namespace of the element inside that annotation.
pub const NS_MASTER: &str = "urn:chatter-fmu:master:1";

/// Errors reading or writing system descriptions.
#[derive(Debug, thiserror::Error)]
pub enum SspError {
    /// Malformed XML.
    #[error("{file}: XML error: {message}")]
    Xml {
        /// The file.
        file: String,
        /// The parser's message.
        message: String,
    },
    /// Well-formed XML that is not a usable SSD.
    #[error("{file}: {message}")]
    Invalid {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// Archive or file-system problem.
    #[error("{0}")]
    Io(String),
}

/// Kind of a connector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum ConnectorKind {
    Input,
    Output,
    Parameter,
    CalculatedParameter,
    Inout,
}

impl ConnectorKind {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "input" => Self::Input,
            "output" => Self::Output,
            "parameter" => Self::Parameter,
            "calculatedParameter" => Self::CalculatedParameter,
            "inout" => Self::Inout,
            _ => return None,
        })
    }

    /// The SSD spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Input => "input",
            Self::Output => "output",
            Self::Parameter => "parameter",
            Self::CalculatedParameter => "calculatedParameter",
            Self::Inout => "inout",
        }
    }
}

/// Declared type of a connector (`ssc:Real` …).
#[derive(Clone, Debug, PartialEq)]
pub enum ConnectorType {
    /// `ssc:Real`, optional unit.
    Real(Option<String>),
    /// `ssc:Integer`.
    Integer,
    /// `ssc:Boolean`.
    Boolean,
    /// `ssc:String`.
    String,
    /// `ssc:Enumeration name=…`.
    Enumeration(String),
}

/// A connector of a component.
#[derive(Clone, Debug, PartialEq)]
pub struct Connector {
    /// Variable name in the FMU.
    pub name: String,
    /// Kind.
    pub kind: ConnectorKind,
    /// Declared type, if any.
    pub ty: Option<ConnectorType>,
}

/// A parameter value of an `ssv:Parameter`.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamValue {
    /// `ssv:Real value unit`.
    Real(f64, Option<String>),
    /// `ssv:Integer`.
    Integer(i32),
    /// `ssv:Boolean`.
    Boolean(bool),
    /// `ssv:String`.
    String(String),
    /// `ssv:Enumeration value=` (the item name).
    Enumeration(String),
}

impl std::fmt::Display for ParamValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParamValue::Real(x, _) => write!(f, "{x}"),
            ParamValue::Integer(i) => write!(f, "{i}"),
            ParamValue::Boolean(b) => write!(f, "{b}"),
            ParamValue::String(s) | ParamValue::Enumeration(s) => write!(f, "{s}"),
        }
    }
}

/// A parameter binding entry (name as resolved: prefix applied).
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// Variable name (component level) or `element.variable` (system level).
    pub name: String,
    /// Value.
    pub value: ParamValue,
}

/// An `ssd:Component`.
#[derive(Clone, Debug, PartialEq)]
pub struct ComponentDesc {
    /// Element name (unique in the system).
    pub name: String,
    /// `source` URI, e.g. `resources/MillingPlant.fmu`.
    pub source: String,
    /// `implementation` attribute, if given.
    pub implementation: Option<String>,
    /// Description attribute.
    pub description: Option<String>,
    /// Connectors.
    pub connectors: Vec<Connector>,
    /// Inline parameters (bare variable names).
    pub parameters: Vec<Parameter>,
}

/// A linear transformation on a connection: `end = factor·start + offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Linear {
    /// Factor.
    pub factor: f64,
    /// Offset.
    pub offset: f64,
}

/// An `ssd:Connection`.
#[derive(Clone, Debug, PartialEq)]
pub struct Connection {
    /// Start element (None: the system itself).
    pub start_element: Option<String>,
    /// Start connector.
    pub start_connector: String,
    /// End element (None: the system itself).
    pub end_element: Option<String>,
    /// End connector.
    pub end_connector: String,
    /// Optional linear transformation.
    pub linear: Option<Linear>,
}

impl Connection {
    /// `plant.x → controller.y` style label.
    pub fn label(&self) -> String {
        format!(
            "{}.{} → {}.{}",
            self.start_element.as_deref().unwrap_or("(system)"),
            self.start_connector,
            self.end_element.as_deref().unwrap_or("(system)"),
            self.end_connector
        )
    }
}

/// Stepping order of the run engine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Order {
    /// Sequential: each component steps with inputs from components already stepped this round.
    #[default]
    GaussSeidel,
    /// Parallel: all components step with the outputs of the previous communication point.
    Jacobi,
}

impl Order {
    /// Parse `gauss-seidel` / `jacobi`.
    pub fn parse(s: &str) -> Option<Order> {
        match s.to_ascii_lowercase().replace('_', "-").as_str() {
            "gauss-seidel" | "gs" | "sequential" => Some(Order::GaussSeidel),
            "jacobi" | "parallel" => Some(Order::Jacobi),
            _ => None,
        }
    }

    /// Canonical spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Order::GaussSeidel => "gauss-seidel",
            Order::Jacobi => "jacobi",
        }
    }
}

/// This master's settings, stored as an annotation of `ssd:DefaultExperiment`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct MasterSettings {
    /// Communication step size [s].
    pub step_size: Option<f64>,
    /// Stepping order.
    pub order: Option<Order>,
    /// Component sequence for Gauss–Seidel (element names, first steps first).
    pub sequence: Vec<String>,
}

/// A whole system structure description (one flat system of components).
#[derive(Clone, Debug, PartialEq)]
pub struct SystemDescription {
    /// `name` of the root element.
    pub name: String,
    /// `name` of the `ssd:System`.
    pub system_name: String,
    /// Description of the system.
    pub description: Option<String>,
    /// Components in document order.
    pub components: Vec<ComponentDesc>,
    /// Connections.
    pub connections: Vec<Connection>,
    /// System-level parameters (`element.variable` names).
    pub parameters: Vec<Parameter>,
    /// `ssd:DefaultExperiment` start time.
    pub start_time: Option<f64>,
    /// `ssd:DefaultExperiment` stop time.
    pub stop_time: Option<f64>,
    /// This master's settings.
    pub master: MasterSettings,
}

// ---------------------------------------------------------------------------
// A tiny namespace-resolved DOM

#[derive(Debug, Clone)]
struct El {
    ns: String,
    local: String,
    attrs: Vec<(String, String)>,
    children: Vec<El>,
}

impl El {
    fn attr(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str())
    }
    fn is(&self, ns: &str, local: &str) -> bool {
        self.ns == ns && self.local == local
    }
    fn child(&self, ns: &str, local: &str) -> Option<&El> {
        self.children.iter().find(|c| c.is(ns, local))
    }
    fn children_named<'a>(&'a self, ns: &'a str, local: &'a str) -> impl Iterator<Item = &'a El> + 'a {
        self.children.iter().filter(move |c| c.is(ns, local))
    }
}

fn parse_dom(xml: &str, file: &str) -> Result<El, SspError> {
    let xml_err = |e: &dyn std::fmt::Display| SspError::Xml { file: file.to_string(), message: e.to_string() };
    let mut reader = quick_xml::reader::NsReader::from_str(xml);
    reader.config_mut().trim_text(true);
    let mut stack: Vec<El> = Vec::new();
    let mut root: Option<El> = None;
    loop {
        let (ns, ev) = reader.read_resolved_event().map_err(|e| xml_err(&e))?;
        let ns = match ns {
            ResolveResult::Bound(n) => String::from_utf8_lossy(n.as_ref()).into_owned(),
            ResolveResult::Unbound => String::new(),
            ResolveResult::Unknown(p) => {
                return Err(xml_err(&format!("undeclared namespace prefix '{}'", String::from_utf8_lossy(&p))));
            }
        };
        match ev {
            Event::Start(ref e) | Event::Empty(ref e) => {
                let mut attrs = Vec::new();
                for a in e.attributes() {
                    let a = a.map_err(|e| xml_err(&e))?;
                    if a.key.as_namespace_binding().is_some() {
                        continue;
                    }
                    let key = String::from_utf8_lossy(a.key.local_name().as_ref()).into_owned();
                    let value = a.unescape_value().map_err(|e| xml_err(&e))?.into_owned();
                    attrs.push((key, value));
                }
                let el = El {
                    ns,
                    local: String::from_utf8_lossy(e.local_name().as_ref()).into_owned(),
                    attrs,
                    children: Vec::new(),
                };
                if matches!(ev, Event::Start(_)) {
                    stack.push(el);
                } else if let Some(parent) = stack.last_mut() {
                    parent.children.push(el);
                } else {
                    root = Some(el);
                }
            }
            Event::End(_) => {
                let el = stack.pop().ok_or_else(|| xml_err(&"unbalanced end tag"))?;
                if let Some(parent) = stack.last_mut() {
                    parent.children.push(el);
                } else {
                    root = Some(el);
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    root.ok_or_else(|| xml_err(&"empty document"))
}

// ---------------------------------------------------------------------------
// Reading

fn invalid(file: &str, message: impl Into<String>) -> SspError {
    SspError::Invalid { file: file.to_string(), message: message.into() }
}

fn parse_f64(file: &str, what: &str, s: &str) -> Result<f64, SspError> {
    s.trim().parse::<f64>().map_err(|_| invalid(file, format!("{what}: '{s}' is not a number")))
}

fn parse_bool(s: &str) -> Option<bool> {
    match s.trim() {
        "true" | "1" => Some(true),
        "false" | "0" => Some(false),
        _ => None,
    }
}

fn parse_parameter_set(set: &El, prefix: &str, file: &str) -> Result<Vec<Parameter>, SspError> {
    let mut out = Vec::new();
    let Some(params) = set.child(NS_SSV, "Parameters") else { return Ok(out) };
    for p in params.children_named(NS_SSV, "Parameter") {
        let name = p.attr("name").ok_or_else(|| invalid(file, "ssv:Parameter without a name"))?;
        let full = format!("{prefix}{name}");
        let ty = p
            .children
            .iter()
            .find(|c| c.ns == NS_SSV && c.local != "Annotations")
            .ok_or_else(|| invalid(file, format!("parameter {full} has no value element")))?;
        let value = ty.attr("value").ok_or_else(|| invalid(file, format!("parameter {full}: no value attribute")))?;
        let what = format!("parameter {full}");
        let v = match ty.local.as_str() {
            "Real" => ParamValue::Real(parse_f64(file, &what, value)?, ty.attr("unit").map(str::to_owned)),
            "Integer" => ParamValue::Integer(
                value.trim().parse().map_err(|_| invalid(file, format!("{what}: '{value}' is not an integer")))?,
            ),
            "Boolean" => ParamValue::Boolean(
                parse_bool(value).ok_or_else(|| invalid(file, format!("{what}: '{value}' is not a boolean")))?,
            ),
            "String" => ParamValue::String(value.to_string()),
            "Enumeration" => ParamValue::Enumeration(value.to_string()),
            other => return Err(invalid(file, format!("{what}: unsupported value type ssv:{other}"))),
        };
        out.push(Parameter { name: full, value: v });
    }
    Ok(out)
}

/// Reads referenced `.ssv` files (`source=` of a binding), relative to the SSD.
pub type SourceReader<'a> = &'a dyn Fn(&str) -> Result<String, SspError>;

fn parse_bindings(el: &El, file: &str, read: Option<SourceReader<'_>>) -> Result<Vec<Parameter>, SspError> {
    let mut out = Vec::new();
    let Some(bindings) = el.child(NS_SSD, "ParameterBindings") else { return Ok(out) };
    for b in bindings.children_named(NS_SSD, "ParameterBinding") {
        let prefix = b.attr("prefix").unwrap_or("");
        if let Some(t) = b.attr("type")
            && t != "application/x-ssp-parameter-set"
        {
            return Err(invalid(file, format!("parameter binding of unsupported type {t}")));
        }
        if b.child(NS_SSD, "ParameterMapping").is_some() {
            return Err(invalid(file, "ssd:ParameterMapping is not supported by this master"));
        }
        if let Some(src) = b.attr("source") {
            let read = read.ok_or_else(|| {
                invalid(
                    file,
                    format!("parameter binding refers to {src}, but this SSD has no location to read it from"),
                )
            })?;
            let text = read(src)?;
            let dom = parse_dom(&text, src)?;
            if !dom.is(NS_SSV, "ParameterSet") {
                return Err(invalid(src, "root element is not ssv:ParameterSet"));
            }
            out.extend(parse_parameter_set(&dom, prefix, src)?);
        }
        if let Some(values) = b.child(NS_SSD, "ParameterValues") {
            for set in values.children_named(NS_SSV, "ParameterSet") {
                out.extend(parse_parameter_set(set, prefix, file)?);
            }
        }
    }
    Ok(out)
}

fn parse_connector_type(c: &El) -> Option<ConnectorType> {
    c.children.iter().find(|t| t.ns == NS_SSC).and_then(|t| match t.local.as_str() {
        "Real" => Some(ConnectorType::Real(t.attr("unit").map(str::to_owned))),
        "Integer" => Some(ConnectorType::Integer),
        "Boolean" => Some(ConnectorType::Boolean),
        "String" => Some(ConnectorType::String),
        "Enumeration" => Some(ConnectorType::Enumeration(t.attr("name").unwrap_or("").to_owned())),
        _ => None,
    })
}

fn parse_master_annotation(annotations: Option<&El>, file: &str) -> Result<MasterSettings, SspError> {
    let mut m = MasterSettings::default();
    let Some(anns) = annotations else { return Ok(m) };
    for a in anns.children_named(NS_SSC, "Annotation") {
        if a.attr("type") != Some(ANNOTATION_TYPE) {
            continue;
        }
        let Some(s) = a.children.iter().find(|c| c.ns == NS_MASTER && c.local == "Settings") else { continue };
        if let Some(v) = s.attr("stepSize") {
            m.step_size = Some(parse_f64(file, "stepSize", v)?);
        }
        if let Some(v) = s.attr("order") {
            m.order = Some(Order::parse(v).ok_or_else(|| invalid(file, format!("unknown order '{v}'")))?);
        }
        if let Some(v) = s.attr("sequence") {
            m.sequence = v.split_whitespace().map(str::to_owned).collect();
        }
    }
    Ok(m)
}

impl SystemDescription {
    /// Parse an SSD document. `read_source` resolves `source=` references of
    /// parameter bindings relative to the SSD (None: such references are an error).
    pub fn from_xml(xml: &str, file: &str, read_source: Option<SourceReader<'_>>) -> Result<Self, SspError> {
        let root = parse_dom(xml, file)?;
        if !root.is(NS_SSD, "SystemStructureDescription") {
            return Err(invalid(
                file,
                format!(
                    "root element is {{{}}}{}, expected ssd:SystemStructureDescription in namespace {NS_SSD}",
                    root.ns, root.local
                ),
            ));
        }
        let version = root.attr("version").unwrap_or("");
        if !version.starts_with("1.") {
            return Err(invalid(file, format!("SSD version '{version}' (this master reads SSP 1.x)")));
        }
        let system = root.child(NS_SSD, "System").ok_or_else(|| invalid(file, "no ssd:System element"))?;
        let mut components = Vec::new();
        if let Some(elements) = system.child(NS_SSD, "Elements") {
            for e in &elements.children {
                if e.is(NS_SSD, "System") {
                    return Err(invalid(file, "nested ssd:System elements are not supported by this master"));
                }
                if !e.is(NS_SSD, "Component") {
                    return Err(invalid(file, format!("unsupported element ssd:{}", e.local)));
                }
                let name = e.attr("name").ok_or_else(|| invalid(file, "ssd:Component without a name"))?.to_string();
                if let Some(t) = e.attr("type")
                    && t != "application/x-fmu-sharedlibrary"
                {
                    return Err(invalid(file, format!("component {name}: type {t} is not an FMU")));
                }
                let source = e
                    .attr("source")
                    .ok_or_else(|| invalid(file, format!("component {name} has no source")))?
                    .to_string();
                let implementation = e.attr("implementation").map(str::to_owned);
                if implementation.as_deref() == Some("ModelExchange") {
                    return Err(invalid(
                        file,
                        format!("component {name}: implementation ModelExchange (this master runs CoSimulation)"),
                    ));
                }
                let mut connectors = Vec::new();
                if let Some(cs) = e.child(NS_SSD, "Connectors") {
                    for c in cs.children_named(NS_SSD, "Connector") {
                        let cname = c.attr("name").ok_or_else(|| invalid(file, "connector without a name"))?;
                        let kind = c.attr("kind").and_then(ConnectorKind::parse).ok_or_else(|| {
                            invalid(file, format!("connector {name}.{cname}: missing or unknown kind"))
                        })?;
                        connectors.push(Connector { name: cname.to_string(), kind, ty: parse_connector_type(c) });
                    }
                }
                let parameters = parse_bindings(e, file, read_source)?;
                components.push(ComponentDesc {
                    name,
                    source,
                    implementation,
                    description: e.attr("description").map(str::to_owned),
                    connectors,
                    parameters,
                });
            }
        }
        let mut names = std::collections::HashSet::new();
        for c in &components {
            if !names.insert(c.name.as_str()) {
                return Err(invalid(file, format!("two components are named {}", c.name)));
            }
        }
        let mut connections = Vec::new();
        if let Some(cs) = system.child(NS_SSD, "Connections") {
            for c in cs.children_named(NS_SSD, "Connection") {
                let req = |a: &str| {
                    c.attr(a).map(str::to_owned).ok_or_else(|| invalid(file, format!("ssd:Connection without {a}")))
                };
                let linear = match c.child(NS_SSC, "LinearTransformation") {
                    Some(t) => Some(Linear {
                        factor: t.attr("factor").map(|v| parse_f64(file, "factor", v)).transpose()?.unwrap_or(1.0),
                        offset: t.attr("offset").map(|v| parse_f64(file, "offset", v)).transpose()?.unwrap_or(0.0),
                    }),
                    None => None,
                };
                if c.children.iter().any(|t| t.ns == NS_SSC && t.local.ends_with("MappingTransformation")) {
                    return Err(invalid(file, "mapping transformations on connections are not supported"));
                }
                connections.push(Connection {
                    start_element: c.attr("startElement").map(str::to_owned),
                    start_connector: req("startConnector")?,
                    end_element: c.attr("endElement").map(str::to_owned),
                    end_connector: req("endConnector")?,
                    linear,
                });
            }
        }
        let parameters = parse_bindings(system, file, read_source)?;
        let (mut start_time, mut stop_time, mut master) = (None, None, MasterSettings::default());
        if let Some(de) = root.child(NS_SSD, "DefaultExperiment") {
            start_time = de.attr("startTime").map(|v| parse_f64(file, "startTime", v)).transpose()?;
            stop_time = de.attr("stopTime").map(|v| parse_f64(file, "stopTime", v)).transpose()?;
            master = parse_master_annotation(de.child(NS_SSD, "Annotations"), file)?;
        }
        Ok(SystemDescription {
            name: root.attr("name").unwrap_or("").to_string(),
            system_name: system.attr("name").unwrap_or("").to_string(),
            description: system.attr("description").map(str::to_owned),
            components,
            connections,
            parameters,
            start_time,
            stop_time,
            master,
        })
    }

    /// The component named `name`.
    pub fn component(&self, name: &str) -> Option<&ComponentDesc> {
        self.components.iter().find(|c| c.name == name)
    }

    /// Render as a standard `SystemStructure.ssd` (SSP 1.0).
    pub fn to_xml(&self) -> String {
        let mut w = String::new();
        w.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        w.push_str(&format!(
            "<ssd:SystemStructureDescription xmlns:ssd=\"{NS_SSD}\" xmlns:ssc=\"{NS_SSC}\" xmlns:ssv=\"{NS_SSV}\" version=\"1.0\" name=\"{}\" generationTool=\"chatter-fmu fmi-master {}\">\n",
            esc(&self.name),
            env!("CARGO_PKG_VERSION")
        ));
        w.push_str(&format!("  <ssd:System name=\"{}\"", esc(&self.system_name)));
        if let Some(d) = &self.description {
            w.push_str(&format!(" description=\"{}\"", esc(d)));
        }
        w.push_str(">\n");
        if !self.parameters.is_empty() {
            write_bindings(&mut w, "    ", &self.parameters, "system parameters");
        }
        if !self.components.is_empty() {
            w.push_str("    <ssd:Elements>\n");
            for c in &self.components {
                w.push_str(&format!(
                    "      <ssd:Component name=\"{}\" type=\"application/x-fmu-sharedlibrary\" source=\"{}\"",
                    esc(&c.name),
                    esc(&c.source)
                ));
                if let Some(i) = &c.implementation {
                    w.push_str(&format!(" implementation=\"{}\"", esc(i)));
                }
                if let Some(d) = &c.description {
                    w.push_str(&format!(" description=\"{}\"", esc(d)));
                }
                if c.connectors.is_empty() && c.parameters.is_empty() {
                    w.push_str("/>\n");
                    continue;
                }
                w.push_str(">\n");
                if !c.connectors.is_empty() {
                    w.push_str("        <ssd:Connectors>\n");
                    for k in &c.connectors {
                        let head =
                            format!("          <ssd:Connector name=\"{}\" kind=\"{}\"", esc(&k.name), k.kind.as_str());
                        match &k.ty {
                            None => w.push_str(&format!("{head}/>\n")),
                            Some(t) => {
                                let ty = match t {
                                    ConnectorType::Real(Some(u)) => format!("<ssc:Real unit=\"{}\"/>", esc(u)),
                                    ConnectorType::Real(None) => "<ssc:Real/>".into(),
                                    ConnectorType::Integer => "<ssc:Integer/>".into(),
                                    ConnectorType::Boolean => "<ssc:Boolean/>".into(),
                                    ConnectorType::String => "<ssc:String/>".into(),
                                    ConnectorType::Enumeration(n) => format!("<ssc:Enumeration name=\"{}\"/>", esc(n)),
                                };
                                w.push_str(&format!("{head}>\n            {ty}\n          </ssd:Connector>\n"));
                            }
                        }
                    }
                    w.push_str("        </ssd:Connectors>\n");
                }
                if !c.parameters.is_empty() {
                    write_bindings(&mut w, "        ", &c.parameters, &format!("{} parameters", c.name));
                }
                w.push_str("      </ssd:Component>\n");
            }
            w.push_str("    </ssd:Elements>\n");
        }
        if !self.connections.is_empty() {
            w.push_str("    <ssd:Connections>\n");
            for c in &self.connections {
                w.push_str("      <ssd:Connection");
                if let Some(e) = &c.start_element {
                    w.push_str(&format!(" startElement=\"{}\"", esc(e)));
                }
                w.push_str(&format!(" startConnector=\"{}\"", esc(&c.start_connector)));
                if let Some(e) = &c.end_element {
                    w.push_str(&format!(" endElement=\"{}\"", esc(e)));
                }
                w.push_str(&format!(" endConnector=\"{}\"", esc(&c.end_connector)));
                match c.linear {
                    None => w.push_str("/>\n"),
                    Some(l) => w.push_str(&format!(
                        ">\n        <ssc:LinearTransformation factor=\"{}\" offset=\"{}\"/>\n      </ssd:Connection>\n",
                        num(l.factor),
                        num(l.offset)
                    )),
                }
            }
            w.push_str("    </ssd:Connections>\n");
        }
        w.push_str("  </ssd:System>\n");
        let m = &self.master;
        let has_master = m.step_size.is_some() || m.order.is_some() || !m.sequence.is_empty();
        if self.start_time.is_some() || self.stop_time.is_some() || has_master {
            w.push_str("  <ssd:DefaultExperiment");
            if let Some(t) = self.start_time {
                w.push_str(&format!(" startTime=\"{}\"", num(t)));
            }
            if let Some(t) = self.stop_time {
                w.push_str(&format!(" stopTime=\"{}\"", num(t)));
            }
            if has_master {
                w.push_str(">\n    <ssd:Annotations>\n");
                w.push_str(&format!("      <ssc:Annotation type=\"{ANNOTATION_TYPE}\">\n"));
                w.push_str(&format!("        <master:Settings xmlns:master=\"{NS_MASTER}\""));
                if let Some(h) = m.step_size {
                    w.push_str(&format!(" stepSize=\"{}\"", num(h)));
                }
                if let Some(o) = m.order {
                    w.push_str(&format!(" order=\"{}\"", o.as_str()));
                }
                if !m.sequence.is_empty() {
                    w.push_str(&format!(" sequence=\"{}\"", esc(&m.sequence.join(" "))));
                }
                w.push_str("/>\n      </ssc:Annotation>\n    </ssd:Annotations>\n  </ssd:DefaultExperiment>\n");
            } else {
                w.push_str("/>\n");
            }
        }
        w.push_str("</ssd:SystemStructureDescription>\n");
        w
    }
}

fn write_bindings(w: &mut String, ind: &str, params: &[Parameter], set_name: &str) {
    w.push_str(&format!(
        "{ind}<ssd:ParameterBindings>\n{ind}  <ssd:ParameterBinding>\n{ind}    <ssd:ParameterValues>\n"
    ));
    w.push_str(&format!(
        "{ind}      <ssv:ParameterSet version=\"1.0\" name=\"{}\">\n{ind}        <ssv:Parameters>\n",
        esc(set_name)
    ));
    for p in params {
        let v = match &p.value {
            ParamValue::Real(x, Some(u)) => format!("<ssv:Real value=\"{}\" unit=\"{}\"/>", num(*x), esc(u)),
            ParamValue::Real(x, None) => format!("<ssv:Real value=\"{}\"/>", num(*x)),
            ParamValue::Integer(i) => format!("<ssv:Integer value=\"{i}\"/>"),
            ParamValue::Boolean(b) => format!("<ssv:Boolean value=\"{b}\"/>"),
            ParamValue::String(s) => format!("<ssv:String value=\"{}\"/>", esc(s)),
            ParamValue::Enumeration(s) => format!("<ssv:Enumeration value=\"{}\"/>", esc(s)),
        };
        w.push_str(&format!(
            "{ind}          <ssv:Parameter name=\"{}\">\n{ind}            {v}\n{ind}          </ssv:Parameter>\n",
            esc(&p.name)
        ));
    }
    w.push_str(&format!("{ind}        </ssv:Parameters>\n{ind}      </ssv:ParameterSet>\n{ind}    </ssd:ParameterValues>\n{ind}  </ssd:ParameterBinding>\n{ind}</ssd:ParameterBindings>\n"));
}

/// Shortest round-tripping decimal form of a double, valid as `xs:double`.
fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:?}")
    } else if x.is_nan() {
        "NaN".into()
    } else if x > 0.0 {
        "INF".into()
    } else {
        "-INF".into()
    }
}

fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\n' => o.push_str("&#10;"),
            '\t' => o.push_str("&#9;"),
            c => o.push(c),
        }
    }
    o
}

/// Read `SystemStructure.ssd` from an `.ssp` archive (without extracting it).
pub fn read_ssd_from_ssp(ssp: &Path) -> Result<String, SspError> {
    let bytes = crate::unzip::read_entry(ssp, "SystemStructure.ssd")
        .map_err(|e| SspError::Io(e.to_string()))?
        .ok_or_else(|| SspError::Io(format!("{} has no SystemStructure.ssd", ssp.display())))?;
    String::from_utf8(bytes).map_err(|_| SspError::Io(format!("{}: SystemStructure.ssd is not UTF-8", ssp.display())))
}

/// Write a standard SSP archive: `SystemStructure.ssd` (the given text) and
/// each FMU as `resources/<name>`. The SSD is parsed first, and every
/// component `source` must be one of the FMUs packed (so the archive is
/// self-contained). Written atomically (temporary file, then rename).
pub fn write_ssp_archive(out: &Path, ssd: &str, fmus: &[(&str, &Path)]) -> anyhow::Result<()> {
    use anyhow::Context;
    let desc = SystemDescription::from_xml(ssd, "SystemStructure.ssd", None)?;
    for c in &desc.components {
        let ok = fmus.iter().any(|(n, _)| c.source == format!("resources/{n}"));
        anyhow::ensure!(
            ok,
            "component {} has source {}, which is not among the FMUs packed ({})",
            c.name,
            c.source,
            fmus.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
        );
    }
    for (n, _) in fmus {
        anyhow::ensure!(
            crate::unzip::safe_entry_path(n).is_ok() && !n.contains('/'),
            "FMU name {n} must be a plain file name"
        );
    }
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let tmp = out.with_extension("ssp.partial");
    let file = std::fs::File::create(&tmp).with_context(|| format!("creating {}", tmp.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let deflate = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    zip.start_file("SystemStructure.ssd", deflate)?;
    zip.write_all(ssd.as_bytes())?;
    zip.add_directory("resources/", deflate)?;
    for (name, path) in fmus {
        let data = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
        // FMUs are zip files already: store them.
        let stored = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
        zip.start_file(format!("resources/{name}"), stored)?;
        zip.write_all(&data)?;
    }
    zip.finish()?;
    std::fs::rename(&tmp, out).with_context(|| format!("renaming {} to {}", tmp.display(), out.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const FOREIGN: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<SystemStructureDescription xmlns="http://ssp-standard.org/SSP1/SystemStructureDescription"
    xmlns:c="http://ssp-standard.org/SSP1/SystemStructureCommon"
    xmlns:v="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="Foreign">
  <System name="Root">
    <ParameterBindings>
      <ParameterBinding prefix="b.">
        <ParameterValues>
          <v:ParameterSet version="1.0" name="sys">
            <v:Parameters>
              <v:Parameter name="gain"><v:Real value="2.5" unit="1"/></v:Parameter>
            </v:Parameters>
          </v:ParameterSet>
        </ParameterValues>
      </ParameterBinding>
    </ParameterBindings>
    <Elements>
      <Component name="a" source="resources/A.fmu" implementation="CoSimulation">
        <Connectors>
          <Connector name="y" kind="output"><c:Real unit="m"/></Connector>
        </Connectors>
        <ParameterBindings>
          <ParameterBinding>
            <ParameterValues>
              <v:ParameterSet version="1.0" name="a">
                <v:Parameters>
                  <v:Parameter name="n"><v:Integer value="-3"/></v:Parameter>
                  <v:Parameter name="on"><v:Boolean value="true"/></v:Parameter>
                  <v:Parameter name="mode"><v:Enumeration value="fast"/></v:Parameter>
                  <v:Parameter name="label"><v:String value="a &amp; b"/></v:Parameter>
                </v:Parameters>
              </v:ParameterSet>
            </ParameterValues>
          </ParameterBinding>
        </ParameterBindings>
      </Component>
      <Component name="b" source="resources/B.fmu">
        <Connectors><Connector name="u" kind="input"/></Connectors>
      </Component>
    </Elements>
    <Connections>
      <Connection startElement="a" startConnector="y" endElement="b" endConnector="u">
        <c:LinearTransformation factor="1000" offset="0.5"/>
      </Connection>
    </Connections>
  </System>
  <DefaultExperiment startTime="0" stopTime="2.5"/>
</SystemStructureDescription>"#;

    #[test]
    fn parses_a_description_with_other_prefixes() {
        let d = SystemDescription::from_xml(FOREIGN, "foreign.ssd", None).unwrap();
        assert_eq!(d.name, "Foreign");
        assert_eq!(d.system_name, "Root");
        assert_eq!(d.components.len(), 2);
        let a = d.component("a").unwrap();
        assert_eq!(a.source, "resources/A.fmu");
        assert_eq!(
            a.connectors[0],
            Connector {
                name: "y".into(),
                kind: ConnectorKind::Output,
                ty: Some(ConnectorType::Real(Some("m".into())))
            }
        );
        assert_eq!(
            a.parameters,
            vec![
                Parameter { name: "n".into(), value: ParamValue::Integer(-3) },
                Parameter { name: "on".into(), value: ParamValue::Boolean(true) },
                Parameter { name: "mode".into(), value: ParamValue::Enumeration("fast".into()) },
                Parameter { name: "label".into(), value: ParamValue::String("a & b".into()) },
            ]
        );
        assert_eq!(
            d.parameters,
            vec![Parameter { name: "b.gain".into(), value: ParamValue::Real(2.5, Some("1".into())) }]
        );
        assert_eq!(d.connections[0].linear, Some(Linear { factor: 1000.0, offset: 0.5 }));
        assert_eq!(d.connections[0].label(), "a.y → b.u");
        assert_eq!((d.start_time, d.stop_time), (Some(0.0), Some(2.5)));
        assert_eq!(d.master, MasterSettings::default());
    }

    #[test]
    fn write_then_parse_round_trips() {
        let mut d = SystemDescription::from_xml(FOREIGN, "foreign.ssd", None).unwrap();
        d.master = MasterSettings {
            step_size: Some(1e-5),
            order: Some(Order::Jacobi),
            sequence: vec!["b".into(), "a".into()],
        };
        d.description = Some("quote \" and <tag>".into());
        let xml = d.to_xml();
        let back = SystemDescription::from_xml(&xml, "written.ssd", None).unwrap();
        assert_eq!(back, d);
        // Canonical: writing again gives the same text.
        assert_eq!(back.to_xml(), xml);
        assert!(xml.contains("stepSize=\"1e-5\""), "{xml}");
    }

    /// Writes `target/ssd-test/Full.ssd` (every construct the writer emits:
    /// system and component bindings of all five types, typed connectors, a
    /// linear transformation, the master annotation), which
    /// `tests/python/test_ssd_schema.py` validates against the SSP 1.0 XSD.
    #[test]
    fn writes_a_full_description_for_schema_validation() {
        let mut d = SystemDescription::from_xml(FOREIGN, "foreign.ssd", None).unwrap();
        d.master = MasterSettings {
            step_size: Some(1e-5),
            order: Some(Order::GaussSeidel),
            sequence: vec!["b".into(), "a".into()],
        };
        d.description = Some("all constructs".into());
        d.components[1].connectors.push(Connector {
            name: "mode".into(),
            kind: ConnectorKind::Parameter,
            ty: Some(ConnectorType::Enumeration("Mode".into())),
        });
        d.components[1].connectors.push(Connector {
            name: "n".into(),
            kind: ConnectorKind::Input,
            ty: Some(ConnectorType::Integer),
        });
        d.components[1].connectors.push(Connector {
            name: "b".into(),
            kind: ConnectorKind::Output,
            ty: Some(ConnectorType::Boolean),
        });
        d.components[1].connectors.push(Connector {
            name: "s".into(),
            kind: ConnectorKind::Parameter,
            ty: Some(ConnectorType::String),
        });
        let xml = d.to_xml();
        let target = std::env::var_os("CARGO_TARGET_DIR")
            .map(std::path::PathBuf::from)
            .unwrap_or_else(|| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target"));
        let dir = target.join("ssd-test");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("Full.ssd"), &xml).unwrap();
        std::fs::write(dir.join("ClosedLoop.ssd"), crate::CLOSED_LOOP_SSD).unwrap();
        assert_eq!(SystemDescription::from_xml(&xml, "Full.ssd", None).unwrap(), d);
    }

    #[test]
    fn the_embedded_closed_loop_is_canonical_and_complete() {
        let d = SystemDescription::from_xml(crate::CLOSED_LOOP_SSD, "ClosedLoop.ssd", None).unwrap();
        assert_eq!(
            d.to_xml(),
            crate::CLOSED_LOOP_SSD,
            "scenarios/ClosedLoop.ssd is not in the writer's canonical form"
        );
        assert_eq!(d.components.len(), 2);
        assert!(d.components.iter().all(|c| c.source.starts_with("resources/") && c.source.ends_with(".fmu")));
        assert_eq!(d.connections.len(), 2, "the closed loop has one feedback and one command connection");
        // Every connection's end points are declared connectors of matching kinds.
        for c in &d.connections {
            let s = d.component(c.start_element.as_deref().unwrap()).unwrap();
            let e = d.component(c.end_element.as_deref().unwrap()).unwrap();
            assert!(
                s.connectors.iter().any(|k| k.name == c.start_connector && k.kind == ConnectorKind::Output),
                "{}",
                c.label()
            );
            assert!(
                e.connectors.iter().any(|k| k.name == c.end_connector && k.kind == ConnectorKind::Input),
                "{}",
                c.label()
            );
        }
        assert!(d.master.step_size.is_some() && d.stop_time.is_some());
    }

    #[test]
    fn malformed_descriptions_are_clear_errors() {
        let e = SystemDescription::from_xml("<a><b></a>", "x.ssd", None).unwrap_err();
        assert!(e.to_string().contains("x.ssd: XML error"), "{e}");
        let e = SystemDescription::from_xml("<root/>", "x.ssd", None).unwrap_err();
        assert!(e.to_string().contains("expected ssd:SystemStructureDescription"), "{e}");
        let bad = FOREIGN.replace(r#"<v:Real value="2.5" unit="1"/>"#, r#"<v:Real value="fast"/>"#);
        let e = SystemDescription::from_xml(&bad, "x.ssd", None).unwrap_err();
        assert!(e.to_string().contains("parameter b.gain: 'fast' is not a number"), "{e}");
        let nested = FOREIGN.replace(
            r#"<Component name="b" source="resources/B.fmu">"#,
            r#"<System name="sub"/><Component name="b" source="resources/B.fmu">"#,
        );
        let e = SystemDescription::from_xml(&nested, "x.ssd", None).unwrap_err();
        assert!(e.to_string().contains("nested"), "{e}");
    }

    #[test]
    fn parameter_sources_are_read_through_the_callback() {
        let xml = FOREIGN.replace(
            r#"<ParameterBinding prefix="b.">"#,
            r#"<ParameterBinding prefix="b." source="resources/extra.ssv">"#,
        );
        let ssv = r#"<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="x">
  <ssv:Parameters><ssv:Parameter name="k"><ssv:Real value="7"/></ssv:Parameter></ssv:Parameters></ssv:ParameterSet>"#;
        let read = |src: &str| -> Result<String, SspError> {
            assert_eq!(src, "resources/extra.ssv");
            Ok(ssv.to_string())
        };
        let d = SystemDescription::from_xml(&xml, "x.ssd", Some(&read)).unwrap();
        assert_eq!(d.parameters[0], Parameter { name: "b.k".into(), value: ParamValue::Real(7.0, None) });
        assert_eq!(d.parameters[1].name, "b.gain");
        assert!(SystemDescription::from_xml(&xml, "x.ssd", None).is_err());
    }

    #[test]
    fn ssp_archive_is_written_and_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("A.fmu");
        let b = dir.path().join("B.fmu");
        std::fs::write(&a, b"fake A").unwrap();
        std::fs::write(&b, b"fake B").unwrap();
        let ssd = SystemDescription::from_xml(FOREIGN, "f", None).unwrap().to_xml();
        let out = dir.path().join("out/Sys.ssp");
        write_ssp_archive(&out, &ssd, &[("A.fmu", &a), ("B.fmu", &b)]).unwrap();
        assert_eq!(read_ssd_from_ssp(&out).unwrap(), ssd);
        assert_eq!(crate::unzip::read_entry(&out, "resources/B.fmu").unwrap().unwrap(), b"fake B");
        // A component whose FMU is not packed is refused.
        let err = write_ssp_archive(&out, &ssd, &[("A.fmu", &a)]).unwrap_err();
        assert!(err.to_string().contains("resources/B.fmu"), "{err}");
    }
}
