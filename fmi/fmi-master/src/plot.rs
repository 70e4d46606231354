//! PNG plots with plotters: stacked time histories (min/max envelopes, so a
//! 3-million-sample run draws as fast and as faithfully as a short one) and
//! single-sided amplitude spectra with marked reference frequencies, in the
//! style of the seed's Figures 6 and 7; `cosim plot` of a results CSV with
//! the units of the FMUs' model descriptions.
//!
//! Every figure is meant to go into a paper as it is: units on every axis
//! ([`Quantity`]), ticks at round values with the decimals they need
//! ([`Axis`]), one legend per figure, the x axis named once under the
//! bottom panel of a stack.
//!
//! The CI machine has no system fonts: a TrueType font shipped inside the
//! crates.io crate `epaint_default_fonts` (Ubuntu Light) is registered with
//! plotters, and text is placed by [`Canvas`] (plotters' own ab_glyph
//! layout drops the glyphs' side bearings: `canvas` says more).

mod axis;
mod canvas;
mod csv_plot;
mod spectra;

pub use axis::{Axis, Quantity, nice_step, takes_prefix};
pub use canvas::{Area, Canvas, canvas};
pub use csv_plot::{Variable, plot_csv, variables};
pub use spectra::{Mark, frequency_range, spectra};

use crate::csv::CsvError;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
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

/// Line colours of the panels and curves (colour-blind-safe "tab10" order).
pub const COLORS: [RGBColor; 4] =
    [RGBColor(31, 119, 180), RGBColor(255, 127, 14), RGBColor(44, 160, 44), RGBColor(214, 39, 40)];

/// Colours of the curves that share one axis: black first (the reference, e.g. the open loop),
/// then a colour-blind-safe order.
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 0, 0),
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
];

/// One legend entry: a line of this colour, and its text.
pub type LegendEntry = (String, RGBColor);

/// A legend as one centred row of entries (a short line and its text), drawn once for a figure.
pub fn legend_row(area: &Area<'_>, entries: &[LegendEntry], note: Option<&str>) -> Result<(), DrawError> {
    let style = TextStyle::from((FONT, 15).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    let (line, gap) = (24, 28);
    let widths: Vec<i32> = entries
        .iter()
        .map(|(t, _)| area.estimate_text_size(t, &style).map(|s| s.0 as i32))
        .collect::<Result<_, _>>()?;
    let note_w = match note {
        Some(n) => area.estimate_text_size(n, &style)?.0 as i32 + gap,
        None => 0,
    };
    let total: i32 = widths.iter().map(|w| line + 6 + w + gap).sum::<i32>() + note_w - gap;
    let (w, h) = area.dim_in_pixel();
    let (mut x, y) = (((w as i32 - total) / 2).max(0), h as i32 / 2);
    for ((text, color), tw) in entries.iter().zip(widths) {
        area.draw(&PathElement::new(vec![(x, y), (x + line, y)], color.stroke_width(2)))?;
        area.draw(&Text::new(text.clone(), (x + line + 6, y), style.clone()))?;
        x += line + 6 + tw + gap;
    }
    if let Some(n) = note {
        area.draw(&Text::new(n.to_string(), (x, y), style.color(&RGBColor(90, 90, 90))))?;
    }
    Ok(())
}

/// Draw `title` centred at the top of `area` — its first line at `size` px, further lines (a
/// subtitle: what was run) at 16 px — and return the area below it.
pub fn titled<'a>(area: &Area<'a>, title: &str, size: u32) -> Result<Area<'a>, DrawError> {
    let mut lines = title.lines();
    let first = lines.next().unwrap_or("");
    let rest: Vec<&str> = lines.collect();
    let (top, below) = area.split_vertically(title_height(title, size));
    let x = top.dim_in_pixel().0 as i32 / 2;
    let centred = |px: u32| TextStyle::from((FONT, px).into_font()).pos(Pos::new(HPos::Center, VPos::Center));
    top.draw(&Text::new(first.to_string(), (x, (size as i32 + 16) / 2), centred(size)))?;
    for (i, line) in rest.iter().enumerate() {
        let y = size as i32 + 16 + 22 * i as i32 + 8;
        top.draw(&Text::new(line.to_string(), (x, y), centred(16).color(&RGBColor(60, 60, 60))))?;
    }
    Ok(below)
}

