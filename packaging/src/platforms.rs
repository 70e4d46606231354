//! # The platforms of the FMUs' binaries, and how each is built
//!
//! One FMU (one `modelDescription.xml`, one GUID) carries a binary per platform under
//! `binaries/<platform>/`. Packaging builds every platform whose toolchain is on this machine
//! with the `fmu-symbols` profile (release code with line tables, which [`split_debug`] moves
//! into a separate debug file before the binary is shipped):
//!
//! | FMI folder | Rust target | built by | needs |
//! |---|---|---|---|
//! | `linux64` | `x86_64-unknown-linux-gnu.2.17` | `cargo zigbuild` | `cargo-zigbuild` + `ziglang` (PyPI) |
//! | `linux64` (only with `FMU_PLATFORMS=linux64`) | the host | `cargo build` | — (binary needs this machine's glibc) |
//! | `win64` | `x86_64-pc-windows-gnu` | `cargo build` | `rustup target add x86_64-pc-windows-gnu`, `x86_64-w64-mingw32-gcc` (Debian `gcc-mingw-w64-x86-64`) |
//! | `darwin64` (only when `FMU_PLATFORMS` names it) | `universal2-apple-darwin` (x86_64 + arm64 in one Mach-O) | `cargo zigbuild` | `cargo-zigbuild` + `ziglang`, `rustup target add x86_64-apple-darwin aarch64-apple-darwin` |
//!
//! The portable linux64 build links against glibc 2.17's symbol versions (zig ships the
//! version scripts), so the binary loads on every distribution from RHEL/CentOS 7 on. It is
//! always built: without cargo-zigbuild packaging installs it (and ziglang) into `.venv` from
//! PyPI, and stops with what to do when it cannot (issue 31: the README's first command on a
//! fresh machine gave a binary needing GLIBC 2.33–2.35). `FMU_PLATFORMS=linux64` asks for the
//! host build instead (the binary then needs the build machine's glibc). A platform whose
//! toolchain is missing is skipped with the reason printed, unless `FMU_PLATFORMS` names it:
//! `FMU_PLATFORMS=linux64-portable,win64` (the README test command sets it) makes a missing
//! toolchain an error instead of a quieter FMU.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The rustc target of the portable linux64 build (glibc 2.17 symbol versions, by zig).
pub const LINUX_PORTABLE_TARGET: &str = "x86_64-unknown-linux-gnu.2.17";
/// The cargo-zigbuild target of the darwin64 build (a universal x86_64 + arm64 dylib).
pub const DARWIN_TARGET: &str = "universal2-apple-darwin";
/// The cargo profile of the darwin64 build: no debug info in the dylib (Mach-O has no
/// `.gnu_debuglink`; a dSYM bundle would be the separate-symbols route).
pub const DARWIN_PROFILE: &str = "fmu-release";
/// The rustc target of the win64 build.
pub const WINDOWS_TARGET: &str = "x86_64-pc-windows-gnu";
/// The cargo profile of the FMU binaries (see the workspace `Cargo.toml`): release code with
/// line tables, which [`split_debug`] moves into a separate debug file.
pub const PROFILE: &str = "fmu-symbols";

/// How one platform's binaries were built.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Build {
    /// linux64 against glibc 2.17 with `cargo zigbuild`.
    LinuxPortable,
    /// linux64 for this machine's glibc only (no `cargo-zigbuild`).
    LinuxHost,
    /// win64 with mingw-w64.
    Windows,
    /// darwin64: x86_64 + aarch64 universal dylib with `cargo zigbuild` (built here, run only
    /// on a Mac).
    Darwin,
}

impl Build {
    /// The FMI platform folder under `binaries/`.
    pub fn folder(&self) -> &'static str {
        match self {
            Build::LinuxPortable | Build::LinuxHost => "linux64",
            Build::Windows => "win64",
            Build::Darwin => "darwin64",
        }
    }

    /// The name `FMU_PLATFORMS` uses for this build.
    pub fn name(&self) -> &'static str {
        match self {
            Build::LinuxPortable => "linux64-portable",
            Build::LinuxHost => "linux64",
            Build::Windows => "win64",
            Build::Darwin => "darwin64",
        }
    }

    /// The file name of the binary of `identifier` on this platform.
    pub fn file_name(&self, identifier: &str) -> String {
        match self {
            Build::LinuxPortable | Build::LinuxHost => format!("{identifier}.so"),
            Build::Windows => format!("{identifier}.dll"),
            Build::Darwin => format!("{identifier}.dylib"),
        }
    }

    /// Where cargo writes the library of `identifier` (under `target`).
    pub fn artifact(&self, target: &Path, identifier: &str) -> PathBuf {
        match self {
            Build::LinuxPortable => {
                target.join("x86_64-unknown-linux-gnu").join(PROFILE).join(format!("lib{identifier}.so"))
            }
            Build::LinuxHost => target.join(PROFILE).join(format!("lib{identifier}.so")),
            Build::Windows => target.join(WINDOWS_TARGET).join(PROFILE).join(format!("{identifier}.dll")),
            Build::Darwin => target.join(DARWIN_TARGET).join(DARWIN_PROFILE).join(format!("lib{identifier}.dylib")),
        }
    }
}

