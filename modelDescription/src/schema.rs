//! Serde mirror of the FMI 2.0.4 `fmiModelDescription` schema (the parts a
//! co-simulation FMU uses). Attributes are `@`-renamed fields.

use serde::{Deserialize, Serialize};

/// Root element `fmiModelDescription`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename = "fmiModelDescription")]
pub struct ModelDescription {
    /// Always `"2.0"`.
    #[serde(rename = "@fmiVersion")]
    pub fmi_version: String,
    /// Model name.
    #[serde(rename = "@modelName")]
    pub model_name: String,
    /// GUID checked by `fmi2Instantiate`.
    #[serde(rename = "@guid")]
    pub guid: String,
    /// Description text.
    #[serde(rename = "@description", default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// Author.
    #[serde(rename = "@author", default, skip_serializing_if = "Option::is_none")]
    pub author: Option<String>,
    /// Model version.
    #[serde(rename = "@version", default, skip_serializing_if = "Option::is_none")]
    pub version: Option<String>,
    /// Copyright notice.
    #[serde(rename = "@copyright", default, skip_serializing_if = "Option::is_none")]
    pub copyright: Option<String>,
    /// License (SPDX expression).
    #[serde(rename = "@license", default, skip_serializing_if = "Option::is_none")]
    pub license: Option<String>,
    /// Tool that generated the FMU.
    #[serde(rename = "@generationTool", default, skip_serializing_if = "Option::is_none")]
    pub generation_tool: Option<String>,
    /// When the FMU was generated (`xs:dateTime`); packaging derives it from the sources' commit
    /// date, not the clock, so rebuilds are identical. Not part of the GUID.
    #[serde(rename = "@generationDateAndTime", default, skip_serializing_if = "Option::is_none")]
    pub generation_date_and_time: Option<String>,
    /// `flat` or `structured`.
    #[serde(rename = "@variableNamingConvention", default, skip_serializing_if = "Option::is_none")]
    pub variable_naming_convention: Option<String>,
    /// Number of event indicators (0 for co-simulation).
    #[serde(rename = "@numberOfEventIndicators", default, skip_serializing_if = "Option::is_none")]
    pub number_of_event_indicators: Option<u32>,
    /// Model-exchange interface (never written by us; kept when parsing).
    #[serde(rename = "ModelExchange", default, skip_serializing_if = "Option::is_none")]
    pub model_exchange: Option<ModelExchange>,
    /// Co-simulation interface.
    #[serde(rename = "CoSimulation", default, skip_serializing_if = "Option::is_none")]
    pub co_simulation: Option<CoSimulation>,
    /// Units.
    #[serde(rename = "UnitDefinitions", default, skip_serializing_if = "Option::is_none")]
    pub unit_definitions: Option<UnitDefinitions>,
    /// Types (enumerations).
    #[serde(rename = "TypeDefinitions", default, skip_serializing_if = "Option::is_none")]
    pub type_definitions: Option<TypeDefinitions>,
    /// Log categories.
    #[serde(rename = "LogCategories", default, skip_serializing_if = "Option::is_none")]
    pub log_categories: Option<LogCategories>,
    /// Default experiment.
    #[serde(rename = "DefaultExperiment", default, skip_serializing_if = "Option::is_none")]
    pub default_experiment: Option<DefaultExperiment>,
    /// Vendor annotations (we read and write only the [`WorkBound`] of [`WORK_BOUND_TOOL`];
    /// other tools' content is skipped when parsing).
    #[serde(rename = "VendorAnnotations", default, skip_serializing_if = "Option::is_none")]
    pub vendor_annotations: Option<VendorAnnotations>,
    /// Variables.
    #[serde(rename = "ModelVariables")]
    pub model_variables: ModelVariables,
    /// Model structure.
    #[serde(rename = "ModelStructure")]
    pub model_structure: ModelStructure,
}

/// `ModelExchange` element (only its identifier is kept).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelExchange {
    /// Model identifier.
    #[serde(rename = "@modelIdentifier")]
    pub model_identifier: String,
}

