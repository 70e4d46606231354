//! The figures of a fit: measured against fitted FRFs (magnitude on a log axis, phase), and the
//! stabilisation diagram over the FRFs' magnitude.

use super::FrfFit;
use crate::frf::MeasuredFrf;
use fmi_master::plot::{Axis, DrawError, FONT, LegendEntry, PALETTE, PlotError, canvas, drawn, legend_row, titled};
use modal_fit::stabilisation::Stability;
use plotters::prelude::*;
use std::path::Path;

const GREY: RGBColor = RGBColor(150, 150, 150);

/// Decades spanning `lo..hi` (both > 0).
fn decades(lo: f64, hi: f64) -> (f64, f64) {
    (10f64.powf(lo.log10().floor()), 10f64.powf(hi.log10().ceil()))
}

/// `1e-7` style tick labels.
fn sci(v: &f64) -> String {
    let e = v.log10().round() as i32;
    if (v / 10f64.powi(e) - 1.0).abs() < 1e-6 { format!("1e{e}") } else { format!("{v:.0e}") }
}

/// Measured vs fitted magnitude and phase of every fitted FRF (one row per FRF); the fit with
/// its residual terms and the modes alone.
pub fn overlay_png(path: &Path, title: &str, frf: &MeasuredFrf, fit: &FrfFit) -> Result<(), PlotError> {
    drawn(path, draw_overlay(path, title, frf, fit))
}

fn draw_overlay(path: &Path, title: &str, frf: &MeasuredFrf, fit: &FrfFit) -> Result<(), DrawError> {
    let rows = fit.pairs.len();
    let root = canvas(path, (1400, 60 + 300 * rows as u32))?;
    let below = titled(&root, title, 22)?;
    let (key, area) = below.split_vertically(30);
    let fitted_colour = PALETTE[0];
    let modes_colour = PALETTE[1];
    let legend: Vec<LegendEntry> = vec![
        ("measured".into(), GREY),
        ("fit: modes and residual terms".into(), fitted_colour),
        ("modes alone (machine file, FMU)".into(), modes_colour),
    ];
    legend_row(&key, &legend, None)?;
    let (a, b) = fit.band_hz;
    let pts: Vec<usize> = (0..frf.freq_hz.len()).filter(|&k| (a..=b).contains(&frf.freq_hz[k])).collect();
    let fine: Vec<f64> = (0..=1500).map(|k| a + (b - a) * f64::from(k) / 1500.0).collect();
    let panels = area.split_evenly((rows, 2));
    for (o, p) in fit.pairs.iter().enumerate() {
        let meas: Vec<(f64, num_complex::Complex64)> = pts.iter().map(|&k| (frf.freq_hz[k], frf.h[p][k])).collect();
        let full: Vec<(f64, num_complex::Complex64)> = fine.iter().map(|&f| (f, fit.value(o, f, true))).collect();
        let modal: Vec<(f64, num_complex::Complex64)> = fine.iter().map(|&f| (f, fit.value(o, f, false))).collect();
        // magnitude, log axis
        let mags = meas.iter().chain(&full).map(|v| v.1.norm()).filter(|m| *m > 0.0);
        let (lo, hi) = mags.fold((f64::INFINITY, 0.0f64), |acc, m| (acc.0.min(m), acc.1.max(m)));
        let (lo, hi) = decades(lo.max(hi * 1e-4), hi);
        let mut c = ChartBuilder::on(&panels[2 * o])
            .margin(12)
            .caption(format!("{} magnitude", p.name()), (FONT, 17))
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(Axis::linear(a, b, 9), (lo..hi).log_scale())?;
        c.configure_mesh()
            .x_desc("frequency (Hz)")
            .y_desc("|H| (m/N)")
            .y_label_formatter(&sci)
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 15))
            .draw()?;
        c.draw_series(meas.iter().map(|(f, h)| Circle::new((*f, h.norm().max(lo)), 2, GREY.filled())))?;
        c.draw_series(LineSeries::new(
            modal.iter().map(|(f, h)| (*f, h.norm().max(lo))),
            modes_colour.stroke_width(2),
        ))?;
        c.draw_series(LineSeries::new(
            full.iter().map(|(f, h)| (*f, h.norm().max(lo))),
            fitted_colour.stroke_width(2),
        ))?;
        // phase
        let mut c = ChartBuilder::on(&panels[2 * o + 1])
            .margin(12)
            .caption(format!("{} phase", p.name()), (FONT, 17))
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(Axis::linear(a, b, 9), Axis::linear(-180.0, 180.0, 9))?;
        c.configure_mesh()
            .x_desc("frequency (Hz)")
            .y_desc("phase (deg)")
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 15))
            .draw()?;
        let deg = |h: &num_complex::Complex64| h.arg().to_degrees();
        c.draw_series(meas.iter().map(|(f, h)| Circle::new((*f, deg(h)), 2, GREY.filled())))?;
        // lines broken at the ±180° wrap
        for (series, colour) in [(&modal, modes_colour), (&full, fitted_colour)] {
            let mut run: Vec<(f64, f64)> = Vec::new();
            for (f, h) in series.iter() {
                let y = deg(h);
                if run.last().is_some_and(|l| (l.1 - y).abs() > 180.0) {
                    c.draw_series(LineSeries::new(std::mem::take(&mut run), colour.stroke_width(2)))?;
                }
                run.push((*f, y));
            }
            c.draw_series(LineSeries::new(run, colour.stroke_width(2)))?;
        }
    }
    root.present()?;
    Ok(())
}

