//! FRFs as CSV: one frequency column and a real and an imaginary column per direction pair, the
//! header naming each column's pair and unit.
//!
//! ```text
//! # tap test, 12 mm end mill, 2026-11-26          (lines starting with # are comments)
//! frequency [Hz],xx real [m/N],xx imag [m/N],yy real [m/N],yy imag [m/N]
//! 1,5.00e-08,-1.2e-10,4.00e-08,-1.1e-10
//! ```
//!
//! One file may hold one pair or several; several files are merged by
//! [`super::MeasuredFrf::read`]. The frequency unit is `Hz`, `kHz` or `rad/s`; an FRF unit is a
//! receptance (`m/N`, `mm/N`, `um/N`), a mobility (`m/s/N`) or an accelerance (`m/s^2/N`, `g/N`),
//! converted to receptance by the harmonic rule of [`super`]. The separator is `,`, `;` or a tab
//! (whichever the header uses).

use super::{FrfError, Kind, MeasuredFrf, Pair, check_rows, frf_unit, to_receptance};
use num_complex::Complex64;
use std::fmt::Write as _;

const EXAMPLE: &str = "frequency [Hz],xx real [m/N],xx imag [m/N]";

/// A column of the header.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Column {
    Frequency(f64),
    Part { pair: Pair, imag: bool, kind: Kind, factor: f64 },
}

/// `name [unit]` or `name (unit)`.
fn name_and_unit(cell: &str) -> (String, Option<String>) {
    let c = cell.trim().trim_matches('"');
    for (open, close) in [('[', ']'), ('(', ')')] {
        if let (Some(a), Some(b)) = (c.find(open), c.rfind(close))
            && b > a
        {
            return (c[..a].trim().to_lowercase(), Some(c[a + 1..b].trim().to_string()));
        }
    }
    (c.to_lowercase(), None)
}

fn column(file: &str, line: usize, index: usize, cell: &str) -> Result<Column, FrfError> {
    let err = |m: String| FrfError::at(file, Some(line), m);
    let (name, unit) = name_and_unit(cell);
    if index == 0 {
        if !["frequency", "freq", "f"].contains(&name.as_str()) {
            return Err(err(format!(
                "the first column is {cell:?}: it must be the frequency, e.g. a header {EXAMPLE:?}"
            )));
        }
        let unit = unit.ok_or_else(|| err(format!("column {cell:?} names no unit: write \"frequency [Hz]\"")))?;
        let factor = match unit.as_str() {
            "Hz" => 1.0,
            "kHz" => 1e3,
            "rad/s" => 1.0 / (2.0 * std::f64::consts::PI),
            _ => return Err(err(format!("frequency unit {unit:?}: use Hz, kHz or rad/s"))),
        };
        return Ok(Column::Frequency(factor));
    }
    let mut words = name.split_whitespace();
    let (p, part) = (words.next().unwrap_or(""), words.next().unwrap_or(""));
    let pair = Pair::parse(p).ok_or_else(|| {
        err(format!(
            "column {} is {cell:?}: name its direction pair (xx, xy, yx or yy), e.g. \"xx real [m/N]\"",
            index + 1
        ))
    })?;
    let imag = match part {
        "real" | "re" => false,
        "imag" | "im" | "imaginary" => true,
        _ => {
            return Err(err(format!(
                "column {} is {cell:?}: say which part, \"{} real [m/N]\" or \"{} imag [m/N]\"",
                index + 1,
                pair.name(),
                pair.name()
            )));
        }
    };
    let unit =
        unit.ok_or_else(|| err(format!("column {cell:?} names no unit: write e.g. \"{} real [m/N]\"", pair.name())))?;
    let (kind, factor) = frf_unit(&unit).map_err(|m| err(format!("column {cell:?}: {m}")))?;
    Ok(Column::Part { pair, imag, kind, factor })
}

