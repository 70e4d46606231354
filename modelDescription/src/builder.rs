//! [`ModelBuilder`]: a model's variable table → [`ModelDescription`], with the derived
//! `ModelStructure`, the deterministic GUID and the consistency checks.

use crate::*;
use std::collections::HashSet;

/// Builds a [`ModelDescription`] from a variable table, derives the model
/// structure and the GUID, and checks the table for consistency.
#[derive(Clone, Debug)]
pub struct ModelBuilder {
    md: ModelDescription,
}

impl ModelBuilder {
    /// Start a co-simulation model whose `modelIdentifier` is `identifier`.
    pub fn new(model_name: &str, identifier: &str) -> Self {
        ModelBuilder {
            md: ModelDescription {
                fmi_version: "2.0".into(),
                model_name: model_name.into(),
                guid: String::new(),
                description: None,
                author: None,
                version: None,
                copyright: None,
                license: None,
                generation_date_and_time: None,
                generation_tool: Some(format!("chatter-fmu model-description {}", env!("CARGO_PKG_VERSION"))),
                variable_naming_convention: Some("structured".into()),
                number_of_event_indicators: Some(0),
                co_simulation: Some(CoSimulation {
                    model_identifier: identifier.into(),
                    needs_execution_tool: Some(false),
                    can_handle_variable_communication_step_size: Some(true),
                    can_interpolate_inputs: Some(false),
                    max_output_derivative_order: Some(0),
                    can_run_asynchronuously: Some(false),
                    can_be_instantiated_only_once_per_process: Some(false),
                    can_not_use_memory_management_functions: Some(true),
                    can_get_and_set_fmu_state: Some(true),
                    can_serialize_fmu_state: Some(true),
                    provides_directional_derivative: Some(false),
                }),
                model_exchange: None,
                unit_definitions: None,
                type_definitions: None,
                log_categories: None,
                default_experiment: None,
                vendor_annotations: None,
                model_variables: ModelVariables { variables: Vec::new() },
                model_structure: ModelStructure::default(),
            },
        }
    }

    /// Declare the work bound (a [`WORK_BOUND_TOOL`] vendor annotation); checked by
    /// [`ModelBuilder::build`]: the parameter must be a Real parameter with a positive lower bound.
    pub fn work_bound(mut self, bound: WorkBound) -> Self {
        let tools = &mut self.md.vendor_annotations.get_or_insert_with(VendorAnnotations::default).tools;
        tools.retain(|t| t.name != WORK_BOUND_TOOL);
        tools.push(Tool { name: WORK_BOUND_TOOL.into(), work_bound: Some(bound) });
        self
    }

    /// Set the model description text.
    pub fn description(mut self, text: &str) -> Self {
        self.md.description = Some(text.into());
        self
    }

    /// Set author and version.
    pub fn author_version(mut self, author: &str, version: &str) -> Self {
        self.md.author = Some(author.into());
        self.md.version = Some(version.into());
        self
    }

    /// Set the copyright notice and the license (an SPDX expression).
    pub fn legal(mut self, copyright: &str, license: &str) -> Self {
        self.md.copyright = Some(copyright.into());
        self.md.license = Some(license.into());
        self
    }

    /// Declare a unit by its SI base-unit exponents: `kg, m, s, A, K, mol, cd, rad`.
    pub fn unit(self, name: &str, exps: [i32; 8]) -> Self {
        self.unit_scaled(name, exps, 1.0)
    }

    /// Declare a unit of [`units::UNITS`] by name (once: later calls with the same name are ignored).
    pub fn known_unit(self, name: &str) -> Result<Self, DescriptionError> {
        if self.md.unit_definitions.iter().flat_map(|u| u.units.iter()).any(|u| u.name == name) {
            return Ok(self);
        }
        if units::named_unit(name) {
            let mut b = self;
            b.md.unit_definitions
                .get_or_insert_with(|| UnitDefinitions { units: Vec::new() })
                .units
                .push(Unit { name: name.into(), base_unit: None });
            return Ok(b);
        }
        let (exps, factor) = units::known_unit(name).ok_or_else(|| {
            DescriptionError::Invalid(format!("unknown unit {name:?} (add it to model_description::units)"))
        })?;
        Ok(self.unit_scaled(name, exps, factor))
    }

