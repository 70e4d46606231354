//! PNG plots with plotters: stacked time histories (min/max envelopes, so a
//! 3-million-sample run draws as fast and as faithfully as a short one) and
//! single-sided amplitude spectra with marked reference frequencies, in the
//! style of the seed's Figures 6 and 7.
//!
//! The CI machine has no system fonts: a TrueType font shipped inside the
//! crates.io crate `epaint_default_fonts` (Ubuntu Light) is registered with
//! plotters before drawing.

use crate::csv::CsvError;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// Errors of the plot functions.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The CSV to plot could not be read.
    #[error(transparent)]
    Csv(#[from] CsvError),
    /// The data cannot be plotted (missing column, too few rows).
    #[error("{0}")]
    Data(String),
    /// Drawing or writing the PNG failed.
    #[error("cannot draw {}: {message}", path.display())]
    Draw {
        /// The PNG file.
        path: PathBuf,
        /// The plotting library's message.
        message: String,
    },
}

/// What the drawing code's `?` collects (plotters' error types are generic).
pub type DrawError = Box<dyn std::error::Error + Send + Sync>;

/// A drawing function's result as a [`PlotError`] naming the file.
pub fn drawn(path: &Path, r: Result<(), DrawError>) -> Result<(), PlotError> {
    r.map_err(|e| PlotError::Draw { path: path.to_path_buf(), message: e.to_string() })
}

/// The font family every plot uses (registered by [`register_font`]).
pub const FONT: &str = "sans-serif";

/// Register the shipped TrueType font with plotters (once per process); call before drawing text.
pub fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a valid TTF compiled into the binary; a failure here
        // would be a packaging bug, reported on first use of text.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT);
    });
}

/// A white 1400-pixel-wide canvas with a title row and `n` stacked panels.
type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
fn stacked<'a>(path: &'a Path, title: &str, n: usize) -> Result<(Area<'a>, Vec<Area<'a>>), DrawError> {
    register_font();
    let root = BitMapBackend::new(path, (1400, 220 * n as u32 + 60)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, body) = root.split_vertically(50);
    top.titled(title, (FONT, 26))?;
    Ok((root, body.split_evenly((n, 1))))
}

/// Min/max envelope of a long signal in `bins` time bins (for drawing).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Envelope {
    t0: f64,
    t1: f64,
    /// Per bin: (min, max); NaN if empty.
    pub bins: Vec<(f64, f64)>,
}

impl Envelope {
    /// An empty envelope over `[t0, t1]`.
    pub fn new(t0: f64, t1: f64, bins: usize) -> Envelope {
        Envelope { t0, t1, bins: vec![(f64::NAN, f64::NAN); bins.max(1)] }
    }

    /// Add a sample.
    #[inline]
    pub fn add(&mut self, t: f64, x: f64) {
        let n = self.bins.len();
        let i = (((t - self.t0) / (self.t1 - self.t0)) * n as f64).floor();
        let i = (i.max(0.0) as usize).min(n - 1);
        let b = &mut self.bins[i];
        if b.0.is_nan() || x < b.0 {
            b.0 = x;
        }
        if b.1.is_nan() || x > b.1 {
            b.1 = x;
        }
    }

    fn time(&self, i: usize) -> f64 {
        self.t0 + (i as f64 + 0.5) / self.bins.len() as f64 * (self.t1 - self.t0)
    }

    fn extent(&self) -> f64 {
        self.bins.iter().filter(|b| !b.0.is_nan()).map(|b| b.0.abs().max(b.1.abs())).fold(0.0, f64::max)
    }
}

/// One panel of a stacked plot.
pub struct Panel<'a, T> {
    /// Panel title (e.g. the controller).
    pub title: String,
    /// Data.
    pub data: &'a T,
}

const COLORS: [RGBColor; 4] =
    [RGBColor(31, 119, 180), RGBColor(255, 127, 14), RGBColor(44, 160, 44), RGBColor(214, 39, 40)];

