//! Measured tool-point FRFs: a tap test's `xx`, `xy`, `yx`, `yy` as receptances in m/N on one
//! frequency grid, read from and written to CSV ([`csv`]) and UFF 58 ([`uff`], ASCII and
//! binary), fitted to modes ([`crate::frf_fit`]) and used directly as the receptance of the zero-order
//! lobes ([`MeasuredReceptance`]).
//!
//! # Units
//!
//! Receptance (displacement/force, m/N) is what the lobes need. A mobility `H_v` (velocity/force,
//! m/s/N) or an accelerance `H_a` (acceleration/force, m/s²/N, or `g/N` with g = 9.80665 m/s²)
//! is converted by the harmonic rule `H = H_v/(iω) = −H_a/ω²` (ω = 2πf); at f = 0 neither has a
//! receptance, so a 0 Hz row of a mobility or accelerance is dropped (and said so).
//!
//! # Directions
//!
//! `xy` is the displacement along x for a force along y (response first, the UFF 58 order).
//! The tool point needs `xx` and `yy`. A missing cross FRF is taken from the other by
//! reciprocity (`yx = xy`); with neither, the cross terms are zero and every result says so.

pub mod csv;
pub mod uff;

use delay_stability::frequency::Receptance;
use nalgebra::Matrix2;
use num_complex::Complex64;
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::fmt;
use std::path::Path;

/// One FRF of the tool point: response direction, force direction (0 = x, 1 = y).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Pair(pub usize, pub usize);

impl Pair {
    /// The four pairs in file order.
    pub const ALL: [Pair; 4] = [Pair(0, 0), Pair(0, 1), Pair(1, 0), Pair(1, 1)];

    /// `xx`, `xy`, `yx` or `yy`.
    pub fn name(self) -> &'static str {
        ["xx", "xy", "yx", "yy"][self.0 * 2 + self.1]
    }

    /// From `xx`, `xy`, `yx`, `yy` (any case).
    pub fn parse(text: &str) -> Option<Pair> {
        Pair::ALL.into_iter().find(|p| p.name().eq_ignore_ascii_case(text))
    }
}

/// What an FRF's numerator measures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// Displacement per force \[m/N\].
    Receptance,
    /// Velocity per force \[m/s/N\].
    Mobility,
    /// Acceleration per force \[m/s²/N\].
    Accelerance,
}

impl Kind {
    /// The receptance of a value of this kind at `f_hz` (`None` at 0 Hz for mobility and
    /// accelerance).
    pub fn to_receptance(self, value: Complex64, f_hz: f64) -> Option<Complex64> {
        let w = 2.0 * PI * f_hz;
        match self {
            Kind::Receptance => Some(value),
            _ if w == 0.0 => None,
            Kind::Mobility => Some(value / Complex64::new(0.0, w)),
            Kind::Accelerance => Some(-value / (w * w)),
        }
    }

    /// In words.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Receptance => "receptance",
            Kind::Mobility => "mobility",
            Kind::Accelerance => "accelerance",
        }
    }
}

/// An FRF unit: its kind and the factor of its numbers to SI (`mm/N` is receptance × 1e-3).
pub fn frf_unit(text: &str) -> Result<(Kind, f64), String> {
    let t = text.trim();
    // `g/N` (g = standard gravity): a gram per newton is no FRF, so the reading is unambiguous
    let gravity = t.replace(' ', "");
    if gravity == "g/N" || gravity == "gn/N" {
        return Ok((Kind::Accelerance, 9.80665));
    }
    let (factor, dim, _) = crate::units::parse_unit(t)?;
    let same = |d: crate::units::Dim| crate::units::same_dim(d, dim);
    let kind = if same([-1.0, 0.0, 2.0]) {
        Kind::Receptance
    } else if same([-1.0, 0.0, 1.0]) {
        Kind::Mobility
    } else if same([-1.0, 0.0, 0.0]) {
        Kind::Accelerance
    } else {
        return Err(format!(
            "unit {t:?} is {}, not an FRF: write m/N (receptance), m/s/N (mobility) or m/s^2/N or g/N (accelerance)",
            crate::units::describe(dim)
        ));
    };
    Ok((kind, factor))
}

