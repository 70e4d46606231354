//! # Packaging of the project's FMUs
//!
//! `cargo run --release -p packaging` builds the model cdylibs (profile `fmu-symbols`: release
//! code with line tables) for each platform it can, moves their debug info into
//! `target/fmu-debug/<modelIdentifier>.<platform>.debug` (the shipped binaries carry none, and a
//! `.gnu_debuglink` to that file) and writes, under `target/fmu/`:
//!
//! * `<modelIdentifier>.fmu` for each product ([`PRODUCTS`]): `modelDescription.xml`
//!   (from the model's one variable table), `binaries/linux64/<modelIdentifier>.so` and, where
//!   the toolchain is installed, `binaries/win64/<modelIdentifier>.dll` ([`platforms`]: the
//!   linux64 binary is built against glibc 2.17 with `cargo zigbuild` when available),
//!   `documentation/index.html` (generated from the same table) and
//!   `resources/` (a README naming the FMU; our models read no resource files);
//! * `products.json`: the model identifiers of all products, in [`PRODUCTS`] order (the
//!   Python conformance tests parametrize over it, so a product added to [`PRODUCTS`] is
//!   checked without naming it anywhere else, and a stale `.fmu` left in the folder is not);
//! * `ClosedLoop.ssp`: the closed-loop system (plant + controller) as a
//!   standard SSP 1.0 archive with both FMUs under `resources/`;
//! * `ClosedLoopTable2.ssp`: the same system with the paper's Table 2 controller
//!   gains as SSP parameter bindings (the FMU defaults are the PSO-tuned gains).
//!
//! The cdylib's library name, the `modelIdentifier` and the binary's file name
//! are one string, checked by this crate's tests. Archives are written with
//! `fmi-archive`'s deterministic zip writer (fixed order, timestamps and
//! permissions), so rebuilding the same sources gives the same files; the SSDs
//! are written and edited with the `ssp` crate.

use anyhow::{Context, Result};
use fmi_archive::{Compression, ZipBuilder};
use fmi2_export::Fmi2Model;
use model_description::{ModelDescription, VarKind};
use std::path::{Path, PathBuf};

pub mod platforms;
pub use platforms::Build;

/// The project's closed-loop system (plant + controller), `packaging/scenarios/ClosedLoop.ssd`:
/// the `SystemStructure.ssd` of `ClosedLoop.ssp` (and, with the Table 2 bindings, of
/// `ClosedLoopTable2.ssp`), and the studies' scenario when no `.ssp` is at hand.
pub const CLOSED_LOOP_SSD: &str = include_str!("../scenarios/ClosedLoop.ssd");

/// Seed 000's plant decomposed into process + structure + actuator, with the controller
/// (`packaging/scenarios/DecomposedPlant.ssd`, shipped as `DecomposedPlant.ssp`).
pub const DECOMPOSED_PLANT_SSD: &str = include_str!("../scenarios/DecomposedPlant.ssd");

/// The FMUs of [`DECOMPOSED_PLANT_SSD`].
pub const DECOMPOSED_PLANT_FMUS: [&str; 4] =
    ["MillingProcess.fmu", "ModalStructure.fmu", "InertialActuator.fmu", "ChatterController.fmu"];

/// Seed 004's closed loop (MillingForcePlant + FrohMracController),
/// `packaging/scenarios/ForceControl.ssd`: the `SystemStructure.ssd` of `ForceControl.ssp`.
pub const FORCE_CONTROL_SSD: &str = include_str!("../scenarios/ForceControl.ssd");

/// Seed 002's spindle in closed loop (`packaging/scenarios/Spindle.ssd`, shipped as
/// `Spindle.ssp`): MillingProcess (power law, full immersion, 4 teeth) + SpindleStructure +
/// LinearController with the printed §6.1 gains.
pub const SPINDLE_SSD: &str = include_str!("../scenarios/Spindle.ssd");