/// Stacked time histories (envelopes), common y range; `scale` multiplies
/// values (e.g. 1e6 for µm) and `unit` labels the y axis.
pub fn time_histories(
    path: &Path,
    title: &str,
    panels: &[Panel<'_, Envelope>],
    scale: f64,
    unit: &str,
) -> Result<(), PlotError> {
    drawn(path, draw_time_histories(path, title, panels, scale, unit))
}

fn draw_time_histories(
    path: &Path,
    title: &str,
    panels: &[Panel<'_, Envelope>],
    scale: f64,
    unit: &str,
) -> Result<(), DrawError> {
    let (root, areas) = stacked(path, title, panels.len())?;
    let ymax = panels.iter().map(|p| p.data.extent()).fold(0.0, f64::max) * scale * 1.05;
    let ymax = if ymax > 0.0 { ymax } else { 1.0 };
    for (k, (area, p)) in areas.iter().zip(panels).enumerate() {
        let e = p.data;
        let mut chart = ChartBuilder::on(area)
            .caption(&p.title, (FONT, 18))
            .margin(8)
            .margin_right(30)
            .x_label_area_size(35)
            .y_label_area_size(70)
            .build_cartesian_2d(e.t0..e.t1, -ymax..ymax)?;
        chart
            .configure_mesh()
            .x_desc("time [s]")
            .y_desc(unit)
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 15))
            .draw()?;
        let color = COLORS[k % COLORS.len()];
        // One vertical segment per bin from min to max, joined: the envelope.
        let mut pts = Vec::with_capacity(2 * e.bins.len());
        for (i, b) in e.bins.iter().enumerate() {
            if b.0.is_nan() {
                continue;
            }
            let t = e.time(i);
            pts.push((t, b.0 * scale));
            pts.push((t, b.1 * scale));
        }
        chart.draw_series(LineSeries::new(pts, color.stroke_width(1)))?;
    }
    root.present()?;
    Ok(())
}

/// A marked reference frequency.
#[derive(Clone, Debug)]
pub struct Mark {
    /// Frequency [Hz].
    pub freq: f64,
    /// Legend text.
    pub label: String,
}

/// Stacked single-sided amplitude spectra up to `f_max`, with vertical marks.
pub fn spectra(
    path: &Path,
    title: &str,
    panels: &[Panel<'_, crate::spectrum::Spectrum>],
    f_max: f64,
    marks: &[Mark],
    scale: f64,
    unit: &str,
) -> Result<(), PlotError> {
    drawn(path, draw_spectra(path, title, panels, f_max, marks, scale, unit))
}

fn draw_spectra(
    path: &Path,
    title: &str,
    panels: &[Panel<'_, crate::spectrum::Spectrum>],
    f_max: f64,
    marks: &[Mark],
    scale: f64,
    unit: &str,
) -> Result<(), DrawError> {
    let (root, areas) = stacked(path, title, panels.len())?;
    let ymax = panels
        .iter()
        .flat_map(|p| p.data.freq.iter().zip(&p.data.amp).filter(|(f, _)| **f > 0.5 && **f <= f_max).map(|(_, a)| *a))
        .fold(0.0, f64::max)
        * scale
        * 1.1;
    let ymax = if ymax > 0.0 { ymax } else { 1.0 };
    let mark_colors = [RGBColor(120, 120, 120), RGBColor(200, 0, 150), RGBColor(0, 150, 150)];
    for (k, (area, p)) in areas.iter().zip(panels).enumerate() {
        let mut chart = ChartBuilder::on(area)
            .caption(&p.title, (FONT, 18))
            .margin(8)
            .margin_right(30)
            .x_label_area_size(35)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..f_max, 0.0..ymax)?;
        chart
            .configure_mesh()
            .x_desc("frequency [Hz]")
            .x_label_formatter(&|f| format!("{f:.0}"))
            .y_desc(unit)
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 15))
            .draw()?;
        let color = COLORS[k % COLORS.len()];
        let pts = p.data.freq.iter().zip(&p.data.amp).filter(|(f, _)| **f <= f_max).map(|(f, a)| (*f, a * scale));
        chart.draw_series(LineSeries::new(pts, color.stroke_width(1)))?;
        for (j, m) in marks.iter().enumerate() {
            let c = mark_colors[j % mark_colors.len()];
            chart
                .draw_series(LineSeries::new(vec![(m.freq, 0.0), (m.freq, ymax)], c.stroke_width(1)))?
                .label(format!("{} ({:.1} Hz)", m.label, m.freq))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        }
        if !marks.is_empty() {
            chart
                .configure_series_labels()
                .label_font((FONT, 13))
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .position(SeriesLabelPosition::UpperRight)
                .draw()?;
        }
    }
    root.present()?;
    Ok(())
}

