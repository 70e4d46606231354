//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The workspace root.
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The project's Python venv (created by `tests/run_all.sh`, or `FMI_MASTER_VENV`).
pub fn venv() -> PathBuf {
    let v = std::env::var_os("FMI_MASTER_VENV").map(PathBuf::from).unwrap_or_else(|| workspace_root().join(".venv"));
    assert!(
        v.join("bin/python").exists(),
        "the Python venv {} is missing: create it with `python3 -m venv .venv && .venv/bin/pip install -r tests/python/requirements.txt` \
         (tests/run_all.sh does this)",
        v.display()
    );
    v
}

/// The project's packaged FMUs (the fixtures of these tests): where they are, and one of them.
#[allow(unused_imports)] // not every test file uses both
pub use packaging::{fmu_dir, packaged};

/// The cosim binary built by cargo for this test run.
pub fn cosim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_cosim"))
}

/// Path of the shared libpython of the venv's interpreter (pythonfmu FMUs need it preloaded).
pub fn libpython() -> PathBuf {
    let out = Command::new(venv().join("bin/python"))
        .args([
            "-c",
            "import sysconfig, os; print(os.path.join(sysconfig.get_config_var('LIBDIR'), sysconfig.get_config_var('INSTSONAME')))",
        ])
        .output()
        .expect("running the venv's python");
    assert!(out.status.success(), "python failed: {}", String::from_utf8_lossy(&out.stderr));
    let p = PathBuf::from(String::from_utf8(out.stdout).unwrap().trim());
    assert!(p.exists(), "libpython {} does not exist (Python built without --enable-shared?)", p.display());
    p
}

/// Build the third-party test FMU `fixtures/pythonfmu/<name>.py` with the PyPI
/// package `pythonfmu` (`pythonfmu build -f`), into `dir`; returns the `.fmu`.
pub fn build_pythonfmu(name: &str, dir: &Path) -> PathBuf {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/pythonfmu").join(format!("{name}.py"));
    let out = Command::new(venv().join("bin/pythonfmu"))
        .args(["build", "-f"])
        .arg(&script)
        .arg("-d")
        .arg(dir)
        .output()
        .expect("running pythonfmu (pip install pythonfmu into the venv)");
    assert!(
        out.status.success(),
        "pythonfmu build failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let fmu = dir.join(format!("{name}.fmu"));
    assert!(fmu.exists(), "pythonfmu did not write {}", fmu.display());
    fmu
}

/// Rewrite a zip archive, transforming entries: `f(name, data)` returns the
/// new content, or `None` to drop the entry.
pub fn rewrite_zip(src: &Path, dst: &Path, f: impl Fn(&str, Vec<u8>) -> Option<Vec<u8>>) {
    use std::io::{Read, Write};
    let mut zin = zip::ZipArchive::new(std::fs::File::open(src).unwrap()).unwrap();
    let mut zout = zip::ZipWriter::new(std::fs::File::create(dst).unwrap());
    for i in 0..zin.len() {
        let mut e = zin.by_index(i).unwrap();
        let name = e.name().to_string();
        let mut data = Vec::new();
        e.read_to_end(&mut data).unwrap();
        if let Some(data) = f(&name, data) {
            let opts = zip::write::SimpleFileOptions::default().unix_permissions(e.unix_mode().unwrap_or(0o644));
            zout.start_file(name.as_str(), opts).unwrap();
            zout.write_all(&data).unwrap();
        }
    }
    zout.finish().unwrap();
}

/// Run a command, return (success, stdout, stderr).
pub fn run(cmd: &mut Command) -> (bool, String, String) {
    let out = cmd.output().expect("spawning the command");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