/// A problem in an FRF file: the file, the line (1-based) when there is one, what and the fix.
#[derive(Clone, Debug, PartialEq)]
pub struct FrfError {
    /// The file.
    pub file: String,
    /// The line, 1-based.
    pub line: Option<usize>,
    /// What is wrong and how to fix it.
    pub message: String,
}

impl FrfError {
    /// An error of `file` at `line`.
    pub fn at(file: &str, line: Option<usize>, message: impl Into<String>) -> FrfError {
        FrfError { file: file.to_string(), line, message: message.into() }
    }
}

impl fmt::Display for FrfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{l}: {}", self.file, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for FrfError {}

/// Tool-point FRFs on one grid, receptance in m/N.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredFrf {
    /// Where they came from (file names, for reports).
    pub source: String,
    /// Frequencies \[Hz\], increasing, ≥ 0.
    pub freq_hz: Vec<f64>,
    /// The FRFs present, receptance \[m/N\].
    pub h: BTreeMap<Pair, Vec<Complex64>>,
    /// What was converted or assumed while reading (said with every result).
    pub notes: Vec<String>,
}

impl MeasuredFrf {
    /// Read FRF files (`.csv`; `.uff`, `.unv` or `.58`: UFF 58 ASCII or binary) into one set:
    /// every file on the same frequency grid, each pair once, `xx` and `yy` present.
    pub fn read(paths: &[impl AsRef<Path>]) -> Result<MeasuredFrf, FrfError> {
        let mut all: Option<MeasuredFrf> = None;
        if paths.is_empty() {
            return Err(FrfError::at("<none>", None, "no FRF file given"));
        }
        for p in paths {
            let p = p.as_ref();
            let name = p.display().to_string();
            let bytes = std::fs::read(p).map_err(|e| FrfError::at(&name, None, format!("cannot read: {e}")))?;
            let one = match p.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
                Some("csv") | Some("txt") => csv::parse(&bytes, &name)?,
                Some("uff") | Some("unv") | Some("58") => uff::parse(&bytes, &name)?,
                _ => {
                    return Err(FrfError::at(
                        &name,
                        None,
                        "unknown FRF file type: name it .csv (frequency, real, imaginary columns) or .uff/.unv (UFF 58)",
                    ));
                }
            };
            all = Some(match all {
                None => one,
                Some(acc) => acc.merge(one)?,
            });
        }
        let m = all.expect("at least one file");
        m.complete()
    }

    /// Merge another file's FRFs (same grid, no pair twice).
    fn merge(mut self, other: MeasuredFrf) -> Result<MeasuredFrf, FrfError> {
        let same_grid = self.freq_hz.len() == other.freq_hz.len()
            && self.freq_hz.iter().zip(&other.freq_hz).all(|(a, b)| (a - b).abs() <= 1e-9 * a.abs().max(1.0));
        if !same_grid {
            return Err(FrfError::at(
                &other.source,
                None,
                format!(
                    "{} frequencies {}–{} Hz, but {} has {} over {}–{} Hz: export every FRF on one frequency grid",
                    other.freq_hz.len(),
                    other.freq_hz.first().unwrap_or(&0.0),
                    other.freq_hz.last().unwrap_or(&0.0),
                    self.source,
                    self.freq_hz.len(),
                    self.freq_hz.first().unwrap_or(&0.0),
                    self.freq_hz.last().unwrap_or(&0.0)
                ),
            ));
        }
        for (pair, h) in other.h {
            if self.h.contains_key(&pair) {
                return Err(FrfError::at(
                    &other.source,
                    None,
                    format!("a second {} FRF (also in {}): give each direction pair once", pair.name(), self.source),
                ));
            }
            self.h.insert(pair, h);
        }
        self.source = format!("{}, {}", self.source, other.source);
        self.notes.extend(other.notes);
        Ok(self)
    }

    /// Check `xx` and `yy` are there; fill a missing cross FRF by reciprocity.
    pub fn complete(mut self) -> Result<MeasuredFrf, FrfError> {
        for p in [Pair(0, 0), Pair(1, 1)] {
            if !self.h.contains_key(&p) {
                let have: Vec<&str> = self.h.keys().map(|p| p.name()).collect();
                return Err(FrfError::at(
                    &self.source,
                    None,
                    format!(
                        "no {} FRF (found: {}): the tool point needs xx and yy (xy and yx are optional)",
                        p.name(),
                        have.join(", ")
                    ),
                ));
            }
        }
        match (self.h.get(&Pair(0, 1)).cloned(), self.h.get(&Pair(1, 0)).cloned()) {
            (Some(xy), None) => {
                self.h.insert(Pair(1, 0), xy);
                self.notes.push("yx taken equal to xy (reciprocity)".into());
            }
            (None, Some(yx)) => {
                self.h.insert(Pair(0, 1), yx);
                self.notes.push("xy taken equal to yx (reciprocity)".into());
            }
            (None, None) => self.notes.push("no cross FRF: x and y taken as uncoupled (xy = yx = 0)".into()),
            _ => {}
        }
        Ok(self)
    }

    /// Were cross FRFs measured (or one of them)?
    pub fn has_cross(&self) -> bool {
        self.h.contains_key(&Pair(0, 1))
    }

    /// `G(f_k)` as a 2 × 2 matrix (missing cross terms 0).
    pub fn matrix(&self, k: usize) -> Matrix2<Complex64> {
        let z = Complex64::new(0.0, 0.0);
        let g = |p: Pair| self.h.get(&p).map_or(z, |h| h[k]);
        Matrix2::new(g(Pair(0, 0)), g(Pair(0, 1)), g(Pair(1, 0)), g(Pair(1, 1)))
    }

    /// The FRFs for [`modal_fit`]: the pairs present and their data (a pair filled by
    /// reciprocity is left out: it adds no information).
    pub fn for_fit(&self) -> (modal_fit::Frfs, Vec<modal_fit::modes::Pair>) {
        let filled = self.notes.iter().any(|n| n.contains("reciprocity"));
        let mut outputs = Vec::new();
        let mut pairs = Vec::new();
        for (p, h) in &self.h {
            let is_filled_copy = filled && *p == Pair(1, 0) && self.h.get(&Pair(0, 1)) == Some(h);
            if is_filled_copy {
                continue;
            }
            outputs.push(h.clone());
            pairs.push((p.0, p.1));
        }
        (modal_fit::Frfs { freq_hz: self.freq_hz.clone(), outputs }, pairs)
    }

    /// The frequency of the largest `|xx| + |yy|` \[Hz\] (the dominant mode).
    pub fn peak_hz(&self) -> f64 {
        let s = |k: usize| self.h[&Pair(0, 0)][k].norm() + self.h[&Pair(1, 1)][k].norm();
        let k = (0..self.freq_hz.len()).max_by(|&a, &b| s(a).total_cmp(&s(b))).expect("non-empty");
        self.freq_hz[k]
    }

    /// The lowest and highest frequency \[Hz\].
    pub fn range_hz(&self) -> (f64, f64) {
        (self.freq_hz[0], *self.freq_hz.last().expect("non-empty"))
    }
}

