//! Helpers shared by the artifact tests.
#![allow(dead_code, missing_docs)]

use packaging::{fmu_dir, workspace_root};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Extract `binaries/<folder>/<id>.<ext>` of `<fmu_dir>/<id>.fmu` into `tmp/<folder>/`; `None`
/// when the FMU has no binary for that platform.
///
/// # Panics
/// When the FMU is missing (build it with `cargo run --release -p packaging`).
pub fn packaged_binary(id: &str, folder: &str, tmp: &Path) -> Option<PathBuf> {
    let fmu = fmu_dir().join(format!("{id}.fmu"));
    let f = std::fs::File::open(&fmu)
        .unwrap_or_else(|e| panic!("{}: {e} (run `cargo run --release -p packaging`)", fmu.display()));
    let mut z = zip::ZipArchive::new(f).unwrap();
    let ext = match folder {
        f if f.starts_with("win") => "dll",
        f if f.starts_with("darwin") => "dylib",
        _ => "so",
    };
    let name = format!("binaries/{folder}/{id}.{ext}");
    let mut entry = z.by_name(&name).ok()?;
    let dir = tmp.join(folder);
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join(format!("{id}.{ext}"));
    let mut file = std::fs::File::create(&out).unwrap();
    std::io::copy(&mut entry, &mut file).unwrap();
    Some(out)
}

/// The platforms `FMU_PLATFORMS` requires (the README test command sets it): a check of a
/// required platform fails instead of skipping.
pub fn required(platform: &str) -> bool {
    std::env::var("FMU_PLATFORMS").unwrap_or_default().split(',').any(|p| p.trim() == platform)
}

/// Directory of the official FMI 2.0 headers inside the `fmi-sys` package
/// (a never-built dependency of this crate, fetched by cargo).
pub fn official_headers() -> PathBuf {
    let out = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .args(["metadata", "--format-version", "1"])
        .current_dir(workspace_root())
        .output()
        .expect("cargo metadata");
    assert!(out.status.success(), "cargo metadata failed: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    // the package entry (`"name":"fmi-sys","version":…`), not a dependency entry of a package
    // that uses it (`"name":"fmi-sys","source":…`, e.g. the `fmi` importer's)
    let pos = text.find("\"name\":\"fmi-sys\",\"version\"").expect("fmi-sys in cargo metadata");
    let tail = &text[pos..];
    let key = "\"manifest_path\":\"";
    let start = tail.find(key).unwrap() + key.len();
    let manifest = &tail[start..start + tail[start..].find('"').unwrap()];
    let dir = Path::new(manifest).parent().unwrap().join("fmi-standard2").join("headers");
    assert!(dir.join("fmi2Functions.h").exists(), "no FMI 2.0 headers in {}", dir.display());
    dir
}
