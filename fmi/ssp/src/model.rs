//! The system model the master works with: one flat system of FMU
//! components, their connectors, connections, parameter values, and the
//! default experiment with this master's settings. [`crate::read`] builds it
//! from XML, [`crate::write`] turns it back into a standard SSD.

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
    /// Parse the SSD spelling (`input`, `calculatedParameter` …).
    pub fn parse(s: &str) -> Option<Self> {
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
    /// Parameters of all its bindings in document order (bare variable
    /// names; a later binding of the same name wins).
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

/// This master's settings, stored as an annotation of `ssd:DefaultExperiment`
/// (type [`crate::ANNOTATION_TYPE`]): SSP 1.0 has no attribute for them.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct MasterSettings {
    /// Communication step size [s].
    pub step_size: Option<f64>,
    /// Stepping order.
    pub order: Option<Order>,
    /// Component sequence for Gauss–Seidel (element names, first steps first).
    pub sequence: Vec<String>,
}

impl MasterSettings {
    /// Nothing set (then no annotation is written).
    pub fn is_empty(&self) -> bool {
        self.step_size.is_none() && self.order.is_none() && self.sequence.is_empty()
    }
}

/// A whole system structure description (one flat system of components).
#[derive(Clone, Debug, PartialEq)]
pub struct SystemDescription {
    /// `name` of the root element.
    pub name: String,
    /// `generationTool` of the root element (kept when read; written if set).
    pub generation_tool: Option<String>,
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

impl SystemDescription {
    /// An empty system named `name` (root and `ssd:System`), generated by this crate.
    pub fn new(name: &str) -> Self {
        SystemDescription {
            name: name.to_string(),
            generation_tool: Some(concat!("chatter-fmu ssp ", env!("CARGO_PKG_VERSION")).to_string()),
            system_name: name.to_string(),
            description: None,
            components: Vec::new(),
            connections: Vec::new(),
            parameters: Vec::new(),
            start_time: None,
            stop_time: None,
            master: MasterSettings::default(),
        }
    }

    /// The component named `name`.
    pub fn component(&self, name: &str) -> Option<&ComponentDesc> {
        self.components.iter().find(|c| c.name == name)
    }

    /// The component named `name`, mutable (e.g. to bind parameters before writing).
    pub fn component_mut(&mut self, name: &str) -> Option<&mut ComponentDesc> {
        self.components.iter_mut().find(|c| c.name == name)
    }
}
