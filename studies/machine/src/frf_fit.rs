//! Measured FRFs to modes ([`modal_fit`]): the band, the stabilisation diagram, the picked
//! modes as the machine file's modes, and what the fit leaves out (residual terms, complex
//! modes) said in the report.

pub mod plots;
pub mod synth;

use crate::frf::{MeasuredFrf, Pair};
use crate::machine::Mode;
use modal_fit::{FitError, Identified};
use num_complex::Complex64;
use std::f64::consts::PI;
use std::fmt::Write as _;

/// How to fit.
#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// The band \[Hz\] (None: [`auto_band`]).
    pub band_hz: Option<(f64, f64)>,
    /// The highest model order of the stabilisation diagram (orders 4, 6, …, this).
    pub max_order: usize,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions { band_hz: None, max_order: 40 }
    }
}

/// Without a cross FRF, a pole's share of `φ²` in a direction below this is leakage, not a mode.
pub const UNCOUPLED_SHARE: f64 = 0.05;

/// A mode of the fit is called complex (and said so) beyond this complexity.
pub const COMPLEX_MODE: f64 = 0.2;

/// The default band: where the driving points' summed magnitude is above 5 % of its peak,
/// widened by 30 % of that span on each side and kept within the data.
pub fn auto_band(frf: &MeasuredFrf) -> (f64, f64) {
    let s: Vec<f64> =
        (0..frf.freq_hz.len()).map(|k| frf.h[&Pair(0, 0)][k].norm() + frf.h[&Pair(1, 1)][k].norm()).collect();
    let peak = s.iter().copied().fold(0.0, f64::max);
    let above: Vec<f64> = frf.freq_hz.iter().zip(&s).filter(|(_, v)| **v >= 0.05 * peak).map(|(f, _)| *f).collect();
    let (lo, hi) = (above[0], above[above.len() - 1]);
    let pad = 0.3 * (hi - lo).max(0.1 * hi);
    let (f0, f1) = frf.range_hz();
    ((lo - pad).max(f0), (hi + pad).min(f1))
}

/// A fit and what it came from.
#[derive(Clone, Debug)]
pub struct FrfFit {
    /// The band fitted \[Hz\].
    pub band_hz: (f64, f64),
    /// The FRFs fitted, in the order of the identification's outputs.
    pub pairs: Vec<Pair>,
    /// The identification (diagram, residues, modes, error).
    pub id: Identified,
    /// The modes as the machine file holds them (stiffness along the unit shape).
    pub modes: Vec<Mode>,
    /// The complexity of the identified mode each of [`FrfFit::modes`] comes from.
    pub complexity: Vec<f64>,
    /// What the user should know about the fit.
    pub notes: Vec<String>,
}