/// The stabilisation diagram: the poles of each model order by frequency (stable: frequency
/// and damping within tolerance of the previous order; frequency only; new), the picked modes
/// as vertical lines, and the driving points' summed magnitude (log, scaled to the orders).
pub fn stabilisation_png(path: &Path, title: &str, frf: &MeasuredFrf, fit: &FrfFit) -> Result<(), PlotError> {
    drawn(path, draw_stabilisation(path, title, frf, fit))
}

fn draw_stabilisation(path: &Path, title: &str, frf: &MeasuredFrf, fit: &FrfFit) -> Result<(), DrawError> {
    let root = canvas(path, (1200, 700 + 22 * title.lines().count().saturating_sub(1) as u32))?;
    let below = titled(&root, title, 22)?;
    let (key, area) = below.split_vertically(30);
    let (stable, freq_only, new, picked, mag) = (PALETTE[0], PALETTE[2], GREY, PALETTE[3], RGBColor(40, 40, 40));
    legend_row(
        &key,
        &[
            ("stable (f within 1 %, ζ within 5 %)".into(), stable),
            ("frequency stable".into(), freq_only),
            ("new".into(), new),
            ("picked mode".into(), picked),
            ("|xx| + |yy| (log, scaled)".into(), mag),
        ],
        None,
    )?;
    let (a, b) = fit.band_hz;
    let orders = &fit.id.diagram.orders;
    let top = orders.last().map_or(40, |o| o.0) as f64;
    let mut c = ChartBuilder::on(&area)
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(Axis::linear(a, b, 11), Axis::linear(0.0, top + 2.0, 11))?;
    c.configure_mesh()
        .x_desc("frequency (Hz)")
        .y_desc("model order")
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 16))
        .draw()?;
    // the magnitude, log-scaled into the order axis
    let k: Vec<usize> = (0..frf.freq_hz.len()).filter(|&k| (a..=b).contains(&frf.freq_hz[k])).collect();
    let s: Vec<f64> = k
        .iter()
        .map(|&k| {
            (frf.h[&crate::frf::Pair(0, 0)][k].norm() + frf.h[&crate::frf::Pair(1, 1)][k].norm())
                .max(f64::MIN_POSITIVE)
                .log10()
        })
        .collect();
    let (lo, hi) = s.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |acc, v| (acc.0.min(*v), acc.1.max(*v)));
    let scale = |v: f64| 1.0 + (top) * (v - lo) / (hi - lo).max(1e-12);
    c.draw_series(LineSeries::new(k.iter().zip(&s).map(|(&k, v)| (frf.freq_hz[k], scale(*v))), mag.stroke_width(1)))?;
    for m in &fit.modes {
        c.draw_series(LineSeries::new([(m.frequency_hz, 0.0), (m.frequency_hz, top + 2.0)], picked.stroke_width(1)))?;
    }
    for (n, poles) in orders {
        let y = *n as f64;
        for (p, st) in poles {
            let f = p.frequency_hz();
            if !(a..=b).contains(&f) {
                continue;
            }
            match st {
                Stability::Stable => c.draw_series([Circle::new((f, y), 4, stable.filled())])?,
                Stability::Frequency => c.draw_series([TriangleMarker::new((f, y), 5, freq_only.filled())])?,
                Stability::New => c.draw_series([Cross::new((f, y), 3, new.stroke_width(1))])?,
            };
        }
    }
    root.present()?;
    Ok(())
}