/// The height [`titled`] takes for `title` at `size`.
pub fn title_height(title: &str, size: u32) -> u32 {
    size + 16 + 22 * title.lines().count().saturating_sub(1) as u32
}

/// A canvas 1400 pixels wide for `n` stacked panels under a title ([`titled`]) (and a legend row when
/// `legend` has entries or a note): the root and the panels' areas.
fn stacked<'a>(
    path: &'a Path,
    title: &str,
    (legend, note): (&[LegendEntry], Option<&str>),
    n: usize,
) -> Result<(Area<'a>, Vec<Area<'a>>), DrawError> {
    let legend_h = if legend.is_empty() && note.is_none() { 0 } else { 30 };
    let title_h = title_height(title, 24);
    let root = canvas(path, (1400, PANEL_H * n as u32 + title_h + legend_h + X_DESC_H))?;
    let below = titled(&root, title, 24)?;
    let (key, body) = below.split_vertically(legend_h);
    if legend_h > 0 {
        legend_row(&key, legend, note)?;
    }
    // equal panels; the last also holds the x axis' name
    let sizes: Vec<u32> = (1..n).map(|k| k as u32 * PANEL_H).collect();
    Ok((root, body.split_by_breakpoints(Vec::<u32>::new(), sizes).into_iter().collect()))
}

/// Height of one panel of a stack, and what the bottom panel adds for the x axis' name.
const PANEL_H: u32 = 210;
const X_DESC_H: u32 = 25;

/// A panel of a stack on `axes` with its caption and mesh drawn: the y axis named `y_desc`, the
/// x axis named only when `x_desc` is given (under the bottom panel).
fn panel_chart<'a, 'b>(
    area: &'a Area<'b>,
    caption: &str,
    axes: (Axis, Axis),
    (x_desc, y_desc): (Option<&str>, &str),
) -> Result<ChartContext<'a, Canvas<'b>, Cartesian2d<Axis, Axis>>, DrawError> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (FONT, 18))
        .margin(8)
        .margin_right(30)
        .x_label_area_size(if x_desc.is_some() { 30 + X_DESC_H } else { 30 })
        .y_label_area_size(80)
        .build_cartesian_2d(axes.0, axes.1)?;
    let mut mesh = chart.configure_mesh();
    mesh.y_desc(y_desc).label_style((FONT, 14)).axis_desc_style((FONT, 15));
    if let Some(x) = x_desc {
        mesh.x_desc(x);
    }
    mesh.draw()?;
    Ok(chart)
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

    /// The largest magnitude.
    pub fn extent(&self) -> f64 {
        let (lo, hi) = self.bounds();
        lo.abs().max(hi.abs())
    }

    /// The smallest and the largest value (NaN, NaN when empty).
    pub fn bounds(&self) -> (f64, f64) {
        let filled = self.bins.iter().filter(|b| !b.0.is_nan());
        filled.fold((f64::NAN, f64::NAN), |(lo, hi), b| (b.0.min(lo), b.1.max(hi)))
    }
}

/// One panel of a stacked plot.
pub struct Panel<'a, T> {
    /// Panel title (e.g. the controller).
    pub title: String,
    /// Data.
    pub data: &'a T,
    /// What the y axis shows (scale and label with unit).
    pub y: Quantity,
}