    /// Declare a unit that is `factor` times its SI base units (e.g. rpm = 2π/60 rad/s).
    pub fn unit_scaled(mut self, name: &str, exps: [i32; 8], factor: f64) -> Self {
        let nz = |e: i32| if e == 0 { None } else { Some(e) };
        let base = BaseUnit {
            kg: nz(exps[0]),
            m: nz(exps[1]),
            s: nz(exps[2]),
            a: nz(exps[3]),
            k: nz(exps[4]),
            mol: nz(exps[5]),
            cd: nz(exps[6]),
            rad: nz(exps[7]),
            factor: (factor - 1.0).abs().gt(&0.0).then_some(factor),
            offset: None,
        };
        self.md
            .unit_definitions
            .get_or_insert_with(|| UnitDefinitions { units: Vec::new() })
            .units
            .push(Unit { name: name.into(), base_unit: Some(base) });
        self
    }

    /// Declare an enumeration type with items `(name, description)`, valued 1, 2, ….
    pub fn enumeration(mut self, name: &str, description: &str, items: &[(&str, &str)]) -> Self {
        let items = items
            .iter()
            .enumerate()
            .map(|(i, (n, d))| EnumItem { name: (*n).into(), value: i as i32 + 1, description: Some((*d).into()) })
            .collect();
        self.md.type_definitions.get_or_insert_with(|| TypeDefinitions { simple_types: Vec::new() }).simple_types.push(
            SimpleType {
                name: name.into(),
                description: Some(description.into()),
                enumeration: Some(EnumerationType { items }),
            },
        );
        self
    }

    /// Declare a log category.
    pub fn log_category(mut self, name: &str, description: &str) -> Self {
        self.md
            .log_categories
            .get_or_insert_with(|| LogCategories { categories: Vec::new() })
            .categories
            .push(Category { name: name.into(), description: Some(description.into()) });
        self
    }

    /// Set the default experiment.
    pub fn default_experiment(mut self, start: f64, stop: f64, step: f64) -> Self {
        self.md.default_experiment = Some(DefaultExperiment {
            start_time: Some(start),
            stop_time: Some(stop),
            tolerance: None,
            step_size: Some(step),
        });
        self
    }

    /// Change co-simulation capability flags.
    pub fn capabilities(mut self, f: impl FnOnce(&mut CoSimulation)) -> Self {
        if let Some(cs) = self.md.co_simulation.as_mut() {
            f(cs);
        }
        self
    }

    /// Add a variable.
    pub fn var(mut self, v: ScalarVariable) -> Self {
        self.md.model_variables.variables.push(v);
        self
    }