/// The FMUs of [`SPINDLE_SSD`].
pub const SPINDLE_FMUS: [&str; 3] = ["MillingProcess.fmu", "SpindleStructure.fmu", "LinearController.fmu"];
/// Seed 002's synthesised controller designs (`chatter synth --case all`: §6.1 and Table II
/// n_c = 0, 2, 4), SSP parameter sets with the `LinearController` names, written to
/// `<fmu dir>/designs/` to bind to `controller` in `Spindle.ssp` (or `chatter spindle
/// validate --design`).
pub const SPINDLE_DESIGNS: [(&str, &str); 4] = [
    ("sec6_1.ssv", include_str!("../designs/sec6_1.ssv")),
    ("table2_nc0.ssv", include_str!("../designs/table2_nc0.ssv")),
    ("table2_nc2.ssv", include_str!("../designs/table2_nc2.ssv")),
    ("table2_nc4.ssv", include_str!("../designs/table2_nc4.ssv")),
];
/// Seed 003's closed loop (ToolXyPlant + SlidingModeFuzzyController),
/// `packaging/scenarios/SlidingModeFuzzy.ssd`: the `SystemStructure.ssd` of `SlidingModeFuzzy.ssp`.
pub const SLIDING_MODE_FUZZY_SSD: &str = include_str!("../scenarios/SlidingModeFuzzy.ssd");
/// Seed 001's closed loop (TurningProcess + AfracController), `packaging/scenarios/Afrac.ssd`:
/// the `SystemStructure.ssd` of `Afrac.ssp`.
pub const AFRAC_SSD: &str = include_str!("../scenarios/Afrac.ssd");

/// One FMU product of the project.
pub struct Product {
    /// Cargo package of the cdylib.
    pub package: &'static str,
    /// Its folder in the workspace.
    pub dir: &'static str,
    /// The model's description (its `modelIdentifier` is the cdylib's library name).
    pub description: fn() -> &'static ModelDescription,
    /// Long documentation (Markdown-ish text shown in `documentation/index.html`).
    pub documentation: &'static str,
}

/// The FMUs this project ships.
pub const PRODUCTS: [Product; 13] = [
    Product {
        package: "fmu-plant-cdylib",
        dir: "fmu-plant/cdylib",
        description: fmu_plant::MillingPlant::description,
        documentation: fmu_plant::DOCUMENTATION,
    },
    Product {
        package: "fmu-controller-cdylib",
        dir: "fmu-controller/cdylib",
        description: fmu_controller::ChatterController::description,
        documentation: fmu_controller::DOCUMENTATION,
    },
    Product {
        package: "fmu-process-cdylib",
        dir: "fmu-process/cdylib",
        description: fmu_process::MillingProcess::description,
        documentation: fmu_process::DOCUMENTATION,
    },
    Product {
        package: "fmu-structure-cdylib",
        dir: "fmu-structure/cdylib",
        description: fmu_structure::ModalStructure::description,
        documentation: fmu_structure::DOCUMENTATION,
    },
    Product {
        package: "fmu-actuator-cdylib",
        dir: "fmu-actuator/cdylib",
        description: fmu_actuator::InertialActuator::description,
        documentation: fmu_actuator::DOCUMENTATION,
    },
    Product {
        package: "fmu-force-plant-cdylib",
        dir: "fmu-force-plant/cdylib",
        description: fmu_force_plant::MillingForcePlant::description,
        documentation: fmu_force_plant::DOCUMENTATION,
    },
    Product {
        package: "fmu-froh-mrac-cdylib",
        dir: "fmu-froh-mrac/cdylib",
        description: fmu_froh_mrac::FrohMracController::description,
        documentation: fmu_froh_mrac::DOCUMENTATION,
    },
    Product {
        package: "fmu-spindle-cdylib",
        dir: "fmu-spindle/cdylib",
        description: fmu_spindle::SpindleStructure::description,
        documentation: fmu_spindle::DOCUMENTATION,
    },
    Product {
        package: "fmu-linear-controller-cdylib",
        dir: "fmu-linear-controller/cdylib",
        description: fmu_linear_controller::LinearController::description,
        documentation: fmu_linear_controller::DOCUMENTATION,
    },
    Product {
        package: "fmu-tool-xy-cdylib",
        dir: "fmu-tool-xy/cdylib",
        description: fmu_tool_xy::ToolXyPlant::description,
        documentation: fmu_tool_xy::DOCUMENTATION,
    },
    Product {
        package: "fmu-sliding-fuzzy-cdylib",
        dir: "fmu-sliding-fuzzy/cdylib",
        description: fmu_sliding_fuzzy::SlidingModeFuzzyController::description,
        documentation: fmu_sliding_fuzzy::DOCUMENTATION,
    },
    Product {
        package: "fmu-turning-cdylib",
        dir: "fmu-turning/cdylib",
        description: fmu_turning::TurningProcessFmu::description,
        documentation: fmu_turning::DOCUMENTATION,
    },
    Product {
        package: "fmu-afrac-cdylib",
        dir: "fmu-afrac/cdylib",
        description: fmu_afrac::AfracController::description,
        documentation: fmu_afrac::DOCUMENTATION,
    },
];

