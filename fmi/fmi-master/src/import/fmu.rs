//! [`Fmu`]: opening an `.fmu` — safe extraction into its own temporary
//! directory ([`fmi_archive`], with its size and ratio limits), parsing the
//! size-capped `modelDescription.xml`, requiring `<CoSimulation>`, finding
//! `binaries/<platform>/<modelIdentifier>.<ext>` of the host ([`PLATFORM`],
//! [`LIBRARY_EXTENSION`]; naming the platforms the archive has when it is missing), then loading it ([`super::ffi`]) — and
//! instantiating it with the GUID of the XML and a `file:///…/resources` URI.

use crate::error::FmuError;
use crate::import::ffi::{Loaded, RawInstance};
use crate::import::instance::Instance;
use crate::import::log::LogState;
use crate::import::process::ScratchDir;
use model_description::ModelDescription;
use std::ffi::CString;
use std::path::Path;
use std::sync::Arc;

/// The platform directory under `binaries/` this build loads (FMI 2.0 section 2.3: the
/// platform of the master's own build).
pub const PLATFORM: &str = if cfg!(all(target_os = "windows", target_pointer_width = "64")) {
    "win64"
} else if cfg!(all(target_os = "windows", target_pointer_width = "32")) {
    "win32"
} else if cfg!(all(target_os = "macos", target_pointer_width = "64")) {
    "darwin64"
} else if cfg!(all(target_os = "linux", target_pointer_width = "32")) {
    "linux32"
} else {
    "linux64"
};
/// The file extension of the binaries of [`PLATFORM`].
pub const LIBRARY_EXTENSION: &str = if cfg!(target_os = "windows") {
    "dll"
} else if cfg!(target_os = "macos") {
    "dylib"
} else {
    "so"
};
/// Largest `modelDescription.xml` read [bytes].
pub const MAX_MODEL_DESCRIPTION_BYTES: u64 = 64 << 20;

/// An opened FMU: its description, its extracted files and its loaded binary.
///
/// Cheap to share: instances keep the library alive through an `Arc`.
pub struct Fmu {
    name: String,
    md: ModelDescription,
    loaded: Arc<Loaded>,
}

impl std::fmt::Debug for Fmu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fmu").field("name", &self.name).field("model", &self.md.model_name).finish()
    }
}

fn file_name(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "?".into())
}

fn parse_description(bytes: Vec<u8>, fmu: &str) -> Result<ModelDescription, FmuError> {
    let description = |message: String| FmuError::Description { fmu: fmu.to_string(), message };
    let xml = String::from_utf8(bytes).map_err(|_| description("modelDescription.xml is not UTF-8".into()))?;
    ModelDescription::from_xml(&xml).map_err(|e| description(e.to_string()))
}

/// Read and parse the `modelDescription.xml` of an `.fmu` without extracting
/// or loading anything (for `cosim info`).
pub fn read_model_description(path: &Path) -> Result<ModelDescription, FmuError> {
    let name = file_name(path);
    let bytes =
        fmi_archive::read_entry(path, "modelDescription.xml", MAX_MODEL_DESCRIPTION_BYTES)?.ok_or_else(|| {
            FmuError::Description { fmu: name.clone(), message: "no modelDescription.xml in the archive".into() }
        })?;
    parse_description(bytes, &name)
}

fn available_platforms(dir: &Path) -> String {
    let mut v: Vec<String> = std::fs::read_dir(dir.join("binaries"))
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .filter(|e| e.path().is_dir())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    if v.is_empty() { "no binaries at all".into() } else { v.join(", ") }
}

