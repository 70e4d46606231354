//! The workspace's shape, as tests (see `ARCHITECTURE.md`).
//!
//! * Every member belongs to exactly one layer of `[workspace.metadata.layers]` in the root
//!   `Cargo.toml` by its folder (`cores/*`, `fmi/fmi2-export`, `fmu-*`, ...), is named as its
//!   folder, and depends only on the layers [`ALLOWED`] lists for it: the physics and control
//!   cores know nothing of FMI, the generic master nothing of the models. Adapter folders are
//!   named for their FMU (`fmu-<modelIdentifier in kebab case>`).
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
    ("studies", &["studies", "master", "packaging", "adapter", "export", "schema", "core", "kit"]),
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
        "fmi/fmi2-export/src/ffi.rs",
        "the C boundary: every unsafe block of the export side, one `with` pattern per fmi2 function",
    ),
    ("fmi/fmi2-export/src/instance.rs", "one algorithm: the FMI 2.0 state machine and its variable rules"),
    ("cores/delay-stability/src/zero_order.rs", "one algorithm: the exact zero-order lobe solver with its tests"),
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// Adapter folders that keep the design card's names instead of `fmu-<modelIdentifier>`.
const DESIGN_CARD_ADAPTERS: &[(&str, &str)] = &[("fmu-plant", "MillingPlant"), ("fmu-controller", "ChatterController")];

/// Members whose package name is not their folder's, with the reason.
const NAME_EXCEPTIONS: &[(&str, &str, &str)] =
    &[("modelDescription", "model-description", "the design card's folder name; Rust crate names are snake_case")];

#[derive(Clone, Debug)]
struct Member {
    name: String,
    /// Folder relative to the workspace root, `/`-separated (`cores/milling-plant`).
    path: String,
    /// (dependency name, kind: "normal" | "dev" | "build")
    deps: Vec<(String, String)>,
    /// The `[lib] name` (for a cdylib: the FMU's modelIdentifier).
    lib: Option<String>,
}

fn members() -> Vec<Member> {
    let out = Command::new(env!("CARGO"))
        .args(["metadata", "--format-version", "1", "--no-deps", "--offline"])
        .current_dir(root())
        .output()
        .expect("cargo metadata");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let root = root().canonicalize().unwrap();
    v["packages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let dir = PathBuf::from(p["manifest_path"].as_str().unwrap()).parent().unwrap().canonicalize().unwrap();
            Member {
                name: p["name"].as_str().unwrap().to_string(),
                path: dir.strip_prefix(&root).unwrap().to_string_lossy().replace('\\', "/"),
                deps: p["dependencies"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|d| {
                        (d["name"].as_str().unwrap().to_string(), d["kind"].as_str().unwrap_or("normal").to_string())
                    })
                    .collect(),
                lib: p["targets"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .find(|t| t["kind"].as_array().unwrap().iter().any(|k| k == "lib" || k == "cdylib"))
                    .map(|t| t["name"].as_str().unwrap().to_string()),
            }
        })
        .collect()
}

/// `[workspace.metadata.layers]` of the root `Cargo.toml`: (folder pattern, layer) in file order.
fn layer_patterns() -> Vec<(String, String)> {
    let text = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let mut out = Vec::new();
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
        let (layer, list) = line.split_once('=').expect("layer = [\"folder pattern\", ...]");
        for pat in list.trim().trim_start_matches('[').trim_end_matches(']').split(',') {
            let pat = pat.trim().trim_matches('"');
            if !pat.is_empty() {
                out.push((pat.to_string(), layer.trim().to_string()));
            }
        }
    }
    out
}

/// Does the folder `path` match `pattern`? `*` stands for one path component or the rest of
/// one (`fmu-*` matches `fmu-plant`, `fmu-*/cdylib` matches `fmu-plant/cdylib`).
fn matches(pattern: &str, path: &str) -> bool {
    let (pp, fp): (Vec<&str>, Vec<&str>) = (pattern.split('/').collect(), path.split('/').collect());
    pp.len() == fp.len()
        && pp.iter().zip(&fp).all(|(p, f)| match p.split_once('*') {
            Some((pre, post)) => f.len() > pre.len() + post.len() && f.starts_with(pre) && f.ends_with(post),
            None => p == f,
        })
}

/// The layer of a folder: the plain path that names it, else the one pattern with a `*` that
/// matches it; `Err` if none or two match.
fn layer_of(path: &str, patterns: &[(String, String)]) -> Result<String, String> {
    let hits: Vec<&(String, String)> = patterns.iter().filter(|(p, _)| matches(p, path)).collect();
    let exact: Vec<_> = hits.iter().filter(|(p, _)| !p.contains('*')).collect();
    let globs: Vec<_> = hits.iter().filter(|(p, _)| p.contains('*')).collect();
    match (exact.as_slice(), globs.as_slice()) {
        ([(_, l)], _) => Ok(l.clone()),
        ([], [(_, l)]) => Ok(l.clone()),
        ([], []) => Err(format!("{path} matches no folder pattern of [workspace.metadata.layers]")),
        _ => Err(format!("{path} matches several folder patterns: {hits:?}")),
    }
}

/// `MillingProcess` → `milling-process`.
fn kebab(identifier: &str) -> String {
    let mut s = String::new();
    for (i, c) in identifier.chars().enumerate() {
        if c.is_uppercase() && i > 0 {
            s.push('-');
        }
        s.extend(c.to_lowercase());
    }
    s
}

