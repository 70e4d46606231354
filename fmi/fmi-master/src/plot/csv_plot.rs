//! `cosim plot`: the columns of a results CSV as time histories (and spectra), each labelled
//! with its variable's unit and description from the model description of the FMU it comes
//! from (a column `component.variable` of a system, a bare `variable` of a single-FMU run).

use super::{Envelope, Mark, Panel, PlotError, Quantity, spectra, time_histories};
use crate::SystemFile;
use crate::spectrum::{Spectrum, single_sided};
use std::collections::BTreeMap;
use std::path::Path;

/// What a model description says of a variable.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Variable {
    /// Unit (empty when it declares none).
    pub unit: String,
    /// Description.
    pub description: Option<String>,
}

/// The variables behind CSV columns of a run of `sys`: `component.variable` (the component
/// name has no dot; the variable name may), or the bare variable name when `sys` is a single
/// FMU. `None` for a column that names no variable of the system's FMUs.
pub fn variables(sys: &SystemFile, columns: &[String]) -> Result<Vec<Option<Variable>>, PlotError> {
    let mut descriptions = BTreeMap::new();
    let mut out = Vec::with_capacity(columns.len());
    for col in columns {
        let found = if sys.is_single_fmu() {
            sys.desc.components.first().map(|c| (c, col.as_str()))
        } else {
            col.split_once('.')
                .and_then(|(comp, var)| sys.desc.components.iter().find(|c| c.name == comp).map(|c| (c, var)))
        };
        let Some((component, var)) = found else {
            out.push(None);
            continue;
        };
        if !descriptions.contains_key(&component.name) {
            let path = sys.fmu_path(component).map_err(|e| PlotError::Data(e.to_string()))?;
            let md = crate::import::read_model_description(&path).map_err(|e| PlotError::Data(e.to_string()))?;
            descriptions.insert(component.name.clone(), md);
        }
        out.push(
            descriptions[&component.name].variable(var).map(|v| Variable {
                unit: v.unit().unwrap_or_default().to_string(),
                description: v.description.clone(),
            }),
        );
    }
    Ok(out)
}

/// Plot columns of a CSV (`cosim plot`): time histories of each, and optionally their spectra
/// within `(0, f_max]` with marks. With `system` (the system the CSV comes from), every axis
/// carries its variable's unit and every panel its description.
pub fn plot_csv(
    csv: &Path,
    vars: &[String],
    out: &Path,
    spectrum: Option<(f64, Vec<Mark>)>,
    system: Option<&SystemFile>,
) -> Result<(), PlotError> {
    let table = crate::csv::read_csv(csv)?;
    let data = |m: String| PlotError::Data(m);
    let time = table.column("time").ok_or_else(|| data(format!("{} has no time column", csv.display())))?.to_vec();
    if time.len() < 2 {
        return Err(data(format!("{} has fewer than two rows", csv.display())));
    }
    let names: Vec<String> = if vars.is_empty() { table.names[1..].to_vec() } else { vars.to_vec() };
    let info = match system {
        Some(sys) => variables(sys, &names)?,
        None => vec![None; names.len()],
    };
    let mut envs = Vec::new();
    let mut specs = Vec::new();
    for n in &names {
        let col = table
            .column(n)
            .ok_or_else(|| data(format!("{} has no column {n} (it has: {})", csv.display(), table.names.join(", "))))?;
        let mut e = Envelope::new(time[0], *time.last().expect("two rows"), 1200);
        for (t, x) in time.iter().zip(col) {
            e.add(*t, *x);
        }
        envs.push(e);
        if spectrum.is_some() {
            let dt = (time[time.len() - 1] - time[0]) / (time.len() - 1) as f64;
            specs.push(single_sided(col, 1.0 / dt));
        }
    }
    let file = csv.file_name().map_or_else(|| csv.display().to_string(), |f| f.to_string_lossy().into_owned());
    let from = system.map(|s| format!(" (a run of {})", file_name(&s.origin))).unwrap_or_default();
    let bare = system.is_some_and(|s| s.is_single_fmu());
    let extents: Vec<f64> = envs.iter().map(Envelope::extent).collect();
    let panels: Vec<Panel<'_, Envelope>> = labels(&names, &info, &extents, bare, "")
        .into_iter()
        .zip(&envs)
        .map(|((title, y), data)| Panel { title, data, y })
        .collect();
    time_histories(out, &format!("{file}{from}"), &panels, false)?;
    if let Some((f_max, marks)) = spectrum {
        let sp =
            out.with_file_name(format!("{}_spectrum.png", out.file_stem().and_then(|s| s.to_str()).unwrap_or("plot")));
        let peak = |s: &Spectrum| {
            s.freq.iter().zip(&s.amp).skip(1).filter(|(f, _)| **f <= f_max).map(|(_, a)| *a).fold(0.0, f64::max)
        };
        let peaks: Vec<f64> = specs.iter().map(peak).collect();
        let panels: Vec<Panel<'_, Spectrum>> = labels(&names, &info, &peaks, bare, "|P1| of ")
            .into_iter()
            .zip(&specs)
            .map(|((title, y), data)| Panel { title, data, y })
            .collect();
        let title = format!("{file}{from}: single-sided amplitude spectra |P1(f)|");
        spectra(&sp, &title, &panels, f_max, &marks, false)?;
    }
    Ok(())
}