/// The workspace root (where `Cargo.toml` of the workspace is).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("packaging sits in the workspace").to_path_buf()
}

/// The cargo target directory (`CARGO_TARGET_DIR` or `<root>/target`).
pub fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR").map(PathBuf::from).unwrap_or_else(|| workspace_root().join("target"))
}

/// THE directory of the project's FMUs and systems: `$FMU_DIR` if set (the variable the Python
/// tests use too), else `<target>/fmu`, where packaging writes them. Every tool and test of the
/// workspace finds the FMUs through this function.
pub fn fmu_dir() -> PathBuf {
    match std::env::var_os("FMU_DIR") {
        Some(d) => PathBuf::from(d),
        None => target_dir().join("fmu"),
    }
}

/// A file of [`fmu_dir`] (`MillingPlant.fmu`, `ClosedLoop.ssp`, …).
///
/// # Panics
/// With instructions when it is missing: for tests and tools that need the packaged FMUs.
pub fn packaged(file: &str) -> PathBuf {
    let p = fmu_dir().join(file);
    assert!(
        p.is_file(),
        "{} is missing: build the FMUs first with `cargo run --release -p packaging` \
         (tests/run_all.sh does this before `cargo test`)",
        p.display()
    );
    p
}

/// Where packaging writes the FMU binaries' separate debug files: `<target>/fmu-debug/`
/// (`<modelIdentifier>.<platform>.debug`, see [`platforms::split_debug`]).
pub fn debug_dir() -> PathBuf {
    target_dir().join("fmu-debug")
}