/// Every problem of the layout and the layer rules: a member in no layer or in two, a package
/// not named as its folder, an adapter folder not named for its FMU, a dependency on a layer
/// not allowed, a core or kit using an FMI crate, the master using a model crate.
fn layer_problems(members: &[Member], patterns: &[(String, String)]) -> Vec<String> {
    let mut problems = Vec::new();
    let mut layer_of_name = BTreeMap::new();
    for m in members {
        match layer_of(&m.path, patterns) {
            Ok(l) => {
                layer_of_name.insert(m.name.clone(), l);
            }
            Err(e) => problems.push(format!("{}: {e}", m.name)),
        }
        let folder = m.path.rsplit('/').next().unwrap();
        let expected = if folder == "cdylib" {
            format!("{}-cdylib", m.path.split('/').rev().nth(1).unwrap_or(""))
        } else {
            NAME_EXCEPTIONS.iter().find(|(p, ..)| *p == m.path).map_or(folder.to_string(), |(_, n, _)| n.to_string())
        };
        if m.name != expected {
            problems.push(format!(
                "package {} sits in {}: the folder must be named as the package ({expected})",
                m.name, m.path
            ));
        }
        if folder == "cdylib" {
            let adapter = m.path.split('/').rev().nth(1).unwrap_or("");
            let id = m.lib.clone().unwrap_or_default();
            let want = DESIGN_CARD_ADAPTERS
                .iter()
                .find(|(_, i)| *i == id)
                .map_or(format!("fmu-{}", kebab(&id)), |(f, _)| f.to_string());
            if adapter != want {
                problems.push(format!("the adapter of {id}.fmu sits in {adapter}: name it {want}"));
            }
        }
    }
    for m in members {
        let Some(layer) = layer_of_name.get(&m.name) else { continue };
        let allowed = ALLOWED.iter().find(|(l, _)| l == layer).map_or(&[][..], |a| a.1);
        for (dep, kind) in &m.deps {
            let Some(dep_layer) = layer_of_name.get(dep) else { continue }; // external crate
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
    for (layer, _) in ALLOWED {
        if !patterns.iter().any(|(_, l)| l == layer) {
            problems.push(format!("layer {layer} has no folder in [workspace.metadata.layers]"));
        }
    }
    problems
}

#[test]
fn every_member_is_in_one_layer_in_its_folder_and_depends_only_on_the_layers_below_it() {
    let problems = layer_problems(&members(), &layer_patterns());
    assert!(problems.is_empty(), "{problems:#?}");
}

/// The rule itself can fail: the workspace with one bad member added or changed is reported,
/// for each way of breaking it.
#[test]
fn the_layer_rule_catches_a_bad_member() {
    let good = members();
    let patterns = layer_patterns();
    assert!(layer_problems(&good, &patterns).is_empty());
    let with = |f: &dyn Fn(&mut Vec<Member>)| {
        let mut m = good.clone();
        f(&mut m);
        layer_problems(&m, &patterns)
    };
    fn member(m: &[Member], name: &str) -> usize {
        m.iter().position(|x| x.name == name).unwrap()
    }
    type Change = Box<dyn Fn(&mut Vec<Member>)>;
    let cases: [(&str, Change, &str); 6] = [
        (
            "a core that uses the FMI export layer",
            Box::new(|m| {
                let i = member(m, "milling-plant");
                m[i].deps.push(("fmi2-export".into(), "normal".into()));
            }),
            "core crate milling-plant depends on the FMI crate fmi2-export",
        ),
        (
            "a core put into the FMI folder",
            Box::new(|m| {
                let i = member(m, "milling-process");
                m[i].path = "fmi/milling-process".into();
            }),
            "milling-process: fmi/milling-process matches no folder pattern",
        ),
        (
            "a member in no layer",
            Box::new(|m| {
                m.push(Member { name: "scratch".into(), path: "scratch".into(), deps: vec![], lib: None });
            }),
            "scratch: scratch matches no folder pattern",
        ),
        (
            "a package not named as its folder",
            Box::new(|m| {
                let i = member(m, "linear-control");
                m[i].name = "lin-ctrl".into();
            }),
            "package lin-ctrl sits in cores/linear-control",
        ),
        (
            "an adapter folder not named for its FMU",
            Box::new(|m| {
                let i = member(m, "fmu-modal-structure-cdylib");
                m[i].lib = Some("ToolXyPlant".into());
            }),
            "the adapter of ToolXyPlant.fmu sits in fmu-modal-structure: name it fmu-tool-xy-plant",
        ),
        (
            "the master using a model crate",
            Box::new(|m| {
                let i = member(m, "fmi-master");
                m[i].deps.push(("fmu-plant".into(), "dev".into()));
            }),
            "the generic master depends on the model crate fmu-plant",
        ),
    ];
    for (what, change, expect) in cases {
        let problems = with(&*change);
        assert!(problems.iter().any(|p| p.contains(expect)), "{what}: {problems:#?}");
    }
    assert!(matches("fmu-*/cdylib", "fmu-plant/cdylib") && !matches("fmu-*", "fmu-plant/cdylib"));
    assert_eq!(kebab("SlidingModeFuzzyController"), "sliding-mode-fuzzy-controller");
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
        let src = root().join(&m.path).join("src");
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
        rust_files(&root().join(&m.path), &mut files);
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