/// Panel titles and y axes of CSV columns: the title is the column and its variable's
/// description, the axis `{prefix}{variable} [unit]`, scaled for values of magnitude `extents`
/// (the component left out of the axis unless the columns are bare variable names).
fn labels(
    names: &[String],
    info: &[Option<Variable>],
    extents: &[f64],
    bare: bool,
    prefix: &str,
) -> Vec<(String, Quantity)> {
    names
        .iter()
        .zip(info)
        .zip(extents)
        .map(|((n, v), extent)| {
            let title = match v.as_ref().and_then(|v| v.description.as_ref()) {
                Some(d) => format!("{n}: {d}"),
                None => n.clone(),
            };
            let var = if bare { n.as_str() } else { n.split_once('.').map_or(n.as_str(), |p| p.1) };
            let unit = v.as_ref().map_or("", |v| v.unit.as_str());
            (title, Quantity::scaled(&format!("{prefix}{var}"), unit, *extent))
        })
        .collect()
}

/// The last component of a path as text.
fn file_name(path: &str) -> String {
    Path::new(path).file_name().map_or_else(|| path.to_string(), |f| f.to_string_lossy().into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn closed_loop() -> SystemFile {
        let ssp = packaging::fmu_dir().join("ClosedLoop.ssp");
        assert!(ssp.is_file(), "build the FMUs first: cargo run --release -p packaging");
        SystemFile::open(&ssp, None).unwrap()
    }

    #[test]
    fn columns_take_unit_and_description_from_the_model_description() {
        let sys = closed_loop();
        let names: Vec<String> = ["plant.x", "controller.u", "plant.ghost", "nobody.x"].map(String::from).to_vec();
        let info = variables(&sys, &names).unwrap();
        assert_eq!(info[0].as_ref().map(|v| v.unit.as_str()), Some("m"));
        assert!(info[0].as_ref().unwrap().description.is_some(), "{info:?}");
        assert_eq!(info[1].as_ref().map(|v| v.unit.as_str()), Some("N"));
        assert_eq!(info[2..], [None, None]);
        // the y labels: the variable, its unit with the prefix its magnitude asks for
        let l = labels(&names[..2], &info[..2], &[3.6e-5, 27.0], false, "");
        assert_eq!(l[0].1, Quantity { scale: 1e6, label: "x [µm]".into() });
        assert_eq!(l[1].1.label, "u [N]");
        assert!(l[0].0.starts_with("plant.x: "), "{}", l[0].0);
        // without the system, nothing to say but the magnitude
        assert_eq!(labels(&names[..1], &[None], &[3.6e-5], false, "")[0].1.label, "x [×10^-6]");
    }

    #[test]
    fn a_csv_is_plotted_with_units() {
        let dir = tempfile::tempdir().unwrap();
        let csv = dir.path().join("r.csv");
        let mut text = String::from("\"time\",\"plant.x\",\"controller.u\"\n");
        for i in 0..2000 {
            let t = i as f64 * 1e-4;
            let w = (2.0 * std::f64::consts::PI * 133.3 * t).sin();
            text.push_str(&format!("{t},{},{}\n", 3e-6 * w + 1e-6, 20.0 * w));
        }
        std::fs::write(&csv, text).unwrap();
        let out = dir.path().join("p.png");
        let marks = vec![Mark { freq: 133.3, label: "tooth passing".into() }];
        plot_csv(&csv, &[], &out, Some((1000.0, marks)), Some(&closed_loop())).unwrap();
        for f in [out.clone(), dir.path().join("p_spectrum.png")] {
            assert!(std::fs::metadata(&f).unwrap().len() > 5000, "{}", f.display());
        }
    }
}