/// Plot columns of a CSV (`cosim plot`): time histories of each, and
/// optionally their spectra up to `f_max` with marks.
pub fn plot_csv(csv: &Path, vars: &[String], out: &Path, spectrum: Option<(f64, Vec<Mark>)>) -> Result<(), PlotError> {
    let table = crate::csv::read_csv(csv)?;
    let data = |m: String| PlotError::Data(m);
    let time = table.column("time").ok_or_else(|| data(format!("{} has no time column", csv.display())))?.to_vec();
    if time.len() < 2 {
        return Err(data(format!("{} has fewer than two rows", csv.display())));
    }
    let names: Vec<String> = if vars.is_empty() { table.names[1..].to_vec() } else { vars.to_vec() };
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
            specs.push(crate::spectrum::single_sided(col, 1.0 / dt));
        }
    }
    let panels: Vec<Panel<'_, Envelope>> =
        names.iter().zip(&envs).map(|(n, e)| Panel { title: n.clone(), data: e }).collect();
    time_histories(out, &format!("{}", csv.display()), &panels, 1.0, "value")?;
    if let Some((f_max, marks)) = spectrum {
        let sp =
            out.with_file_name(format!("{}_spectrum.png", out.file_stem().and_then(|s| s.to_str()).unwrap_or("plot")));
        let panels: Vec<Panel<'_, crate::spectrum::Spectrum>> =
            names.iter().zip(&specs).map(|(n, s)| Panel { title: n.clone(), data: s }).collect();
        spectra(
            &sp,
            &format!("{} — single-sided amplitude spectrum", csv.display()),
            &panels,
            f_max,
            &marks,
            1.0,
            "|P1(f)|",
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn envelope_bins_min_and_max() {
        let mut e = Envelope::new(0.0, 1.0, 4);
        for i in 0..1000 {
            let t = i as f64 / 1000.0;
            e.add(t, (t * 40.0).sin() * if t < 0.5 { 1.0 } else { 2.0 });
        }
        assert!(e.bins[0].0 < -0.99 && e.bins[0].1 > 0.99);
        assert!(e.bins[3].0 < -1.98 && e.bins[3].1 > 1.98);
        approx::assert_abs_diff_eq!(e.extent(), 2.0, epsilon = 1e-3);
    }

    #[test]
    fn plots_are_written_with_the_shipped_font() {
        let dir = tempfile::tempdir().unwrap();
        let mut e = Envelope::new(0.0, 2.0, 300);
        let fs = 2000.0;
        let x: Vec<f64> =
            (0..4000).map(|i| (2.0 * std::f64::consts::PI * 133.3 * i as f64 / fs).sin() * 1e-6).collect();
        for (i, v) in x.iter().enumerate() {
            e.add(i as f64 / fs, *v);
        }
        let p = dir.path().join("t.png");
        time_histories(&p, "test", &[Panel { title: "x".into(), data: &e }], 1e6, "x [µm]").unwrap();
        let s = crate::spectrum::single_sided(&x, fs).up_to(400.0);
        let q = dir.path().join("s.png");
        spectra(
            &q,
            "test",
            &[Panel { title: "x".into(), data: &s }],
            400.0,
            &[Mark { freq: 133.3, label: "tooth".into() }],
            1e6,
            "µm",
        )
        .unwrap();
        for f in [p, q] {
            let bytes = std::fs::read(&f).unwrap();
            assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{} is not a PNG", f.display());
            assert!(bytes.len() > 5000, "{} is suspiciously small", f.display());
        }
    }
}