/// Build the product cdylibs for every platform this machine can build ([`platforms::plan`])
/// and split their debug info into [`debug_dir`]; prints what is skipped and why. Returns the
/// builds done.
pub fn build_cdylibs() -> Result<Vec<Build>> {
    let venv = workspace_root().join(".venv");
    let plan = platforms::plan(&venv)?;
    for (name, why) in &plan.skipped {
        eprintln!("packaging: {name} skipped: {why}");
    }
    let packages: Vec<&str> = PRODUCTS.iter().map(|p| p.package).collect();
    for build in &plan.builds {
        platforms::run(build, &workspace_root(), &venv, &packages)?;
        for p in &PRODUCTS {
            let id = (p.description)().model_identifier().context("no modelIdentifier")?.to_string();
            platforms::split_debug(build, &target_dir(), &debug_dir(), &id)?;
        }
    }
    Ok(plan.builds)
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// `documentation/index.html`, generated from the variable table and the model docs.
pub fn documentation_html(md: &ModelDescription, docs: &str) -> String {
    let mut h = String::new();
    let title = esc(&md.model_name);
    h.push_str(&format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{title}</title>\n\
         <style>body{{font-family:sans-serif;max-width:70em;margin:auto}}table{{border-collapse:collapse}}\
         td,th{{border:1px solid #999;padding:2px 6px;font-size:90%}}pre{{white-space:pre-wrap}}</style></head><body>\n\
         <h1>{title}</h1>\n<p>{}</p>\n<p>FMI 2.0 Co-Simulation, modelIdentifier <code>{}</code>, GUID <code>{}</code>.</p>\n",
        esc(md.description.as_deref().unwrap_or("")),
        esc(md.model_identifier().unwrap_or("")),
        esc(&md.guid)
    ));
    h.push_str("<h2>Model</h2>\n<pre>");
    h.push_str(&esc(docs));
    h.push_str("</pre>\n<h2>Variables</h2>\n<table><tr><th>name</th><th>causality</th><th>variability</th><th>type</th><th>start</th><th>unit</th><th>min</th><th>max</th><th>description</th></tr>\n");
    for v in md.variables() {
        let ty = match &v.kind {
            VarKind::Enumeration(e) => {
                let items = md.enumeration_items(&e.declared_type);
                let items: Vec<_> = items.iter().map(|(n, i)| format!("{i}={n}")).collect();
                format!("{} ({})", e.declared_type, items.join(", "))
            }
            _ => format!("{:?}", v.scalar_type()),
        };
        let start = v.start_value().map(|s| match s {
            model_description::Value::Real(x) => format!("{x}"),
            model_description::Value::Integer(i) => i.to_string(),
            model_description::Value::Boolean(b) => b.to_string(),
            model_description::Value::String(s) => format!("\"{s}\""),
        });
        let (lo, hi) = v.range();
        h.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{:?}</td><td>{:?}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            esc(&v.name),
            v.causality,
            v.variability,
            esc(&ty),
            esc(&start.unwrap_or_default()),
            esc(v.unit().unwrap_or("")),
            lo.map(|x| x.to_string()).unwrap_or_default(),
            hi.map(|x| x.to_string()).unwrap_or_default(),
            esc(v.description.as_deref().unwrap_or("")),
        ));
    }
    h.push_str("</table>\n</body></html>\n");
    h
}

/// Write one `.fmu` archive with the binary of each of `builds` (one model description, one
/// GUID, a `binaries/<platform>/` folder per build).
pub fn write_fmu(md: &ModelDescription, docs: &str, builds: &[Build], out: &Path) -> Result<()> {
    let id = md.model_identifier().context("model has no CoSimulation interface")?;
    let readme =
        format!("{} needs no resource files; this directory exists for masters that expect it.\n", md.model_name);
    let mut zip = ZipBuilder::new();
    zip.file("modelDescription.xml", md.to_xml()?, Compression::Deflated);
    for build in builds {
        let library = platforms::shipped(build, &target_dir(), id);
        let bytes = std::fs::read(&library).with_context(|| format!("reading {}", library.display()))?;
        zip.executable(format!("binaries/{}/{}", build.folder(), build.file_name(id)), bytes, Compression::Deflated);
    }
    zip.file("documentation/index.html", documentation_html(md, docs), Compression::Deflated).file(
        "resources/README.txt",
        readme,
        Compression::Deflated,
    );
    zip.write_to(out)?;
    Ok(())
}

/// File name of the product list in [`fmu_dir`] (see [`product_list_json`]).
pub const PRODUCT_LIST: &str = "products.json";

/// The model identifiers of [`PRODUCTS`] as a JSON array of strings (`["MillingPlant", …]`),
/// written by [`package_all`] as [`PRODUCT_LIST`].
pub fn product_list_json() -> String {
    let ids: Vec<String> = PRODUCTS
        .iter()
        .map(|p| format!("\"{}\"", (p.description)().model_identifier().expect("co-simulation product")))
        .collect();
    format!("[{}]\n", ids.join(", "))
}