    /// Check the table, derive `ModelStructure` and the GUID.
    pub fn build(mut self) -> Result<ModelDescription, DescriptionError> {
        if let Some(w) = self.md.work_bound() {
            check_work_bound(w, &self.md)?;
        }
        let vars = &self.md.model_variables.variables;
        let mut names = HashSet::new();
        let mut vrs = HashSet::new();
        let enum_names: HashSet<String> =
            self.md.type_definitions.iter().flat_map(|t| t.simple_types.iter().map(|s| s.name.clone())).collect();
        let unit_names: HashSet<String> =
            self.md.unit_definitions.iter().flat_map(|u| u.units.iter().map(|u| u.name.clone())).collect();
        for v in vars {
            if !names.insert(v.name.clone()) {
                return Err(DescriptionError::Invalid(format!("duplicate variable name {}", v.name)));
            }
            if !vrs.insert((v.scalar_type().api_type(), v.value_reference)) {
                return Err(DescriptionError::Invalid(format!("duplicate value reference {}", v.value_reference)));
            }
            if let VarKind::Enumeration(e) = &v.kind
                && !enum_names.contains(&e.declared_type)
            {
                return Err(DescriptionError::Invalid(format!("{}: unknown type {}", v.name, e.declared_type)));
            }
            if let Some(u) = v.unit()
                && !unit_names.contains(u)
            {
                return Err(DescriptionError::Invalid(format!("{}: undeclared unit {u}", v.name)));
            }
            let needs_start = matches!(v.causality, Causality::Input | Causality::Parameter)
                || v.variability == Variability::Constant
                || matches!(v.effective_initial(), Some(Initial::Exact | Initial::Approx));
            if needs_start && v.start_value().is_none() {
                return Err(DescriptionError::Invalid(format!("{} needs a start value", v.name)));
            }
            if v.effective_initial() == Some(Initial::Calculated) && v.start_value().is_some() {
                return Err(DescriptionError::Invalid(format!(
                    "{} is calculated and must not have a start value",
                    v.name
                )));
            }
            if let (Some(lo), Some(hi)) = v.range()
                && lo > hi
            {
                return Err(DescriptionError::Invalid(format!("{}: min > max", v.name)));
            }
            if let (Some(Value::Real(s)), (lo, hi)) = (v.start_value(), v.range())
                && (lo.is_some_and(|lo| s < lo) || hi.is_some_and(|hi| s > hi))
            {
                return Err(DescriptionError::Invalid(format!("{}: start {s} outside [min,max]", v.name)));
            }
        }
        // ModelStructure: indices are 1-based positions in ModelVariables.
        let index_of_input = |vr: ValueReference| -> Result<usize, DescriptionError> {
            vars.iter()
                .position(|v| v.causality == Causality::Input && v.value_reference == vr)
                .map(|i| i + 1)
                .ok_or_else(|| DescriptionError::Invalid(format!("dependency on unknown input vr {vr}")))
        };
        let mut outputs = Vec::new();
        let mut initial_unknowns = Vec::new();
        for (i, v) in vars.iter().enumerate() {
            let deps = match &v.depends_on {
                Some(list) => {
                    let mut idx = list.iter().map(|&vr| index_of_input(vr)).collect::<Result<Vec<_>, _>>()?;
                    idx.sort_unstable();
                    Some(idx.iter().map(|i| i.to_string()).collect::<Vec<_>>().join(" "))
                }
                None => None,
            };
            if v.causality == Causality::Output {
                outputs.push(Unknown { index: i + 1, dependencies: deps.clone(), dependencies_kind: None });
            }
            let init = v.effective_initial();
            if (v.causality == Causality::Output && matches!(init, Some(Initial::Approx | Initial::Calculated)))
                || v.causality == Causality::CalculatedParameter
            {
                initial_unknowns.push(Unknown { index: i + 1, dependencies: None, dependencies_kind: None });
            }
        }
        self.md.model_structure = ModelStructure {
            outputs: (!outputs.is_empty()).then_some(UnknownList { unknowns: outputs }),
            derivatives: None,
            initial_unknowns: (!initial_unknowns.is_empty()).then_some(UnknownList { unknowns: initial_unknowns }),
        };
        self.md.guid = String::new();
        // the GUID identifies the model, not the moment it was packaged
        let when = self.md.generation_date_and_time.take();
        let body = self.md.to_xml()?;
        self.md.generation_date_and_time = when;
        let ns = uuid::Uuid::from_bytes(*b"chatter-fmu-ns-1");
        self.md.guid = format!("{{{}}}", uuid::Uuid::new_v5(&ns, body.as_bytes()));
        Ok(self.md)
    }
}

/// A declared work bound must be usable by a master: a finite limit above the extra steps, and
/// an internal-step parameter that is a Real parameter whose lower bound keeps `h / p` finite.
fn check_work_bound(w: &WorkBound, md: &ModelDescription) -> Result<(), DescriptionError> {
    let bad = |why: &str| Err(DescriptionError::Invalid(format!("work bound: {why}")));
    let (max, extra) = (w.max_internal_steps_per_call, w.extra_internal_steps_per_call);
    if !(max.is_finite() && extra.is_finite() && extra >= 0.0 && max > extra) {
        return bad(&format!(
            "maxInternalStepsPerCall {max} must be finite and above extraInternalStepsPerCall {extra} >= 0"
        ));
    }
    let Some(v) = md.variable(&w.internal_step_parameter) else {
        return bad(&format!("no variable {}", w.internal_step_parameter));
    };
    if v.scalar_type() != ScalarType::Real || v.causality != Causality::Parameter {
        return bad(&format!("{} must be a Real parameter", v.name));
    }
    if !v.range().0.is_some_and(|lo| lo > 0.0) {
        return bad(&format!("{} needs a positive min (the master divides by it)", v.name));
    }
    Ok(())
}
