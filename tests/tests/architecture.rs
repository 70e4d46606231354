//! The workspace's shape, as tests (see `ARCHITECTURE.md`).
//!
//! * Every member belongs to one layer of `[workspace.metadata.layers]` in the root
//!   `Cargo.toml`, and depends only on the layers [`ALLOWED`] lists for it: the physics and
//!   control cores know nothing of FMI, the generic master nothing of the models.
//! * No crate has a cycle among its modules (`use crate::a` in `b` and `use crate::b` in `a`).
//! * No source file is longer than [`MAX_LINES`] unless [`LONG_FILES`] says why.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Which layers a layer's crates may depend on (their own layer included explicitly).
const ALLOWED: &[(&str, &[&str])] = &[
    ("kit", &[]),
    ("core", &["kit", "core"]),
    ("schema", &["schema"]),
    ("abi", &[]),
    ("export", &["abi", "schema", "kit"]),
    ("adapter", &["export", "schema", "core", "kit"]),
    ("cdylib", &["export", "adapter"]),
    ("master", &["abi", "schema"]),
    ("packaging", &["adapter", "export", "schema", "core", "kit"]),
    ("studies", &["master", "packaging", "adapter", "export", "schema", "core", "kit"]),
    ("python", &["studies", "master", "schema"]),
    ("tests", &["studies", "master", "packaging", "adapter", "export", "abi", "schema", "core", "kit"]),
];

/// Crates that must not depend, even for their tests, on any of these.
const FMI_CRATES: &[&str] = &["fmi2-export", "fmi2-abi", "model-description", "fmi-master"];

/// Longest source file allowed without a reason.
const MAX_LINES: usize = 600;

/// Files allowed to be longer, with the reason (one algorithm, or a table).
const LONG_FILES: &[(&str, &str)] = &[
    (
        "fmi2-export/src/ffi.rs",
        "the C boundary: every unsafe block of the export side, one `with` pattern per fmi2 function",
    ),
    ("fmi2-export/src/instance.rs", "one algorithm: the FMI 2.0 state machine and its variable rules"),
    ("studies/src/lobes.rs", "one algorithm: the exact zero-order lobe solver with its tests"),
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

struct Member {
    name: String,
    dir: PathBuf,
    /// (dependency name, kind: "normal" | "dev" | "build")
    deps: Vec<(String, String)>,
}

fn members() -> Vec<Member> {
    let out = Command::new(env!("CARGO"))
        .args(["metadata", "--format-version", "1", "--no-deps", "--offline"])
        .current_dir(root())
        .output()
        .expect("cargo metadata");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    v["packages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| Member {
            name: p["name"].as_str().unwrap().to_string(),
            dir: PathBuf::from(p["manifest_path"].as_str().unwrap()).parent().unwrap().to_path_buf(),
            deps: p["dependencies"]
                .as_array()
                .unwrap()
                .iter()
                .map(|d| (d["name"].as_str().unwrap().to_string(), d["kind"].as_str().unwrap_or("normal").to_string()))
                .collect(),
        })
        .collect()
}

fn layers() -> BTreeMap<String, String> {
    let text = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let mut map = BTreeMap::new();
    let mut inside = false;
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            inside = line == "[workspace.metadata.layers]";
            continue;
        }
        if !inside || line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (layer, list) = line.split_once('=').expect("layer = [\"crate\", ...]");
        for name in list.trim().trim_start_matches('[').trim_end_matches(']').split(',') {
            let name = name.trim().trim_matches('"');
            if !name.is_empty() {
                assert!(map.insert(name.to_string(), layer.trim().to_string()).is_none(), "{name} is in two layers");
            }
        }
    }
    map
}

#[test]
fn every_crate_depends_only_on_the_layers_below_it() {
    let layers = layers();
    let members = members();
    let names: BTreeSet<&str> = members.iter().map(|m| m.name.as_str()).collect();
    let mut problems = Vec::new();
    for m in &members {
        let Some(layer) = layers.get(&m.name) else {
            problems.push(format!("{} is in no layer of [workspace.metadata.layers]", m.name));
            continue;
        };
        let allowed = ALLOWED.iter().find(|(l, _)| l == layer).unwrap_or_else(|| panic!("unknown layer {layer}")).1;
        for (dep, kind) in &m.deps {
            if !names.contains(dep.as_str()) {
                continue; // external crate
            }
            let dep_layer = &layers[dep];
            if kind == "normal" && !allowed.contains(&dep_layer.as_str()) {
                problems.push(format!("{} ({layer}) depends on {dep} ({dep_layer})", m.name));
            }
            if matches!(layer.as_str(), "core" | "kit") && FMI_CRATES.contains(&dep.as_str()) {
                problems.push(format!("core crate {} depends on the FMI crate {dep} ({kind})", m.name));
            }
            if layer == "master" && matches!(dep_layer.as_str(), "core" | "adapter" | "cdylib") {
                problems.push(format!("the generic master depends on the model crate {dep} ({kind})"));
            }
        }
    }
    for name in layers.keys() {
        if !names.contains(name.as_str()) {
            problems.push(format!("[workspace.metadata.layers] lists {name}, which is not a member"));
        }
    }
    assert!(problems.is_empty(), "{problems:#?}");
}