/// `CoSimulation` element with capability flags.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[allow(missing_docs)]
pub struct CoSimulation {
    #[serde(rename = "@modelIdentifier")]
    pub model_identifier: String,
    #[serde(rename = "@needsExecutionTool", default, skip_serializing_if = "Option::is_none")]
    pub needs_execution_tool: Option<bool>,
    #[serde(rename = "@canHandleVariableCommunicationStepSize", default, skip_serializing_if = "Option::is_none")]
    pub can_handle_variable_communication_step_size: Option<bool>,
    #[serde(rename = "@canInterpolateInputs", default, skip_serializing_if = "Option::is_none")]
    pub can_interpolate_inputs: Option<bool>,
    #[serde(rename = "@maxOutputDerivativeOrder", default, skip_serializing_if = "Option::is_none")]
    pub max_output_derivative_order: Option<u32>,
    #[serde(rename = "@canRunAsynchronuously", default, skip_serializing_if = "Option::is_none")]
    pub can_run_asynchronuously: Option<bool>,
    #[serde(rename = "@canBeInstantiatedOnlyOncePerProcess", default, skip_serializing_if = "Option::is_none")]
    pub can_be_instantiated_only_once_per_process: Option<bool>,
    #[serde(rename = "@canNotUseMemoryManagementFunctions", default, skip_serializing_if = "Option::is_none")]
    pub can_not_use_memory_management_functions: Option<bool>,
    #[serde(rename = "@canGetAndSetFMUstate", default, skip_serializing_if = "Option::is_none")]
    pub can_get_and_set_fmu_state: Option<bool>,
    #[serde(rename = "@canSerializeFMUstate", default, skip_serializing_if = "Option::is_none")]
    pub can_serialize_fmu_state: Option<bool>,
    #[serde(rename = "@providesDirectionalDerivative", default, skip_serializing_if = "Option::is_none")]
    pub provides_directional_derivative: Option<bool>,
}

/// `UnitDefinitions`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UnitDefinitions {
    /// Units.
    #[serde(rename = "Unit", default)]
    pub units: Vec<Unit>,
}

/// One unit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Unit {
    /// Unit name as used in `unit="…"`.
    #[serde(rename = "@name")]
    pub name: String,
    /// SI base-unit exponents.
    #[serde(rename = "BaseUnit", default, skip_serializing_if = "Option::is_none")]
    pub base_unit: Option<BaseUnit>,
}

/// SI base-unit exponents of a unit.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[allow(missing_docs)]
pub struct BaseUnit {
    #[serde(rename = "@kg", default, skip_serializing_if = "Option::is_none")]
    pub kg: Option<i32>,
    #[serde(rename = "@m", default, skip_serializing_if = "Option::is_none")]
    pub m: Option<i32>,
    #[serde(rename = "@s", default, skip_serializing_if = "Option::is_none")]
    pub s: Option<i32>,
    #[serde(rename = "@A", default, skip_serializing_if = "Option::is_none")]
    pub a: Option<i32>,
    #[serde(rename = "@K", default, skip_serializing_if = "Option::is_none")]
    pub k: Option<i32>,
    #[serde(rename = "@mol", default, skip_serializing_if = "Option::is_none")]
    pub mol: Option<i32>,
    #[serde(rename = "@cd", default, skip_serializing_if = "Option::is_none")]
    pub cd: Option<i32>,
    #[serde(rename = "@rad", default, skip_serializing_if = "Option::is_none")]
    pub rad: Option<i32>,
    #[serde(rename = "@factor", default, skip_serializing_if = "Option::is_none")]
    pub factor: Option<f64>,
    #[serde(rename = "@offset", default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<f64>,
}

/// `TypeDefinitions`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TypeDefinitions {
    /// Simple types.
    #[serde(rename = "SimpleType", default)]
    pub simple_types: Vec<SimpleType>,
}

/// A simple type; we only declare enumerations (other kinds are skipped when parsing).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimpleType {
    /// Type name.
    #[serde(rename = "@name")]
    pub name: String,
    /// Description.
    #[serde(rename = "@description", default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// Enumeration items.
    #[serde(rename = "Enumeration", default, skip_serializing_if = "Option::is_none")]
    pub enumeration: Option<EnumerationType>,
}

/// Enumeration type body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnumerationType {
    /// Items.
    #[serde(rename = "Item", default)]
    pub items: Vec<EnumItem>,
}

/// An enumeration item.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnumItem {
    /// Item name.
    #[serde(rename = "@name")]
    pub name: String,
    /// Item value.
    #[serde(rename = "@value")]
    pub value: i32,
    /// Description.
    #[serde(rename = "@description", default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
}

/// `LogCategories`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogCategories {
    /// Categories.
    #[serde(rename = "Category", default)]
    pub categories: Vec<Category>,
}

/// A log category.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Category {
    /// Name.
    #[serde(rename = "@name")]
    pub name: String,
    /// Description.
    #[serde(rename = "@description", default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
}

