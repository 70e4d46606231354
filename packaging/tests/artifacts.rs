//! Checks of the built FMU artifacts: names, exported symbols, shared-library
//! dependencies, archive layout, and the C header check against the official
//! FMI 2.0 headers.
//!
//! The artifact tests need `cargo run --release -p packaging` to have run
//! (the README test command does it first); without the files they fail.
#![allow(missing_docs)]

mod common;
use common::{official_headers, packaged_binary};
use packaging::{PRODUCTS, fmu_dir, workspace_root};
use std::path::{Path, PathBuf};
use std::process::Command;

fn lib_name_of(package_dir: &str) -> String {
    let manifest = std::fs::read_to_string(workspace_root().join(package_dir).join("Cargo.toml")).unwrap();
    let lib = manifest.split("[lib]").nth(1).expect("[lib] section");
    let line = lib.lines().find(|l| l.trim_start().starts_with("name")).expect("lib name");
    line.split('"').nth(1).unwrap().to_string()
}

#[test]
fn cdylib_name_model_identifier_and_binary_name_are_one_string() {
    for p in &PRODUCTS {
        let md = (p.description)();
        let id = md.model_identifier().unwrap();
        assert_eq!(lib_name_of(p.dir), id, "{}: [lib] name must equal modelIdentifier", p.package);
        assert_eq!(md.model_name, id);
        let fmu = fmu_dir().join(format!("{id}.fmu"));
        let f = std::fs::File::open(&fmu)
            .unwrap_or_else(|e| panic!("{}: {e} (run `cargo run --release -p packaging`)", fmu.display()));
        let mut z = zip::ZipArchive::new(f).unwrap();
        let names: Vec<String> = z.file_names().map(String::from).collect();
        let required =
            ["modelDescription.xml", &format!("binaries/linux64/{id}.so"), "documentation/index.html", "model.png"];
        for required in required {
            assert!(names.iter().any(|n| n == required), "{id}.fmu lacks {required}: {names:?}");
        }
        let mut xml = String::new();
        std::io::Read::read_to_string(&mut z.by_name("modelDescription.xml").unwrap(), &mut xml).unwrap();
        let parsed = model_description::ModelDescription::from_xml(&xml).unwrap();
        assert_eq!(parsed.guid, md.guid, "the packaged XML is the model's own table");
        // issue 31: the optional attributes tools show, the generation time from the sources
        assert_eq!(parsed.license.as_deref(), Some("MIT OR Apache-2.0"), "{id}");
        assert!(parsed.copyright.is_some(), "{id}");
        assert_eq!(
            parsed.generation_date_and_time,
            packaging::source_date(),
            "{id}: generationDateAndTime is not the commit time of HEAD (rebuild the FMUs after a commit: \
             cargo run --release -p packaging)"
        );
    }
}

/// The linux64 binary of every product, as shipped inside its FMU (extracted into `tmp`).
fn libraries(tmp: &Path) -> Vec<(String, PathBuf)> {
    PRODUCTS
        .iter()
        .map(|p| {
            let id = (p.description)().model_identifier().unwrap().to_string();
            let lib = packaged_binary(&id, "linux64", tmp).expect("every FMU has a linux64 binary");
            (id, lib)
        })
        .collect()
}

