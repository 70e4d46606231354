//! [`ZipBuilder`]: a deterministic zip writer for `.fmu` and `.ssp` files.
//!
//! Entries are written in the order they were added, with the zip epoch
//! (1980-01-01 00:00) as their time stamp and fixed permissions (0644 for
//! files, 0755 for executables and directories), so the same input gives the
//! same bytes. The archive is written to `<name>.partial` next to the target
//! and renamed into place, so readers never see half an archive.

use crate::entry_path::safe_entry_path;
use crate::error::ArchiveError;
use std::io::Write;
use std::path::{Path, PathBuf};
use zip::write::SimpleFileOptions;

/// How an entry's data is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compression {
    /// Uncompressed (for content that is compressed already, e.g. an `.fmu` inside an `.ssp`).
    Stored,
    /// Deflate.
    Deflated,
}

#[derive(Clone, Debug)]
enum Content {
    File { data: Vec<u8>, compression: Compression, mode: u32 },
    Directory,
}

/// Collects entries, then writes them as one zip archive (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct ZipBuilder {
    entries: Vec<(String, Content)>,
}

impl ZipBuilder {
    /// An empty archive.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add a regular file (mode 0644).
    pub fn file(&mut self, name: impl Into<String>, data: impl Into<Vec<u8>>, compression: Compression) -> &mut Self {
        self.entries.push((name.into(), Content::File { data: data.into(), compression, mode: 0o644 }));
        self
    }

    /// Add an executable file (mode 0755), e.g. a shared library.
    pub fn executable(
        &mut self,
        name: impl Into<String>,
        data: impl Into<Vec<u8>>,
        compression: Compression,
    ) -> &mut Self {
        self.entries.push((name.into(), Content::File { data: data.into(), compression, mode: 0o755 }));
        self
    }

    /// Add a directory entry (`name` ends with `/`, which is added if missing).
    pub fn directory(&mut self, name: impl Into<String>) -> &mut Self {
        let mut name = name.into();
        if !name.ends_with('/') {
            name.push('/');
        }
        self.entries.push((name, Content::Directory));
        self
    }

    /// Names of the entries added so far, in order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.entries.iter().map(|(n, _)| n.as_str())
    }

    fn check_names(&self, out: &Path) -> Result<(), ArchiveError> {
        let mut seen = std::collections::HashSet::new();
        for (name, _) in &self.entries {
            let bad =
                |reason: String| ArchiveError::BadEntryName { path: out.to_path_buf(), entry: name.clone(), reason };
            let rel = safe_entry_path(name).map_err(|why| bad(format!("is not a safe relative path ({why})")))?;
            if name.contains('\\') || rel.as_os_str().is_empty() {
                return Err(bad("must be a non-empty path with '/' separators".into()));
            }
            if !seen.insert(rel) {
                return Err(bad("is given twice".into()));
            }
        }
        Ok(())
    }

    /// Write the archive to `out` (atomically; parent directories are created).
    pub fn write_to(&self, out: &Path) -> Result<(), ArchiveError> {
        self.check_names(out)?;
        if let Some(dir) = out.parent()
            && !dir.as_os_str().is_empty()
        {
            std::fs::create_dir_all(dir).map_err(|error| ArchiveError::Io {
                context: "cannot create directory",
                path: dir.to_path_buf(),
                error,
            })?;
        }
        let mut partial = out.as_os_str().to_owned();
        partial.push(".partial");
        let tmp = PathBuf::from(partial);
        let result = self.write_file(&tmp, out).and_then(|()| {
            std::fs::rename(&tmp, out).map_err(|error| ArchiveError::Io {
                context: "cannot create",
                path: out.to_path_buf(),
                error,
            })
        });
        if result.is_err() {
            let _ = std::fs::remove_file(&tmp);
        }
        result
    }

    fn write_file(&self, tmp: &Path, out: &Path) -> Result<(), ArchiveError> {
        let zerr = |e: zip::result::ZipError| ArchiveError::Write { path: out.to_path_buf(), reason: e.to_string() };
        let ioerr = |error| ArchiveError::Io { context: "cannot write", path: tmp.to_path_buf(), error };
        let file = std::fs::File::create(tmp).map_err(ioerr)?;
        let mut zip = zip::ZipWriter::new(std::io::BufWriter::new(file));
        let base = SimpleFileOptions::default().last_modified_time(zip::DateTime::default());
        for (name, content) in &self.entries {
            match content {
                Content::Directory => zip.add_directory(name.as_str(), base.unix_permissions(0o755)).map_err(zerr)?,
                Content::File { data, compression, mode } => {
                    let method = match compression {
                        Compression::Stored => zip::CompressionMethod::Stored,
                        Compression::Deflated => zip::CompressionMethod::Deflated,
                    };
                    let opts = base
                        .compression_method(method)
                        .unix_permissions(*mode)
                        .large_file(data.len() >= u32::MAX as usize);
                    zip.start_file(name.as_str(), opts).map_err(zerr)?;
                    zip.write_all(data).map_err(ioerr)?;
                }
            }
        }
        let mut w = zip.finish().map_err(zerr)?;
        w.flush().map_err(ioerr)?;
        let file = w.into_inner().map_err(|e| ioerr(e.into_error()))?;
        file.sync_all().map_err(ioerr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> ZipBuilder {
        let mut z = ZipBuilder::new();
        z.file("modelDescription.xml", b"<fmiModelDescription/>".to_vec(), Compression::Deflated)
            .executable("binaries/linux64/M.so", vec![0x7f, b'E', b'L', b'F'], Compression::Deflated)
            .directory("resources")
            .file("resources/inner.fmu", b"PK stored".to_vec(), Compression::Stored);
        z
    }

    #[test]
    fn same_entries_give_the_same_bytes_in_the_given_order() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.zip"), dir.path().join("sub/b.zip"));
        sample().write_to(&a).unwrap();
        std::thread::sleep(std::time::Duration::from_millis(1100));
        sample().write_to(&b).unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        assert!(!dir.path().join("a.zip.partial").exists());
        let mut zip = zip::ZipArchive::new(std::fs::File::open(&a).unwrap()).unwrap();
        let names: Vec<String> = (0..zip.len()).map(|i| zip.by_index(i).unwrap().name().to_string()).collect();
        assert_eq!(names, ["modelDescription.xml", "binaries/linux64/M.so", "resources/", "resources/inner.fmu"]);
        let so = zip.by_name("binaries/linux64/M.so").unwrap();
        assert_eq!(so.unix_mode().unwrap() & 0o777, 0o755);
        assert_eq!(so.last_modified().unwrap(), zip::DateTime::default());
        drop(so);
        assert_eq!(zip.by_name("resources/inner.fmu").unwrap().compression(), zip::CompressionMethod::Stored);
        // What we write, we extract.
        let dest = tempfile::tempdir().unwrap();
        crate::extract(&a, dest.path()).unwrap();
        assert_eq!(std::fs::read(dest.path().join("resources/inner.fmu")).unwrap(), b"PK stored");
    }

    #[test]
    fn unsafe_or_repeated_names_are_refused_before_writing() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("x.zip");
        let mut z = sample();
        z.file("../evil", Vec::new(), Compression::Stored);
        let err = z.write_to(&out).unwrap_err();
        assert!(err.to_string().contains("entry name '../evil' is not a safe relative path"), "{err}");
        let mut z = sample();
        z.file("./modelDescription.xml", Vec::new(), Compression::Stored);
        let err = z.write_to(&out).unwrap_err();
        assert!(err.to_string().contains("is given twice"), "{err}");
        assert!(!out.exists() && !dir.path().join("x.zip.partial").exists());
    }
}
