//! The FMUs' debug symbols ship separately: every binary inside an FMU carries no debug
//! sections but a `.gnu_debuglink` naming `target/fmu-debug/<id>.<platform>.debug` with that
//! file's CRC-32, and the debug file resolves the address of the binary's `fmi2DoStep` to a
//! Rust source line (`addr2line`), which the shipped binary alone cannot.
//!
//! win64 is checked when the FMUs carry it (required when `FMU_PLATFORMS` names win64).
#![allow(missing_docs)]

mod common;
use common::{packaged_binary, required};
use packaging::{PRODUCTS, debug_dir};
use std::path::Path;
use std::process::Command;

fn ids() -> Vec<String> {
    PRODUCTS.iter().map(|p| (p.description)().model_identifier().unwrap().to_string()).collect()
}

fn output(cmd: &mut Command) -> String {
    let out = cmd.output().unwrap_or_else(|e| panic!("running {cmd:?}: {e}"));
    assert!(out.status.success(), "{cmd:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// CRC-32 (IEEE 802.3, reflected, as `.gnu_debuglink` and zlib use), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 { (crc >> 1) ^ 0xEDB8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

#[test]
fn crc32_of_a_known_string() {
    assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
}

/// The `.gnu_debuglink` of `binary`: the file name and the CRC (NUL-terminated name, padded to
/// 4 bytes, then the little-endian CRC-32 of the debug file).
fn debuglink(objcopy: &str, binary: &Path, tmp: &Path) -> (String, u32) {
    let sect = tmp.join("debuglink.bin");
    output(
        Command::new(objcopy)
            .arg(format!("--dump-section=.gnu_debuglink={}", sect.display()))
            .arg(binary)
            .arg(tmp.join("scratch")),
    );
    let raw = std::fs::read(&sect).unwrap();
    let nul = raw.iter().position(|b| *b == 0).expect("a NUL-terminated name");
    let at = (nul + 1).next_multiple_of(4);
    let crc = u32::from_le_bytes(raw[at..at + 4].try_into().unwrap());
    (String::from_utf8(raw[..nul].to_vec()).unwrap(), crc)
}

/// `addr2line -e file ADDR`: `file:line` or `??:0`.
fn source_line(addr2line: &str, file: &Path, addr: u64) -> String {
    output(Command::new(addr2line).arg("-e").arg(file).arg(format!("{addr:#x}"))).trim().to_string()
}

/// The address of `fmi2DoStep` in `file` as `nm` lists it.
fn do_step_address(nm: &str, args: &[&str], file: &Path) -> u64 {
    let text = output(Command::new(nm).args(args).arg(file));
    let line = text
        .lines()
        .find(|l| l.split_whitespace().last() == Some("fmi2DoStep"))
        .unwrap_or_else(|| panic!("no fmi2DoStep in {}:\n{text:.2000}", file.display()));
    u64::from_str_radix(line.split_whitespace().next().unwrap(), 16).unwrap()
}

fn check(id: &str, folder: &str, binary: &Path, tools: (&str, &str, &str), nm_args: &[&str], tmp: &Path) {
    let (objcopy, nm, addr2line) = tools;
    let (name, crc) = debuglink(objcopy, binary, tmp);
    assert_eq!(name, format!("{id}.{folder}.debug"), "{id} {folder}: the debuglink names the debug file");
    let debug = debug_dir().join(&name);
    let bytes = std::fs::read(&debug).unwrap_or_else(|e| panic!("{}: {e}", debug.display()));
    assert_eq!(crc, crc32(&bytes), "{id} {folder}: the debuglink's CRC is the debug file's");
    let addr = do_step_address(nm, nm_args, binary);
    let resolved = source_line(addr2line, &debug, addr);
    let (file, line) = resolved.rsplit_once(':').unwrap_or(("", ""));
    assert!(
        file.ends_with(".rs") && line.split_whitespace().next().unwrap().parse::<u32>().unwrap_or(0) > 0,
        "{id} {folder}: fmi2DoStep at {addr:#x} resolves to {resolved:?} in {}",
        debug.display()
    );
    // the check can fail: the shipped binary alone has no line tables
    assert!(source_line(addr2line, binary, addr).starts_with("??"), "{id} {folder}: shipped with line tables");
}

#[test]
fn linux64_debug_files_resolve_fmi2dostep_and_the_binaries_link_to_them() {
    let tmp = tempfile::tempdir().unwrap();
    for id in ids() {
        let so = packaged_binary(&id, "linux64", tmp.path()).unwrap();
        check(&id, "linux64", &so, ("objcopy", "nm", "addr2line"), &["-D", "--defined-only"], tmp.path());
    }
}

/// gdb follows the debuglink: with the debug file next to the extracted binary, `info line
/// fmi2DoStep` names a source line (without it, gdb knows only the symbol).
#[test]
fn gdb_finds_the_linux64_debug_file_through_the_debuglink() {
    if Command::new("gdb").arg("--version").output().is_err() {
        eprintln!("skipped: no gdb (apt install gdb); the addr2line checks still ran");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let id = &ids()[0];
    let so = packaged_binary(id, "linux64", tmp.path()).unwrap();
    let info = |so: &Path| output(Command::new("gdb").args(["-nx", "-batch", "-ex", "info line fmi2DoStep"]).arg(so));
    let alone = info(&so);
    assert!(!alone.contains("Line "), "{id}: gdb found line tables without the debug file: {alone}");
    let name = format!("{id}.linux64.debug");
    std::fs::copy(debug_dir().join(&name), so.parent().unwrap().join(&name)).unwrap();
    let with = info(&so);
    assert!(with.contains("Line ") && with.contains("<fmi2DoStep"), "{id}: {with}");
}

#[test]
fn win64_debug_files_resolve_fmi2dostep_and_the_dlls_link_to_them() {
    let tmp = tempfile::tempdir().unwrap();
    let ids = ids();
    if packaged_binary(&ids[0], "win64", tmp.path()).is_none() {
        assert!(!required("win64"), "FMU_PLATFORMS requires win64 but the FMUs carry no win64 binary");
        eprintln!("skipped: the FMUs carry no win64 binaries (no mingw-w64 toolchain when they were packaged)");
        return;
    }
    for id in ids {
        let dll = packaged_binary(&id, "win64", tmp.path()).unwrap();
        let tools = ("x86_64-w64-mingw32-objcopy", "x86_64-w64-mingw32-nm", "x86_64-w64-mingw32-addr2line");
        check(&id, "win64", &dll, tools, &["--defined-only"], tmp.path());
    }
}
