//! FRFs as universal file dataset 58 (function at nodal DOF), ASCII and binary (58b), the
//! format every modal-test system exports.
//!
//! A file is a sequence of datasets, each between lines `    -1`. A dataset 58 is an ID line,
//! five text lines, then records 6–11 (fixed-width fields, read as the format specifies):
//!
//! | record | fields used |
//! |---|---|
//! | 6 | function type (4 = FRF), response node and direction, reference node and direction (1 = +x, 2 = +y, −1, −2 the opposite sense) |
//! | 7 | ordinate type (5, 6: complex single, double), number of points, even spacing, abscissa start and step |
//! | 8 | abscissa type (18 = frequency, Hz) |
//! | 9 | ordinate numerator type (8 displacement, 11 velocity, 12 acceleration) and units label |
//! | 10 | ordinate denominator type (13 excitation force) and units label |
//! | 12 | the data: ASCII in the specified widths, or binary (58b: byte order and IEEE format in the ID line) |
//!
//! Units: the numerator's and denominator's units labels when they name a unit (`m/s^2`, `g`,
//! `N`), else the data type's SI unit, with the factors of a units dataset 164 (if one precedes)
//! applied; a velocity or acceleration is converted to receptance as [`super`] says. A negative
//! direction flips the sign. Datasets of other types, FRFs along z and non-FRF functions are
//! skipped (and said so).
//!
//! Written files hold one dataset 58 per pair, complex double precision, node 1, evenly spaced
//! when the grid is (the ASCII abscissa fields have 6 significant digits, the format's own
//! limit; binary files store an uneven abscissa in double precision when the step would lose
//! digits).

use super::{FrfError, Kind, MeasuredFrf, Pair, check_rows, frf_unit, to_receptance};
use num_complex::Complex64;

/// Byte reader with line numbers.
struct Cursor<'a> {
    b: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Cursor<'a> {
    /// The next line (without its end), and its 1-based line number.
    fn line(&mut self) -> Option<(usize, &'a str)> {
        if self.pos >= self.b.len() {
            return None;
        }
        let rest = &self.b[self.pos..];
        let end = rest.iter().position(|&c| c == b'\n').unwrap_or(rest.len());
        let raw = &rest[..end];
        self.pos += (end + 1).min(rest.len());
        self.line += 1;
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        Some((self.line, std::str::from_utf8(raw).unwrap_or("\u{fffd}")))
    }
}

fn is_delimiter(l: &str) -> bool {
    l.trim_end() == "    -1" || (l.trim() == "-1" && l.len() <= 80)
}

/// A fixed-width field `[a, b)` of a line (short lines give empty fields).
fn field(l: &str, a: usize, b: usize) -> &str {
    let b = b.min(l.len());
    if a >= b { "" } else { l.get(a..b).unwrap_or("").trim() }
}

/// What a dataset 58 header says.
#[derive(Debug)]
struct Header {
    func_type: i64,
    rsp: (i64, i64),
    refr: (i64, i64),
    ord_type: i64,
    n: usize,
    even: bool,
    x0: f64,
    dx: f64,
    abscissa: (i64, String),
    numerator: (i64, String),
    denominator: (i64, String),
}

fn ints(file: &str, line: usize, l: &str, widths: &[(usize, usize)], what: &str) -> Result<Vec<i64>, FrfError> {
    let fixed: Option<Vec<i64>> = widths.iter().map(|&(a, b)| field(l, a, b).parse().ok()).collect();
    fixed.ok_or_else(|| FrfError::at(file, Some(line), format!("{what}: fields not where UFF 58 puts them: {l:?}")))
}

