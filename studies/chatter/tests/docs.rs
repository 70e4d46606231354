//! The docs book's CLI reference (`docs/book/cli.md`) names every command of `chatter` and of
//! `cosim`, as the binaries' own help lists them (clap's "Commands:" sections, followed into
//! every subcommand that has subcommands of its own). A command is named when the reference
//! holds its full path in code, e.g. `` `chatter plan main-job` ``.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The workspace root: the nearest folder above this package that holds the docs book.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .find(|d| d.join("docs/book/cli.md").is_file())
        .expect("docs/book/cli.md above this package")
        .to_path_buf()
}

/// The subcommands in a clap help text (the names under "Commands:", without `help`).
fn subcommands(help: &str) -> Vec<String> {
    help.lines()
        .skip_while(|l| l.trim() != "Commands:")
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_string)
        .collect()
}

/// Every command path of `program` (`["plan"]`, `["plan", "main-job"]`, …), from its help.
fn command_tree(program: &Path, prefix: &[String]) -> Vec<Vec<String>> {
    let out = Command::new(program).args(prefix).arg("--help").output().expect("running the binary");
    assert!(out.status.success(), "{} {prefix:?} --help failed", program.display());
    let mut paths = Vec::new();
    for name in subcommands(&String::from_utf8_lossy(&out.stdout)) {
        let mut path = prefix.to_vec();
        path.push(name);
        paths.extend(command_tree(program, &path));
        paths.push(path);
    }
    paths
}

/// The commands of `program` (shown as `shown`) that the CLI reference does not name.
fn missing_from_reference(program: &Path, shown: &str) -> Vec<String> {
    let reference = std::fs::read_to_string(root().join("docs/book/cli.md")).unwrap();
    let tree = command_tree(program, &[]);
    assert!(tree.len() >= 4, "{shown}: the help lists only {tree:?}");
    tree.into_iter()
        .map(|path| format!("`{shown} {}`", path.join(" ")))
        .filter(|name| !reference.contains(name.as_str()))
        .collect()
}

#[test]
fn every_chatter_command_is_in_the_cli_reference() {
    let missing = missing_from_reference(Path::new(env!("CARGO_BIN_EXE_chatter")), "chatter");
    assert!(missing.is_empty(), "docs/book/cli.md lacks {}", missing.join(", "));
}

/// The newest modification time of the files under `dir`.
fn newest(dir: &Path) -> std::time::SystemTime {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            if e.file_type().unwrap().is_dir() { newest(&e.path()) } else { e.metadata().unwrap().modified().unwrap() }
        })
        .max()
        .unwrap_or(std::time::UNIX_EPOCH)
}

#[test]
fn every_cosim_command_is_in_the_cli_reference() {
    // `cosim` is fmi-master's binary: cargo builds it beside `chatter` for fmi-master's own tests
    // (`cargo test --workspace`), but not for this package's, so it must be there and current.
    let bin = Path::new(env!("CARGO_BIN_EXE_chatter")).with_file_name(format!("cosim{}", std::env::consts::EXE_SUFFIX));
    let build = "cargo build --release -p fmi-master --bin cosim (or cargo test --workspace --release)";
    let built = std::fs::metadata(&bin)
        .and_then(|m| m.modified())
        .unwrap_or_else(|_| panic!("{} is missing: {build}", bin.display()));
    assert!(
        built >= newest(&root().join("fmi/fmi-master/src")),
        "{} is older than its sources: {build}",
        bin.display()
    );
    let missing = missing_from_reference(&bin, "cosim");
    assert!(missing.is_empty(), "docs/book/cli.md lacks {}", missing.join(", "));
}

#[test]
fn subcommands_are_read_from_the_commands_section() {
    let help = "About\n\nUsage: x <COMMAND>\n\nCommands:\n  run   Run it\n  plan  Plan\n  help  Print\n\nOptions:\n  -h, --help\n";
    assert_eq!(subcommands(help), ["run", "plan"]);
}

/// The crate doc of the `chatter` binary (`src/main.rs`) names every top-level command.
#[test]
fn the_crate_doc_names_every_chatter_command() {
    let doc: String = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/main.rs"))
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("//!"))
        .collect::<Vec<_>>()
        .join("\n");
    let tree = command_tree(Path::new(env!("CARGO_BIN_EXE_chatter")), &[]);
    let missing: Vec<String> = tree
        .iter()
        .filter(|p| p.len() == 1)
        .map(|p| format!("`chatter {}`", p[0]))
        .filter(|name| !doc.contains(name.as_str()))
        .collect();
    assert!(missing.is_empty(), "studies/chatter/src/main.rs's doc lacks {}", missing.join(", "));
}