/// `DefaultExperiment`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[allow(missing_docs)]
pub struct DefaultExperiment {
    #[serde(rename = "@startTime", default, skip_serializing_if = "Option::is_none")]
    pub start_time: Option<f64>,
    #[serde(rename = "@stopTime", default, skip_serializing_if = "Option::is_none")]
    pub stop_time: Option<f64>,
    #[serde(rename = "@tolerance", default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    #[serde(rename = "@stepSize", default, skip_serializing_if = "Option::is_none")]
    pub step_size: Option<f64>,
}

/// `VendorAnnotations`: one `Tool` element per tool.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct VendorAnnotations {
    /// Tools.
    #[serde(rename = "Tool", default)]
    pub tools: Vec<Tool>,
}

/// A `Tool` of `VendorAnnotations`: its name and, for [`WORK_BOUND_TOOL`], the work bound.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tool {
    /// Tool name.
    #[serde(rename = "@name")]
    pub name: String,
    /// The work bound ([`WORK_BOUND_TOOL`] only).
    #[serde(rename = "WorkBound", default, skip_serializing_if = "Option::is_none")]
    pub work_bound: Option<WorkBound>,
}

/// The `name` of the vendor-annotation `Tool` that carries a [`WorkBound`]: the export layer
/// that enforces it.
pub const WORK_BOUND_TOOL: &str = "fmi2-export";

/// The most work one `fmi2DoStep` may cost, declared so that a master can refuse a step size
/// before instantiating (`<Tool name="fmi2-export"><WorkBound …/></Tool>`).
///
/// A step of size `h` costs `h / p + extraInternalStepsPerCall` internal steps, `p` being the
/// value of the Real parameter `internalStepParameter` (the model's internal step, in s); the
/// FMU refuses (`fmi2Error`) a step costing more than `maxInternalStepsPerCall`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WorkBound {
    /// Most internal steps one `fmi2DoStep` may cost.
    #[serde(rename = "@maxInternalStepsPerCall")]
    pub max_internal_steps_per_call: f64,
    /// Name of the Real parameter holding the internal step (s).
    #[serde(rename = "@internalStepParameter")]
    pub internal_step_parameter: String,
    /// Internal steps a call costs besides `h / p` (partial steps at either end).
    #[serde(rename = "@extraInternalStepsPerCall", default)]
    pub extra_internal_steps_per_call: f64,
}

impl WorkBound {
    /// Internal steps a communication step `h` costs with the internal step `internal_step`
    /// (NaN or infinite for a non-positive or non-finite internal step).
    pub fn cost(&self, h: f64, internal_step: f64) -> f64 {
        if internal_step > 0.0 && internal_step.is_finite() {
            h / internal_step + self.extra_internal_steps_per_call
        } else {
            f64::NAN
        }
    }

    /// Does a step `h` cost more than the bound (or is its cost undefined)?
    pub fn exceeded(&self, h: f64, internal_step: f64) -> bool {
        let cost = self.cost(h, internal_step);
        cost.is_nan() || cost > self.max_internal_steps_per_call
    }

    /// The largest communication step within the bound for `internal_step`.
    pub fn max_step(&self, internal_step: f64) -> f64 {
        (self.max_internal_steps_per_call - self.extra_internal_steps_per_call) * internal_step
    }
}

/// `ModelVariables`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelVariables {
    /// Variables, in order (ModelStructure indices are 1-based positions here).
    #[serde(rename = "ScalarVariable", default)]
    pub variables: Vec<ScalarVariable>,
}

/// FMI causality.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "camelCase")]
#[allow(missing_docs)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    #[default]
    Local,
    Independent,
}

/// FMI variability.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "camelCase")]
#[allow(missing_docs)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    #[default]
    Continuous,
}

/// FMI `initial` attribute.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
#[allow(missing_docs)]
pub enum Initial {
    Exact,
    Approx,
    Calculated,
}

/// `ScalarVariable`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScalarVariable {
    /// Name (structured naming: `cutting.kt`).
    #[serde(rename = "@name")]
    pub name: String,
    /// Value reference.
    #[serde(rename = "@valueReference")]
    pub value_reference: u32,
    /// Description.
    #[serde(rename = "@description", default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// Causality.
    #[serde(rename = "@causality", default)]
    pub causality: Causality,
    /// Variability.
    #[serde(rename = "@variability", default)]
    pub variability: Variability,
    /// Initial.
    #[serde(rename = "@initial", default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<Initial>,
    /// Type and type-specific attributes.
    #[serde(rename = "$value")]
    pub kind: VarKind,
    /// Inputs (by value reference) this output depends on; used only to build
    /// `ModelStructure`, not written as an attribute.
    #[serde(skip)]
    pub depends_on: Option<Vec<u32>>,
}