impl Fmu {
    /// Open an `.fmu`: extract, parse, check, load and resolve.
    pub fn open(path: &Path) -> Result<Fmu, FmuError> {
        let name = file_name(path);
        if !path.is_file() {
            return Err(FmuError::Io {
                context: "cannot open FMU",
                path: path.to_path_buf(),
                error: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
            });
        }
        let dir = ScratchDir::new("fmi-master-").map_err(|error| FmuError::Io {
            context: "cannot create a temporary directory for",
            path: path.to_path_buf(),
            error,
        })?;
        fmi_archive::extract(path, dir.path())?;
        let xml_path = dir.path().join("modelDescription.xml");
        let bytes = fmi_archive::read_file_capped(&xml_path, MAX_MODEL_DESCRIPTION_BYTES).map_err(|e| {
            FmuError::Description { fmu: name.clone(), message: format!("cannot read modelDescription.xml: {e}") }
        })?;
        let md = parse_description(bytes, &name)?;
        if !md.fmi_version.starts_with("2.") {
            return Err(FmuError::Description {
                fmu: name,
                message: format!("fmiVersion is \"{}\"; this master imports FMI 2.0", md.fmi_version),
            });
        }
        let Some(id) = md.model_identifier().map(str::to_owned) else {
            return Err(FmuError::NotCoSimulation { fmu: name });
        };
        let so = dir.path().join("binaries").join(PLATFORM).join(format!("{id}.{LIBRARY_EXTENSION}"));
        if !so.is_file() {
            return Err(FmuError::MissingBinary {
                fmu: name,
                platform: PLATFORM,
                available: available_platforms(dir.path()),
            });
        }
        let loaded = Loaded::open(&so, dir, &name)?;
        Ok(Fmu { name, md, loaded: Arc::new(loaded) })
    }

    /// The FMU's file name (used in messages).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The parsed `modelDescription.xml`.
    pub fn model_description(&self) -> &ModelDescription {
        &self.md
    }

    /// The extraction directory (exists as long as the FMU or an instance does).
    pub fn directory(&self) -> &Path {
        self.loaded.dir()
    }

    /// The `file:///…/resources` URI passed to `fmi2Instantiate`.
    pub fn resource_uri(&self) -> String {
        file_uri(&self.loaded.dir().join("resources"))
    }

    /// Instantiate a co-simulation slave named `instance_name`.
    ///
    /// `logging_on` is passed to `fmi2Instantiate` (FMUs still report
    /// warnings and errors through the logger when it is off, if they
    /// follow the standard's advice). With `echo`, log lines are also
    /// printed to stderr as they arrive.
    pub fn instantiate(&self, instance_name: &str, logging_on: bool, echo: bool) -> Result<Instance, FmuError> {
        let model = self.md.model_identifier().unwrap_or_default().to_string();
        let arg = |what: &str, s: &str| {
            CString::new(s).map_err(|_| FmuError::Argument {
                instance: instance_name.to_string(),
                call: "fmi2Instantiate",
                message: format!("{what} contains a NUL byte"),
            })
        };
        let c_name = arg("the instance name", instance_name)?;
        let c_guid = arg("the GUID", &self.md.guid)?;
        let c_res = arg("the resource location", &self.resource_uri())?;
        let log = LogState::new(instance_name, echo);
        let raw = RawInstance::instantiate(&self.loaded, &c_name, &c_guid, &c_res, logging_on, log)
            .map_err(|log| FmuError::Instantiate { instance: instance_name.to_string(), model: model.clone(), log })?;
        Ok(Instance::new(raw, instance_name, &model))
    }
}

/// `file:///` URI of an absolute path, percent-encoding what RFC 3986 requires.
pub fn file_uri(path: &Path) -> String {
    let abs = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().map(|d| d.join(path)).unwrap_or_else(|_| path.to_path_buf())
    };
    let mut s = String::from("file://");
    for b in abs.to_string_lossy().bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'.' | b'_' | b'~' => s.push(b as char),
            _ => s.push_str(&format!("%{b:02X}")),
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_uris_are_percent_encoded() {
        assert_eq!(file_uri(Path::new("/tmp/a b/résources")), "file:///tmp/a%20b/r%C3%A9sources");
        assert_eq!(file_uri(Path::new("/x/y_z-1.0~")), "file:///x/y_z-1.0~");
    }
}
