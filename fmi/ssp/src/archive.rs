//! `.ssd` files and `.ssp` archives on disk.
//!
//! An `.ssp` is a zip archive with `SystemStructure.ssd` at its root and the
//! component FMUs (conventionally under `resources/`). Reading goes through
//! [`fmi_archive`]: safe extraction with its limits, and size-capped reads
//! of the SSD and of `.ssv` files ([`MAX_SSD_BYTES`]). `source` references
//! of parameter bindings are resolved relative to the SSD and may not leave
//! its directory.

use crate::bindings::SourceReader;
use crate::error::{SspError, invalid};
use crate::model::SystemDescription;
use fmi_archive::{Compression, ZipBuilder, read_entry, read_file_capped, safe_entry_path};
use std::path::Path;

/// Name of the system description inside an `.ssp`.
pub const SSD_ENTRY: &str = "SystemStructure.ssd";
/// Largest `SystemStructure.ssd` or `.ssv` file read [bytes].
pub const MAX_SSD_BYTES: u64 = 16 << 20;

fn utf8(bytes: Vec<u8>, file: &str) -> Result<String, SspError> {
    String::from_utf8(bytes).map_err(|_| invalid(file, "is not UTF-8 text"))
}

fn relative(src: &str, file: &str) -> Result<String, SspError> {
    let rel = safe_entry_path(src).map_err(|why| {
        invalid(file, format!("parameter source '{src}' is not a relative path inside the system ({why})"))
    })?;
    Ok(rel.to_string_lossy().replace('\\', "/"))
}

/// Read a text file next to an SSD (`source` of a binding), size-capped.
fn read_beside(dir: &Path, src: &str, file: &str) -> Result<String, SspError> {
    let path = dir.join(relative(src, file)?);
    utf8(read_file_capped(&path, MAX_SSD_BYTES)?, &path.display().to_string())
}

impl SystemDescription {
    /// Read a bare `.ssd` file; `source` files of its bindings are read from its directory.
    pub fn from_file(path: &Path) -> Result<SystemDescription, SspError> {
        let file = path.display().to_string();
        let xml = utf8(read_file_capped(path, MAX_SSD_BYTES)?, &file)?;
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        let read = |src: &str| read_beside(&dir, src, &file);
        SystemDescription::from_xml(&xml, &file, Some(&read))
    }

    /// Parse SSD text whose `source` files live in `dir` (e.g. an extracted archive).
    pub fn from_xml_in(xml: &str, file: &str, dir: &Path) -> Result<SystemDescription, SspError> {
        let read = |src: &str| read_beside(dir, src, file);
        SystemDescription::from_xml(xml, file, Some(&read))
    }
}

/// Read `SystemStructure.ssd` from an `.ssp` archive (without extracting it).
pub fn read_ssd_from_ssp(ssp: &Path) -> Result<String, SspError> {
    let file = format!("{}!{SSD_ENTRY}", ssp.display());
    let bytes = read_entry(ssp, SSD_ENTRY, MAX_SSD_BYTES)?
        .ok_or_else(|| invalid(&ssp.display().to_string(), format!("the archive has no {SSD_ENTRY}")))?;
    utf8(bytes, &file)
}

/// Read the system of an `.ssp` archive without extracting it (`.ssv`
/// sources are read from the archive too). Component sources stay as written.
pub fn read_ssp(ssp: &Path) -> Result<SystemDescription, SspError> {
    let xml = read_ssd_from_ssp(ssp)?;
    let file = format!("{}!{SSD_ENTRY}", ssp.display());
    let read = |src: &str| -> Result<String, SspError> {
        let entry = relative(src, &file)?;
        let label = format!("{}!{entry}", ssp.display());
        let bytes = read_entry(ssp, &entry, MAX_SSD_BYTES)?
            .ok_or_else(|| invalid(&file, format!("parameter source {src} is not in the archive")))?;
        utf8(bytes, &label)
    };
    let read: SourceReader<'_> = &read;
    SystemDescription::from_xml(&xml, &file, Some(read))
}

/// Extract an `.ssp` safely into the existing directory `dest` and parse its
/// `SystemStructure.ssd` (component sources then resolve against `dest`).
pub fn extract_ssp(ssp: &Path, dest: &Path) -> Result<SystemDescription, SspError> {
    fmi_archive::extract(ssp, dest)?;
    let file = format!("{}!{SSD_ENTRY}", ssp.display());
    let path = dest.join(SSD_ENTRY);
    if !path.is_file() {
        return Err(invalid(&ssp.display().to_string(), format!("the archive has no {SSD_ENTRY}")));
    }
    let xml = utf8(read_file_capped(&path, MAX_SSD_BYTES)?, &file)?;
    SystemDescription::from_xml_in(&xml, &file, dest)
}

/// Write a standard SSP archive: `SystemStructure.ssd` (the given text) and
/// each FMU as `resources/<name>`, stored (FMUs are compressed already).
/// The SSD is parsed first, and every component `source` must be one of the
/// FMUs packed, so the archive is self-contained. Deterministic and atomic
/// ([`fmi_archive::ZipBuilder`]).
pub fn write_ssp_archive(out: &Path, ssd: &str, fmus: &[(&str, &Path)]) -> Result<(), SspError> {
    let label = out.display().to_string();
    let desc = SystemDescription::from_xml(ssd, SSD_ENTRY, None)?;
    for (n, _) in fmus {
        if safe_entry_path(n).is_err() || n.contains(['/', '\\']) {
            return Err(invalid(&label, format!("FMU name {n} must be a plain file name")));
        }
    }
    for c in &desc.components {
        if !fmus.iter().any(|(n, _)| c.source == format!("resources/{n}")) {
            let packed: Vec<&str> = fmus.iter().map(|(n, _)| *n).collect();
            return Err(invalid(
                &label,
                format!(
                    "component {} has source {}, which is not among the FMUs packed ({})",
                    c.name,
                    c.source,
                    packed.join(", ")
                ),
            ));
        }
    }
    let mut zip = ZipBuilder::new();
    zip.file(SSD_ENTRY, ssd.as_bytes(), Compression::Deflated).directory("resources/");
    for (name, path) in fmus {
        let data = std::fs::read(path).map_err(|error| fmi_archive::ArchiveError::Io {
            context: "cannot read",
            path: path.to_path_buf(),
            error,
        })?;
        zip.file(format!("resources/{name}"), data, Compression::Stored);
    }
    zip.write_to(out)?;
    Ok(())
}

/// [`write_ssp_archive`] of a description (written with [`SystemDescription::to_xml`]).
pub fn write_ssp(out: &Path, desc: &SystemDescription, fmus: &[(&str, &Path)]) -> Result<(), SspError> {
    write_ssp_archive(out, &desc.to_xml()?, fmus)
}