fn tool(cmd: &str, args: &[&str], lib: &Path) -> String {
    let out = Command::new(cmd).args(args).arg(lib).output().unwrap_or_else(|e| panic!("running {cmd}: {e}"));
    assert!(out.status.success(), "{cmd} failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn only_fmi2_symbols_are_exported() {
    let tmp = tempfile::tempdir().unwrap();
    for (id, lib) in libraries(tmp.path()) {
        let out = tool("nm", &["-D", "--defined-only"], &lib);
        let symbols: Vec<&str> = out.lines().filter_map(|l| l.split_whitespace().nth(2)).collect();
        let foreign: Vec<&&str> = symbols.iter().filter(|s| !s.starts_with("fmi2")).collect();
        assert!(foreign.is_empty(), "{id}: non-FMI symbols exported: {foreign:?}");
        for f in ["fmi2Instantiate", "fmi2DoStep", "fmi2GetReal", "fmi2SerializeFMUstate", "fmi2GetBooleanStatus"] {
            assert!(symbols.contains(&f), "{id}: {f} not exported");
        }
        assert_eq!(symbols.len(), 34, "{id}: the 34 common and co-simulation functions of FMI 2.0");
    }
}

#[test]
fn depends_on_the_c_runtime_only() {
    // libgcc_s provides the unwinder that turns a panic into fmi2Fatal; it is
    // part of every GNU/Linux C runtime installation.
    let allowed = [
        "libc.so.6",
        "libm.so.6",
        "libgcc_s.so.1",
        "ld-linux-x86-64.so.2",
        "libpthread.so.0",
        "libdl.so.2",
        "librt.so.1",
    ];
    let tmp = tempfile::tempdir().unwrap();
    for (id, lib) in libraries(tmp.path()) {
        let out = tool("readelf", &["-d"], &lib);
        for line in out.lines().filter(|l| l.contains("(NEEDED)")) {
            let name = line.split('[').nth(1).and_then(|s| s.split(']').next()).unwrap();
            assert!(allowed.contains(&name), "{id} needs {name}");
        }
    }
}

/// The C header of the export layer's entry points, written by cbindgen from
/// `fmi2-export/src/exports.rs` into `header`; returns its text.
fn generated_header(header: &Path) -> String {
    let config = cbindgen::Config {
        language: cbindgen::Language::C,
        no_includes: true,
        usize_is_size_t: true,
        include_guard: Some("FMI2_EXPORT_GENERATED_H".into()),
        ..Default::default()
    };
    cbindgen::Builder::new()
        .with_config(config)
        .with_src(workspace_root().join("fmi/fmi2-export/src/exports.rs"))
        .generate()
        .expect("cbindgen")
        .write_to_file(header);
    std::fs::read_to_string(header).unwrap()
}

/// The function names the generated header declares.
fn header_functions(text: &str) -> Vec<String> {
    let mut names: Vec<String> = text
        .lines()
        .filter(|l| l.contains(" fmi2") && l.contains('('))
        .filter_map(|l| l.split('(').next()?.split_whitespace().last().map(|n| n.trim_start_matches('*').to_string()))
        .collect();
    names.sort();
    names
}

#[test]
fn every_product_exports_exactly_the_functions_of_the_checked_header() {
    let tmp = tempfile::tempdir().unwrap();
    let declared = header_functions(&generated_header(&tmp.path().join("fmi2_export.h")));
    assert_eq!(declared.len(), 34, "{declared:?}");
    for (id, lib) in libraries(tmp.path()) {
        let out = tool("nm", &["-D", "--defined-only"], &lib);
        let mut exported: Vec<String> =
            out.lines().filter_map(|l| l.split_whitespace().nth(2)).map(String::from).collect();
        exported.sort();
        assert_eq!(exported, declared, "{id}: the exported symbols are not the header's functions");
    }
}

#[test]
fn the_product_list_beside_the_fmus_is_packagings() {
    let path = fmu_dir().join(packaging::PRODUCT_LIST);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (run `cargo run --release -p packaging`)", path.display()));
    assert_eq!(text, packaging::product_list_json(), "{} is stale: run packaging again", path.display());
    for p in &PRODUCTS {
        let id = (p.description)().model_identifier().unwrap();
        assert!(text.contains(&format!("\"{id}\"")), "{id} missing from {}", path.display());
        assert!(fmu_dir().join(format!("{id}.fmu")).is_file(), "{id}.fmu missing");
    }
}

#[test]
fn c_header_matches_the_official_fmi2_headers() {
    let tmp = tempfile::tempdir().unwrap();
    let text = generated_header(&tmp.path().join("fmi2_export.h"));
    assert_eq!(text.lines().filter(|l| l.contains(" fmi2") && l.contains('(')).count(), 34, "{text}");
    let abi_size = std::mem::size_of::<fmi2_abi::fmi2CallbackFunctions>();
    let check = tmp.path().join("check.c");
    std::fs::write(
        &check,
        format!(
            "#include <stddef.h>\n#include \"fmi2Functions.h\"\n#include \"fmi2_export.h\"\n\
             _Static_assert(sizeof(fmi2CallbackFunctions) == {abi_size}, \"fmi2CallbackFunctions size\");\n\
             _Static_assert(offsetof(fmi2CallbackFunctions, componentEnvironment) == {}, \"offset\");\n\
             _Static_assert(sizeof(fmi2Status) == {}, \"fmi2Status size\");\n\
             int main(void) {{ fmi2DoStepTYPE *f = fmi2DoStep; fmi2InstantiateTYPE *g = fmi2Instantiate; return f == 0 || g == 0; }}\n",
            std::mem::offset_of!(fmi2_abi::fmi2CallbackFunctions, componentEnvironment),
            std::mem::size_of::<fmi2_abi::fmi2Status>(),
        ),
    )
    .unwrap();
    let out = Command::new("gcc")
        .args(["-std=c11", "-Wall", "-Werror", "-fsyntax-only", "-I"])
        .arg(official_headers())
        .arg("-I")
        .arg(tmp.path())
        .arg(&check)
        .output()
        .expect("gcc");
    assert!(out.status.success(), "C header check failed:\n{}\n{text}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn a_signature_mismatch_fails_the_c_check() {
    // The check above must be able to fail: a header with one wrong parameter type is rejected.
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("bad.h"),
        "fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Real wrong);\n",
    )
    .unwrap();
    std::fs::write(tmp.path().join("check.c"), "#include \"fmi2Functions.h\"\n#include \"bad.h\"\n").unwrap();
    let out = Command::new("gcc")
        .args(["-std=c11", "-fsyntax-only", "-I"])
        .arg(official_headers())
        .arg("-I")
        .arg(tmp.path())
        .arg(tmp.path().join("check.c"))
        .output()
        .unwrap();
    assert!(!out.status.success());
}
