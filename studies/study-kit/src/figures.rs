//! The studies' figures: line plots over a numeric or categorical axis, and heat maps on a
//! common colour scale (plotters' bitmap backend, the font `fmi_master::plot` registers).

use fmi_master::plot::{DrawError, FONT, PlotError, drawn, register_font};
use plotters::prelude::*;
use std::path::Path;

/// A named curve.
pub type Curve = (String, Vec<(f64, f64)>);

const COLORS: [RGBColor; 6] = [BLACK, BLUE, RED, GREEN, MAGENTA, CYAN];

/// Curves `y(x)` on common axes (markers at the points).
pub fn plot_xy(path: &Path, title: &str, xlabel: &str, ylabel: &str, curves: &[Curve]) -> Result<(), PlotError> {
    register_font();
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
    register_font();
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
    let pad = ((x1 - x0) * 0.03).max(0.5);
    let root = BitMapBackend::new(path, (1000, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(x0 - pad..x1 + pad, 0.0..y1 * 1.08)?;
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(xlabel).y_desc(ylabel).label_style((FONT, 15));
    let integer = |v: &f64| format!("{v:.0}");
    if let Some(n) = categories {
        mesh.x_labels(n + 2).x_label_formatter(&integer);
    }
    mesh.draw()?;
    for (i, (name, p)) in curves.iter().enumerate() {
        let c = COLORS[i % COLORS.len()];
        let p: Vec<(f64, f64)> = p.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
        chart
            .draw_series(LineSeries::new(p.clone(), c.stroke_width(2)))?
            .label(name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        chart.draw_series(p.into_iter().map(|q| Circle::new(q, 4, c.filled())))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((FONT, 15))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
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
    register_font();
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
    let root = BitMapBackend::new(path, (560 * panels.len() as u32 + 140, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, (FONT, 22))?;
    let (maps, bar) = root.split_horizontally(560 * panels.len() as u32);
    for (area, p) in maps.split_evenly((1, panels.len())).iter().zip(panels) {
        let mut chart = ChartBuilder::on(area)
            .caption(&p.title, (FONT, 18))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(x[0] - dx..x[x.len() - 1] + dx, y[0] - dy..y[y.len() - 1] + dy)?;
        chart.configure_mesh().disable_mesh().x_desc(xlabel).y_desc(ylabel).label_style((FONT, 14)).draw()?;
        chart.draw_series(p.values.iter().enumerate().flat_map(|(i, row)| {
            row.iter().enumerate().map(move |(j, v)| {
                let c = if v.is_finite() { colour(v / vmax) } else { RGBColor(128, 128, 128) };
                Rectangle::new([(x[j] - dx, y[i] - dy), (x[j] + dx, y[i] + dy)], c.filled())
            })
        }))?;
    }
    let mut cb = ChartBuilder::on(&bar)
        .margin(20)
        .y_label_area_size(60)
        .caption(unit, (FONT, 14))
        .build_cartesian_2d(0.0..1.0, 0.0..vmax)?;
    cb.configure_mesh().disable_mesh().disable_x_axis().label_style((FONT, 14)).draw()?;
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
