//! The documentation's maps stay true to the workspace:
//!
//! * the README is a front door of at most [`README_MAX_LINES`] lines;
//! * the architecture chapter's layer table lists, per layer, exactly the workspace members that
//!   `[workspace.metadata.layers]` puts there, and its crate and FMU tables name every member
//!   exactly once, each crate with its folder and layer (from `cargo metadata --no-deps`);
//! * the README, the book's FMU index and the book's navigation link the page of every FMU that
//!   packaging ships (`packaging::PRODUCTS`).
//!
//! The CLI reference is checked against the `chatter` and `cosim` binaries by
//! `studies/tests/docs.rs`; the FMU pages against their generated text by packaging's tests.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The README's length limit: a front door, the rest is in the book.
const README_MAX_LINES: usize = 300;

/// The book's architecture chapter.
const ARCHITECTURE: &str = "docs/book/architecture.md";

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(root().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// Whether `path` matches a layer pattern of `[workspace.metadata.layers]` (`*` within one
/// path segment).
fn matches(pattern: &str, path: &str) -> bool {
    let (p, s): (Vec<&str>, Vec<&str>) = (pattern.split('/').collect(), path.split('/').collect());
    p.len() == s.len()
        && p.iter().zip(&s).all(|(p, s)| match p.split_once('*') {
            Some((pre, post)) => s.len() >= pre.len() + post.len() && s.starts_with(pre) && s.ends_with(post),
            None => p == s,
        })
}

/// Every workspace member as name → (folder relative to the root, layer). A plain path in the
/// layer table wins over a pattern (as the architecture test reads it).
fn members() -> BTreeMap<String, (String, String)> {
    let out = Command::new(env!("CARGO"))
        .args(["metadata", "--format-version", "1", "--no-deps", "--offline"])
        .current_dir(root())
        .output()
        .expect("cargo metadata");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let layers: Vec<(String, String)> = v["metadata"]["layers"]
        .as_object()
        .expect("[workspace.metadata.layers]")
        .iter()
        .flat_map(|(layer, pats)| {
            pats.as_array().unwrap().iter().map(move |p| (layer.clone(), p.as_str().unwrap().to_string()))
        })
        .collect();
    let root = root().canonicalize().unwrap();
    v["packages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let dir = Path::new(p["manifest_path"].as_str().unwrap()).parent().unwrap();
            let rel = dir.strip_prefix(&root).unwrap().to_string_lossy().replace('\\', "/");
            let exact = layers.iter().find(|(_, pat)| *pat == rel);
            let layer = exact
                .or_else(|| layers.iter().find(|(_, pat)| matches(pat, &rel)))
                .map(|(l, _)| l.clone())
                .unwrap_or_else(|| panic!("{rel} is in no layer"));
            (p["name"].as_str().unwrap().to_string(), (rel, layer))
        })
        .collect()
}

/// The Markdown tables of `text`: (header cells, rows of cells).
fn tables(text: &str) -> Vec<(Vec<String>, Vec<Vec<String>>)> {
    let cells = |l: &str| -> Vec<String> {
        l.trim().trim_start_matches('|').trim_end_matches('|').split(" | ").map(|c| c.trim().to_string()).collect()
    };
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i + 1 < lines.len() {
        if lines[i].starts_with('|') && lines[i + 1].starts_with("|---") {
            let header = cells(lines[i]);
            let mut rows = Vec::new();
            i += 2;
            while i < lines.len() && lines[i].starts_with('|') {
                rows.push(cells(lines[i]));
                i += 1;
            }
            out.push((header, rows));
        } else {
            i += 1;
        }
    }
    out
}

/// The `code` spans of a table cell (`` `a`, `b` `` → a, b).
fn code_spans(cell: &str) -> Vec<String> {
    cell.split('`').skip(1).step_by(2).map(str::to_string).collect()
}

/// The column `name` of the table whose header has it.
fn column(header: &[String], name: &str) -> Option<usize> {
    header.iter().position(|h| h == name)
}

#[test]
fn the_readme_is_a_front_door_of_at_most_300_lines() {
    let n = read("README.md").lines().count();
    assert!(
        n <= README_MAX_LINES,
        "README.md has {n} lines (at most {README_MAX_LINES}): move the details into docs/book"
    );
}

