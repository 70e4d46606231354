//! The project's closed loop as a system of FMUs: where it comes from, and which of its
//! components are the plant and the controller.

use fmi_master::SystemFile;
use fmi_master::import::Fmu;
use std::path::Path;
use study_kit::StudyError;

/// The project's closed-loop system: `ClosedLoop.ssp` in `fmu_dir` if it exists, else the SSD of
/// `packaging` with the FMUs of `fmu_dir`.
pub fn closed_loop_system(fmu_dir: &Path) -> Result<SystemFile, StudyError> {
    let ssp = fmu_dir.join("ClosedLoop.ssp");
    Ok(if ssp.is_file() {
        SystemFile::open(&ssp, Some(fmu_dir))?
    } else {
        SystemFile::from_text(packaging::CLOSED_LOOP_SSD, "ClosedLoop.ssd", fmu_dir)?
    })
}

/// The plant and controller components of the system and the variables the job uses.
#[derive(Clone, Debug, PartialEq)]
pub struct Roles {
    /// Plant component name (its FMU is `MillingPlant`).
    pub plant: String,
    /// Controller component name (its FMU is `ChatterController`).
    pub controller: String,
}

impl Roles {
    /// The measured output, recorded and evaluated.
    pub fn measured(&self) -> String {
        format!("{}.x", self.plant)
    }
    /// The command, recorded.
    pub fn command(&self) -> String {
        format!("{}.u", self.controller)
    }
}

/// The components whose FMUs are the project's plant and controller (by `modelIdentifier`).
pub fn roles(sys: &SystemFile) -> Result<Roles, StudyError> {
    use fmi2_export::Fmi2Model;
    roles_with(sys, fmu_controller::ChatterController::description().model_identifier().unwrap_or_default())
}

/// The components whose FMUs are the project's plant and the controller FMU `ctrl_id` (by
/// `modelIdentifier`; `LinearController` for the Table 8 benchmark).
pub fn roles_with(sys: &SystemFile, ctrl_id: &str) -> Result<Roles, StudyError> {
    use fmi2_export::Fmi2Model;
    let plant_id = fmu_plant::MillingPlant::description().model_identifier().unwrap_or_default();
    let (mut plant, mut controller) = (Vec::new(), Vec::new());
    for c in &sys.desc.components {
        let fmu = Fmu::open(&sys.fmu_path(c)?)?;
        match fmu.model_description().model_identifier() {
            Some(id) if id == plant_id => plant.push(c.name.clone()),
            Some(id) if id == ctrl_id => controller.push(c.name.clone()),
            _ => {}
        }
    }
    let one = |found: Vec<String>, id: &str| match <[String; 1]>::try_from(found) {
        Ok([name]) => Ok(name),
        Err(found) => Err(StudyError::Invalid(format!(
            "{}: the main job needs exactly one {id} component, found {}",
            sys.origin,
            found.len()
        ))),
    };
    Ok(Roles { plant: one(plant, plant_id)?, controller: one(controller, ctrl_id)? })
}

/// The controller gains a study starts from: a named choice on the command line (`--preset`)
/// and in a case manifest (by its name).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum GainPreset {
    /// The shipped FMU defaults (tuned by PSO under the robust saturation check).
    Tuned,
    /// The seed's Table 2.
    Table2,
}

impl GainPreset {
    /// The preset's controller parameters.
    pub fn params(self) -> chatter_control::ControllerParams {
        match self {
            GainPreset::Tuned => chatter_control::ControllerParams::tuned(),
            GainPreset::Table2 => chatter_control::ControllerParams::paper_table2(),
        }
    }

    /// The name (as on the command line and in manifests).
    pub fn name(self) -> &'static str {
        match self {
            GainPreset::Tuned => "tuned",
            GainPreset::Table2 => "table2",
        }
    }
}

impl std::fmt::Display for GainPreset {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Where a study finds the FMUs by default (`$FMU_DIR`, else `target/fmu`), as an absolute path
/// so that workers in other folders read the same files.
pub fn default_fmu_dir() -> std::path::PathBuf {
    std::path::absolute(packaging::fmu_dir()).unwrap_or_else(|_| packaging::fmu_dir())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::ValueEnum;

    #[test]
    fn gain_presets_have_one_name_on_the_command_line_and_in_manifests() {
        for p in GainPreset::value_variants() {
            let cli = p.to_possible_value().unwrap();
            assert_eq!(cli.get_name(), p.name());
            assert_eq!(serde_json::to_string(p).unwrap(), format!("\"{}\"", p.name()));
        }
        assert_eq!(GainPreset::Table2.params(), chatter_control::ControllerParams::paper_table2());
    }
}
