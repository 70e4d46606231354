//! Stacked amplitude spectra over a frequency range chosen from what they hold: the marked
//! reference frequencies and the band where the spectra have energy, with margins, rounded to
//! ticks ([`frequency_range`]). The 0 Hz (DC) bin, the signal's mean, is never drawn.

use super::{Area, Axis, COLORS, DrawError, LegendEntry, Panel, PlotError, drawn, panel_chart, stacked};
use crate::spectrum::Spectrum;
use plotters::prelude::*;
use std::path::Path;

/// A marked reference frequency.
#[derive(Clone, Debug)]
pub struct Mark {
    /// Frequency [Hz].
    pub freq: f64,
    /// Legend text.
    pub label: String,
}

/// Share of the largest peak above which a bin counts as energy for the range.
const ENERGY: f64 = 0.1;

/// The frequency range to show for `spectra`, within `(0, f_max]`: every mark in `marks`
/// (frequencies) and every bin whose amplitude is at least a tenth of the largest one (the DC bin
/// excepted), widened by a quarter of that span on each side (at least 10 % of its upper end and
/// five bins) and rounded out to ticks; from 0 when that comes close to it.
pub fn frequency_range(spectra: &[&Spectrum], marks: &[f64], f_max: f64) -> (f64, f64) {
    let bins = || spectra.iter().flat_map(|s| s.freq.iter().zip(&s.amp).skip(1)).filter(|(f, _)| **f <= f_max);
    let peak = bins().map(|(_, a)| *a).fold(0.0, f64::max);
    let df = spectra.iter().filter_map(|s| s.freq.get(1).copied()).fold(0.0, f64::max);
    let energetic = bins().filter(|(_, a)| peak > 0.0 && **a >= ENERGY * peak).map(|(f, _)| *f);
    let marked = marks.iter().copied().filter(|f| *f > 0.0 && *f <= f_max);
    let (lo, hi) = energetic.chain(marked).fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), f| (l.min(f), h.max(f)));
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, f_max);
    }
    let margin = (0.25 * (hi - lo)).max(0.1 * hi).max(5.0 * df);
    let (lo, hi) = ((lo - margin).max(0.0), (hi + margin).min(f_max));
    let lo = if lo < 0.25 * hi { 0.0 } else { lo };
    let rounded = Axis::linear_rounded(lo, hi, 9).ends();
    (rounded.0.max(0.0), rounded.1.min(f_max))
}

/// Colours of the marks (grey, magenta, teal, …).
const MARK_COLORS: [RGBColor; 3] = [RGBColor(110, 110, 110), RGBColor(200, 0, 150), RGBColor(0, 150, 150)];