fn header(file: &str, lines: &[(usize, &str)]) -> Result<Header, FrfError> {
    let (l6, r6) = lines[5];
    // 2(I5,I10),2(1X,10A1,I10,I4)
    let v6 =
        ints(file, l6, r6, &[(0, 5), (5, 15), (41, 51), (51, 55), (66, 76), (76, 80)], "record 6").or_else(|_| {
            // free format: type id version case name node dir name node dir
            let t: Vec<&str> = r6.split_whitespace().collect();
            let p = |i: usize| t.get(i).and_then(|s| s.parse::<i64>().ok());
            match (p(0), p(1), p(5), p(6), p(8), p(9)) {
                (Some(a), Some(b), Some(c), Some(d), Some(e), Some(f)) => Ok(vec![a, b, c, d, e, f]),
                _ => Err(FrfError::at(file, Some(l6), format!("record 6 (DOF identification) unreadable: {r6:?}"))),
            }
        })?;
    let (l7, r7) = lines[6];
    // 3I10,3E13.5
    let v7 = ints(file, l7, r7, &[(0, 10), (10, 20), (20, 30)], "record 7")?;
    let x0 = fortran_f64(field(r7, 30, 43));
    let dx = fortran_f64(field(r7, 43, 56));
    let (Some(x0), Some(dx)) = (x0, dx) else {
        return Err(FrfError::at(file, Some(l7), format!("record 7: abscissa start and step unreadable: {r7:?}")));
    };
    let chars = |k: usize| -> Result<(i64, String), FrfError> {
        let (ln, r) = lines[k];
        let t = ints(file, ln, r, &[(0, 10)], &format!("record {}", k + 2))?;
        Ok((t[0], field(r, 47, 67).to_string()))
    };
    let n = usize::try_from(v7[1]).map_err(|_| FrfError::at(file, Some(l7), format!("record 7: {} points", v7[1])))?;
    Ok(Header {
        func_type: v6[0],
        rsp: (v6[2], v6[3]),
        refr: (v6[4], v6[5]),
        ord_type: v7[0],
        n,
        even: v7[2] == 1,
        x0,
        dx,
        abscissa: chars(7)?,
        numerator: chars(8)?,
        denominator: chars(9)?,
    })
}

/// Function type names for messages.
fn function_name(t: i64) -> &'static str {
    match t {
        0 => "general",
        1 => "time response",
        2 => "auto spectrum",
        3 => "cross spectrum",
        4 => "frequency response function",
        6 => "coherence",
        _ => "another function",
    }
}

/// The kind and SI factor of a dataset's ordinate.
fn ordinate_unit(
    file: &str,
    line: usize,
    h: &Header,
    units164: f64,
    notes: &mut Vec<String>,
) -> Result<(Kind, f64), FrfError> {
    let by_type = match h.numerator.0 {
        8 => Some(Kind::Receptance),
        11 => Some(Kind::Mobility),
        12 => Some(Kind::Accelerance),
        0 | 1 => None,
        t => {
            return Err(FrfError::at(
                file,
                Some(line),
                format!(
                    "record 9: ordinate data type {t} is not a displacement (8), velocity (11) or acceleration (12)"
                ),
            ));
        }
    };
    if ![0, 1, 9, 13].contains(&h.denominator.0) {
        return Err(FrfError::at(
            file,
            Some(line + 1),
            format!("record 10: denominator data type {} is not a force (13 excitation force)", h.denominator.0),
        ));
    }
    let label = |s: &str| !s.is_empty() && !s.eq_ignore_ascii_case("NONE");
    if label(&h.numerator.1) {
        let den = if label(&h.denominator.1) { h.denominator.1.clone() } else { "N".into() };
        let unit = if h.numerator.1.contains('/') && h.numerator.1.ends_with('N') && !label(&h.denominator.1) {
            h.numerator.1.clone()
        } else {
            format!("{}/{den}", h.numerator.1)
        };
        match frf_unit(&unit) {
            Ok((kind, factor)) => {
                if let Some(t) = by_type
                    && t != kind
                {
                    return Err(FrfError::at(
                        file,
                        Some(line),
                        format!(
                            "record 9 says {} but the units label {unit:?} says {}: correct one of them",
                            t.name(),
                            kind.name()
                        ),
                    ));
                }
                return Ok((kind, factor));
            }
            Err(m) => {
                notes.push(format!("{file}: units label {unit:?} not understood ({m}); the data type's SI unit taken"))
            }
        }
    }
    let kind = by_type.ok_or_else(|| {
        FrfError::at(
            file,
            Some(line),
            "record 9: the ordinate is neither typed (8, 11, 12) nor labelled with a unit: say whether it is displacement, velocity or acceleration",
        )
    })?;
    Ok((kind, units164))
}