/// Fit modes to measured FRFs.
pub fn fit(frf: &MeasuredFrf, o: &FitOptions) -> Result<FrfFit, FitError> {
    let band = o.band_hz.unwrap_or_else(|| auto_band(frf));
    if o.max_order < 12 || o.max_order > 200 {
        return Err(FitError::Data(format!("max order {}: use 12..=200 (a pole needs 5 stable orders)", o.max_order)));
    }
    let (data, pairs) = frf.for_fit();
    let id = modal_fit::identify(&data, band, (4..=o.max_order).step_by(2), &pairs)?;
    let pairs: Vec<Pair> = pairs.iter().map(|&(p, q)| Pair(p, q)).collect();
    let mut notes = frf.notes.clone();
    let (mut modes, mut complexity) = (Vec::new(), Vec::new());
    for (i, m) in id.modes.iter().enumerate() {
        let mode = |label: String, shape: [f64; 2], stiffness: f64| Mode {
            label,
            frequency_hz: m.frequency_hz,
            damping: m.damping,
            stiffness,
            shape,
        };
        if frf.has_cross() {
            modes.push(mode(format!("fit[{i}]"), m.direction(), m.stiffness()));
            complexity.push(m.complexity);
            continue;
        }
        // No cross FRF: the data say G = diag(G_xx, G_yy) (xy = yx = 0, said in the notes). A
        // pole seen in both driving points is then two uncoupled modes, one per direction, so
        // that the modal model has no cross terms either; a component below UNCOUPLED_SHARE of
        // the mode's φ² is the other FRF's leakage (noise, a neighbour) and left out.
        let w2 = (2.0 * PI * m.frequency_hz).powi(2);
        let phi2 = [m.shape[0] * m.shape[0], m.shape[1] * m.shape[1]];
        let total = phi2[0] + phi2[1];
        let kept: Vec<usize> = (0..2).filter(|&d| phi2[d] >= UNCOUPLED_SHARE * total).collect();
        for &d in &kept {
            let mut shape = [0.0; 2];
            shape[d] = 1.0;
            modes.push(mode(format!("fit[{i}].{}", ["x", "y"][d]), shape, w2 / phi2[d]));
            complexity.push(m.complexity);
        }
        if kept.len() == 2 {
            notes.push(format!(
                "mode {} ({:.1} Hz) shows in xx and in yy, and no cross FRF was measured: written as two uncoupled modes (x, y) at that frequency",
                i + 1,
                m.frequency_hz
            ));
        }
    }
    for (i, m) in id.modes.iter().enumerate() {
        if m.complexity > COMPLEX_MODE {
            notes.push(format!(
                "mode {} ({:.1} Hz) is complex (complexity {:.2}): the real-mode model approximates it; compare the lobes from the data and from the modes",
                i + 1,
                m.frequency_hz,
                m.complexity
            ));
        }
    }
    let dropped = id.residues.poles.len() - id.modes.len();
    if dropped > 0 {
        notes.push(format!("{dropped} stable pole(s) with no positive driving-point residue left out (computational)"));
    }
    Ok(FrfFit { band_hz: band, pairs, id, modes, complexity, notes })
}

impl FrfFit {
    /// The fitted FRF of pair `o` (index into [`FrfFit::pairs`]) at `f_hz`: with the residual
    /// terms (`full`) or the modes alone (what the machine file and the FMU hold).
    pub fn value(&self, o: usize, f_hz: f64, full: bool) -> Complex64 {
        let w = 2.0 * PI * f_hz;
        if full { self.id.residues.synthesise(o, w) } else { self.id.residues.modal(o, w) }
    }

    /// The fitted FRFs on the measured grid within the band, as [`MeasuredFrf`].
    pub fn fitted(&self, frf: &MeasuredFrf, full: bool) -> MeasuredFrf {
        let idx = modal_fit::Frfs { freq_hz: frf.freq_hz.clone(), outputs: vec![] }.band(self.band_hz);
        let freq_hz: Vec<f64> = frf.freq_hz[idx].to_vec();
        let h = self
            .pairs
            .iter()
            .enumerate()
            .map(|(o, p)| (*p, freq_hz.iter().map(|f| self.value(o, *f, full)).collect()))
            .collect();
        MeasuredFrf {
            source: format!("fit of {}", frf.source),
            freq_hz,
            h,
            notes: vec![if full { "modes and residual terms" } else { "modes alone" }.to_string()],
        }
    }

