//! Seed 002's semi-discretisation cases (Section 6) as named presets of `chatter sd-lobes`.

use delay_stability::milling::MillingModel;
use delay_stability::presets::{SEED002_GAINS, seed002, seed002_gain};
use seed000::sd_lobes::stab;
use study_kit::StudyError;

/// Seed 002's cases (Section 6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// §6.1 open loop: x_F = 1, full immersion, 36000–38000 rpm.
    Seed002Open61,
    /// §6.1 with the printed static gains (k₁ = 697.1599, k₂ = −1071.058 N/mm, β = 1).
    Seed002Closed61,
    /// §6.2 open loop: x_F = 0.744, 34000–36000 rpm.
    Seed002Open62,
}

impl Preset {
    /// All presets with their command-line names.
    pub const ALL: [(&'static str, Preset); 3] = [
        ("seed002-6.1", Preset::Seed002Open61),
        ("seed002-6.1-closed", Preset::Seed002Closed61),
        ("seed002-6.2", Preset::Seed002Open62),
    ];

    /// By command-line name.
    pub fn by_name(name: &str) -> Result<Preset, StudyError> {
        Self::ALL.iter().find(|(n, _)| *n == name).map(|&(_, p)| p).ok_or_else(|| {
            let names: Vec<_> = Self::ALL.iter().map(|(n, _)| *n).collect();
            StudyError::Invalid(format!("unknown preset {name:?} (one of {})", names.join(", ")))
        })
    }

    /// The model.
    pub fn model(&self) -> Result<MillingModel, StudyError> {
        let (k1, k2) = SEED002_GAINS;
        match self {
            Preset::Seed002Open61 => seed002(1.0, None),
            Preset::Seed002Closed61 => seed002(1.0, Some(seed002_gain(k1, k2))),
            Preset::Seed002Open62 => seed002(0.744, None),
        }
        .map_err(stab)
    }

    /// The paper's speed range \[rpm\].
    pub fn speed_range(&self) -> (f64, f64) {
        match self {
            Preset::Seed002Open61 | Preset::Seed002Closed61 => (36000.0, 38000.0),
            Preset::Seed002Open62 => (34000.0, 36000.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_by_name() {
        for (name, p) in Preset::ALL {
            assert_eq!(Preset::by_name(name).unwrap(), p);
        }
        assert!(Preset::by_name("seed002-9").unwrap_err().to_string().contains("seed002-6.1-closed"));
    }
}
