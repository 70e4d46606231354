//! # FMI 2.0 `modelDescription.xml`, declared once
//!
//! An FMU built with this project declares every variable exactly once, as a
//! [`ScalarVariable`] in a [`ModelDescription`] built by [`ModelBuilder`].  From
//! that one declaration come:
//!
//! * the `modelDescription.xml` shipped in the `.fmu` ([`ModelDescription::to_xml`]),
//! * the runtime get/set dispatch, start values and settability checks of the
//!   export layer (`fmi2-export` reads the same struct),
//! * `ModelStructure` (outputs, their dependencies, initial unknowns), derived in
//!   [`ModelBuilder::build`],
//! * a deterministic GUID: a UUIDv5 of the XML rendered with an empty GUID, so
//!   changing any variable changes the GUID.
//!
//! The same types parse an XML file back ([`ModelDescription::from_xml`]); the
//! FMI master uses this to read third-party FMUs.
//!
//! The serde structs mirror the XML schema of FMI 2.0.4 (`fmiModelDescription.xsd`):
//! attributes are fields renamed `@name`, child elements are plain fields.

use serde::{Deserialize, Serialize};

mod builder;
mod schema;
pub mod units;
pub use builder::ModelBuilder;
pub use schema::*;

/// Errors when building or parsing a model description.
#[derive(Debug, thiserror::Error)]
pub enum DescriptionError {
    /// The XML could not be parsed.
    #[error("cannot parse modelDescription.xml: {0}")]
    Parse(String),
    /// The XML could not be written.
    #[error("cannot write modelDescription.xml: {0}")]
    Write(String),
    /// The variable table is inconsistent.
    #[error("invalid variable table: {0}")]
    Invalid(String),
}

/// Value reference, the FMI handle of a variable.
pub type ValueReference = u32;

/// Scalar type of a variable (enumerations are integers at the C API).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ScalarType {
    /// `fmi2Real`
    Real,
    /// `fmi2Integer`
    Integer,
    /// `fmi2Boolean`
    Boolean,
    /// `fmi2String`
    String,
    /// Enumeration (accessed with `fmi2Get/SetInteger`)
    Enumeration,
}

impl ScalarType {
    /// The C API type used to access this variable (`Enumeration` → `Integer`).
    pub fn api_type(self) -> ScalarType {
        match self {
            ScalarType::Enumeration => ScalarType::Integer,
            t => t,
        }
    }
}

/// A runtime value of a variable.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Value {
    /// Real value
    Real(f64),
    /// Integer or enumeration value
    Integer(i32),
    /// Boolean value
    Boolean(bool),
    /// String value
    String(String),
}

impl ScalarVariable {
    /// The scalar type of the variable.
    pub fn scalar_type(&self) -> ScalarType {
        match &self.kind {
            VarKind::Real(_) => ScalarType::Real,
            VarKind::Integer(_) => ScalarType::Integer,
            VarKind::Boolean(_) => ScalarType::Boolean,
            VarKind::String(_) => ScalarType::String,
            VarKind::Enumeration(_) => ScalarType::Enumeration,
        }
    }

    /// The declared start value, if any.
    pub fn start_value(&self) -> Option<Value> {
        match &self.kind {
            VarKind::Real(r) => r.start.map(Value::Real),
            VarKind::Integer(i) => i.start.map(Value::Integer),
            VarKind::Boolean(b) => b.start.map(Value::Boolean),
            VarKind::String(s) => s.start.clone().map(Value::String),
            VarKind::Enumeration(e) => e.start.map(Value::Integer),
        }
    }

    /// The value a variable holds before anything is set: its start value,
    /// or zero / false / empty for calculated variables.
    pub fn initial_value(&self) -> Value {
        self.start_value().unwrap_or(match self.scalar_type() {
            ScalarType::Real => Value::Real(0.0),
            ScalarType::Integer | ScalarType::Enumeration => Value::Integer(0),
            ScalarType::Boolean => Value::Boolean(false),
            ScalarType::String => Value::String(String::new()),
        })
    }

    /// Effective `initial` attribute (FMI 2.0 Table of defaults, section 2.2.7).
    pub fn effective_initial(&self) -> Option<Initial> {
        if let Some(i) = self.initial {
            return Some(i);
        }
        use Causality as C;
        use Variability as V;
        match (self.causality, self.variability) {
            (C::Input, _) | (C::Independent, _) => None,
            (_, V::Constant) => Some(Initial::Exact),
            (C::Parameter, _) => Some(Initial::Exact),
            (C::CalculatedParameter, _) => Some(Initial::Calculated),
            (C::Output, _) | (C::Local, _) => Some(Initial::Calculated),
        }
    }