/// A y range for values within `[lo, hi]`: symmetric about 0 when they change sign, 5 % margins,
/// a small band around a constant.
fn y_span(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (-1.0, 1.0);
    }
    if hi - lo <= 1e-12 * hi.abs().max(lo.abs()) {
        let d = if hi == 0.0 { 1.0 } else { 0.05 * hi.abs() };
        return (lo - d, hi + d);
    }
    if lo < 0.0 && hi > 0.0 {
        let m = lo.abs().max(hi) * 1.05;
        return (-m, m);
    }
    let pad = 0.05 * (hi - lo);
    (if lo >= 0.0 && lo - pad < 0.0 { 0.0 } else { lo - pad }, hi + pad)
}

/// Stacked time histories (envelopes) on one time axis; each panel's values are multiplied by
/// its [`Quantity`]'s scale. `common_y`: one y range for all panels (to compare them), else each
/// its own.
pub fn time_histories(
    path: &Path,
    title: &str,
    panels: &[Panel<'_, Envelope>],
    common_y: bool,
) -> Result<(), PlotError> {
    drawn(path, draw_time_histories(path, title, panels, common_y))
}

fn draw_time_histories(
    path: &Path,
    title: &str,
    panels: &[Panel<'_, Envelope>],
    common_y: bool,
) -> Result<(), DrawError> {
    let (root, areas) = stacked(path, title, (&[], None), panels.len())?;
    let scaled = |p: &Panel<'_, Envelope>| {
        let (lo, hi) = p.data.bounds();
        (lo * p.y.scale, hi * p.y.scale)
    };
    let all = panels.iter().map(scaled).fold((f64::NAN, f64::NAN), |a, b| (a.0.min(b.0), a.1.max(b.1)));
    for (k, (area, p)) in areas.iter().zip(panels).enumerate() {
        let e = p.data;
        let (lo, hi) = if common_y { all } else { scaled(p) };
        let (y0, y1) = y_span(lo, hi);
        let x_desc = (k + 1 == panels.len()).then_some("time [s]");
        let axes = (Axis::linear(e.t0, e.t1, 9), Axis::linear(y0, y1, 9));
        let mut chart = panel_chart(area, &p.title, axes, (x_desc, &p.y.label))?;
        let color = COLORS[k % COLORS.len()];
        // One vertical segment per bin from min to max, joined: the envelope.
        let mut pts = Vec::with_capacity(2 * e.bins.len());
        for (i, b) in e.bins.iter().enumerate() {
            if b.0.is_nan() {
                continue;
            }
            let t = e.time(i);
            pts.push((t, b.0 * p.y.scale));
            pts.push((t, b.1 * p.y.scale));
        }
        chart.draw_series(LineSeries::new(pts, color.stroke_width(1)))?;
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // exact values are intended in these tests
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
    fn y_ranges_are_symmetric_across_zero_and_padded_otherwise() {
        let (lo, hi) = y_span(-3.0, 2.0);
        approx::assert_abs_diff_eq!(lo, -3.15, epsilon = 1e-12);
        approx::assert_abs_diff_eq!(hi, 3.15, epsilon = 1e-12);
        let (lo, hi) = y_span(10.0, 20.0);
        approx::assert_abs_diff_eq!(lo, 9.5);
        approx::assert_abs_diff_eq!(hi, 20.5);
        assert_eq!(y_span(0.0, 0.0), (-1.0, 1.0));
        assert_eq!(y_span(0.01, 1.0).0, 0.0, "a positive quantity near zero starts at zero");
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
        let y = Quantity::new("x", "µm", 1e6);
        time_histories(&p, "test", &[Panel { title: "x".into(), data: &e, y: y.clone() }], true).unwrap();
        let s = crate::spectrum::single_sided(&x, fs).up_to(400.0);
        let q = dir.path().join("s.png");
        let marks = [Mark { freq: 133.3, label: "tooth".into() }];
        spectra(&q, "test", &[Panel { title: "x".into(), data: &s, y }], 400.0, &marks, true).unwrap();
        for f in [p, q] {
            let bytes = std::fs::read(&f).unwrap();
            assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{} is not a PNG", f.display());
            assert!(bytes.len() > 5000, "{} is suspiciously small", f.display());
        }
    }
}