/// Parse a CSV file's bytes (`file` names it in errors).
pub fn parse(bytes: &[u8], file: &str) -> Result<MeasuredFrf, FrfError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| FrfError::at(file, None, format!("not UTF-8 text ({e}): is it a UFF file? name it .uff")))?;
    let mut lines =
        text.lines().enumerate().map(|(i, l)| (i + 1, l.trim())).filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (hline, header) = lines.next().ok_or_else(|| {
        FrfError::at(file, None, format!("no header: the first line must name the columns, e.g. {EXAMPLE:?}"))
    })?;
    let sep = [',', ';', '\t'].into_iter().max_by_key(|c| header.matches(*c).count()).expect("three separators");
    let cols: Vec<Column> =
        header.split(sep).enumerate().map(|(i, c)| column(file, hline, i, c)).collect::<Result<_, _>>()?;
    let freq_factor = match cols[0] {
        Column::Frequency(f) => f,
        Column::Part { .. } => unreachable!("column 0 is the frequency"),
    };
    // every pair once with both parts in one unit
    let mut pairs: Vec<(Pair, Kind, f64, usize, usize)> = Vec::new();
    for (i, c) in cols.iter().enumerate().skip(1) {
        let Column::Part { pair, imag, kind, factor } = *c else {
            return Err(FrfError::at(file, Some(hline), format!("column {} is a second frequency column", i + 1)));
        };
        match pairs.iter_mut().find(|p| p.0 == pair) {
            None => {
                pairs.push((pair, kind, factor, if imag { usize::MAX } else { i }, if imag { i } else { usize::MAX }))
            }
            Some(p) => {
                let slot = if imag { &mut p.4 } else { &mut p.3 };
                if *slot != usize::MAX {
                    return Err(FrfError::at(
                        file,
                        Some(hline),
                        format!("two {} {} columns", pair.name(), if imag { "imag" } else { "real" }),
                    ));
                }
                if p.1 != kind || p.2.to_bits() != factor.to_bits() {
                    return Err(FrfError::at(
                        file,
                        Some(hline),
                        format!("the {} real and imag columns have different units", pair.name()),
                    ));
                }
                *slot = i;
            }
        }
    }
    if pairs.is_empty() {
        return Err(FrfError::at(file, Some(hline), format!("no FRF column: e.g. {EXAMPLE:?}")));
    }
    if let Some(p) = pairs.iter().find(|p| p.3 == usize::MAX || p.4 == usize::MAX) {
        let missing = if p.3 == usize::MAX { "real" } else { "imag" };
        return Err(FrfError::at(
            file,
            Some(hline),
            format!("{} has no {missing} column: give both parts", p.0.name()),
        ));
    }
    let mut freq = Vec::new();
    let mut line_no = Vec::new();
    let mut values: Vec<Vec<Complex64>> = vec![Vec::new(); pairs.len()];
    for (n, l) in lines {
        let cells: Vec<&str> = l.split(sep).map(str::trim).collect();
        if cells.len() != cols.len() {
            return Err(FrfError::at(
                file,
                Some(n),
                format!(
                    "{} values, but the header has {} columns: every row needs all of them",
                    cells.len(),
                    cols.len()
                ),
            ));
        }
        let num = |i: usize| -> Result<f64, FrfError> {
            cells[i]
                .parse::<f64>()
                .map_err(|_| FrfError::at(file, Some(n), format!("column {} is {:?}: not a number", i + 1, cells[i])))
        };
        freq.push(num(0)? * freq_factor);
        for (v, p) in values.iter_mut().zip(&pairs) {
            v.push(Complex64::new(num(p.3)?, num(p.4)?));
        }
        line_no.push(n);
    }
    let checked: Vec<(Pair, Vec<Complex64>)> = pairs.iter().zip(&values).map(|(p, v)| (p.0, v.clone())).collect();
    check_rows(file, &freq, &checked, |k| line_no.get(k).copied())?;
    let columns = pairs.iter().zip(values).map(|(p, v)| (p.0, p.1, p.2, v)).collect();
    Ok(to_receptance(file, freq, columns))
}

