//! Every FMU adapter runs the shared checks: the adapter of each product of `PRODUCTS` (the
//! folder of its cdylib) invokes `fmi2_export::adapter_tests!` exactly once, in a test target
//! (`tests/*.rs`), on the model its library declares with `fmi2_export::adapter!`; and every
//! `fmu-*` folder of the workspace is the adapter of a product. So an adapter added without the
//! shared list, or one whose invocation is removed, fails here (the list itself is
//! `fmi2-export`'s `table::checks::adapter_tests!`). Reads the sources only: no FMU needed.
#![allow(missing_docs)]

use packaging::{PRODUCTS, workspace_root};
use std::path::{Path, PathBuf};

/// The `.rs` files under `dir`, recursively, in a stable order.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else { return out };
    let mut paths: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
    paths.sort();
    for p in paths {
        if p.is_dir() {
            out.extend(rust_files(&p));
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
    out
}

/// `text` without its `//` comments (a commented-out invocation does not count).
fn code(text: &str) -> String {
    text.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n")
}

/// The identifier after `key` in the first `name! { ... key IDENT ... }` of `code`, for every
/// invocation of the macro `name`.
fn invocations(code: &str, name: &str, key: &str) -> Vec<String> {
    code.match_indices(&format!("{name}!"))
        .map(|(at, _)| {
            let rest = &code[at..];
            let after = rest.split_once(key).map_or("", |(_, r)| r).trim_start();
            after.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect()
        })
        .collect()
}

/// `alias` resolved through a `type alias = Model;` of `code`.
fn resolve(code: &str, alias: &str) -> String {
    code.split_once(&format!("type {alias} = "))
        .and_then(|(_, r)| r.split(';').next())
        .map_or(alias.to_string(), |t| t.trim().to_string())
}

/// The adapter folder of each product (its cdylib's parent), with the product's identifier.
fn adapters() -> Vec<(String, PathBuf)> {
    PRODUCTS
        .iter()
        .map(|p| {
            let dir = p.dir.strip_suffix("/cdylib").unwrap_or_else(|| panic!("{}: not <adapter>/cdylib", p.dir));
            ((p.description)().model_identifier().unwrap().to_string(), workspace_root().join(dir))
        })
        .collect()
}

/// What is wrong with the adapter in `dir` (empty: it runs the shared checks once, on its model).
fn problems(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let lib = code(&std::fs::read_to_string(dir.join("src/lib.rs")).unwrap_or_default());
    let declared = invocations(&lib, "fmi2_export::adapter", "model:");
    if declared.len() != 1 {
        out.push(format!("src/lib.rs invokes fmi2_export::adapter! {} times, expected once", declared.len()));
    }
    for f in rust_files(&dir.join("src")) {
        if code(&std::fs::read_to_string(&f).unwrap()).contains("adapter_tests!") {
            out.push(format!("{}: adapter_tests! belongs in a test target (tests/)", f.display()));
        }
    }
    let mut checked = Vec::new();
    for f in rust_files(&dir.join("tests")) {
        let text = code(&std::fs::read_to_string(&f).unwrap());
        for model in invocations(&text, "fmi2_export::adapter_tests", "model:") {
            checked.push((f.clone(), resolve(&text, &model)));
        }
    }
    match checked.as_slice() {
        [] => out.push("no test invokes fmi2_export::adapter_tests!".into()),
        [(f, model)] => {
            if declared.first() != Some(model) {
                out.push(format!("{}: adapter_tests! on {model}, the library's model is {declared:?}", f.display()));
            }
        }
        more => out.push(format!("adapter_tests! invoked {} times, expected once: {more:?}", more.len())),
    }
    out
}

#[test]
fn every_adapter_runs_the_shared_checks_once() {
    let adapters = adapters();
    assert_eq!(adapters.len(), PRODUCTS.len());
    let mut failures = Vec::new();
    for (id, dir) in &adapters {
        for p in problems(dir) {
            failures.push(format!("{id} ({}): {p}", dir.display()));
        }
    }
    assert!(failures.is_empty(), "adapters without the shared checks:\n{}", failures.join("\n"));
    println!("{} adapters run fmi2_export::adapter_tests!", adapters.len());
}

#[test]
fn every_fmu_folder_is_the_adapter_of_a_product() {
    let products: Vec<PathBuf> = adapters().into_iter().map(|(_, d)| d).collect();
    let mut folders: Vec<PathBuf> = std::fs::read_dir(workspace_root())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap().to_string_lossy().starts_with("fmu-") && p.join("Cargo.toml").is_file())
        .collect();
    folders.sort();
    let unshipped: Vec<&PathBuf> = folders.iter().filter(|f| !products.contains(f)).collect();
    assert!(unshipped.is_empty(), "fmu-* folders that are no product of PRODUCTS: {unshipped:?}");
    assert_eq!(folders.len(), products.len(), "{folders:?}");
}

/// The scan itself: an invocation that is commented out, missing, doubled or on another model
/// is reported.
#[test]
fn the_scan_reports_what_it_must() {
    let dir = tempfile::tempdir().unwrap();
    let lib = "fmi2_export::adapter! {\n    model: Plant,\n    table: TABLE as Table<P, I, O>,\n}\n";
    let ok = "type M = Plant;\nfmi2_export::adapter_tests! {\n    model: M,\n}\n";
    std::fs::create_dir_all(dir.path().join("src")).unwrap();
    std::fs::create_dir_all(dir.path().join("tests")).unwrap();
    std::fs::write(dir.path().join("src/lib.rs"), lib).unwrap();
    let with_tests = |text: &str| {
        std::fs::write(dir.path().join("tests/a.rs"), text).unwrap();
        problems(dir.path())
    };
    assert_eq!(with_tests(ok), Vec::<String>::new());
    let commented = ok.replace("fmi2_export::adapter_tests!", "// fmi2_export::adapter_tests!");
    assert!(with_tests(&commented)[0].contains("no test invokes"));
    assert!(with_tests(&format!("{ok}{ok}"))[0].contains("invoked 2 times"));
    assert!(with_tests(&ok.replace("= Plant", "= Other"))[0].contains("adapter_tests! on Other"));
    std::fs::write(dir.path().join("src/lib.rs"), format!("{lib}{ok}")).unwrap();
    assert!(with_tests(ok)[0].contains("belongs in a test target"));
}