/// The rule itself can fail: a core crate with an FMI dependency is reported.
#[test]
fn the_layer_rule_catches_a_core_that_uses_fmi() {
    let layers = layers();
    assert_eq!(layers.get("milling-plant").map(String::as_str), Some("core"));
    assert_eq!(layers.get("fmi2-export").map(String::as_str), Some("export"));
    let core_allowed = ALLOWED.iter().find(|(l, _)| *l == "core").unwrap().1;
    assert!(
        !core_allowed.contains(&"export") && !core_allowed.contains(&"schema") && !core_allowed.contains(&"master")
    );
    let master_allowed = ALLOWED.iter().find(|(l, _)| *l == "master").unwrap().1;
    assert!(!master_allowed.contains(&"core") && !master_allowed.contains(&"adapter"));
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n != "target") {
                rust_files(&p, out);
            }
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Top-level module of a file under `src/` (`src/a/b.rs` and `src/a.rs` → `a`; the crate root → None).
fn top_module(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).ok()?;
    let first = rel.components().next()?.as_os_str().to_str()?.to_string();
    let m = first.trim_end_matches(".rs").to_string();
    (!matches!(m.as_str(), "lib" | "main" | "bin")).then_some(m)
}

/// Top-level modules `text` refers to with `crate::NAME`.
fn crate_refs(text: &str) -> BTreeSet<String> {
    let mut refs = BTreeSet::new();
    let code: String = text.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n");
    let mut rest = code.as_str();
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + 7..];
        let name: String = after.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        if !name.is_empty() {
            refs.insert(name);
        }
        // `use crate::{a, b::c}`
        if let Some(group) = after.strip_prefix('{') {
            let group: String = group.chars().take_while(|c| *c != '}').collect();
            for part in group.split(',') {
                let name: String = part.trim().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                if !name.is_empty() {
                    refs.insert(name);
                }
            }
        }
        rest = after;
    }
    refs
}

fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        g: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_string(), 1);
        path.push(n.to_string());
        for m in g.get(n).into_iter().flatten() {
            match state.get(m.as_str()).copied().unwrap_or(0) {
                1 => {
                    let start = path.iter().position(|p| p == m).unwrap();
                    let mut c = path[start..].to_vec();
                    c.push(m.clone());
                    return Some(c);
                }
                0 => {
                    if let Some(c) = visit(m, g, state, path) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        path.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in graph.keys() {
        if state.get(n.as_str()).copied().unwrap_or(0) == 0
            && let Some(c) = visit(n, graph, &mut state, &mut Vec::new())
        {
            return Some(c);
        }
    }
    None
}

#[test]
fn no_crate_has_an_import_cycle_between_its_modules() {
    let mut problems = Vec::new();
    for m in members() {
        let src = m.dir.join("src");
        if !src.is_dir() {
            continue;
        }
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        let modules: BTreeSet<String> = files.iter().filter_map(|f| top_module(&src, f)).collect();
        let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for f in &files {
            let Some(from) = top_module(&src, f) else { continue };
            let text = std::fs::read_to_string(f).unwrap();
            let deps = graph.entry(from.clone()).or_default();
            for to in crate_refs(&text) {
                if to != from && modules.contains(&to) {
                    deps.insert(to);
                }
            }
        }
        if let Some(cycle) = find_cycle(&graph) {
            problems.push(format!("{}: {}", m.name, cycle.join(" → ")));
        }
    }
    assert!(problems.is_empty(), "import cycles: {problems:#?}");
}

#[test]
fn the_cycle_finder_finds_a_cycle() {
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    g.entry("error".into()).or_default().insert("ssp".into());
    g.entry("ssp".into()).or_default().insert("unzip".into());
    g.entry("unzip".into()).or_default().insert("error".into());
    assert_eq!(find_cycle(&g).unwrap(), ["error", "ssp", "unzip", "error"]);
    assert_eq!(
        crate_refs("use crate::{a, b::c};\nfn f() { crate::d::x(); }"),
        ["a", "b", "d"].map(String::from).into()
    );
    g.get_mut("unzip").unwrap().clear();
    assert!(find_cycle(&g).is_none());
}

#[test]
fn no_source_file_is_longer_than_the_limit_without_a_reason() {
    let mut long = Vec::new();
    for m in members() {
        let mut files = Vec::new();
        rust_files(&m.dir, &mut files);
        for f in files {
            let rel = f.strip_prefix(root()).unwrap().to_string_lossy().to_string();
            let n = std::fs::read_to_string(&f).unwrap().lines().count();
            if n > MAX_LINES && !LONG_FILES.iter().any(|(p, _)| *p == rel) {
                long.push(format!("{rel}: {n} lines"));
            }
        }
    }
    assert!(long.is_empty(), "files over {MAX_LINES} lines (split them or add a reason to LONG_FILES): {long:#?}");
}