/// Build everything and write all products and `ClosedLoop.ssp`; returns the written paths.
pub fn package_all() -> Result<Vec<PathBuf>> {
    let builds = build_cdylibs()?;
    let dir = fmu_dir();
    let mut written = Vec::new();
    let mut fmus = Vec::new();
    for p in &PRODUCTS {
        let md = (p.description)();
        let id = md.model_identifier().context("no modelIdentifier")?;
        let out = dir.join(format!("{id}.fmu"));
        write_fmu(md, p.documentation, &builds, &out)?;
        fmus.push((format!("{id}.fmu"), out.clone()));
        written.push(out);
    }
    let list = dir.join(PRODUCT_LIST);
    std::fs::write(&list, product_list_json())?;
    written.push(list);
    let in_ssd = |ssd: &str| -> Vec<(&str, &Path)> {
        fmus.iter()
            .filter(|(n, _)| ssd.contains(&format!("resources/{n}\"")))
            .map(|(n, p)| (n.as_str(), p.as_path()))
            .collect()
    };
    let ssp = dir.join("ForceControl.ssp");
    ssp::write_ssp_archive(&ssp, FORCE_CONTROL_SSD, &in_ssd(FORCE_CONTROL_SSD))?;
    written.push(ssp);
    let ssp = dir.join("Afrac.ssp");
    ssp::write_ssp_archive(&ssp, AFRAC_SSD, &in_ssd(AFRAC_SSD))?;
    written.push(ssp);
    let ssp = dir.join("SlidingModeFuzzy.ssp");
    ssp::write_ssp_archive(&ssp, SLIDING_MODE_FUZZY_SSD, &in_ssd(SLIDING_MODE_FUZZY_SSD))?;
    written.push(ssp);
    let ssp = dir.join("ClosedLoop.ssp");
    let refs = in_ssd(CLOSED_LOOP_SSD);
    ssp::write_ssp_archive(&ssp, CLOSED_LOOP_SSD, &refs)?;
    written.push(ssp);
    let ssp = dir.join("ClosedLoopTable2.ssp");
    ssp::write_ssp_archive(&ssp, &table2_ssd()?, &refs)?;
    written.push(ssp);
    let ssp = dir.join("DecomposedPlant.ssp");
    ssp::write_ssp_archive(&ssp, DECOMPOSED_PLANT_SSD, &in_ssd(DECOMPOSED_PLANT_SSD))?;
    written.push(ssp);
    let ssp = dir.join("Spindle.ssp");
    ssp::write_ssp_archive(&ssp, SPINDLE_SSD, &in_ssd(SPINDLE_SSD))?;
    written.push(ssp);
    let designs = dir.join("designs");
    std::fs::create_dir_all(&designs).with_context(|| designs.display().to_string())?;
    for (name, text) in SPINDLE_DESIGNS {
        let path = designs.join(name);
        std::fs::write(&path, text).with_context(|| path.display().to_string())?;
        written.push(path);
    }
    Ok(written)
}

/// The closed loop with the paper's Table 2 controller gains bound as SSP parameters
/// (`ClosedLoopTable2.ssp`): the shipped FMU defaults are the PSO-tuned gains, and this system
/// reproduces the seed's own settings with the same FMUs, in any SSP-capable tool.
pub fn table2_ssd() -> Result<String> {
    use model_description::Value;
    use ssp::{ParamValue, Parameter, SystemDescription};
    let mut sys = SystemDescription::from_xml(CLOSED_LOOP_SSD, "ClosedLoop.ssd", None)?;
    let md = fmu_controller::ChatterController::description();
    let mut params = Vec::new();
    for (name, value) in fmu_controller::parameter_assignments(&chatter_control::ControllerParams::paper_table2()) {
        let var = md.variable(&name).with_context(|| format!("{name}: not a controller variable"))?;
        let value = match (&var.kind, value) {
            (VarKind::Enumeration(e), Value::Integer(i)) => {
                let items = md.enumeration_items(&e.declared_type);
                let item = items.iter().find(|(_, v)| *v == i).with_context(|| format!("{name} = {i}: no item"))?;
                ParamValue::Enumeration(item.0.clone())
            }
            // No unit attribute: SSP units must be declared in a Units element; the FMU's are SI.
            (_, Value::Real(x)) => ParamValue::Real(x, None),
            (_, Value::Integer(i)) => ParamValue::Integer(i),
            (_, Value::Boolean(b)) => ParamValue::Boolean(b),
            (_, Value::String(s)) => ParamValue::String(s),
        };
        params.push(Parameter { name, value });
    }
    let ctrl = sys
        .components
        .iter_mut()
        .find(|c| c.source.ends_with("ChatterController.fmu"))
        .context("no ChatterController component in the closed-loop SSD")?;
    ctrl.parameters = params;
    sys.name = "ClosedLoopTable2".into();
    sys.description = Some(format!(
        "{} Controller gains: the paper's Table 2 preset (SI reading), not the PSO-tuned FMU defaults.",
        sys.description.unwrap_or_default()
    ));
    Ok(sys.to_xml()?)
}