    /// Declared (min, max) for Real, Integer and Enumeration variables.
    pub fn range(&self) -> (Option<f64>, Option<f64>) {
        match &self.kind {
            VarKind::Real(r) => (r.min, r.max),
            VarKind::Integer(i) => (i.min.map(f64::from), i.max.map(f64::from)),
            VarKind::Enumeration(e) => (e.min.map(f64::from), e.max.map(f64::from)),
            _ => (None, None),
        }
    }

    /// Unit of a Real variable.
    pub fn unit(&self) -> Option<&str> {
        match &self.kind {
            VarKind::Real(r) => r.unit.as_deref(),
            _ => None,
        }
    }

    fn new(name: &str, vr: ValueReference, causality: Causality, variability: Variability, kind: VarKind) -> Self {
        ScalarVariable {
            name: name.to_string(),
            value_reference: vr,
            description: None,
            causality,
            variability,
            initial: None,
            kind,
            depends_on: None,
        }
    }

    /// A Real variable.
    pub fn real(name: &str, vr: ValueReference, causality: Causality, variability: Variability) -> Self {
        Self::new(name, vr, causality, variability, VarKind::Real(RealAttrs::default()))
    }

    /// An Integer variable.
    pub fn integer(name: &str, vr: ValueReference, causality: Causality, variability: Variability) -> Self {
        Self::new(name, vr, causality, variability, VarKind::Integer(IntegerAttrs::default()))
    }

    /// A Boolean variable.
    pub fn boolean(name: &str, vr: ValueReference, causality: Causality, variability: Variability) -> Self {
        Self::new(name, vr, causality, variability, VarKind::Boolean(BooleanAttrs::default()))
    }

    /// A String variable.
    pub fn string(name: &str, vr: ValueReference, causality: Causality, variability: Variability) -> Self {
        Self::new(name, vr, causality, variability, VarKind::String(StringAttrs::default()))
    }

    /// An Enumeration variable of the declared type `type_name` (see [`ModelBuilder::enumeration`]).
    pub fn enumeration(
        name: &str,
        vr: ValueReference,
        causality: Causality,
        variability: Variability,
        type_name: &str,
    ) -> Self {
        Self::new(
            name,
            vr,
            causality,
            variability,
            VarKind::Enumeration(EnumerationAttrs { declared_type: type_name.to_string(), ..Default::default() }),
        )
    }

    /// Set the description.
    pub fn describe(mut self, text: &str) -> Self {
        self.description = Some(text.to_string());
        self
    }

    /// Set the start value (the type must match the variable's).
    ///
    /// # Panics
    /// On a type mismatch: this is a programming error in a model's table.
    pub fn start(mut self, v: impl Into<Value>) -> Self {
        let v = v.into();
        match (&mut self.kind, v) {
            (VarKind::Real(r), Value::Real(x)) => r.start = Some(x),
            (VarKind::Real(r), Value::Integer(x)) => r.start = Some(f64::from(x)),
            (VarKind::Integer(i), Value::Integer(x)) => i.start = Some(x),
            (VarKind::Enumeration(e), Value::Integer(x)) => e.start = Some(x),
            (VarKind::Boolean(b), Value::Boolean(x)) => b.start = Some(x),
            (VarKind::String(s), Value::String(x)) => s.start = Some(x),
            (k, v) => panic!("start value {v:?} does not match variable {} of kind {k:?}", self.name),
        }
        self
    }

    /// Set the unit of a Real variable.
    pub fn unit_of(mut self, unit: &str) -> Self {
        if let VarKind::Real(r) = &mut self.kind {
            r.unit = Some(unit.to_string());
        }
        self
    }

    /// Set min and max (Real, Integer, Enumeration).
    pub fn bounds(mut self, min: f64, max: f64) -> Self {
        match &mut self.kind {
            VarKind::Real(r) => {
                r.min = Some(min);
                r.max = Some(max);
            }
            VarKind::Integer(i) => {
                i.min = Some(min as i32);
                i.max = Some(max as i32);
            }
            VarKind::Enumeration(e) => {
                e.min = Some(min as i32);
                e.max = Some(max as i32);
            }
            _ => {}
        }
        self
    }

    /// Set the `initial` attribute explicitly.
    pub fn initial(mut self, initial: Initial) -> Self {
        self.initial = Some(initial);
        self
    }

