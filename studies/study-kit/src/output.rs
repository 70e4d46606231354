//! CSV and PNG output of stability lobe diagrams.
//!
//! The PNG is drawn on `fmi_master::plot`'s canvas (the shipped font, round ticks; the CI
//! machine has no system fonts): the title (and a second line after a `\n`: what was run),
//! one legend row under it, the diagrams below.

use crate::figures::display_name;
use delay_stability::zero_order::CriticalPoint;
use fmi_master::plot::{Axis, DrawError, FONT, LegendEntry, PALETTE, PlotError, canvas, drawn, legend_row, titled};
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// One named diagram (critical depth vs speed).
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend name.
    pub name: String,
    /// Points on a common speed grid.
    pub points: Vec<CriticalPoint>,
}

/// CSV text: `rpm,b_lim_mm_<name>,...` then `f_chatter_hz_<name>,...` (all series on the same
/// speed grid; an infinite depth, no chatter root in the band, is written as `inf`).
pub fn diagrams_csv(series: &[Series]) -> String {
    let mut s = String::from("rpm");
    for se in series {
        let _ = write!(s, ",b_lim_mm_{}", se.name);
    }
    for se in series {
        let _ = write!(s, ",f_chatter_hz_{}", se.name);
    }
    s.push('\n');
    let n = series.first().map_or(0, |s| s.points.len());
    for i in 0..n {
        let _ = write!(s, "{:.4}", series[0].points[i].rpm);
        for se in series {
            let _ = write!(s, ",{:.6}", se.points[i].depth * 1e3);
        }
        for se in series {
            let _ = write!(s, ",{:.4}", se.points[i].chatter_hz);
        }
        s.push('\n');
    }
    s
}

/// Write [`diagrams_csv`] to a file, atomically: a reader never sees a partial file under the
/// final name.
pub fn write_csv(path: &Path, series: &[Series]) -> Result<(), crate::StudyError> {
    let tmp = path.with_extension("csv.partial");
    std::fs::write(&tmp, diagrams_csv(series)).map_err(|error| crate::StudyError::io(&tmp, error))?;
    std::fs::rename(&tmp, path).map_err(|error| crate::StudyError::io(path, error))
}

/// Plot several diagrams on common axes (depth in mm, linear; logarithmic when the curves span
/// more than a factor 20), PNG `width × height`.
pub fn plot_png(path: &Path, title: &str, series: &[Series], width: u32, height: u32) -> Result<(), PlotError> {
    drawn(path, draw(path, title, series, width, height))
}

fn draw(path: &Path, title: &str, series: &[Series], width: u32, height: u32) -> Result<(), DrawError> {
    let finite = || series.iter().flat_map(|s| s.points.iter()).filter(|p| p.depth.is_finite());
    let x0 = finite().map(|p| p.rpm).fold(f64::INFINITY, f64::min);
    let x1 = finite().map(|p| p.rpm).fold(f64::NEG_INFINITY, f64::max);
    let ymax = finite().map(|p| p.depth * 1e3).fold(0.0, f64::max);
    let ymin = finite().map(|p| p.depth * 1e3).fold(f64::INFINITY, f64::min);
    if !(x0.is_finite() && x1 > x0 && ymax > 0.0) {
        return Err("nothing finite to plot".into());
    }
    // curves spanning more than a factor 20 are drawn on a logarithmic depth axis
    let log = ymax / ymin > 20.0;
    let y_axis =
        if log { Axis::log_rounded(ymin / 1.05, ymax * 1.05, 12) } else { Axis::linear_rounded(0.0, ymax * 1.02, 10) };
    let root = canvas(path, (width, height + 22 * title.lines().count().saturating_sub(1) as u32))?;
    let below = titled(&root, title, 22)?;
    let colour = |i: usize| PALETTE[i % PALETTE.len()];
    let legend: Vec<LegendEntry> = series.iter().enumerate().map(|(i, s)| (display_name(&s.name), colour(i))).collect();
    let (key, area) = below.split_vertically(30);
    legend_row(&key, &legend, None)?;
    let mut chart = ChartBuilder::on(&area)
        .margin(15)
        .margin_top(8)
        .margin_right(25)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d(Axis::linear(x0, x1, 11), y_axis)?;
    chart
        .configure_mesh()
        .x_desc("spindle speed [rpm]")
        .y_desc(if log { "critical axial depth [mm] (log scale)" } else { "critical axial depth [mm]" })
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 16))
        .draw()?;
    for (i, s) in series.iter().enumerate() {
        // a speed without a finite depth (stable over the searched range, or not drawn) breaks the
        // curve instead of joining its neighbours across it
        for run in s.points.split(|p| !p.depth.is_finite()).filter(|r| !r.is_empty()) {
            let pts = run.iter().map(|p| (p.rpm, p.depth * 1e3));
            chart.draw_series(LineSeries::new(pts, colour(i).stroke_width(2)))?;
        }
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series() -> Vec<Series> {
        let pts = |s: f64| {
            (0..50)
                .map(|i| CriticalPoint {
                    rpm: 1000.0 + 40.0 * i as f64,
                    depth: s * (1e-3 + 1e-4 * (i as f64 * 0.3).sin().abs()),
                    chatter_hz: 150.0,
                })
                .collect()
        };
        vec![Series { name: "off".into(), points: pts(1.0) }, Series { name: "pid".into(), points: pts(1.5) }]
    }

    #[test]
    fn csv_has_header_and_rows() {
        let csv = diagrams_csv(&series());
        let mut lines = csv.lines();
        assert_eq!(lines.next().unwrap(), "rpm,b_lim_mm_off,b_lim_mm_pid,f_chatter_hz_off,f_chatter_hz_pid");
        assert_eq!(lines.count(), 50);
    }

    #[test]
    fn png_is_written() {
        let dir = std::env::temp_dir().join(format!("lobes-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("l.png");
        plot_png(&p, "test", &series(), 400, 300).unwrap();
        let bytes = std::fs::read(&p).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