/// The FRFs as CSV text (receptance in m/N, every value to full precision), `comment` lines first.
pub fn write(frf: &MeasuredFrf, comment: &str) -> String {
    let mut out = String::new();
    for line in comment.lines().chain(frf.notes.iter().map(String::as_str)) {
        let _ = writeln!(out, "# {line}");
    }
    out.push_str("frequency [Hz]");
    for p in frf.h.keys() {
        let _ = write!(out, ",{0} real [m/N],{0} imag [m/N]", p.name());
    }
    out.push('\n');
    for (k, f) in frf.freq_hz.iter().enumerate() {
        let _ = write!(out, "{f:e}");
        for h in frf.h.values() {
            let _ = write!(out, ",{:e},{:e}", h[k].re, h[k].im);
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<MeasuredFrf, FrfError> {
        parse(text.as_bytes(), "tap.csv")
    }

    fn rows(n: usize, f: impl Fn(usize) -> String) -> String {
        (1..=n).map(f).collect::<Vec<_>>().join("\n")
    }

    #[test]
    fn reads_units_and_round_trips() {
        let text = format!(
            "# a tap test\nfrequency [Hz],xx real [um/N],xx imag [um/N]\n{}",
            rows(10, |k| format!("{k},{}.5,-1", k))
        );
        let m = read(&text).unwrap();
        assert_eq!(m.freq_hz.len(), 10);
        assert!((m.h[&Pair(0, 0)][2] - Complex64::new(3.5e-6, -1e-6)).norm() < 1e-18);
        // written and read back: the same numbers
        let mut both = m.clone();
        both.h.insert(Pair(1, 1), m.h[&Pair(0, 0)].iter().map(|v| v * 2.0).collect());
        let back = read(&write(&both, "round trip")).unwrap();
        assert_eq!(back.h, both.h);
        assert_eq!(back.freq_hz, both.freq_hz);
    }

    #[test]
    fn accelerance_in_g_drops_zero_hz() {
        let text = format!("frequency [Hz];yy re [g/N];yy im [g/N]\n{}", rows(10, |k| format!("{};1;0", k - 1)));
        let m = read(&text).unwrap();
        assert_eq!(m.freq_hz[0].to_bits(), 1f64.to_bits());
        let w = 2.0 * std::f64::consts::PI;
        assert!((m.h[&Pair(1, 1)][0].re + 9.80665 / (w * w)).abs() < 1e-15);
        assert!(
            m.notes.iter().any(|n| n.contains("0 Hz row dropped")) && m.notes.iter().any(|n| n.contains("accelerance"))
        );
    }

    #[test]
    fn bad_files_name_the_line_and_the_fix() {
        let head = "frequency [Hz],xx real [m/N],xx imag [m/N]\n";
        let ok = |k: usize| format!("{k},1e-7,-1e-7");
        let cases: Vec<(String, &str)> = vec![
            (
                format!("{head}{}\n3,1e-7,-1e-7", rows(9, ok)),
                "tap.csv:11: frequency 3 Hz after 9 Hz: the frequencies must increase",
            ),
            (format!("{head}{}\n10,nan,0", rows(9, ok)), "tap.csv:11: xx at 10 Hz is NaN"),
            (format!("{head}{}\n10,1e-7", rows(9, ok)), "tap.csv:11: 2 values, but the header has 3 columns"),
            (
                format!("frequency [Hz],xx real [N/m],xx imag [N/m]\n{}", rows(10, ok)),
                "tap.csv:1: column \"xx real [N/m]\": unit \"N/m\" is a stiffness",
            ),
            (format!("frequency [Hz],real [m/N],imag [m/N]\n{}", rows(10, ok)), "name its direction pair"),
            (format!("frequency,xx real [m/N],xx imag [m/N]\n{}", rows(10, ok)), "names no unit"),
            (format!("{head}{}\n10,1e-7,abc", rows(9, ok)), "tap.csv:11: column 3 is \"abc\": not a number"),
            (format!("frequency [Hz],xx real [m/N]\n{}", rows(10, |k| format!("{k},1"))), "xx has no imag column"),
            (format!("{head}{}", rows(3, ok)), "3 frequencies: a tap test needs at least 8"),
        ];
        for (text, want) in cases {
            let e = read(&text).unwrap_err().to_string();
            assert!(e.contains(want), "{e}\n  wanted: {want}");
        }
    }
}