    /// Declare which inputs an output depends on at a communication point
    /// (by value reference). An empty list means no direct feedthrough.
    /// Without this call the dependency is left unknown (depends on everything).
    pub fn depends_on(mut self, inputs: &[ValueReference]) -> Self {
        self.depends_on = Some(inputs.to_vec());
        self
    }
}

impl From<f64> for Value {
    fn from(v: f64) -> Self {
        Value::Real(v)
    }
}
impl From<i32> for Value {
    fn from(v: i32) -> Self {
        Value::Integer(v)
    }
}
impl From<bool> for Value {
    fn from(v: bool) -> Self {
        Value::Boolean(v)
    }
}
impl From<&str> for Value {
    fn from(v: &str) -> Self {
        Value::String(v.to_string())
    }
}

impl ModelDescription {
    /// Render as `modelDescription.xml` (UTF-8, with XML declaration).
    pub fn to_xml(&self) -> Result<String, DescriptionError> {
        let mut body = String::new();
        let mut ser = quick_xml::se::Serializer::with_root(&mut body, Some("fmiModelDescription"))
            .map_err(|e| DescriptionError::Write(e.to_string()))?;
        ser.indent(' ', 2);
        self.serialize(ser).map_err(|e| DescriptionError::Write(e.to_string()))?;
        Ok(format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{body}\n"))
    }

    /// Parse a `modelDescription.xml`.
    pub fn from_xml(xml: &str) -> Result<Self, DescriptionError> {
        quick_xml::de::from_str(xml).map_err(|e| DescriptionError::Parse(e.to_string()))
    }

    /// All variables in declaration order.
    pub fn variables(&self) -> &[ScalarVariable] {
        &self.model_variables.variables
    }

    /// Look a variable up by name.
    pub fn variable(&self, name: &str) -> Option<&ScalarVariable> {
        self.variables().iter().find(|v| v.name == name)
    }

    /// The work bound the export layer declared ([`WORK_BOUND_TOOL`]), if any.
    pub fn work_bound(&self) -> Option<&WorkBound> {
        self.vendor_annotations
            .iter()
            .flat_map(|v| v.tools.iter())
            .filter(|t| t.name == WORK_BOUND_TOOL)
            .find_map(|t| t.work_bound.as_ref())
    }

    /// The co-simulation `modelIdentifier`, if the FMU supports co-simulation.
    pub fn model_identifier(&self) -> Option<&str> {
        self.co_simulation.as_ref().map(|c| c.model_identifier.as_str())
    }

    /// What a unit name means in this description: SI base-unit exponents `[kg, m, s, A, K, mol,
    /// cd, rad]`, factor and offset (`SI value = factor·value + offset`), from its
    /// `UnitDefinitions` entry if it has a `BaseUnit`, else from the project's unit registry
    /// ([`units::known_unit`]); `None` when neither defines it.
    pub fn unit_meaning(&self, unit: &str) -> Option<([i32; 8], f64, f64)> {
        let defined = self.unit_definitions.iter().flat_map(|d| d.units.iter()).find(|u| u.name == unit);
        if let Some(b) = defined.and_then(|u| u.base_unit.as_ref()) {
            let e = [b.kg, b.m, b.s, b.a, b.k, b.mol, b.cd, b.rad].map(|x| x.unwrap_or(0));
            return Some((e, b.factor.unwrap_or(1.0), b.offset.unwrap_or(0.0)));
        }
        units::known_unit(unit).map(|(e, f)| (e, f, 0.0))
    }

    /// Items of an enumeration type: `(name, value)`.
    pub fn enumeration_items(&self, type_name: &str) -> Vec<(String, i32)> {
        self.type_definitions
            .iter()
            .flat_map(|t| t.simple_types.iter())
            .filter(|s| s.name == type_name)
            .flat_map(|s| s.enumeration.iter().flat_map(|e| e.items.iter().map(|i| (i.name.clone(), i.value))))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> ModelBuilder {
        ModelBuilder::new("Sample", "Sample")
            .description("a sample")
            .unit("m", [0, 1, 0, 0, 0, 0, 0, 0])
            .enumeration("Mode", "mode", &[("a", "first"), ("b", "second")])
            .log_category("logStatusError", "errors")
            .default_experiment(0.0, 1.0, 1e-3)
            .var(ScalarVariable::real("k", 0, Causality::Parameter, Variability::Fixed).start(2.0).describe("gain"))
            .var(ScalarVariable::real("u", 1, Causality::Input, Variability::Continuous).start(0.0).unit_of("m"))
            .var(ScalarVariable::real("y", 2, Causality::Output, Variability::Continuous).unit_of("m").depends_on(&[]))
            .var(ScalarVariable::enumeration("mode", 0, Causality::Parameter, Variability::Fixed, "Mode").start(1))
            .var(ScalarVariable::boolean("flag", 0, Causality::Output, Variability::Discrete).depends_on(&[1]))
            .var(ScalarVariable::string("label", 0, Causality::Parameter, Variability::Fixed).start("a<&>\"b"))
    }

    #[test]
    fn round_trip_through_xml() {
        let md = sample().build().unwrap();
        let xml = md.to_xml().unwrap();
        assert!(xml.contains("fmiVersion=\"2.0\""), "{xml}");
        assert!(xml.contains("<Unknown index=\"3\" dependencies=\"\""), "{xml}");
        assert!(xml.contains("<Unknown index=\"5\" dependencies=\"2\""), "{xml}");
        let back = ModelDescription::from_xml(&xml).unwrap();
        // `depends_on` is build input only; the XML carries it as ModelStructure.
        let mut md = md;
        md.model_variables.variables.iter_mut().for_each(|v| v.depends_on = None);
        assert_eq!(back, md);
        assert_eq!(back.variable("label").unwrap().start_value(), Some(Value::String("a<&>\"b".into())));
        assert_eq!(back.enumeration_items("Mode"), vec![("a".to_string(), 1), ("b".to_string(), 2)]);
    }

    #[test]
    fn guid_is_deterministic_and_tracks_changes() {
        let a = sample().build().unwrap().guid;
        let b = sample().build().unwrap().guid;
        assert_eq!(a, b);
        let c = sample()
            .var(ScalarVariable::real("extra", 9, Causality::Local, Variability::Continuous))
            .build()
            .unwrap()
            .guid;
        assert_ne!(a, c);
    }

    #[test]
    fn inconsistent_tables_are_rejected() {
        let dup = sample().var(ScalarVariable::real("k", 7, Causality::Parameter, Variability::Fixed).start(1.0));
        assert!(dup.build().is_err());
        let no_start = sample().var(ScalarVariable::real("p", 7, Causality::Parameter, Variability::Fixed));
        assert!(no_start.build().is_err());
        let bad_unit =
            sample().var(ScalarVariable::real("q", 7, Causality::Output, Variability::Continuous).unit_of("furlong"));
        assert!(bad_unit.build().is_err());
        let out_of_range = sample()
            .var(ScalarVariable::real("r", 7, Causality::Parameter, Variability::Fixed).start(5.0).bounds(0.0, 1.0));
        assert!(out_of_range.build().is_err());
    }

    #[test]
    fn parses_a_foreign_description() {
        let xml = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="BouncingBall" guid="{1AE5E10D-9521-4DE3-80B9-D0EAAA7D5AF1}" numberOfEventIndicators="1">
  <CoSimulation modelIdentifier="BouncingBall" canHandleVariableCommunicationStepSize="true"/>
  <LogCategories><Category name="logEvents"/></LogCategories>
  <DefaultExperiment startTime="0" stopTime="3" stepSize="1e-2"/>
  <ModelVariables>
    <ScalarVariable name="time" valueReference="0" causality="independent" variability="continuous"/>
    <ScalarVariable name="h" valueReference="1" causality="output" variability="continuous" initial="exact"><Real start="1" declaredType="Position"/></ScalarVariable>
    <ScalarVariable name="e" valueReference="5" causality="parameter" variability="tunable"><Real start="0.7" min="0.5" max="1"/></ScalarVariable>
  </ModelVariables>
  <ModelStructure><Outputs><Unknown index="2"/></Outputs><InitialUnknowns><Unknown index="2"/></InitialUnknowns></ModelStructure>
</fmiModelDescription>"#;
        // `time` has no type child in some exporters' files; ours requires one, so add it.
        let xml = xml.replace(r#"variability="continuous"/>"#, r#"variability="continuous"><Real/></ScalarVariable>"#);
        let md = ModelDescription::from_xml(&xml).unwrap();
        assert_eq!(md.model_identifier(), Some("BouncingBall"));
        assert_eq!(md.variable("e").unwrap().range(), (Some(0.5), Some(1.0)));
        assert_eq!(md.variable("h").unwrap().start_value(), Some(Value::Real(1.0)));
    }
}
