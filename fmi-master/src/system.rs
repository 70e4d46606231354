//! Where a system comes from: an `.ssp` archive, a bare `.ssd` file, the
//! embedded closed-loop scenario, or a single `.fmu` (a one-component
//! system), and where its components' FMUs are found.

use crate::error::{FmuError, SetupError, SimError};
use crate::ssp::{ComponentDesc, SspError, SystemDescription};
use std::path::{Path, PathBuf};

enum Base {
    /// Sources are relative to this directory (a bare `.ssd`'s folder).
    Dir(PathBuf),
    /// An extracted `.ssp` archive.
    Extracted(tempfile::TempDir),
    /// A single FMU, used as it is.
    Single(PathBuf),
}

/// A system description plus the location its component sources resolve against.
pub struct SystemFile {
    /// The parsed description.
    pub desc: SystemDescription,
    base: Base,
    /// Fallback directory for component FMUs (`--fmu-dir`): `resources/X.fmu` → `<dir>/X.fmu`.
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
    /// Open `.ssp`, `.ssd` or `.fmu` (by extension).
    pub fn open(path: &Path, fmu_dir: Option<&Path>) -> Result<SystemFile, SimError> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        let origin = path.display().to_string();
        match ext.as_str() {
            "ssp" => {
                let dir =
                    tempfile::Builder::new().prefix("fmi-master-ssp-").tempdir().map_err(|source| FmuError::Io {
                        context: "cannot create a temporary directory for",
                        path: path.to_path_buf(),
                        source,
                    })?;
                crate::unzip::extract(path, dir.path())?;
                let ssd_path = dir.path().join("SystemStructure.ssd");
                let xml = std::fs::read_to_string(&ssd_path)
                    .map_err(|e| SspError::Io(format!("{origin}: cannot read SystemStructure.ssd: {e}")))?;
                let base_dir = dir.path().to_path_buf();
                let read = move |src: &str| read_relative(&base_dir, src);
                let desc = SystemDescription::from_xml(&xml, &format!("{origin}!SystemStructure.ssd"), Some(&read))?;
                Ok(SystemFile { desc, base: Base::Extracted(dir), fmu_dir: fmu_dir.map(Path::to_path_buf), origin })
            }
            "ssd" | "xml" => {
                let xml =
                    std::fs::read_to_string(path).map_err(|e| SspError::Io(format!("cannot read {origin}: {e}")))?;
                let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
                let d2 = dir.clone();
                let read = move |src: &str| read_relative(&d2, src);
                let desc = SystemDescription::from_xml(&xml, &origin, Some(&read))?;
                Ok(SystemFile { desc, base: Base::Dir(dir), fmu_dir: fmu_dir.map(Path::to_path_buf), origin })
            }
            "fmu" => {
                let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("fmu").to_string();
                let desc = SystemDescription {
                    name: stem.clone(),
                    system_name: stem.clone(),
                    description: None,
                    components: vec![ComponentDesc {
                        name: stem,
                        source: path.display().to_string(),
                        implementation: None,
                        description: None,
                        connectors: Vec::new(),
                        parameters: Vec::new(),
                    }],
                    connections: Vec::new(),
                    parameters: Vec::new(),
                    start_time: None,
                    stop_time: None,
                    master: Default::default(),
                };
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
        let dir = fmu_dir.to_path_buf();
        let read = move |src: &str| read_relative(&dir, src);
        let desc = SystemDescription::from_xml(xml, origin, Some(&read))?;
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
        if let Base::Single(p) = &self.base {
            return Ok(p.clone());
        }
        let rel = crate::unzip::safe_entry_path(&c.source).map_err(|why| {
            SetupError::Invalid(format!(
                "component {}: source '{}' is not a relative path inside the system ({why})",
                c.name, c.source
            ))
        })?;
        let base = match &self.base {
            Base::Dir(d) => d.clone(),
            Base::Extracted(t) => t.path().to_path_buf(),
            Base::Single(_) => unreachable!(),
        };
        let mut tried = Vec::new();
        let direct = base.join(&rel);
        if direct.is_file() {
            return Ok(direct);
        }
        tried.push(direct);
        if let (Some(dir), Some(file)) = (&self.fmu_dir, rel.file_name()) {
            let p = dir.join(file);
            if p.is_file() {
                return Ok(p);
            }
            tried.push(p);
        }
        Err(SetupError::Invalid(format!(
            "component {}: FMU '{}' not found (looked at {}){}",
            c.name,
            c.source,
            tried.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", "),
            if self.fmu_dir.is_some() { "; build the FMUs with `cargo run --release -p packaging`" } else { "" }
        ))
        .into())
    }
}

fn read_relative(base: &Path, src: &str) -> Result<String, SspError> {
    let rel = crate::unzip::safe_entry_path(src)
        .map_err(|why| SspError::Io(format!("parameter source '{src}' is not a relative path ({why})")))?;
    let p = base.join(rel);
    std::fs::read_to_string(&p).map_err(|e| SspError::Io(format!("cannot read {}: {e}", p.display())))
}

/// The default directory of the project's FMUs: `$FMU_DIR` if set (the
/// variable the Python tests use too), else `$CARGO_TARGET_DIR/fmu` if set,
/// else `target/fmu` of this workspace (if it exists), else `./target/fmu`.
pub fn default_fmu_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("FMU_DIR") {
        return PathBuf::from(d);
    }
    if let Some(t) = std::env::var_os("CARGO_TARGET_DIR") {
        return PathBuf::from(t).join("fmu");
    }
    let ws = Path::new(env!("CARGO_MANIFEST_DIR")).parent().map(|p| p.join("target").join("fmu"));
    match ws {
        Some(p) if p.is_dir() => p,
        _ => PathBuf::from("target").join("fmu"),
    }
}