/// The type element of a scalar variable.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[allow(missing_docs)]
pub enum VarKind {
    Real(RealAttrs),
    Integer(IntegerAttrs),
    Boolean(BooleanAttrs),
    String(StringAttrs),
    Enumeration(EnumerationAttrs),
}

/// Attributes of `<Real>`.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[allow(missing_docs)]
pub struct RealAttrs {
    #[serde(rename = "@declaredType", default, skip_serializing_if = "Option::is_none")]
    pub declared_type: Option<String>,
    #[serde(rename = "@unit", default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    #[serde(rename = "@min", default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    #[serde(rename = "@max", default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
    #[serde(rename = "@nominal", default, skip_serializing_if = "Option::is_none")]
    pub nominal: Option<f64>,
    #[serde(rename = "@start", default, skip_serializing_if = "Option::is_none")]
    pub start: Option<f64>,
}

/// Attributes of `<Integer>`.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[allow(missing_docs)]
pub struct IntegerAttrs {
    #[serde(rename = "@declaredType", default, skip_serializing_if = "Option::is_none")]
    pub declared_type: Option<String>,
    #[serde(rename = "@min", default, skip_serializing_if = "Option::is_none")]
    pub min: Option<i32>,
    #[serde(rename = "@max", default, skip_serializing_if = "Option::is_none")]
    pub max: Option<i32>,
    #[serde(rename = "@start", default, skip_serializing_if = "Option::is_none")]
    pub start: Option<i32>,
}

/// Attributes of `<Boolean>`.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[allow(missing_docs)]
pub struct BooleanAttrs {
    #[serde(rename = "@declaredType", default, skip_serializing_if = "Option::is_none")]
    pub declared_type: Option<String>,
    #[serde(rename = "@start", default, skip_serializing_if = "Option::is_none")]
    pub start: Option<bool>,
}

/// Attributes of `<String>`.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[allow(missing_docs)]
pub struct StringAttrs {
    #[serde(rename = "@declaredType", default, skip_serializing_if = "Option::is_none")]
    pub declared_type: Option<String>,
    #[serde(rename = "@start", default, skip_serializing_if = "Option::is_none")]
    pub start: Option<String>,
}

/// Attributes of `<Enumeration>`.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[allow(missing_docs)]
pub struct EnumerationAttrs {
    #[serde(rename = "@declaredType")]
    pub declared_type: String,
    #[serde(rename = "@min", default, skip_serializing_if = "Option::is_none")]
    pub min: Option<i32>,
    #[serde(rename = "@max", default, skip_serializing_if = "Option::is_none")]
    pub max: Option<i32>,
    #[serde(rename = "@start", default, skip_serializing_if = "Option::is_none")]
    pub start: Option<i32>,
}

/// `ModelStructure`.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct ModelStructure {
    /// Outputs.
    #[serde(rename = "Outputs", default, skip_serializing_if = "Option::is_none")]
    pub outputs: Option<UnknownList>,
    /// Derivatives (model exchange; kept when parsing).
    #[serde(rename = "Derivatives", default, skip_serializing_if = "Option::is_none")]
    pub derivatives: Option<UnknownList>,
    /// Initial unknowns.
    #[serde(rename = "InitialUnknowns", default, skip_serializing_if = "Option::is_none")]
    pub initial_unknowns: Option<UnknownList>,
}

/// A list of `Unknown`s.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UnknownList {
    /// Unknowns.
    #[serde(rename = "Unknown", default)]
    pub unknowns: Vec<Unknown>,
}

/// An `Unknown`: 1-based variable index and its dependencies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Unknown {
    /// 1-based index into `ModelVariables`.
    #[serde(rename = "@index")]
    pub index: usize,
    /// Space-separated 1-based indices; `Some("")` means no dependency, `None` unknown.
    #[serde(rename = "@dependencies", default, skip_serializing_if = "Option::is_none")]
    pub dependencies: Option<String>,
    /// Dependency kinds (kept when parsing).
    #[serde(rename = "@dependenciesKind", default, skip_serializing_if = "Option::is_none")]
    pub dependencies_kind: Option<String>,
}