/// Stacked single-sided amplitude spectra with vertical lines at `marks`, over the range
/// [`frequency_range`] chooses within `(0, f_max]`; the marks in one legend for the figure, the
/// DC bin not drawn (and said so). `common_y`: one amplitude range for all panels.
pub fn spectra(
    path: &Path,
    title: &str,
    panels: &[Panel<'_, Spectrum>],
    f_max: f64,
    marks: &[Mark],
    common_y: bool,
) -> Result<(), PlotError> {
    drawn(path, draw_spectra(path, title, panels, f_max, marks, common_y))
}

fn draw_spectra(
    path: &Path,
    title: &str,
    panels: &[Panel<'_, Spectrum>],
    f_max: f64,
    marks: &[Mark],
    common_y: bool,
) -> Result<(), DrawError> {
    let data: Vec<&Spectrum> = panels.iter().map(|p| p.data).collect();
    let freqs: Vec<f64> = marks.iter().map(|m| m.freq).collect();
    let (f0, f1) = frequency_range(&data, &freqs, f_max);
    let legend: Vec<LegendEntry> = marks
        .iter()
        .enumerate()
        .map(|(j, m)| (format!("{}: {:.1} Hz", m.label, m.freq), MARK_COLORS[j % MARK_COLORS.len()]))
        .collect();
    let (root, areas) = stacked(path, title, (&legend, Some("0 Hz (DC) bin not drawn")), panels.len())?;
    // the largest amplitude shown (the DC bin excepted), per panel in plotted units
    let shown = |p: &Panel<'_, Spectrum>| {
        let bins = p.data.freq.iter().zip(&p.data.amp).skip(1);
        bins.filter(|(f, _)| **f >= f0 && **f <= f1).map(|(_, a)| a * p.y.scale).fold(0.0, f64::max)
    };
    let all = panels.iter().map(shown).fold(0.0, f64::max);
    for (k, (area, p)) in areas.iter().zip(panels).enumerate() {
        let top = if common_y { all } else { shown(p) };
        let top = if top > 0.0 { top * 1.1 } else { 1.0 };
        draw_panel(area, p, (f0, f1), top, (marks, k + 1 == panels.len()), COLORS[k % COLORS.len()])?;
    }
    root.present()?;
    Ok(())
}

fn draw_panel(
    area: &Area<'_>,
    p: &Panel<'_, Spectrum>,
    (f0, f1): (f64, f64),
    top: f64,
    (marks, last): (&[Mark], bool),
    color: RGBColor,
) -> Result<(), DrawError> {
    let axes = (Axis::linear(f0, f1, 17), Axis::linear(0.0, top, 8));
    let mut chart = panel_chart(area, &p.title, axes, (last.then_some("frequency [Hz]"), &p.y.label))?;
    for (j, m) in marks.iter().enumerate().filter(|(_, m)| m.freq >= f0 && m.freq <= f1) {
        let c = MARK_COLORS[j % MARK_COLORS.len()];
        chart.draw_series(DashedLineSeries::new(vec![(m.freq, 0.0), (m.freq, top)], 6, 4, c.stroke_width(1)))?;
    }
    // the bins within the range, the DC bin never
    let (f, a) = (&p.data.freq, &p.data.amp);
    let first = f.iter().position(|f| *f >= f0).unwrap_or(f.len()).max(1);
    let end = f.iter().position(|f| *f > f1).unwrap_or(f.len()).max(first);
    chart.draw_series(LineSeries::new((first..end).map(|i| (f[i], a[i] * p.y.scale)), color.stroke_width(1)))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::single_sided;

    /// 30 s at 1 kHz: a mean (DC), a line at 133.3 Hz and a weaker resonance band near 150 Hz.
    fn milling_like() -> Spectrum {
        let fs = 1000.0;
        let x: Vec<f64> = (0..30_000)
            .map(|i| {
                let t = i as f64 / fs;
                let w = |f: f64| (2.0 * std::f64::consts::PI * f * t).sin();
                5e-6 + 2e-6 * w(133.3) + 0.5e-6 * (w(147.0) + w(151.0)) + 0.01e-6 * w(400.0 - 7.0)
            })
            .collect();
        single_sided(&x, fs)
    }

    #[test]
    fn the_range_holds_the_marks_and_the_energy_and_not_dc() {
        let s = milling_like();
        assert!(s.amp[0] > 2.0 * s.amp.iter().skip(1).fold(0.0, |a: f64, b| a.max(*b)), "the mean dominates");
        let (lo, hi) = frequency_range(&[&s], &[133.3, 142.4], 500.0);
        assert!(lo > 0.0, "DC is out of view: {lo}–{hi} Hz");
        assert!(lo < 133.3 - 5.0 && hi > 151.0 + 5.0, "marks and the resonance band with margins: {lo}–{hi} Hz");
        assert!(hi - lo < 150.0, "the range follows the content, not 0–500 Hz: {lo}–{hi} Hz");
        assert_eq!((lo, hi), (110.0, 170.0));
        // a mark far from the energy is kept in view
        let (lo, hi) = frequency_range(&[&s], &[50.0, 133.3], 500.0);
        assert!(lo <= 45.0 && hi >= 151.0, "{lo}–{hi} Hz");
        // and the range stays within what the spectrum holds
        assert!(frequency_range(&[&s], &[480.0], 400.0).1 <= 400.0);
    }

    #[test]
    fn an_empty_spectrum_shows_the_whole_band() {
        let s = Spectrum { freq: vec![0.0, 1.0, 2.0], amp: vec![1.0, 0.0, 0.0] };
        assert_eq!(frequency_range(&[&s], &[], 2.0), (0.0, 2.0));
    }
}
