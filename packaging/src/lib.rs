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
//!   `model.png` (the block symbol, [`icon`]), `documentation/index.html` (the adapter's Markdown documentation and a variable table from
//!   the same description, rendered to HTML by [`documentation`]) and
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
use model_description::ModelDescription;
use std::path::{Path, PathBuf};

pub mod documentation;
pub use documentation::documentation_html;
pub mod icon;
pub mod platforms;
pub use platforms::Build;
pub mod systems;
pub use systems::*;

/// One FMU product of the project.
pub struct Product {
    /// Cargo package of the cdylib.
    pub package: &'static str,
    /// Its folder in the workspace.
    pub dir: &'static str,
    /// The model's description (its `modelIdentifier` is the cdylib's library name).
    pub description: fn() -> &'static ModelDescription,
    /// The model's documentation as Markdown ([`documentation`] renders it, with the variable
    /// table, into `documentation/index.html` and the FMU's page of the book).
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
        package: "fmu-milling-process-cdylib",
        dir: "fmu-milling-process/cdylib",
        description: fmu_milling_process::MillingProcess::description,
        documentation: fmu_milling_process::DOCUMENTATION,
    },
    Product {
        package: "fmu-modal-structure-cdylib",
        dir: "fmu-modal-structure/cdylib",
        description: fmu_modal_structure::ModalStructure::description,
        documentation: fmu_modal_structure::DOCUMENTATION,
    },
    Product {
        package: "fmu-inertial-actuator-cdylib",
        dir: "fmu-inertial-actuator/cdylib",
        description: fmu_inertial_actuator::InertialActuator::description,
        documentation: fmu_inertial_actuator::DOCUMENTATION,
    },
    Product {
        package: "fmu-milling-force-plant-cdylib",
        dir: "fmu-milling-force-plant/cdylib",
        description: fmu_milling_force_plant::MillingForcePlant::description,
        documentation: fmu_milling_force_plant::DOCUMENTATION,
    },
    Product {
        package: "fmu-froh-mrac-controller-cdylib",
        dir: "fmu-froh-mrac-controller/cdylib",
        description: fmu_froh_mrac_controller::FrohMracController::description,
        documentation: fmu_froh_mrac_controller::DOCUMENTATION,
    },
    Product {
        package: "fmu-spindle-structure-cdylib",
        dir: "fmu-spindle-structure/cdylib",
        description: fmu_spindle_structure::SpindleStructure::description,
        documentation: fmu_spindle_structure::DOCUMENTATION,
    },
    Product {
        package: "fmu-linear-controller-cdylib",
        dir: "fmu-linear-controller/cdylib",
        description: fmu_linear_controller::LinearController::description,
        documentation: fmu_linear_controller::DOCUMENTATION,
    },
    Product {
        package: "fmu-tool-xy-plant-cdylib",
        dir: "fmu-tool-xy-plant/cdylib",
        description: fmu_tool_xy_plant::ToolXyPlant::description,
        documentation: fmu_tool_xy_plant::DOCUMENTATION,
    },
    Product {
        package: "fmu-sliding-mode-fuzzy-controller-cdylib",
        dir: "fmu-sliding-mode-fuzzy-controller/cdylib",
        description: fmu_sliding_mode_fuzzy_controller::SlidingModeFuzzyController::description,
        documentation: fmu_sliding_mode_fuzzy_controller::DOCUMENTATION,
    },
    Product {
        package: "fmu-turning-process-cdylib",
        dir: "fmu-turning-process/cdylib",
        description: fmu_turning_process::TurningProcessFmu::description,
        documentation: fmu_turning_process::DOCUMENTATION,
    },
    Product {
        package: "fmu-afrac-controller-cdylib",
        dir: "fmu-afrac-controller/cdylib",
        description: fmu_afrac_controller::AfracController::description,
        documentation: fmu_afrac_controller::DOCUMENTATION,
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

/// The `generationDateAndTime` of the FMUs: the time of the sources, not of the build, so that a
/// rebuild of the same commit writes the same archives: `SOURCE_DATE_EPOCH` (the reproducible-
/// builds convention) if set, else the commit time of the workspace's `HEAD` (`git log -1
/// --format=%ct`), else none (a source tree without git and without the variable).
pub fn source_date() -> Option<String> {
    let epoch = match std::env::var("SOURCE_DATE_EPOCH") {
        Ok(s) => s.trim().parse::<i64>().ok()?,
        Err(_) => {
            let out = std::process::Command::new("git")
                .args(["log", "-1", "--format=%ct"])
                .current_dir(workspace_root())
                .output()
                .ok()?;
            String::from_utf8(out.stdout).ok()?.trim().parse::<i64>().ok()?
        }
    };
    Some(utc_date_time(epoch))
}

/// Seconds since 1970-01-01T00:00:00Z as `xs:dateTime` in UTC (`2026-11-26T14:03:00Z`), by the
/// days-to-civil algorithm of H. Hinnant (proleptic Gregorian calendar).
pub fn utc_date_time(epoch: i64) -> String {
    let (days, secs) = (epoch.div_euclid(86_400), epoch.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z", secs / 3600, secs % 3600 / 60, secs % 60)
}

/// Write one `.fmu` archive with the binary of each of `builds` (one model description, one
/// GUID, a `binaries/<platform>/` folder per build); its `modelDescription.xml` carries the
/// [`source_date`] as `generationDateAndTime`.
pub fn write_fmu(md: &ModelDescription, docs: &str, builds: &[Build], out: &Path) -> Result<()> {
    let mut md = md.clone();
    md.generation_date_and_time = source_date();
    let md = &md;
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
    zip.file("model.png", icon::model_png(md)?, Compression::Stored);
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

#[cfg(test)]
mod tests {
    #[test]
    fn dates_are_utc_xs_date_times() {
        assert_eq!(super::utc_date_time(0), "1970-01-01T00:00:00Z");
        assert_eq!(super::utc_date_time(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(super::utc_date_time(1_795_701_780), "2026-11-26T14:03:00Z");
        assert_eq!(super::utc_date_time(-1), "1969-12-31T23:59:59Z");
    }

    #[test]
    fn the_source_date_comes_from_source_date_epoch() {
        // SAFETY of the test: no other test of this crate reads the variable
        unsafe { std::env::set_var("SOURCE_DATE_EPOCH", "86400") };
        assert_eq!(super::source_date().as_deref(), Some("1970-01-02T00:00:00Z"));
        unsafe { std::env::remove_var("SOURCE_DATE_EPOCH") };
    }
}
