//! The studies' figures: line plots over a numeric or categorical axis, and heat maps on a
//! common colour scale (`fmi_master::plot`'s canvas, font and axes: round ticks with the
//! decimals they need). A title may hold a second line (what was run) after a `\n`; legends
//! and panels name the controllers as the papers do ([`display_name`]).

use fmi_master::plot::{Axis, DrawError, FONT, LegendEntry, PALETTE, PlotError, canvas, drawn, legend_row, titled};
use plotters::prelude::*;
use std::path::Path;

/// A series or panel name as a figure shows it: the controller structures' item names as the
/// papers write them (`off` → open loop, `adrc_fopid` → ADRC-FOPID), anything else unchanged.
pub fn display_name(name: &str) -> String {
    match name {
        "off" => "open loop".into(),
        "pid" => "PID".into(),
        "fopid" => "FOPID".into(),
        "adrc_fopid" => "ADRC-FOPID".into(),
        _ => name.into(),
    }
}

/// A named curve.
pub type Curve = (String, Vec<(f64, f64)>);

/// Curves `y(x)` on common axes (markers at the points).
pub fn plot_xy(path: &Path, title: &str, xlabel: &str, ylabel: &str, curves: &[Curve]) -> Result<(), PlotError> {
    drawn(path, draw_xy(path, title, xlabel, ylabel, curves, None))
}

/// Values per sample point (1, 2, …, n on the x axis), one curve per series.
pub fn plot_points(
    path: &Path,
    title: &str,
    labels: &[String],
    series: &[(String, Vec<f64>)],
    ylabel: &str,
) -> Result<(), PlotError> {
    let curves: Vec<Curve> = series
        .iter()
        .map(|(n, v)| (n.clone(), v.iter().enumerate().map(|(i, y)| ((i + 1) as f64, *y)).collect()))
        .collect();
    drawn(path, draw_xy(path, title, "sample point (numbered as in the table)", ylabel, &curves, Some(labels.len())))
}

fn draw_xy(
    path: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    curves: &[Curve],
    categories: Option<usize>,
) -> Result<(), DrawError> {
    let pts = || curves.iter().flat_map(|c| c.1.iter()).filter(|p| p.0.is_finite() && p.1.is_finite());
    let (x0, x1) = pts().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| (a.0.min(p.0), a.1.max(p.0)));
    let y1 = pts().fold(0.0f64, |a, p| a.max(p.1));
    if !(x0.is_finite() && x1 >= x0 && y1 > 0.0) {
        return Err("nothing finite to plot".into());
    }
    // categories 1…n sit half a step inside the frame; numbers 3 % of their span
    let pad = match categories {
        Some(_) => 0.5,
        None if x1 > x0 => (x1 - x0) * 0.03,
        None => (x0.abs() * 0.05).max(1e-9),
    };
    let x_axis = match categories {
        Some(n) => Axis::linear(x0 - pad, x1 + pad, n + 2),
        None => Axis::linear(x0 - pad, x1 + pad, 11),
    };
    let root = canvas(path, (1000, 600 + 22 * title.lines().count().saturating_sub(1) as u32))?;
    let below = titled(&root, title, 22)?;
    // one curve: the axis says what it is; more: one legend row under the title, off the data
    let colour = |i: usize| PALETTE[i % PALETTE.len()];
    let legend: Vec<LegendEntry> = curves.iter().enumerate().map(|(i, c)| (display_name(&c.0), colour(i))).collect();
    let (key, area) = below.split_vertically(if curves.len() > 1 { 30 } else { 0 });
    if curves.len() > 1 {
        legend_row(&key, &legend, None)?;
    }
    let mut chart = ChartBuilder::on(&area)
        .margin(15)
        .margin_top(8)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(x_axis, Axis::linear_rounded(0.0, y1 * 1.03, 9))?;
    chart.configure_mesh().x_desc(xlabel).y_desc(ylabel).label_style((FONT, 15)).axis_desc_style((FONT, 16)).draw()?;
    for (i, (_, p)) in curves.iter().enumerate() {
        let c = colour(i);
        let p: Vec<(f64, f64)> = p.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
        chart.draw_series(LineSeries::new(p.clone(), c.stroke_width(2)))?;
        chart.draw_series(p.into_iter().map(|q| Circle::new(q, 4, c.filled())))?;
    }
    root.present()?;
    Ok(())
}

/// One heat map: `values[i][j]` at (`x[j]`, `y[i]`).
pub struct Heat<'a> {
    /// Panel title.
    pub title: String,
    /// Cell values.
    pub values: &'a [Vec<f64>],
}

