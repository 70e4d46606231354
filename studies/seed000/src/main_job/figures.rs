//! The main job's Figures 6 and 7 and how its titles name the system that was run.

use super::{MainJobSpec, RefFreqs, Result};
use crate::scenario::Roles;
use fmi_master::SystemFile;
use fmi_master::plot::{Envelope, Mark, Panel, Quantity};
use fmi_master::spectrum::Spectrum;
use std::path::Path;

/// The system as the titles name it: its file name, and the job's `--set` overrides if any.
pub(super) fn system_label(spec: &MainJobSpec, sys: &SystemFile) -> String {
    let path = Path::new(&sys.origin);
    let name = path.file_name().map_or_else(|| sys.origin.clone(), |f| f.to_string_lossy().into_owned());
    if spec.overrides.is_empty() { name } else { format!("{name} with --set {}", spec.overrides.join(", ")) }
}

/// Figures 6 and 7 from the first seed's envelope and spectrum of each case.
pub(super) fn figures(
    spec: &MainJobSpec,
    sys: &SystemFile,
    roles: &Roles,
    (fig6, fig7): (&Path, &Path),
    firsts: &[(&String, &(Envelope, Spectrum))],
    (tooth, natural, dist): RefFreqs,
) -> Result<()> {
    let first_seed = spec.seeds[0];
    let measured = roles.measured();
    // the unit and description of the measured variable, as the plant FMU declares them
    let var = fmi_master::plot::variables(sys, std::slice::from_ref(&measured))?.remove(0).unwrap_or_default();
    let unit = if var.unit.is_empty() { "m".to_string() } else { var.unit };
    let what = var.description.unwrap_or_else(|| "tip displacement".into());
    let name = measured.split_once('.').map_or(measured.as_str(), |p| p.1);
    let extent = firsts.iter().map(|(_, (e, _))| e.extent()).fold(0.0, f64::max);
    let y = Quantity::scaled(name, &unit, extent);
    let system = system_label(spec, sys);
    let panels: Vec<Panel<'_, Envelope>> = firsts
        .iter()
        .map(|(l, (e, _))| Panel { title: format!("{l} (seed {first_seed})"), data: e, y: y.clone() })
        .collect();
    let what = what.chars().next().map_or(String::new(), |c| c.to_uppercase().chain(what.chars().skip(1)).collect());
    let title = format!("{what} ({measured}): {system} (cf. seed Figure 6)");
    fmi_master::plot::time_histories(fig6, &title, &panels, true)?;
    let marks: Vec<Mark> =
        [(dist, "disturbance"), (tooth, "tooth passing Z·N/60"), (natural, "first natural frequency")]
            .into_iter()
            .filter_map(|(f, label)| f.map(|freq| Mark { freq, label: label.into() }))
            .collect();
    // the spectra in the unit of the time histories
    let y = Quantity { label: y.label.replacen(name, &format!("|P1| of {name}"), 1), ..y };
    let panels: Vec<Panel<'_, Spectrum>> = firsts
        .iter()
        .map(|(l, (_, s))| Panel { title: format!("{l} (seed {first_seed})"), data: s, y: y.clone() })
        .collect();
    let title = format!("Single-sided amplitude spectrum |P1(f)| of {measured}: {system} (cf. seed Figure 7)");
    fmi_master::plot::spectra(fig7, &title, &panels, 400.0, &marks, true)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn titles_name_the_system_by_its_file_name_and_the_overrides() {
        let sys =
            SystemFile::from_text(packaging::CLOSED_LOOP_SSD, "/some/where/ClosedLoop.ssd", Path::new("/nowhere"))
                .unwrap();
        let mut spec = MainJobSpec {
            system: Some("/some/where/ClosedLoop.ssd".into()),
            fmu_dir: "/nowhere".into(),
            seeds: vec![1],
            stop: None,
            step: None,
            csv_interval: 1e-4,
            cases: vec![("Open loop".into(), "off".into())],
            overrides: vec![],
        };
        assert_eq!(system_label(&spec, &sys), "ClosedLoop.ssd");
        spec.overrides = vec!["plant.depth=0.002".into(), "plant.seed=3".into()];
        assert_eq!(system_label(&spec, &sys), "ClosedLoop.ssd with --set plant.depth=0.002, plant.seed=3");
    }
}
