//! Safe extraction and size-capped reads of zip archives.
//!
//! [`extract_with`] works in two passes: it first checks every entry's name,
//! type and declared sizes against the [`Limits`], and only then writes
//! anything. While writing, no entry produces more bytes than it declared,
//! so the declared sizes checked in the first pass bound what reaches the disk.

use crate::entry_path::safe_entry_path;
use crate::error::ArchiveError;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Bounds on what [`extract_with`] accepts (see [`Limits::DEFAULT`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Largest number of entries.
    pub max_entries: usize,
    /// Largest uncompressed size of one entry [bytes].
    pub max_entry_bytes: u64,
    /// Largest total uncompressed size [bytes].
    pub max_total_bytes: u64,
    /// Largest compression ratio (uncompressed / compressed size), checked
    /// for each entry and for the whole archive once they reach `ratio_floor_bytes`.
    pub max_ratio: u64,
    /// Sizes below this are not ratio-checked (small files of zeros are harmless).
    pub ratio_floor_bytes: u64,
}

impl Limits {
    /// 100 000 entries, 512 MiB per entry, 1 GiB in total, and a compression
    /// ratio of at most 100 for anything of 1 MiB or more (deflate reaches
    /// about 1000 on runs of zeros; binaries and XML stay well under 30).
    pub const DEFAULT: Limits = Limits {
        max_entries: 100_000,
        max_entry_bytes: 512 << 20,
        max_total_bytes: 1 << 30,
        max_ratio: 100,
        ratio_floor_bytes: 1 << 20,
    };
}

impl Default for Limits {
    fn default() -> Self {
        Limits::DEFAULT
    }
}

fn is_symlink(mode: Option<u32>) -> bool {
    mode.is_some_and(|m| m & 0o170000 == 0o120000)
}

fn open_zip(archive: &Path) -> Result<zip::ZipArchive<std::fs::File>, ArchiveError> {
    let file = std::fs::File::open(archive).map_err(|error| ArchiveError::Io {
        context: "cannot open",
        path: archive.to_path_buf(),
        error,
    })?;
    zip::ZipArchive::new(file).map_err(|e| ArchiveError::NotZip { path: archive.to_path_buf(), reason: e.to_string() })
}

/// One entry as planned by the first pass.
struct Planned {
    rel: PathBuf,
    is_dir: bool,
    size: u64,
    mode: Option<u32>,
}

/// `size` exceeds `max_ratio` times `compressed` (and the floor)?
fn ratio_exceeded(size: u64, compressed: u64, l: &Limits) -> bool {
    size >= l.ratio_floor_bytes && size / compressed.max(1) > l.max_ratio
}

/// First pass: check every entry against the name rules and the limits.
fn plan(zip: &mut zip::ZipArchive<std::fs::File>, archive: &Path, l: &Limits) -> Result<Vec<Planned>, ArchiveError> {
    let limit = |message: String| ArchiveError::Limit { path: archive.to_path_buf(), message };
    if zip.len() > l.max_entries {
        return Err(limit(format!("{} entries (at most {} allowed)", zip.len(), l.max_entries)));
    }
    let mut planned = Vec::with_capacity(zip.len());
    let (mut total, mut total_compressed) = (0u64, 0u64);
    for i in 0..zip.len() {
        let f = zip
            .by_index_raw(i)
            .map_err(|e| ArchiveError::NotZip { path: archive.to_path_buf(), reason: e.to_string() })?;
        let name = f.name().to_string();
        let unsafe_entry =
            |reason| ArchiveError::UnsafeEntry { path: archive.to_path_buf(), entry: name.clone(), reason };
        let rel = safe_entry_path(&name).map_err(unsafe_entry)?;
        if is_symlink(f.unix_mode()) {
            return Err(unsafe_entry("symbolic link"));
        }
        let (size, compressed) = (f.size(), f.compressed_size());
        if size > l.max_entry_bytes {
            return Err(limit(format!(
                "entry '{name}' is {size} bytes uncompressed (at most {} bytes per entry)",
                l.max_entry_bytes
            )));
        }
        if ratio_exceeded(size, compressed, l) {
            return Err(limit(format!(
                "entry '{name}' expands from {compressed} to {size} bytes, a compression ratio above {} (a zip bomb?)",
                l.max_ratio
            )));
        }
        total = total.saturating_add(size);
        total_compressed = total_compressed.saturating_add(compressed);
        if total > l.max_total_bytes {
            return Err(limit(format!("the entries add up to more than {} bytes uncompressed", l.max_total_bytes)));
        }
        let is_dir = f.is_dir() || name.ends_with('/') || name.ends_with('\\');
        planned.push(Planned { rel, is_dir, size, mode: f.unix_mode() });
    }
    if ratio_exceeded(total, total_compressed, l) {
        return Err(limit(format!(
            "its entries expand from {total_compressed} to {total} bytes, a compression ratio above {} (a zip bomb?)",
            l.max_ratio
        )));
    }
    Ok(planned)
}

/// Extract `archive` into the existing directory `dest` with the default [`Limits`].
pub fn extract(archive: &Path, dest: &Path) -> Result<(), ArchiveError> {
    extract_with(archive, dest, &Limits::DEFAULT)
}

/// Extract `archive` into the existing directory `dest`; nothing is written
/// unless every entry passes the checks (see the crate documentation).
pub fn extract_with(archive: &Path, dest: &Path, limits: &Limits) -> Result<(), ArchiveError> {
    let mut zip = open_zip(archive)?;
    let planned = plan(&mut zip, archive, limits)?;
    let io = |context: &'static str, path: &Path| {
        let path = path.to_path_buf();
        move |error| ArchiveError::Io { context, path, error }
    };
    for (i, p) in planned.into_iter().enumerate() {
        let target = dest.join(&p.rel);
        if p.is_dir {
            std::fs::create_dir_all(&target).map_err(io("cannot create directory", &target))?;
            continue;
        }
        if let Some(parent) = target.parent() {
            std::fs::create_dir_all(parent).map_err(io("cannot create directory", parent))?;
        }
        let mut f =
            zip.by_index(i).map_err(|e| ArchiveError::NotZip { path: archive.to_path_buf(), reason: e.to_string() })?;
        let mut out = std::fs::File::create(&target).map_err(io("cannot create", &target))?;
        // Never write more than the declared size (a lying header cannot inflate us).
        let got = std::io::copy(&mut (&mut f).take(p.size), &mut out).map_err(io("cannot extract to", &target))?;
        if got != p.size {
            return Err(ArchiveError::Truncated {
                path: archive.to_path_buf(),
                entry: p.rel.display().to_string(),
                got,
                size: p.size,
            });
        }
        #[cfg(unix)]
        if let Some(mode) = p.mode {
            use std::os::unix::fs::PermissionsExt;
            let _ = std::fs::set_permissions(&target, std::fs::Permissions::from_mode(mode & 0o755));
        }
    }
    Ok(())
}