/// Write `frf` to a new file: CSV (`.csv`) or UFF 58 (`.uff`/`.unv`, ASCII or `binary`); an
/// existing file is never overwritten.
pub fn write_new(frf: &MeasuredFrf, path: &Path, binary: bool) -> Result<(), FrfError> {
    use std::io::Write;
    let name = path.display().to_string();
    let bytes = match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("csv") if !binary => csv::write(frf, &frf.source).into_bytes(),
        Some("csv") => return Err(FrfError::at(&name, None, "a CSV is text: write a .uff for UFF 58 binary")),
        Some("uff") | Some("unv") => uff::write(frf, &frf.source, binary),
        _ => return Err(FrfError::at(&name, None, "name the file .csv or .uff")),
    };
    let mut f = std::fs::OpenOptions::new().write(true).create_new(true).open(path).map_err(|e| {
        FrfError::at(&name, None, format!("not written ({e}): nothing is overwritten, choose a new name"))
    })?;
    f.write_all(&bytes).map_err(|e| FrfError::at(&name, None, format!("writing: {e}")))
}

/// Check one file's grid and values as it is read: increasing frequencies, finite values
/// (`line_of(k)` gives the file line of row `k` for the message).
pub(crate) fn check_rows(
    file: &str,
    freq: &[f64],
    values: &[(Pair, Vec<Complex64>)],
    line_of: impl Fn(usize) -> Option<usize>,
) -> Result<(), FrfError> {
    if freq.len() < 8 {
        return Err(FrfError::at(file, None, format!("{} frequencies: a tap test needs at least 8", freq.len())));
    }
    for k in 0..freq.len() {
        if !freq[k].is_finite() || freq[k] < 0.0 {
            return Err(FrfError::at(file, line_of(k), format!("frequency {} Hz: must be finite and ≥ 0", freq[k])));
        }
        if k > 0 && freq[k] <= freq[k - 1] {
            return Err(FrfError::at(
                file,
                line_of(k),
                format!(
                    "frequency {} Hz after {} Hz: the frequencies must increase (sort the rows, remove repeated ones)",
                    freq[k],
                    freq[k - 1]
                ),
            ));
        }
        for (p, h) in values {
            if !(h[k].re.is_finite() && h[k].im.is_finite()) {
                return Err(FrfError::at(
                    file,
                    line_of(k),
                    format!(
                        "{} at {} Hz is {}: every value must be a finite number (remove or re-measure the row)",
                        p.name(),
                        freq[k],
                        h[k]
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Convert read values to receptance (dropping a 0 Hz row of a mobility or accelerance).
pub(crate) fn to_receptance(
    file: &str,
    freq: Vec<f64>,
    columns: Vec<(Pair, Kind, f64, Vec<Complex64>)>,
) -> MeasuredFrf {
    let mut notes = Vec::new();
    let drop_zero = freq.first() == Some(&0.0) && columns.iter().any(|c| c.1 != Kind::Receptance);
    let skip = usize::from(drop_zero);
    if drop_zero {
        notes.push(format!("{file}: the 0 Hz row dropped (a mobility or accelerance has no receptance at 0 Hz)"));
    }
    let mut h = BTreeMap::new();
    for (pair, kind, factor, values) in columns {
        if kind != Kind::Receptance {
            notes.push(format!(
                "{file}: {} converted from {} to receptance (H = H_v/(iω) or −H_a/ω²)",
                pair.name(),
                kind.name()
            ));
        }
        let r: Vec<Complex64> = freq
            .iter()
            .zip(&values)
            .skip(skip)
            .map(|(f, v)| kind.to_receptance(v * factor, *f).expect("0 Hz dropped"))
            .collect();
        h.insert(pair, r);
    }
    MeasuredFrf { source: file.to_string(), freq_hz: freq[skip..].to_vec(), h, notes }
}

/// The measured receptance as a [`Receptance`] for the lobe solvers: linear interpolation of
/// the real and imaginary parts between the measured frequencies, `G(−ω) = conj G(ω)`.
///
/// Outside the measured band there is no data. The zero-order solver asks only inside the band
/// it is given (which [`crate::lobes`] keeps within the data); beyond the data this returns
/// the nearest measured value, so a solver that asks there (the multi-frequency method's side
/// bands) must not be used with it.
#[derive(Clone, Debug)]
pub struct MeasuredReceptance {
    omega: Vec<f64>,
    g: Vec<Matrix2<Complex64>>,
}

impl MeasuredReceptance {
    /// From measured FRFs.
    pub fn new(frf: &MeasuredFrf) -> MeasuredReceptance {
        let omega = frf.freq_hz.iter().map(|f| 2.0 * PI * f).collect();
        let g = (0..frf.freq_hz.len()).map(|k| frf.matrix(k)).collect();
        MeasuredReceptance { omega, g }
    }

    /// The measured band \[rad/s\].
    pub fn band(&self) -> (f64, f64) {
        (self.omega[0], *self.omega.last().expect("non-empty"))
    }
}

impl Receptance for MeasuredReceptance {
    fn receptance(&self, omega: f64) -> Matrix2<Complex64> {
        let w = omega.abs();
        let k = self.omega.partition_point(|x| *x <= w);
        let g = if k == 0 {
            self.g[0]
        } else if k >= self.omega.len() {
            self.g[self.omega.len() - 1]
        } else {
            let t = (w - self.omega[k - 1]) / (self.omega[k] - self.omega[k - 1]);
            self.g[k - 1] * Complex64::new(1.0 - t, 0.0) + self.g[k] * Complex64::new(t, 0.0)
        };
        if omega < 0.0 { g.map(|v| v.conj()) } else { g }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_give_the_kind_and_factor() {
        assert_eq!(frf_unit("m/N").unwrap(), (Kind::Receptance, 1.0));
        let (k, f) = frf_unit("um/N").unwrap();
        assert!(k == Kind::Receptance && (f - 1e-6).abs() < 1e-20);
        assert_eq!(frf_unit("m/s/N").unwrap().0, Kind::Mobility);
        assert_eq!(frf_unit("m/s^2/N").unwrap().0, Kind::Accelerance);
        assert_eq!(frf_unit("g/N").unwrap(), (Kind::Accelerance, 9.80665));
        let e = frf_unit("N/m").unwrap_err();
        assert!(e.contains("stiffness") && e.contains("m/N"), "{e}");
    }

    #[test]
    fn conversion_is_the_harmonic_rule() {
        // x = X sin: v = iω x, a = −ω² x
        let (x, f) = (Complex64::new(2e-7, -1e-7), 500.0);
        let w = 2.0 * PI * f;
        let v = x * Complex64::new(0.0, w);
        let a = -x * w * w;
        for (kind, val) in [(Kind::Mobility, v), (Kind::Accelerance, a)] {
            let back = kind.to_receptance(val, f).unwrap();
            assert!((back - x).norm() < 1e-18, "{kind:?}");
        }
        assert!(Kind::Mobility.to_receptance(v, 0.0).is_none());
    }

    #[test]
    fn interpolation_hits_the_data_and_conjugates() {
        let mut h = BTreeMap::new();
        let freq: Vec<f64> = (1..=10).map(f64::from).collect();
        h.insert(Pair(0, 0), freq.iter().map(|f| Complex64::new(*f, -2.0 * f)).collect());
        h.insert(Pair(1, 1), freq.iter().map(|f| Complex64::new(-f, 0.5)).collect());
        let m = MeasuredFrf { source: "t".into(), freq_hz: freq, h, notes: vec![] }.complete().unwrap();
        let r = MeasuredReceptance::new(&m);
        let w = |f: f64| 2.0 * PI * f;
        assert!((r.receptance(w(3.0))[(0, 0)] - Complex64::new(3.0, -6.0)).norm() < 1e-12);
        assert!((r.receptance(w(3.5))[(0, 0)] - Complex64::new(3.5, -7.0)).norm() < 1e-12);
        assert!((r.receptance(-w(3.5))[(0, 0)] - Complex64::new(3.5, 7.0)).norm() < 1e-12);
        assert_eq!(r.receptance(w(3.5))[(0, 1)], Complex64::new(0.0, 0.0));
        assert!(m.notes.iter().any(|n| n.contains("uncoupled")));
    }
}