/// The parameter bindings of [`SPINDLE_SSD`], by component: every value that differs from the
/// FMU's start value, from seed 002's parameter sets (Table I, §6.1): the process with the
/// power law (x_F = 1), K_t = 462, K_r = 38.6 N/mm² in SI, full immersion (0, π), 4 teeth,
/// a_p = 1 mm, 37000 rpm, f_z = 0.2 mm; the controller with `D_c = [[k₁, −k₂], [k₂, k₁]]`,
/// k₁ = 697.1599, k₂ = −1071.058 N/mm in N/m, β = 1, τ from the speed.
pub fn spindle_bindings() -> Result<Vec<(&'static str, Vec<ssp::Parameter>)>> {
    use milling_process::{ForceLaw, ProcessInputs, ProcessParams};
    use model_description::Value;
    type Pairs = Vec<(String, Value)>;
    // the assignments that differ from the start values, as SSP parameters of the FMU `md`
    let changed = |md: &ModelDescription, now: Pairs, base: Pairs| -> Result<Vec<ssp::Parameter>> {
        let mut out = Vec::new();
        for ((name, value), (_, start)) in now.into_iter().zip(base) {
            if value == start {
                continue;
            }
            let var = md.variable(&name).with_context(|| format!("{name}: not a variable"))?;
            let value = match (&var.kind, value) {
                (VarKind::Enumeration(e), Value::Integer(i)) => {
                    let items = md.enumeration_items(&e.declared_type);
                    let item = items.iter().find(|(_, v)| *v == i).with_context(|| format!("{name} = {i}: no item"))?;
                    ssp::ParamValue::Enumeration(item.0.clone())
                }
                (_, Value::Real(x)) => ssp::ParamValue::Real(x, None),
                (_, Value::Integer(i)) => ssp::ParamValue::Integer(i),
                (_, Value::Boolean(b)) => ssp::ParamValue::Boolean(b),
                (_, Value::String(s)) => ssp::ParamValue::String(s),
            };
            out.push(ssp::Parameter { name, value });
        }
        Ok(out)
    };
    let mut p = ProcessParams {
        explicit_angles: true,
        entry_angle: 0.0,
        exit_angle: std::f64::consts::PI,
        axial_depth: 1e-3,
        ..Default::default()
    };
    p.coefficients.law = ForceLaw::Power;
    p.coefficients.exponent = 1.0;
    p.coefficients.kt = 462e6;
    p.coefficients.kr = 38.6e6;
    let md = fmu_process::MillingProcess::description();
    let mut process =
        changed(md, fmu_process::parameter_assignments(&p), fmu_process::parameter_assignments(&Default::default()))?;
    let inputs = ProcessInputs { spindle_speed_rpm: 37_000.0, feed_per_tooth: 0.2e-3, ..Default::default() };
    let t = &fmu_process::TABLE;
    process.extend(changed(md, t.input_assignments(&inputs), t.input_assignments(&Default::default()))?);
    let (k1, k2) = (697.1599e3, -1071.058e3);
    let c = linear_control::LinearControlParams { dc: [[k1, -k2], [k2, k1]], ..Default::default() };
    let controller = changed(
        fmu_linear_controller::LinearController::description(),
        fmu_linear_controller::parameter_assignments(&c),
        fmu_linear_controller::parameter_assignments(&Default::default()),
    )?;
    Ok(vec![("process", process), ("spindle", Vec::new()), ("controller", controller)])
}

#[cfg(test)]
mod tests {
    use ssp::{ConnectorKind, SystemDescription};