/// The `objcopy` that reads and writes this platform's binaries (GNU binutils: ELF for linux64,
/// PE for win64, whose mingw-w64 binutils come with the mingw-w64 compiler).
pub fn objcopy(build: &Build) -> Option<&'static str> {
    match build {
        Build::LinuxPortable | Build::LinuxHost => Some("objcopy"),
        Build::Windows => Some("x86_64-w64-mingw32-objcopy"),
        Build::Darwin => None,
    }
}

/// The separate debug file of `identifier` on `build`'s platform, under `debug_dir`
/// (`<identifier>.<folder>.debug`, the name the shipped binary's `.gnu_debuglink` holds).
pub fn debug_file(build: &Build, debug_dir: &Path, identifier: &str) -> PathBuf {
    debug_dir.join(format!("{identifier}.{}.debug", build.folder()))
}

/// The binary that goes into the FMU: the cargo artifact without its debug info (under
/// `<target>/fmu-shipped/<folder>/`; cargo's own file is left as it is, so a later build that
/// cargo finds fresh is split again from the full file).
pub fn shipped(build: &Build, target: &Path, identifier: &str) -> PathBuf {
    if *build == Build::Darwin {
        return build.artifact(target, identifier);
    }
    target.join("fmu-shipped").join(build.folder()).join(build.file_name(identifier))
}

fn objcopy_run(tool: &str, args: &[&std::ffi::OsStr]) -> Result<()> {
    let out = Command::new(tool).args(args).output().with_context(|| {
        format!("running {tool} (GNU binutils; for win64 the mingw-w64 binutils) to split the debug info")
    })?;
    if !out.status.success() {
        bail!("{tool} {args:?} failed: {}", String::from_utf8_lossy(&out.stderr).trim());
    }
    Ok(())
}

/// Split the debug info of `identifier`'s library on `build`'s platform: `objcopy
/// --only-keep-debug` writes [`debug_file`], then the shipped copy ([`shipped`]) loses the debug
/// sections (linux64: `--strip-unneeded`, only the dynamic symbols stay, as before; win64:
/// `--strip-debug`) and gains a `.gnu_debuglink` to the debug file (its name and CRC), where gdb,
/// `addr2line` and perf find it (next to the binary or in a debug directory). Returns the
/// shipped binary. darwin64 is built without debug info and shipped as built.
pub fn split_debug(build: &Build, target: &Path, debug_dir: &Path, identifier: &str) -> Result<PathBuf> {
    let Some(tool) = objcopy(build) else { return Ok(shipped(build, target, identifier)) };
    let full = build.artifact(target, identifier);
    let debug = debug_file(build, debug_dir, identifier);
    let out = shipped(build, target, identifier);
    for d in [debug_dir, out.parent().expect("a folder")] {
        std::fs::create_dir_all(d).with_context(|| format!("creating {}", d.display()))?;
    }
    objcopy_run(tool, &["--only-keep-debug".as_ref(), full.as_os_str(), debug.as_os_str()])?;
    let strip = match build {
        Build::LinuxPortable | Build::LinuxHost => "--strip-unneeded",
        Build::Windows | Build::Darwin => "--strip-debug",
    };
    let link = format!("--add-gnu-debuglink={}", debug.display());
    objcopy_run(tool, &[strip.as_ref(), link.as_ref(), full.as_os_str(), out.as_os_str()])?;
    Ok(out)
}