/// Parse UFF bytes (`file` names it in errors).
pub fn parse(bytes: &[u8], file: &str) -> Result<MeasuredFrf, FrfError> {
    let mut c = Cursor { b: bytes, pos: 0, line: 0 };
    let mut freq: Option<(Vec<f64>, String)> = None;
    let mut columns: Vec<(Pair, Kind, f64, Vec<Complex64>)> = Vec::new();
    let mut seen: Vec<(Pair, usize, (i64, i64))> = Vec::new();
    let mut notes = Vec::new();
    let mut units164 = 1.0;
    let mut datasets = 0;
    loop {
        // to the next dataset's start
        let start = loop {
            match c.line() {
                None => break None,
                Some((_, l)) if l.trim().is_empty() => continue,
                Some((n, l)) if is_delimiter(l) => break Some(n),
                Some((n, l)) => {
                    return Err(FrfError::at(
                        file,
                        Some(n),
                        format!("expected a dataset start '    -1', found {l:?}: is this a UFF file?"),
                    ));
                }
            }
        };
        let Some(start) = start else { break };
        let Some((id_line, id)) = c.line() else {
            return Err(FrfError::at(file, Some(start), "a dataset start at the end of the file"));
        };
        datasets += 1;
        let kind_text = field(id, 0, 6);
        let binary = id.as_bytes().get(6).is_some_and(|b| b.eq_ignore_ascii_case(&b'b'));
        let Ok(kind) = kind_text.parse::<i64>() else {
            return Err(FrfError::at(file, Some(id_line), format!("dataset number {id:?} unreadable")));
        };
        if kind != 58 {
            // skip this dataset (binary: by its byte count)
            let body_start = c.pos;
            if binary {
                let v = ints(file, id_line, id, &[(19, 31), (31, 43)], "binary ID line")?;
                for _ in 0..v[0] {
                    c.line();
                }
                c.pos += usize::try_from(v[1]).unwrap_or(0);
            }
            let mut lines_164 = Vec::new();
            loop {
                match c.line() {
                    None => {
                        return Err(FrfError::at(
                            file,
                            Some(id_line),
                            format!("dataset {kind} has no closing '    -1'"),
                        ));
                    }
                    Some((_, l)) if is_delimiter(l) => break,
                    Some((_, l)) => lines_164.push(l.to_string()),
                }
            }
            if kind == 164 {
                let code: i64 = field(&lines_164[0], 0, 10).parse().unwrap_or(1);
                if code != 1 {
                    // factors to SI: SI = file value / factor
                    let f: Vec<f64> =
                        lines_164.get(1).map_or(vec![], |l| l.split_whitespace().filter_map(fortran_f64).collect());
                    if f.len() < 2 || f[0] <= 0.0 || f[1] <= 0.0 {
                        return Err(FrfError::at(
                            file,
                            Some(id_line + 2),
                            "dataset 164 (units): length and force factors unreadable",
                        ));
                    }
                    units164 = f[1] / f[0];
                    notes.push(format!("{file}: units dataset 164 (code {code}): values × {units164} to SI"));
                }
            } else {
                notes.push(format!("{file}: dataset {kind} at line {start} skipped (only 58 holds FRFs)"));
            }
            let _ = body_start;
            continue;
        }
        // eleven header lines
        let mut head = Vec::with_capacity(11);
        for _ in 0..11 {
            let (n, l) = c
                .line()
                .ok_or_else(|| FrfError::at(file, Some(id_line), "dataset 58 ends inside its header (11 lines)"))?;
            head.push((n, l));
        }
        let h = header(file, &head)?;
        let rec7 = head[6].0;
        let values_per_point = match (h.ord_type, h.even) {
            (5 | 6, true) => 2,
            (5 | 6, false) => 3,
            (2 | 4, _) => {
                return Err(FrfError::at(
                    file,
                    Some(rec7),
                    format!("record 7: ordinate type {} is real: an FRF is complex (type 5 or 6)", h.ord_type),
                ));
            }
            (t, _) => return Err(FrfError::at(file, Some(rec7), format!("record 7: unknown ordinate data type {t}"))),
        };
        let double = h.ord_type == 6;
        let mut values: Vec<f64> = Vec::with_capacity(h.n * values_per_point);
        let mut line_of_point: Vec<usize> = Vec::new();
        if binary {
            let v = ints(file, id_line, id, &[(7, 13), (13, 19)], "58b ID line (byte order, float format)")?;
            if v[1] != 2 {
                return Err(FrfError::at(
                    file,
                    Some(id_line),
                    format!("58b floating-point format {}: only IEEE 754 (2) is read", v[1]),
                ));
            }
            let size = if double { 8 } else { 4 };
            let nb = h.n * values_per_point * size;
            let data = bytes.get(c.pos..c.pos + nb).ok_or_else(|| {
                FrfError::at(
                    file,
                    Some(id_line),
                    format!("58b: record 7 says {} points ({nb} bytes) but the file ends before", h.n),
                )
            })?;
            for chunk in data.chunks_exact(size) {
                let x = match (size, v[0]) {
                    (8, 2) => f64::from_be_bytes(chunk.try_into().expect("8 bytes")),
                    (8, _) => f64::from_le_bytes(chunk.try_into().expect("8 bytes")),
                    (_, 2) => f64::from(f32::from_be_bytes(chunk.try_into().expect("4 bytes"))),
                    _ => f64::from(f32::from_le_bytes(chunk.try_into().expect("4 bytes"))),
                };
                values.push(x);
            }
            c.line += data.iter().filter(|&&b| b == b'\n').count();
            c.pos += nb;
            line_of_point = vec![head[10].0 + 1; h.n];
            // the closing delimiter follows the data directly (maybe after a line end)
            let tail = c.line().map(|(n, l)| (n, l.to_string()));
            match tail {
                Some((_, l)) if is_delimiter(&l) => {}
                Some((_, l)) if l.trim().is_empty() => match c.line() {
                    Some((_, l)) if is_delimiter(l) => {}
                    _ => {
                        return Err(FrfError::at(
                            file,
                            Some(id_line),
                            format!("58b: no '    -1' after the {} points of record 7", h.n),
                        ));
                    }
                },
                _ => {
                    return Err(FrfError::at(
                        file,
                        Some(id_line),
                        format!(
                            "58b: no '    -1' after the {} points record 7 announces: the number of points or the data is wrong",
                            h.n
                        ),
                    ));
                }
            }
        } else {
            // fixed-width fields of the specified format
            let widths: &[usize] = match (double, h.even) {
                (false, _) => &[13; 6],
                (true, true) => &[20; 4],
                (true, false) => &[13, 20, 20],
            };
            loop {
                let (n, l) =
                    c.line().ok_or_else(|| FrfError::at(file, Some(id_line), "dataset 58 has no closing '    -1'"))?;
                if is_delimiter(l) {
                    break;
                }
                let mut a = 0;
                for w in widths {
                    let s = field(l, a, a + w);
                    a += w;
                    if s.is_empty() {
                        break;
                    }
                    let x =
                        fortran_f64(s).ok_or_else(|| FrfError::at(file, Some(n), format!("{s:?} is not a number")))?;
                    if values.len().is_multiple_of(values_per_point) {
                        line_of_point.push(n);
                    }
                    values.push(x);
                }
            }
        }
        if values.len() != h.n * values_per_point {
            return Err(FrfError::at(
                file,
                Some(rec7),
                format!(
                    "record 7 says {} points, the data hold {} values ({} per point): the lengths do not match",
                    h.n,
                    values.len(),
                    values_per_point
                ),
            ));
        }
        // the function and its DOFs
        if h.func_type != 4 {
            notes.push(format!(
                "{file}: dataset 58 at line {start} is a {} (type {}), skipped",
                function_name(h.func_type),
                h.func_type
            ));
            continue;
        }
        if ![0, 1, 18].contains(&h.abscissa.0) {
            return Err(FrfError::at(
                file,
                Some(head[7].0),
                format!("record 8: abscissa type {} is not a frequency (18)", h.abscissa.0),
            ));
        }
        let axis = |d: i64| match d {
            1 | -1 => Some(0),
            2 | -2 => Some(1),
            _ => None,
        };
        let (Some(p), Some(q)) = (axis(h.rsp.1), axis(h.refr.1)) else {
            notes.push(format!(
                "{file}: FRF at line {start} (directions {} / {}) is not in the x–y plane, skipped",
                h.rsp.1, h.refr.1
            ));
            continue;
        };
        let pair = Pair(p, q);
        if let Some((_, l, nodes)) = seen.iter().find(|s| s.0 == pair) {
            return Err(FrfError::at(
                file,
                Some(start),
                format!(
                    "a second {} FRF (nodes {}→{}; the first at line {l}, nodes {}→{}): keep only the tool point's",
                    pair.name(),
                    h.rsp.0,
                    h.refr.0,
                    nodes.0,
                    nodes.1
                ),
            ));
        }
        seen.push((pair, start, (h.rsp.0, h.refr.0)));
        let sign = (h.rsp.1.signum() * h.refr.1.signum()) as f64;
        if sign < 0.0 {
            notes.push(format!("{file}: {} measured in the negative sense, sign flipped", pair.name()));
        }
        let (kind, factor) = ordinate_unit(file, head[8].0, &h, units164, &mut notes)?;
        let hz = if h.abscissa.1.eq_ignore_ascii_case("rad/s") { 1.0 / (2.0 * std::f64::consts::PI) } else { 1.0 };
        let (f, data): (Vec<f64>, Vec<Complex64>) = if h.even {
            values
                .chunks_exact(2)
                .enumerate()
                .map(|(k, v)| ((h.x0 + k as f64 * h.dx) * hz, Complex64::new(v[0], v[1]) * sign))
                .unzip()
        } else {
            values.chunks_exact(3).map(|v| (v[0] * hz, Complex64::new(v[1], v[2]) * sign)).unzip()
        };
        check_rows(file, &f, &[(pair, data.clone())], |k| line_of_point.get(k).copied())?;
        match &freq {
            None => freq = Some((f, format!("line {start}"))),
            Some((f0, at)) => {
                let same =
                    f0.len() == f.len() && f0.iter().zip(&f).all(|(a, b)| (a - b).abs() <= 1e-9 * a.abs().max(1.0));
                if !same {
                    return Err(FrfError::at(
                        file,
                        Some(start),
                        format!(
                            "{} points over {}–{} Hz, but the FRF at {at} has {} over {}–{} Hz: export every FRF on one frequency grid",
                            f.len(),
                            f[0],
                            f[f.len() - 1],
                            f0.len(),
                            f0[0],
                            f0[f0.len() - 1]
                        ),
                    ));
                }
            }
        }
        columns.push((pair, kind, factor, data));
    }
    if datasets == 0 {
        return Err(FrfError::at(file, None, "no dataset: a universal file starts with a line '    -1'"));
    }
    let Some((freq, _)) = freq else {
        return Err(FrfError::at(
            file,
            None,
            format!("{datasets} datasets but no FRF (dataset 58, function type 4) along x or y"),
        ));
    };
    let mut m = to_receptance(file, freq, columns);
    notes.append(&mut m.notes);
    m.notes = notes;
    Ok(m)
}

mod write;
use write::fortran_f64;
pub use write::write;
#[cfg(test)]
use write::{e, fits_e13};

#[cfg(test)]
mod tests;