    /// The report (markdown): the modes, the fit errors against `frf` (the data fitted), the
    /// residual terms, the notes.
    pub fn report(&self, frf: &MeasuredFrf) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Modal fit (LSCF poles, LSFD residues) of {} over {:.0}–{:.0} Hz, orders 4–{}: {} modes, relative RMS error {:.2} % (modes and residual terms), {:.2} % (modes alone).\n",
            self.pairs.iter().map(|p| p.name()).collect::<Vec<_>>().join(", "),
            self.band_hz.0,
            self.band_hz.1,
            self.id.diagram.orders.last().map_or(0, |o| o.0),
            self.modes.len(),
            self.id.error * 100.0,
            self.modal_error(frf) * 100.0
        );
        let _ = writeln!(
            s,
            "| mode | frequency (Hz) | damping ratio | stiffness (N/m) | mass (kg) | direction (x, y) | complexity |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|");
        for (i, (m, c)) in self.modes.iter().zip(&self.complexity).enumerate() {
            let _ = writeln!(
                s,
                "| {} | {:.2} | {:.4} | {:.4e} | {:.4} | ({:.3}, {:.3}) | {:.3} |",
                i + 1,
                m.frequency_hz,
                m.damping,
                m.stiffness,
                m.mass(),
                m.shape[0],
                m.shape[1],
                c
            );
        }
        let _ = writeln!(s, "\nResidual terms (not in the modal model; they stand for modes outside the band):\n");
        let _ = writeln!(s, "| FRF | lower residual (1/kg) | upper residual (m/N) | upper / peak |");
        let _ = writeln!(s, "|---|---|---|---|");
        for (o, p) in self.pairs.iter().enumerate() {
            let peak = self.peak(o);
            let _ = writeln!(
                s,
                "| {} | {:.3e} | {:.3e} | {:.3} |",
                p.name(),
                self.id.residues.lower[o],
                self.id.residues.upper[o],
                self.id.residues.upper[o].abs() / peak
            );
        }
        for n in &self.notes {
            let _ = writeln!(s, "\nNote: {n}");
        }
        s
    }

    /// The largest fitted |H| of pair `o` over the band.
    fn peak(&self, o: usize) -> f64 {
        let (a, b) = self.band_hz;
        (0..=400).map(|k| self.value(o, a + (b - a) * k as f64 / 400.0, false).norm()).fold(0.0, f64::max)
    }

    /// The relative RMS error of the modes alone (no residual terms, the model the machine file
    /// and the FMU hold) against the measured FRFs over the band.
    pub fn modal_error(&self, frf: &MeasuredFrf) -> f64 {
        let (mut e, mut n) = (0.0, 0.0);
        for (o, p) in self.pairs.iter().enumerate() {
            for (k, f) in frf.freq_hz.iter().enumerate() {
                if (self.band_hz.0..=self.band_hz.1).contains(f) {
                    let h = frf.h[p][k];
                    e += (h - self.value(o, *f, false)).norm_sqr();
                    n += h.norm_sqr();
                }
            }
        }
        (e / n).sqrt()
    }

    /// The modes as CSV.
    pub fn modes_csv(&self) -> String {
        let mut s = String::from("mode,frequency_hz,damping,stiffness_n_per_m,mass_kg,shape_x,shape_y,complexity\n");
        for (i, (m, c)) in self.modes.iter().zip(&self.complexity).enumerate() {
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{},{}",
                i + 1,
                m.frequency_hz,
                m.damping,
                m.stiffness,
                m.mass(),
                m.shape[0],
                m.shape[1],
                c
            );
        }
        s
    }

    /// The stabilisation diagram as CSV: order, frequency, damping, stability.
    pub fn stabilisation_csv(&self) -> String {
        let mut s = String::from("order,frequency_hz,damping,stability\n");
        for (n, poles) in &self.id.diagram.orders {
            for (p, st) in poles {
                let _ = writeln!(s, "{n},{},{},{}", p.frequency_hz(), p.damping(), stability_name(*st));
            }
        }
        s
    }

    /// The machine file's `[structure]` table of the fitted modes (full precision), with the
    /// measured FRFs (`frf_files`, as the machine file should reference them) if given.
    pub fn structure_toml(&self, frf_files: &[String]) -> String {
        let mut s = String::from("[structure]\n");
        if !frf_files.is_empty() {
            let quoted: Vec<String> = frf_files.iter().map(|f| format!("{f:?}")).collect();
            let _ = writeln!(s, "frf = [{}]", quoted.join(", "));
        }
        let _ = writeln!(s, "modes = [");
        for m in &self.modes {
            let _ = writeln!(
                s,
                "  {{ frequency = \"{} Hz\", damping = {}, stiffness = \"{} N/m\", shape = [{}, {}] }},",
                m.frequency_hz, m.damping, m.stiffness, m.shape[0], m.shape[1]
            );
        }
        s.push_str("]\n");
        s
    }
}

/// A stability class's name in the CSV.
pub fn stability_name(s: modal_fit::stabilisation::Stability) -> &'static str {
    match s {
        modal_fit::stabilisation::Stability::New => "new",
        modal_fit::stabilisation::Stability::Frequency => "frequency",
        modal_fit::stabilisation::Stability::Stable => "stable",
    }
}
