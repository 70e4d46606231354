//! Safe extraction of `.fmu` and `.ssp` archives.
//!
//! Every entry is checked **before anything is written**: an archive with one
//! bad entry extracts nothing. Rejected: absolute paths (`/x`, `\x`, `C:x`),
//! any `..` component, NUL bytes, symbolic links, and archives whose declared
//! uncompressed size exceeds [`MAX_TOTAL_BYTES`] (zip bombs). Backslashes are
//! treated as separators, as some Windows tools write them.

use crate::error::FmuError;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// Upper bound of the total uncompressed size of an archive we extract.
pub const MAX_TOTAL_BYTES: u64 = 8 << 30;
/// Upper bound of the number of entries.
pub const MAX_ENTRIES: usize = 100_000;

/// Check one entry name; return the relative path it extracts to.
pub fn safe_entry_path(name: &str) -> Result<PathBuf, &'static str> {
    if name.contains('\0') {
        return Err("NUL byte in the name");
    }
    let unified = name.replace('\\', "/");
    if unified.starts_with('/') {
        return Err("absolute path");
    }
    let b = unified.as_bytes();
    if b.len() >= 2 && b[0].is_ascii_alphabetic() && b[1] == b':' {
        return Err("absolute path with a drive letter");
    }
    let mut out = PathBuf::new();
    for part in unified.split('/') {
        match part {
            "" | "." => {}
            ".." => return Err("'..' component escapes the extraction directory"),
            p => out.push(p),
        }
    }
    // Belt and braces: the result must be a plain relative path.
    if out.components().any(|c| !matches!(c, Component::Normal(_))) {
        return Err("not a plain relative path");
    }
    Ok(out)
}

fn is_symlink(mode: Option<u32>) -> bool {
    mode.is_some_and(|m| m & 0o170000 == 0o120000)
}

/// Extract `archive` into the existing directory `dest`.
pub fn extract(archive: &Path, dest: &Path) -> Result<(), FmuError> {
    let file = std::fs::File::open(archive).map_err(|source| FmuError::Io {
        context: "cannot open",
        path: archive.to_path_buf(),
        source,
    })?;
    let mut zip = zip::ZipArchive::new(file)
        .map_err(|e| FmuError::Archive { path: archive.to_path_buf(), reason: e.to_string() })?;
    if zip.len() > MAX_ENTRIES {
        return Err(FmuError::Archive {
            path: archive.to_path_buf(),
            reason: format!("{} entries (more than {MAX_ENTRIES})", zip.len()),
        });
    }
    // Pass 1: validate every entry.
    let mut plan = Vec::with_capacity(zip.len());
    let mut total: u64 = 0;
    for i in 0..zip.len() {
        let f = zip
            .by_index_raw(i)
            .map_err(|e| FmuError::Archive { path: archive.to_path_buf(), reason: e.to_string() })?;
        let name = f.name().to_string();
        let rel = safe_entry_path(&name).map_err(|reason| FmuError::UnsafeEntry {
            path: archive.to_path_buf(),
            entry: name.clone(),
            reason,
        })?;
        if is_symlink(f.unix_mode()) {
            return Err(FmuError::UnsafeEntry { path: archive.to_path_buf(), entry: name, reason: "symbolic link" });
        }
        total = total.saturating_add(f.size());
        if total > MAX_TOTAL_BYTES {
            return Err(FmuError::Archive {
                path: archive.to_path_buf(),
                reason: format!("uncompressed size exceeds {MAX_TOTAL_BYTES} bytes"),
            });
        }
        plan.push((rel, f.is_dir() || name.ends_with('/') || name.ends_with('\\'), f.size()));
    }
    // Pass 2: extract.
    let io = |context: &'static str, path: &Path| {
        let path = path.to_path_buf();
        move |source| FmuError::Io { context, path, source }
    };
    for (i, (rel, is_dir, size)) in plan.into_iter().enumerate() {
        let target = dest.join(&rel);
        if is_dir {
            std::fs::create_dir_all(&target).map_err(io("cannot create directory", &target))?;
            continue;
        }
        if let Some(parent) = target.parent() {
            std::fs::create_dir_all(parent).map_err(io("cannot create directory", parent))?;
        }
        let mut f =
            zip.by_index(i).map_err(|e| FmuError::Archive { path: archive.to_path_buf(), reason: e.to_string() })?;
        let mut out = std::fs::File::create(&target).map_err(io("cannot create", &target))?;
        // Never write more than the declared size (a lying header cannot inflate us).
        let copied = std::io::copy(&mut (&mut f).take(size), &mut out).map_err(io("cannot extract to", &target))?;
        if copied != size {
            return Err(FmuError::Archive {
                path: archive.to_path_buf(),
                reason: format!("entry {} is truncated ({copied} of {size} bytes)", rel.display()),
            });
        }
        #[cfg(unix)]
        if let Some(mode) = f.unix_mode() {
            use std::os::unix::fs::PermissionsExt;
            let _ = std::fs::set_permissions(&target, std::fs::Permissions::from_mode(mode & 0o755));
        }
    }
    Ok(())
}