    /// Spindle.ssd is canonical, names only shipped FMUs, and binds exactly
    /// [`crate::spindle_bindings`] (the seed's values, from the adapters' own names).
    #[test]
    fn the_embedded_spindle_system_is_canonical_and_binds_the_seed() {
        let d = SystemDescription::from_xml(crate::SPINDLE_SSD, "Spindle.ssd", None).unwrap();
        let mut want = d.clone();
        for (name, params) in crate::spindle_bindings().unwrap() {
            let c = want.component_mut(name).unwrap();
            c.parameters = params;
        }
        if std::env::var_os("WRITE_SPINDLE_SSD").is_some() {
            std::fs::write(crate::workspace_root().join("packaging/scenarios/Spindle.ssd"), want.to_xml().unwrap())
                .unwrap();
        }
        assert_eq!(d, want, "Spindle.ssd does not bind the seed's values");
        assert_eq!(d.to_xml().unwrap(), crate::SPINDLE_SSD, "Spindle.ssd is not canonical");
        for c in &d.components {
            let file = c.source.strip_prefix("resources/").unwrap();
            assert!(crate::SPINDLE_FMUS.contains(&file), "{file}");
        }
        assert_eq!(d.connections.len(), 8);
        connections_end_on_declared_connectors(&d);
    }

    /// Every connection starts at a declared output connector and ends at a declared input.
    fn connections_end_on_declared_connectors(d: &SystemDescription) {
        for c in &d.connections {
            let s = d.component(c.start_element.as_deref().unwrap()).unwrap();
            let e = d.component(c.end_element.as_deref().unwrap()).unwrap();
            assert!(s.connectors.iter().any(|x| x.name == c.start_connector && x.kind == ConnectorKind::Output));
            assert!(e.connectors.iter().any(|x| x.name == c.end_connector && x.kind == ConnectorKind::Input));
        }
    }

    /// The decomposed plant's SSD is canonical, names only shipped FMUs, and connects every
    /// connection end to a declared connector of the right kind.
    #[test]
    fn the_embedded_decomposed_plant_is_canonical_and_complete() {
        let d = SystemDescription::from_xml(crate::DECOMPOSED_PLANT_SSD, "DecomposedPlant.ssd", None).unwrap();
        assert_eq!(d.to_xml().unwrap(), crate::DECOMPOSED_PLANT_SSD, "DecomposedPlant.ssd is not canonical");
        assert_eq!(d.components.len(), 4);
        for c in &d.components {
            let file = c.source.strip_prefix("resources/").unwrap();
            assert!(crate::DECOMPOSED_PLANT_FMUS.contains(&file), "{file}");
        }
        assert_eq!(d.connections.len(), 8);
        connections_end_on_declared_connectors(&d);
    }

    /// The embedded SSD is in the writer's canonical form; also writes
    /// `target/ssd-test/ClosedLoop.ssd` for `tests/python/test_ssd_schema.py`.
    #[test]
    fn the_embedded_closed_loop_is_canonical_and_complete() {
        let d = SystemDescription::from_xml(crate::CLOSED_LOOP_SSD, "ClosedLoop.ssd", None).unwrap();
        assert_eq!(
            d.to_xml().unwrap(),
            crate::CLOSED_LOOP_SSD,
            "packaging/scenarios/ClosedLoop.ssd is not in the writer's canonical form"
        );
        assert_eq!(d.components.len(), 2);
        assert!(d.components.iter().all(|c| c.source.starts_with("resources/") && c.source.ends_with(".fmu")));
        assert_eq!(d.connections.len(), 2, "the closed loop has one feedback and one command connection");
        // Every connection's end points are declared connectors of matching kinds.
        for c in &d.connections {
            let s = d.component(c.start_element.as_deref().unwrap()).unwrap();
            let e = d.component(c.end_element.as_deref().unwrap()).unwrap();
            let has = |k: &ssp::ComponentDesc, name: &str, kind| {
                k.connectors.iter().any(|x| x.name == name && x.kind == kind)
            };
            assert!(has(s, &c.start_connector, ConnectorKind::Output), "{}", c.label());
            assert!(has(e, &c.end_connector, ConnectorKind::Input), "{}", c.label());
        }
        assert!(d.master.step_size.is_some() && d.stop_time.is_some());
        let target = std::env::var_os("CARGO_TARGET_DIR")
            .map(std::path::PathBuf::from)
            .unwrap_or_else(|| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target"));
        let dir = target.join("ssd-test");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("ClosedLoop.ssd"), crate::CLOSED_LOOP_SSD).unwrap();
    }