/// A colour on a blue → yellow → red scale for `v/vmax` (clamped).
fn colour(f: f64) -> RGBColor {
    let f = f.clamp(0.0, 1.0);
    let lerp = |a: f64, b: f64, t: f64| (a + (b - a) * t).round() as u8;
    if f < 0.5 {
        let t = f / 0.5;
        RGBColor(lerp(30.0, 255.0, t), lerp(60.0, 230.0, t), lerp(200.0, 60.0, t))
    } else {
        let t = (f - 0.5) / 0.5;
        RGBColor(255, lerp(230.0, 20.0, t), lerp(60.0, 20.0, t))
    }
}

/// Heat maps side by side on one colour scale `[0, vmax]` (a colour bar on the right); axes
/// `x` (columns) and `y` (rows) are the cell centres.
#[allow(clippy::too_many_arguments)]
pub fn heat_maps(
    path: &Path,
    title: &str,
    (xlabel, x): (&str, &[f64]),
    (ylabel, y): (&str, &[f64]),
    panels: &[Heat<'_>],
    vmax: f64,
    unit: &str,
) -> Result<(), PlotError> {
    drawn(path, draw_heat(path, title, (xlabel, x), (ylabel, y), panels, vmax, unit))
}

fn draw_heat(
    path: &Path,
    title: &str,
    (xlabel, x): (&str, &[f64]),
    (ylabel, y): (&str, &[f64]),
    panels: &[Heat<'_>],
    vmax: f64,
    unit: &str,
) -> Result<(), DrawError> {
    if x.len() < 2 || y.len() < 2 || panels.is_empty() || !(vmax.is_finite() && vmax > 0.0) {
        return Err("a heat map needs at least 2 × 2 cells and a positive colour scale".into());
    }
    let (dx, dy) = ((x[1] - x[0]) / 2.0, (y[1] - y[0]) / 2.0);
    let root =
        canvas(path, (560 * panels.len() as u32 + 150, 560 + 22 * title.lines().count().saturating_sub(1) as u32))?;
    let below = titled(&root, title, 22)?;
    let (maps, bar) = below.split_horizontally(560 * panels.len() as u32);
    for (area, p) in maps.split_evenly((1, panels.len())).iter().zip(panels) {
        let mut chart = ChartBuilder::on(area)
            .caption(display_name(&p.title), (FONT, 18))
            .margin(10)
            .x_label_area_size(45)
            .y_label_area_size(55)
            .build_cartesian_2d(
                Axis::linear(x[0] - dx, x[x.len() - 1] + dx, 6),
                Axis::linear(y[0] - dy, y[y.len() - 1] + dy, 8),
            )?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(xlabel)
            .y_desc(ylabel)
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 15))
            .draw()?;
        chart.draw_series(p.values.iter().enumerate().flat_map(|(i, row)| {
            row.iter().enumerate().map(move |(j, v)| {
                let c = if v.is_finite() { colour(v / vmax) } else { RGBColor(128, 128, 128) };
                Rectangle::new([(x[j] - dx, y[i] - dy), (x[j] + dx, y[i] + dy)], c.filled())
            })
        }))?;
    }
    // the colour bar, its axis named with the unit
    let mut cb = ChartBuilder::on(&bar)
        .margin(20)
        .margin_top(48)
        .margin_bottom(55)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..1.0, Axis::linear(0.0, vmax, 9))?;
    cb.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(unit)
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .draw()?;
    let n = 100;
    cb.draw_series((0..n).map(|k| {
        let (a, b) = (vmax * k as f64 / n as f64, vmax * (k + 1) as f64 / n as f64);
        Rectangle::new([(0.0, a), (1.0, b)], colour((a + b) / 2.0 / vmax).filled())
    }))?;
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_are_written() {
        let dir = std::env::temp_dir().join(format!("figures-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let c: Vec<Curve> =
            vec![("a".into(), vec![(1.0, 2.0), (2.0, 3.0)]), ("b".into(), vec![(1.0, 1.0), (2.0, 4.0)])];
        plot_xy(&dir.join("xy.png"), "t", "x", "y", &c).unwrap();
        let v = vec![vec![1.0, 2.0, 3.0], vec![4.0, 5.0, f64::NAN]];
        let h = [Heat { title: "p".into(), values: &v }, Heat { title: "q".into(), values: &v }];
        heat_maps(&dir.join("h.png"), "t", ("x", &[1.0, 2.0, 3.0]), ("y", &[0.5, 0.75]), &h, 5.0, "µm").unwrap();
        for f in ["xy.png", "h.png"] {
            assert_eq!(&std::fs::read(dir.join(f)).unwrap()[1..4], b"PNG");
        }
        assert!(heat_maps(&dir.join("bad.png"), "t", ("x", &[1.0]), ("y", &[1.0]), &h, 5.0, "").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