#[test]
fn the_layer_table_lists_every_member_of_every_layer() {
    let members = members();
    let doc = read(ARCHITECTURE);
    let (header, rows) = tables(&doc)
        .into_iter()
        .find(|(h, _)| h.first().map(String::as_str) == Some("layer") && column(h, "crates").is_some())
        .expect("the layer table (| layer | crates | …) in the architecture chapter");
    let c = column(&header, "crates").unwrap();
    let listed: BTreeMap<String, BTreeSet<String>> =
        rows.iter().map(|r| (r[0].clone(), code_spans(&r[c]).into_iter().collect())).collect();
    let mut by_layer: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (name, (_, layer)) in &members {
        by_layer.entry(layer.clone()).or_default().insert(name.clone());
    }
    let mut wrong = Vec::new();
    for (layer, crates) in &by_layer {
        match listed.get(layer) {
            None => wrong.push(format!("layer {layer} has no row")),
            Some(l) if l != crates => wrong.push(format!(
                "layer {layer}: missing {:?}, not members of it {:?}",
                crates.difference(l).collect::<Vec<_>>(),
                l.difference(crates).collect::<Vec<_>>()
            )),
            Some(_) => {}
        }
    }
    for layer in listed.keys().filter(|l| !by_layer.contains_key(*l)) {
        wrong.push(format!("row for layer {layer}, which has no member"));
    }
    assert!(wrong.is_empty(), "{ARCHITECTURE}, layer table:\n{}", wrong.join("\n"));
}

#[test]
fn the_crate_tables_name_every_member_once_with_its_folder_and_layer() {
    let members = members();
    let doc = read(ARCHITECTURE);
    let mut named: BTreeMap<String, usize> = BTreeMap::new();
    let mut wrong = Vec::new();
    for (header, rows) in tables(&doc) {
        if let (Some(c), Some(f), Some(l)) =
            (column(&header, "crate"), column(&header, "folder"), column(&header, "layer"))
        {
            for r in &rows {
                let name = code_spans(&r[c]).concat();
                *named.entry(name.clone()).or_default() += 1;
                let folder = code_spans(&r[f]).concat();
                match members.get(&name) {
                    None => wrong.push(format!("`{name}` is not a workspace member")),
                    Some((dir, layer)) => {
                        if *dir != folder {
                            wrong.push(format!("`{name}` is in `{dir}`, the table says `{folder}`"));
                        }
                        if *layer != r[l] {
                            wrong.push(format!("`{name}` is in layer {layer}, the table says {}", r[l]));
                        }
                    }
                }
            }
        }
        for (col, layer) in [("adapter crate", "adapter"), ("cdylib crate", "cdylib")] {
            let Some(c) = column(&header, col) else { continue };
            for r in &rows {
                let name = code_spans(&r[c]).concat();
                *named.entry(name.clone()).or_default() += 1;
                match members.get(&name) {
                    Some((_, l)) if l == layer => {}
                    Some((_, l)) => wrong.push(format!("`{name}` is in layer {l}, listed as {col}")),
                    None => wrong.push(format!("`{name}` is not a workspace member")),
                }
            }
        }
    }
    for name in members.keys() {
        match named.get(name) {
            None => wrong.push(format!("`{name}` is in no crate table")),
            Some(1) => {}
            Some(n) => wrong.push(format!("`{name}` is named {n} times")),
        }
    }
    assert!(wrong.is_empty(), "{ARCHITECTURE}, crate tables:\n{}", wrong.join("\n"));
}

#[test]
fn the_readme_the_fmu_index_and_the_book_link_every_shipped_fmu() {
    let (readme, index, nav) = (read("README.md"), read("docs/book/fmus/index.md"), read("docs/mkdocs.yml"));
    let mut missing = Vec::new();
    for p in &packaging::PRODUCTS {
        let id = (p.description)().model_identifier().unwrap();
        for (file, text, link) in [
            ("README.md", &readme, format!("(docs/book/fmus/{id}.md)")),
            ("docs/book/fmus/index.md", &index, format!("({id}.md)")),
            ("docs/mkdocs.yml", &nav, format!(": fmus/{id}.md\n")),
        ] {
            if !text.contains(&link) {
                missing.push(format!("{file} does not link {id}'s page ({link})"));
            }
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

#[test]
fn layer_patterns_match_one_segment_per_star() {
    assert!(matches("cores/*", "cores/milling-plant"));
    assert!(matches("fmu-*", "fmu-plant") && !matches("fmu-*", "fmu-plant/cdylib"));
    assert!(matches("fmu-*/cdylib", "fmu-plant/cdylib") && !matches("cores/*", "fuzz"));
    assert_eq!(code_spans("`a`, `b` and c"), ["a", "b"]);
}