/// Read one entry of a zip archive into memory (e.g. `SystemStructure.ssd`).
pub fn read_entry(archive: &Path, entry: &str) -> Result<Option<Vec<u8>>, FmuError> {
    let file = std::fs::File::open(archive).map_err(|source| FmuError::Io {
        context: "cannot open",
        path: archive.to_path_buf(),
        source,
    })?;
    let mut zip = zip::ZipArchive::new(file)
        .map_err(|e| FmuError::Archive { path: archive.to_path_buf(), reason: e.to_string() })?;
    let mut f = match zip.by_name(entry) {
        Ok(f) => f,
        Err(zip::result::ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(FmuError::Archive { path: archive.to_path_buf(), reason: e.to_string() }),
    };
    let mut buf = Vec::new();
    (&mut f).take(MAX_TOTAL_BYTES).read_to_end(&mut buf).map_err(|source| FmuError::Io {
        context: "cannot read from",
        path: archive.to_path_buf(),
        source,
    })?;
    Ok(Some(buf))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn zip_with(entries: &[(&str, &[u8])]) -> tempfile::NamedTempFile {
        let tmp = tempfile::NamedTempFile::new().unwrap();
        let mut z = zip::ZipWriter::new(tmp.reopen().unwrap());
        let opts = zip::write::SimpleFileOptions::default();
        for (name, data) in entries {
            z.start_file(*name, opts).unwrap();
            z.write_all(data).unwrap();
        }
        z.finish().unwrap();
        tmp
    }

    #[test]
    fn entry_names_are_checked() {
        assert_eq!(safe_entry_path("a/b/c.txt").unwrap(), PathBuf::from("a/b/c.txt"));
        assert_eq!(safe_entry_path("./a//b").unwrap(), PathBuf::from("a/b"));
        assert_eq!(safe_entry_path("a\\b").unwrap(), PathBuf::from("a/b"));
        assert!(safe_entry_path("../evil").is_err());
        assert!(safe_entry_path("a/../../evil").is_err());
        assert!(safe_entry_path("a\\..\\evil").is_err());
        assert!(safe_entry_path("/etc/passwd").is_err());
        assert!(safe_entry_path("\\windows\\x").is_err());
        assert!(safe_entry_path("C:evil").is_err());
        assert!(safe_entry_path("a\0b").is_err());
        // A name that merely contains dots is fine.
        assert!(safe_entry_path("a/..b/c..").is_ok());
    }

    #[test]
    fn parent_dir_entry_is_rejected_and_nothing_is_written() {
        let z = zip_with(&[("modelDescription.xml", b"<x/>"), ("../escaped.txt", b"pwned")]);
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("inner");
        std::fs::create_dir(&dest).unwrap();
        let err = extract(z.path(), &dest).unwrap_err();
        let msg = err.to_string();
        assert!(matches!(err, FmuError::UnsafeEntry { .. }), "{msg}");
        assert!(msg.contains("../escaped.txt") && msg.contains(".."), "{msg}");
        assert!(!root.path().join("escaped.txt").exists());
        // Validation precedes extraction: the good entry was not written either.
        assert!(!dest.join("modelDescription.xml").exists());
    }

    #[test]
    fn absolute_entry_is_rejected() {
        let z = zip_with(&[("/tmp/fmi-master-absolute-test.txt", b"x")]);
        let dest = tempfile::tempdir().unwrap();
        let err = extract(z.path(), dest.path()).unwrap_err();
        assert!(err.to_string().contains("absolute path"), "{err}");
        assert!(!Path::new("/tmp/fmi-master-absolute-test.txt").exists());
    }

    #[test]
    fn symlink_entry_is_rejected() {
        let tmp = tempfile::NamedTempFile::new().unwrap();
        let mut z = zip::ZipWriter::new(tmp.reopen().unwrap());
        z.add_symlink("resources/link", "/etc/passwd", zip::write::SimpleFileOptions::default()).unwrap();
        z.finish().unwrap();
        let dest = tempfile::tempdir().unwrap();
        let err = extract(tmp.path(), dest.path()).unwrap_err();
        assert!(err.to_string().contains("symbolic link"), "{err}");
        assert!(!dest.path().join("resources/link").exists());
    }

    #[test]
    fn good_archive_extracts() {
        let z = zip_with(&[("a/b.txt", b"hello"), ("c.txt", b"")]);
        let dest = tempfile::tempdir().unwrap();
        extract(z.path(), dest.path()).unwrap();
        assert_eq!(std::fs::read(dest.path().join("a/b.txt")).unwrap(), b"hello");
        assert!(dest.path().join("c.txt").exists());
        assert_eq!(read_entry(z.path(), "a/b.txt").unwrap().unwrap(), b"hello");
        assert!(read_entry(z.path(), "nope").unwrap().is_none());
    }

    #[test]
    fn not_a_zip_is_a_clear_error() {
        let mut f = tempfile::NamedTempFile::new().unwrap();
        f.write_all(b"this is not a zip file").unwrap();
        let dest = tempfile::tempdir().unwrap();
        let err = extract(f.path(), dest.path()).unwrap_err();
        assert!(err.to_string().contains("not a valid zip archive"), "{err}");
    }
}