/// What packaging found it can build, and why it skips the rest.
#[derive(Debug, Default)]
pub struct Plan {
    /// The builds to run.
    pub builds: Vec<Build>,
    /// Skipped platforms with the reason and the remedy.
    pub skipped: Vec<(&'static str, String)>,
}

fn runs(program: &Path, args: &[&str]) -> bool {
    Command::new(program).args(args).output().map(|o| o.status.success()).unwrap_or(false)
}

/// `name` on `PATH`, or in the workspace's `.venv/bin` (where the test command installs the
/// PyPI tools).
pub fn find_tool(name: &str, venv: &Path) -> Option<PathBuf> {
    let in_venv = venv.join("bin").join(name);
    if in_venv.is_file() {
        return Some(in_venv);
    }
    std::env::var_os("PATH")
        .into_iter()
        .flat_map(|p| std::env::split_paths(&p).collect::<Vec<_>>())
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// The PyPI packages of the portable linux64 build, as `tests/python/requirements.txt` pins them.
pub const ZIGBUILD_PACKAGES: [&str; 2] = ["cargo-zigbuild==0.24.*", "ziglang==0.17.*"];

/// Install cargo-zigbuild and ziglang into `venv` (created with `python3 -m venv` if missing);
/// an error that says what to do when that is not possible.
fn setup_zigbuild(venv: &Path) -> Result<()> {
    eprintln!(
        "packaging: cargo-zigbuild not found; installing {} into {} for the portable linux64 binary (glibc >= 2.17)",
        ZIGBUILD_PACKAGES.join(" "),
        venv.display()
    );
    let python = venv.join("bin").join("python");
    let ok = |c: &mut Command| c.status().is_ok_and(|s| s.success());
    let made = python.is_file() || ok(Command::new("python3").args(["-m", "venv"]).arg(venv));
    let installed = made
        && ok(Command::new(&python)
            .args(["-m", "pip", "install", "--quiet", "--disable-pip-version-check"])
            .args(ZIGBUILD_PACKAGES));
    if !installed {
        bail!(
            "the portable linux64 FMU binaries (glibc >= 2.17) need cargo-zigbuild and ziglang, which could not be \
             installed into {} (python3 with venv and pip, and PyPI, are needed): install them yourself \
             (`pip install {}`), or build binaries for this machine's glibc only with FMU_PLATFORMS=linux64",
            venv.display(),
            ZIGBUILD_PACKAGES.join(" ")
        );
    }
    Ok(())
}

fn rust_target_installed(rustc: &str, target: &str) -> bool {
    let out = Command::new(rustc).args(["--print", "target-libdir", "--target", target]).output();
    match out {
        Ok(o) if o.status.success() => Path::new(String::from_utf8_lossy(&o.stdout).trim()).is_dir(),
        _ => false,
    }
}

/// The builds this machine can do; `FMU_PLATFORMS` (comma-separated build names) lists the ones
/// that must not be skipped.
pub fn plan(venv: &Path) -> Result<Plan> {
    let required: Vec<String> = std::env::var("FMU_PLATFORMS")
        .unwrap_or_default()
        .split(',')
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .collect();
    for r in &required {
        if !["linux64-portable", "linux64", "win64", "darwin64"].contains(&r.as_str()) {
            bail!("FMU_PLATFORMS: unknown platform {r:?} (known: linux64-portable, linux64, win64, darwin64)");
        }
    }
    let mut plan = Plan::default();
    let zig_ok = || find_tool("cargo-zigbuild", venv).is_some_and(|z| runs(&z, &["--version"]));
    // The portable linux64 binary is what the README promises: without cargo-zigbuild, set it
    // up in the venv (PyPI), unless FMU_PLATFORMS asks for this machine's glibc only (linux64).
    let host_only = required.iter().any(|r| r == "linux64") && !required.iter().any(|r| r == "linux64-portable");
    if !host_only && !zig_ok() {
        setup_zigbuild(venv)?;
    }
    if zig_ok() && !host_only {
        plan.builds.push(Build::LinuxPortable);
    } else {
        plan.builds.push(Build::LinuxHost);
        plan.skipped.push((
            "linux64-portable",
            "FMU_PLATFORMS=linux64: the linux64 binary needs this machine's glibc (the default builds one \
             that loads on glibc >= 2.17, with cargo-zigbuild)"
                .into(),
        ));
    }
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let mingw = find_tool("x86_64-w64-mingw32-gcc", venv).is_some();
    let std_ok = rust_target_installed(&rustc, WINDOWS_TARGET);
    if mingw && std_ok {
        plan.builds.push(Build::Windows);
    } else {
        let mut why = Vec::new();
        if !std_ok {
            why.push("rustup target add x86_64-pc-windows-gnu");
        }
        if !mingw {
            why.push("apt install gcc-mingw-w64-x86-64");
        }
        plan.skipped.push(("win64", format!("no win64 toolchain ({})", why.join("; "))));
    }
    // darwin64 only on request: nothing here can run the dylibs, and the two Apple targets
    // are an extra toolchain download
    if required.iter().any(|r| r == "darwin64") {
        let targets = ["x86_64-apple-darwin", "aarch64-apple-darwin"];
        let missing: Vec<&str> = targets.into_iter().filter(|t| !rust_target_installed(&rustc, t)).collect();
        if zig_ok() && missing.is_empty() {
            plan.builds.push(Build::Darwin);
        } else {
            let mut why = Vec::new();
            if !zig_ok() {
                why.push("pip install cargo-zigbuild ziglang".to_string());
            }
            if !missing.is_empty() {
                why.push(format!("rustup target add {}", missing.join(" ")));
            }
            plan.skipped.push(("darwin64", format!("no darwin64 toolchain ({})", why.join("; "))));
        }
    }
    let missing: Vec<String> = plan
        .skipped
        .iter()
        .filter(|(name, _)| required.iter().any(|r| r == name))
        .map(|(name, why)| format!("{name}: {why}"))
        .collect();
    if !missing.is_empty() {
        bail!("FMU_PLATFORMS requires platforms this machine cannot build: {}", missing.join("; "));
    }
    Ok(plan)
}

/// Run one build of the `packages` (cdylib packages) from `root`. darwin64 builds one package
/// per `cargo zigbuild` call: with several packages in one call, cargo-zigbuild 0.24's
/// universal2 step paired the x86_64 and arm64 libraries of different packages (the arm64
/// slice of `ToolXyPlant.dylib` was `SlidingModeFuzzyController`'s, which the darwin64
/// artifact test caught by the slice's install name).
pub fn run(build: &Build, root: &Path, venv: &Path, packages: &[&str]) -> Result<()> {
    if *build == Build::Darwin && packages.len() > 1 {
        return packages.iter().try_for_each(|p| run(build, root, venv, &[p]));
    }
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = match build {
        Build::LinuxPortable | Build::Darwin => {
            let zig = find_tool("cargo-zigbuild", venv).context("cargo-zigbuild vanished")?;
            let mut c = Command::new(zig);
            let t = if *build == Build::Darwin { DARWIN_TARGET } else { LINUX_PORTABLE_TARGET };
            c.args(["zigbuild", "--target", t]);
            // cargo-zigbuild finds zig from the `ziglang` package of the same Python
            if let Some(bin) = zig_python_dir(venv) {
                let path = std::env::var_os("PATH").unwrap_or_default();
                let mut dirs = vec![bin];
                dirs.extend(std::env::split_paths(&path));
                c.env("PATH", std::env::join_paths(dirs).context("PATH")?);
            }
            c
        }
        Build::LinuxHost => {
            let mut c = Command::new(&cargo);
            c.arg("build");
            c
        }
        Build::Windows => {
            let mut c = Command::new(&cargo);
            c.args(["build", "--target", WINDOWS_TARGET]);
            c
        }
    };
    let profile = if *build == Build::Darwin { DARWIN_PROFILE } else { PROFILE };
    cmd.current_dir(root).args(["--profile", profile, "--lib"]);
    for p in packages {
        cmd.args(["-p", p]);
    }
    let status = cmd.status().with_context(|| format!("running the {} build", build.name()))?;
    if !status.success() {
        bail!("the {} build of the FMU cdylibs failed ({status})", build.name());
    }
    Ok(())
}

/// The venv's `bin` folder when it has the `python-zig`/`python` that carries `ziglang`.
fn zig_python_dir(venv: &Path) -> Option<PathBuf> {
    let bin = venv.join("bin");
    bin.join("python").is_file().then_some(bin)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_and_folders_follow_the_fmi_standard() {
        assert_eq!(Build::LinuxPortable.file_name("A"), "A.so");
        assert_eq!(Build::Windows.file_name("A"), "A.dll");
        assert_eq!(Build::LinuxHost.folder(), "linux64");
        assert_eq!(Build::Windows.folder(), "win64");
        let t = Path::new("/t");
        assert_eq!(Build::Windows.artifact(t, "A"), Path::new("/t/x86_64-pc-windows-gnu/fmu-symbols/A.dll"));
        assert_eq!(Build::LinuxPortable.artifact(t, "A"), Path::new("/t/x86_64-unknown-linux-gnu/fmu-symbols/libA.so"));
        assert_eq!(debug_file(&Build::Windows, Path::new("/d"), "A"), Path::new("/d/A.win64.debug"));
        assert_eq!(shipped(&Build::LinuxPortable, t, "A"), Path::new("/t/fmu-shipped/linux64/A.so"));
        assert_eq!(Build::Darwin.folder(), "darwin64");
        assert_eq!(shipped(&Build::Darwin, t, "A"), Path::new("/t/universal2-apple-darwin/fmu-release/libA.dylib"));
    }
}
