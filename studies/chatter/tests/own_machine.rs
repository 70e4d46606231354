//! Your own machine from the command line: the README's quick start, run as written (with a
//! shorter speed grid and a smaller swarm, so that the test takes seconds), and bad machine
//! files refused with one line, exit 1 and nothing written.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap().to_path_buf()
}

fn binary(name: &str) -> PathBuf {
    if name == "chatter" {
        return PathBuf::from(env!("CARGO_BIN_EXE_chatter"));
    }
    let bin =
        Path::new(env!("CARGO_BIN_EXE_chatter")).with_file_name(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(bin.is_file(), "{} is missing: cargo build --release -p fmi-master --bin {name}", bin.display());
    bin
}

/// The shell commands of the README's "Quick start: your own machine" block (continuation
/// lines joined, comments dropped).
fn quick_start() -> Vec<Vec<String>> {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let section = readme.split("## Quick start: your own machine").nth(1).expect("the quick start section");
    let block = section.split("```sh").nth(1).unwrap().split("```").next().unwrap();
    let mut cmds = Vec::new();
    let mut cur = String::new();
    for line in block.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#')) {
        cur.push_str(line.trim_end_matches('\\'));
        cur.push(' ');
        if !line.ends_with('\\') {
            cmds.push(cur.split_whitespace().map(String::from).collect());
            cur.clear();
        }
    }
    cmds
}

#[test]
fn the_readme_quick_start_runs() {
    let out = tempfile::tempdir().unwrap();
    let cmds = quick_start();
    assert!(cmds.len() >= 5, "{cmds:?}");
    for cmd in cmds {
        let program = cmd[0].rsplit('/').next().unwrap().to_string();
        let mut args: Vec<String> = cmd[1..].to_vec();
        // outputs into the test's folder (the README writes them into the working directory)
        for i in 0..args.len() {
            if args[i] == "--out" || args[i] == "-o" {
                args[i + 1] = out.path().join(&args[i + 1]).display().to_string();
            } else if args[i].ends_with(".ssp") && args[i].starts_with("my-") {
                args[i] = out.path().join(&args[i]).display().to_string();
            }
        }
        // seconds, not minutes: fewer speeds, a small swarm
        match (program.as_str(), args.first().map(String::as_str)) {
            ("chatter", Some("lobes")) => args.extend(["--points", "12"].map(String::from)),
            ("chatter", Some("tune")) => args.extend(
                ["--structures", "pid", "--runs", "1", "--particles", "8", "--iterations", "4", "--quiet"]
                    .map(String::from),
            ),
            _ => {}
        }
        let o = Command::new(binary(&program)).args(&args).current_dir(root()).output().unwrap();
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(o.status.success(), "{program} {args:?}: {}\n{stdout}", String::from_utf8_lossy(&o.stderr));
        if args.first().map(String::as_str) == Some("lobes") {
            assert_eq!(stdout.matches(": confirmed").count(), 2, "{stdout}");
            assert!(!stdout.contains("NOT CONFIRMED"), "{stdout}");
        }
    }
    for f in ["my-lobes/lobes.csv", "my-lobes/lobes.png", "my-gains/tuned_pid.ssv", "my-machine.ssp", "my-machine.csv"]
    {
        assert!(out.path().join(f).is_file(), "{f} missing");
    }
}

#[test]
fn a_bad_machine_file_is_refused_with_one_line_and_nothing_written() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(root().join("studies/machine/examples/end_mill.toml")).unwrap();
    let cases = [
        (good.replace("feed_per_tooth = \"0.05 mm\"\n", ""), "operation.feed_per_tooth: missing"),
        (good.replace("kr_ratio", "kr_ratoi"), "material.kr_ratoi: unknown key; did you mean `kr_ratio`?"),
        (
            good.replace("\"12 mm\"", "\"12 kg\""),
            "tool.diameter: \"12 kg\" is a mass, but the tool diameter is a length",
        ),
        (good.replace("\"800 N/mm^2\"", "800"), "did you mean \"800 N/mm^2\""),
        (
            good.replace("damping = 0.02", "damping = 0"),
            "structure.x[1].damping: a damping ratio = 0 must be positive (physical range [1e-4, 0.5])",
        ),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let file = dir.path().join(format!("bad{i}.toml"));
        std::fs::write(&file, text).unwrap();
        let out = dir.path().join(format!("out{i}"));
        let o = Command::new(binary("chatter"))
            .args(["lobes", "--machine", file.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{want}: {err}");
        assert!(err.contains(want) && err.trim().lines().count() == 1, "want {want:?}: {err}");
        assert!(o.stdout.is_empty() && !out.exists(), "{want}: something was written");
    }
}