    /// `SlidingModeFuzzy.ssd` (seed 003) is canonical, binds the forcing, and steps the
    /// controller's sample period.
    #[test]
    fn the_sliding_mode_fuzzy_system_is_canonical_and_steps_the_sample_period() {
        let d = SystemDescription::from_xml(crate::SLIDING_MODE_FUZZY_SSD, "SlidingModeFuzzy.ssd", None).unwrap();
        let canonical = d.to_xml().unwrap();
        if canonical != crate::SLIDING_MODE_FUZZY_SSD {
            let out = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/SlidingModeFuzzy.canonical.ssd");
            std::fs::write(&out, &canonical).unwrap();
            panic!("SlidingModeFuzzy.ssd is not canonical (canonical form written to {})", out.display());
        }
        assert_eq!(d.components.len(), 2);
        assert_eq!(d.connections.len(), 6, "x, y, vx, vy to the controller; u_x, u_y to the plant");
        let plant = d.components.iter().find(|c| c.name == "plant").unwrap();
        assert_eq!(plant.parameters.len(), 2, "the calibrated forcing amplitudes");
        let ts = fmu_sliding_fuzzy::TABLE.read_parameters(&fmi2_export::Values::from_description(
            <fmu_sliding_fuzzy::SlidingModeFuzzyController as fmi2_export::Fmi2Model>::description(),
        ));
        let ts = ts.unwrap().sample_period;
        assert!((ts / d.master.step_size.unwrap() - 1.0).abs() < 1e-12);
    }

    /// `Afrac.ssd` (seed 001) is canonical, connects x, v and the two commands, and steps the
    /// controller's sample period (the loop of `studies::afrac`).
    #[test]
    fn the_afrac_system_is_canonical_and_steps_the_sample_period() {
        let d = SystemDescription::from_xml(crate::AFRAC_SSD, "Afrac.ssd", None).unwrap();
        assert_eq!(d.to_xml().unwrap(), crate::AFRAC_SSD, "Afrac.ssd is not canonical");
        assert_eq!(d.components.len(), 2);
        assert_eq!(d.connections.len(), 4, "x, v to the controller; spindle_speed, feed to the plant");
        let ts = fmu_afrac::TABLE.read_parameters(&fmi2_export::Values::from_description(
            <fmu_afrac::AfracController as fmi2_export::Fmi2Model>::description(),
        ));
        let ts = ts.unwrap().sample_period;
        assert!((ts / d.master.step_size.unwrap() - 1.0).abs() < 1e-12);
    }

    /// `ForceControl.ssd` (seed 004) is canonical, and its step is an integer fraction of the
    /// controller's sample period, as FrohMracController requires.
    #[test]
    fn the_force_control_system_is_canonical_and_steps_a_fraction_of_the_sample_period() {
        let d = SystemDescription::from_xml(crate::FORCE_CONTROL_SSD, "ForceControl.ssd", None).unwrap();
        assert_eq!(d.to_xml().unwrap(), crate::FORCE_CONTROL_SSD, "ForceControl.ssd is not canonical");
        assert_eq!(d.components.len(), 2);
        assert_eq!(d.connections.len(), 3, "force feedback, command mean and command slope");
        let ts = fmu_froh_mrac::TABLE.read_parameters(&fmi2_export::Values::from_description(
            <fmu_froh_mrac::FrohMracController as fmi2_export::Fmi2Model>::description(),
        ));
        let ts = ts.unwrap().sample_period;
        let m = ts / d.master.step_size.unwrap();
        assert!((m - m.round()).abs() < 1e-9 && m.round() >= 1.0, "Ts/h = {m}");
    }
}
