//! Where a system comes from: an `.ssp` archive, a bare `.ssd` file, an SSD
//! given as text (the embedded closed-loop scenario), or a single `.fmu` (a
//! one-component system), and where its components' FMUs are found.
//!
//! An `.ssp` is self-contained: its components' FMUs must be in the archive
//! (a missing one is an error naming it, never replaced by another file). A
//! bare SSD's sources are relative to its directory, with `--fmu-dir` as a
//! fallback for `resources/X.fmu` sources.

use crate::error::{FmuError, SetupError, SimError};
use crate::import::process::ScratchDir;
use fmi_archive::safe_entry_path;
use ssp::{ComponentDesc, SystemDescription};
use std::path::{Path, PathBuf};

enum Base {
    /// Sources are relative to this directory (a bare `.ssd`'s folder).
    Dir(PathBuf),
    /// An extracted `.ssp` archive.
    Extracted(ScratchDir),
    /// A single FMU, used as it is.
    Single(PathBuf),
}

/// A system description plus the location its component sources resolve against.
pub struct SystemFile {
    /// The parsed description.
    pub desc: SystemDescription,
    base: Base,
    /// Fallback directory for the FMUs of a bare SSD (`--fmu-dir`): `resources/X.fmu` → `<dir>/X.fmu`.
    fmu_dir: Option<PathBuf>,
    /// Where the description came from (for messages).
    pub origin: String,
}

impl std::fmt::Debug for SystemFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SystemFile").field("origin", &self.origin).finish()
    }
}

impl SystemFile {
    /// Open `.ssp`, `.ssd` or `.fmu` (by extension). `fmu_dir` is the
    /// fallback directory for the FMUs of an `.ssd` (not used for an `.ssp`).
    pub fn open(path: &Path, fmu_dir: Option<&Path>) -> Result<SystemFile, SimError> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        let origin = path.display().to_string();
        let fmu_dir = fmu_dir.map(Path::to_path_buf);
        match ext.as_str() {
            "ssp" => {
                let dir = ScratchDir::new("fmi-master-ssp-").map_err(|error| FmuError::Io {
                    context: "cannot create a temporary directory for",
                    path: path.to_path_buf(),
                    error,
                })?;
                let desc = ssp::extract_ssp(path, dir.path())?;
                Ok(SystemFile { desc, base: Base::Extracted(dir), fmu_dir: None, origin })
            }
            "ssd" | "xml" => {
                let desc = SystemDescription::from_file(path)?;
                let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
                Ok(SystemFile { desc, base: Base::Dir(dir), fmu_dir, origin })
            }
            "fmu" => {
                let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("fmu").to_string();
                let mut desc = SystemDescription::new(&stem);
                desc.components.push(ComponentDesc {
                    name: stem,
                    source: path.display().to_string(),
                    implementation: None,
                    description: None,
                    connectors: Vec::new(),
                    parameters: Vec::new(),
                });
                Ok(SystemFile { desc, base: Base::Single(path.to_path_buf()), fmu_dir: None, origin })
            }
            _ => Err(SetupError::Invalid(format!(
                "{origin}: expected a .ssp archive, a .ssd file or an .fmu (by file extension)"
            ))
            .into()),
        }
    }

    /// An SSD given as text (e.g. the embedded [`crate::CLOSED_LOOP_SSD`]); its
    /// component sources `resources/X.fmu` are looked up as `<fmu_dir>/X.fmu`.
    pub fn from_text(xml: &str, origin: &str, fmu_dir: &Path) -> Result<SystemFile, SimError> {
        let desc = SystemDescription::from_xml_in(xml, origin, fmu_dir)?;
        Ok(SystemFile {
            desc,
            base: Base::Dir(fmu_dir.to_path_buf()),
            fmu_dir: Some(fmu_dir.to_path_buf()),
            origin: origin.to_string(),
        })
    }

    /// Is this a single FMU run (bare variable names)?
    pub fn is_single_fmu(&self) -> bool {
        matches!(self.base, Base::Single(_))
    }

    /// The `.fmu` file of a component.
    pub fn fmu_path(&self, c: &ComponentDesc) -> Result<PathBuf, SimError> {
        let base = match &self.base {
            Base::Single(p) => return Ok(p.clone()),
            Base::Dir(d) => d.as_path(),
            Base::Extracted(t) => t.path(),
        };
        let rel = safe_entry_path(&c.source).map_err(|why| {
            SetupError::Invalid(format!(
                "component {}: source '{}' is not a relative path inside the system ({why})",
                c.name, c.source
            ))
        })?;
        let missing = |looked_at: String, hint: &str| SetupError::MissingFmu {
            component: c.name.clone(),
            source_uri: c.source.clone(),
            looked_at,
            hint: hint.to_string(),
        };
        let direct = base.join(&rel);
        if direct.is_file() {
            return Ok(direct);
        }
        if let Base::Extracted(_) = self.base {
            let inside = format!("{}!{}", self.origin, rel.to_string_lossy().replace('\\', "/"));
            return Err(missing(inside, "; an .ssp archive must contain the FMUs its components name").into());
        }
        let mut tried = vec![direct];
        if let (Some(dir), Some(file)) = (&self.fmu_dir, rel.file_name()) {
            let p = dir.join(file);
            if p.is_file() {
                return Ok(p);
            }
            tried.push(p);
        }
        let tried = tried.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ");
        let hint = if self.fmu_dir.is_some() { "; build the FMUs with `cargo run --release -p packaging`" } else { "" };
        Err(missing(tried, hint).into())
    }
}