/// Read one entry of a zip archive into memory, refusing entries larger than
/// `max_bytes`; `Ok(None)` if there is no such entry.
pub fn read_entry(archive: &Path, entry: &str, max_bytes: u64) -> Result<Option<Vec<u8>>, ArchiveError> {
    let mut zip = open_zip(archive)?;
    let mut f = match zip.by_name(entry) {
        Ok(f) => f,
        Err(zip::result::ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(ArchiveError::NotZip { path: archive.to_path_buf(), reason: e.to_string() }),
    };
    let too_large =
        |size| ArchiveError::TooLarge { path: archive.to_path_buf(), what: entry.to_string(), size, max: max_bytes };
    if f.size() > max_bytes {
        return Err(too_large(f.size()));
    }
    let mut buf = Vec::new();
    (&mut f).take(max_bytes.saturating_add(1)).read_to_end(&mut buf).map_err(|error| ArchiveError::Io {
        context: "cannot read from",
        path: archive.to_path_buf(),
        error,
    })?;
    if buf.len() as u64 > max_bytes {
        return Err(too_large(buf.len() as u64));
    }
    Ok(Some(buf))
}

/// Read a file (e.g. one already extracted), refusing files larger than `max_bytes`.
pub fn read_file_capped(path: &Path, max_bytes: u64) -> Result<Vec<u8>, ArchiveError> {
    let io = |error| ArchiveError::Io { context: "cannot read", path: path.to_path_buf(), error };
    let f = std::fs::File::open(path).map_err(io)?;
    let too_large =
        |size| ArchiveError::TooLarge { path: path.to_path_buf(), what: "the file".into(), size, max: max_bytes };
    let len = f.metadata().map_err(io)?.len();
    if len > max_bytes {
        return Err(too_large(len));
    }
    let mut buf = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
    f.take(max_bytes.saturating_add(1)).read_to_end(&mut buf).map_err(io)?;
    if buf.len() as u64 > max_bytes {
        return Err(too_large(buf.len() as u64));
    }
    Ok(buf)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn zip_with(entries: &[(&str, &[u8])]) -> tempfile::NamedTempFile {
        let tmp = tempfile::NamedTempFile::new().unwrap();
        let mut z = zip::ZipWriter::new(tmp.reopen().unwrap());
        let opts = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
        for (name, data) in entries {
            z.start_file(*name, opts).unwrap();
            z.write_all(data).unwrap();
        }
        z.finish().unwrap();
        tmp
    }

    fn is_empty(dir: &Path) -> bool {
        std::fs::read_dir(dir).unwrap().next().is_none()
    }

    #[test]
    fn parent_dir_entry_is_rejected_and_nothing_is_written() {
        let z = zip_with(&[("modelDescription.xml", b"<x/>"), ("../escaped.txt", b"pwned")]);
        let root = tempfile::tempdir().unwrap();
        let dest = root.path().join("inner");
        std::fs::create_dir(&dest).unwrap();
        let err = extract(z.path(), &dest).unwrap_err();
        let msg = err.to_string();
        assert!(matches!(err, ArchiveError::UnsafeEntry { .. }), "{msg}");
        assert!(msg.contains("unsafe entry '../escaped.txt'") && msg.contains("'..' component"), "{msg}");
        assert!(!root.path().join("escaped.txt").exists());
        // Validation precedes extraction: the good entry was not written either.
        assert!(is_empty(&dest));
    }

    #[test]
    fn absolute_entry_is_rejected() {
        let z = zip_with(&[("/tmp/fmi-archive-absolute-test.txt", b"x")]);
        let dest = tempfile::tempdir().unwrap();
        let err = extract(z.path(), dest.path()).unwrap_err();
        assert!(err.to_string().contains("absolute path"), "{err}");
        assert!(!Path::new("/tmp/fmi-archive-absolute-test.txt").exists());
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
        assert_eq!(read_entry(z.path(), "a/b.txt", 5).unwrap().unwrap(), b"hello");
        assert!(read_entry(z.path(), "nope", 5).unwrap().is_none());
    }

    #[test]
    fn not_a_zip_is_a_clear_error() {
        let mut f = tempfile::NamedTempFile::new().unwrap();
        f.write_all(b"this is not a zip file").unwrap();
        let dest = tempfile::tempdir().unwrap();
        let err = extract(f.path(), dest.path()).unwrap_err();
        assert!(err.to_string().contains("not a valid zip archive"), "{err}");
    }

    /// Regression (hardening issue): one 8 MiB entry of zeros deflates to a few
    /// KiB (ratio ≈ 1000). The old extractor (8 GiB total, no ratio check) wrote it.
    #[test]
    fn a_highly_compressed_entry_is_refused_as_a_zip_bomb() {
        let zeros = vec![0u8; 8 << 20];
        let z = zip_with(&[("modelDescription.xml", b"<x/>"), ("resources/bomb.bin", &zeros)]);
        let dest = tempfile::tempdir().unwrap();
        let err = extract(z.path(), dest.path()).unwrap_err();
        let msg = err.to_string();
        assert!(matches!(err, ArchiveError::Limit { .. }), "{msg}");
        assert!(msg.contains("entry 'resources/bomb.bin' expands from") && msg.contains("zip bomb"), "{msg}");
        assert!(is_empty(dest.path()));
    }

    /// Many small entries below the per-entry floor still add up: the whole
    /// archive's ratio is checked too.
    #[test]
    fn many_small_compressible_entries_are_refused_together() {
        let zeros = vec![0u8; 512 << 10];
        let names: Vec<String> = (0..8).map(|i| format!("resources/part{i}.bin")).collect();
        let entries: Vec<(&str, &[u8])> = names.iter().map(|n| (n.as_str(), zeros.as_slice())).collect();
        let z = zip_with(&entries);
        let dest = tempfile::tempdir().unwrap();
        let err = extract(z.path(), dest.path()).unwrap_err();
        assert!(err.to_string().contains("its entries expand from"), "{err}");
        assert!(is_empty(dest.path()));
    }

    #[test]
    fn entry_and_total_sizes_are_limited() {
        let data: Vec<u8> = (0..3000u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 24) as u8).collect();
        let z = zip_with(&[("a.bin", &data[..1500]), ("b.bin", &data[1500..])]);
        let dest = tempfile::tempdir().unwrap();
        let one = Limits { max_entry_bytes: 1000, ..Limits::DEFAULT };
        let err = extract_with(z.path(), dest.path(), &one).unwrap_err();
        assert!(
            err.to_string().contains("entry 'a.bin' is 1500 bytes uncompressed (at most 1000 bytes per entry)"),
            "{err}"
        );
        let total = Limits { max_total_bytes: 2000, ..Limits::DEFAULT };
        let err = extract_with(z.path(), dest.path(), &total).unwrap_err();
        assert!(err.to_string().contains("add up to more than 2000 bytes"), "{err}");
        let count = Limits { max_entries: 1, ..Limits::DEFAULT };
        let err = extract_with(z.path(), dest.path(), &count).unwrap_err();
        assert!(err.to_string().contains("2 entries (at most 1 allowed)"), "{err}");
        assert!(is_empty(dest.path()));
        extract(z.path(), dest.path()).unwrap();
        assert_eq!(std::fs::read(dest.path().join("b.bin")).unwrap(), &data[1500..]);
    }

    #[test]
    fn reads_into_memory_are_capped() {
        let z = zip_with(&[("SystemStructure.ssd", &[b'x'; 100])]);
        let err = read_entry(z.path(), "SystemStructure.ssd", 99).unwrap_err();
        assert!(err.to_string().contains("SystemStructure.ssd is 100 bytes, more than the 99 bytes"), "{err}");
        assert_eq!(read_entry(z.path(), "SystemStructure.ssd", 100).unwrap().unwrap().len(), 100);
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("big.xml");
        std::fs::write(&p, [b'y'; 10]).unwrap();
        assert!(read_file_capped(&p, 9).unwrap_err().to_string().contains("the file is 10 bytes"));
        assert_eq!(read_file_capped(&p, 10).unwrap().len(), 10);
        let err = read_file_capped(&dir.path().join("missing"), 10).unwrap_err().to_string();
        assert_eq!(err.matches("os error").count(), 1, "{err}");
    }
}
