//! The UFF 58 writer: ASCII (E13.5 abscissa, E20.12 ordinates) or binary 58b (little-endian
//! doubles), one dataset per FRF, receptance in m/N.

use super::super::MeasuredFrf;
use std::fmt::Write as _;

/// A Fortran real (`1.5E-07`, `1.5D-07`, `1.5e-07`) as f64.
pub(super) fn fortran_f64(s: &str) -> Option<f64> {
    s.trim().replace(['D', 'd'], "e").parse().ok()
}

/// A number as Fortran `E<w>.<d>` the way C prints it (`-1.23456e-07`), right-aligned.
pub(super) fn e(x: f64, width: usize, digits: usize) -> String {
    let s = format!("{x:.digits$e}");
    let (mant, exp) = s.split_once('e').expect("e format");
    let exp: i32 = exp.parse().expect("exponent");
    format!("{:>width$}", format!("{mant}e{}{:02}", if exp < 0 { '-' } else { '+' }, exp.abs()))
}

/// Does `x` survive `E13.5`?
pub(super) fn fits_e13(x: f64) -> bool {
    fortran_f64(&e(x, 13, 5)) == Some(x)
}

/// The FRFs as a universal file: one dataset 58 (ASCII, or binary 58b) per pair.
pub fn write(frf: &MeasuredFrf, title: &str, binary: bool) -> Vec<u8> {
    let f = &frf.freq_hz;
    let n = f.len();
    let dx = (f[n - 1] - f[0]) / (n - 1) as f64;
    let uniform = f.windows(2).all(|w| ((w[1] - w[0]) - dx).abs() <= 1e-9 * dx.abs());
    // the even form stores only start and step, in E13.5
    let even = uniform && fits_e13(f[0]) && fits_e13(dx);
    let mut out = Vec::new();
    for (pair, h) in &frf.h {
        let mut t = String::new();
        let values_per_point = if even { 2 } else { 3 };
        let nb = n * values_per_point * 8;
        t.push_str("    -1\n");
        if binary {
            let _ = writeln!(t, "    58b{:6}{:6}{:12}{:12}{:6}{:6}{:12}{:12}", 1, 2, 11, nb, 0, 0, 0, 0);
        } else {
            let _ = writeln!(t, "    58{:74}", "");
        }
        let id = |s: &str| format!("{:<80.80}\n", if s.is_empty() { "NONE" } else { s });
        t.push_str(&id(&format!("{title} tool-point FRF {}", pair.name())));
        t.push_str(&id(&frf.source));
        t.push_str(&id("NONE"));
        t.push_str(&id(&format!("receptance {} m/N", pair.name())));
        t.push_str(&id("NONE"));
        let _ = writeln!(
            t,
            "{:5}{:10}{:5}{:10} {:>10}{:10}{:4} {:>10}{:10}{:4}",
            4,
            1,
            1,
            0,
            "NONE",
            1,
            pair.0 + 1,
            "NONE",
            1,
            pair.1 + 1
        );
        let _ = writeln!(
            t,
            "{:10}{:10}{:10}{}{}{}",
            6,
            n,
            i32::from(even),
            e(if even { f[0] } else { 0.0 }, 13, 5),
            e(if even { dx } else { 0.0 }, 13, 5),
            e(0.0, 13, 5)
        );
        for (kind, label, units) in
            [(18, "Frequency", "Hz"), (8, "Displacement", "m"), (13, "Force", "N"), (0, "NONE", "NONE")]
        {
            let (len, force) = match kind {
                8 => (1, 0),
                13 => (0, 1),
                _ => (0, 0),
            };
            let _ = writeln!(t, "{kind:10}{len:5}{force:5}{:5} {label:<20} {units:<20}", 0);
        }
        out.extend_from_slice(t.as_bytes());
        let flat: Vec<f64> = (0..n)
            .flat_map(|k| {
                let v = [f[k], h[k].re, h[k].im];
                if even { v[1..].to_vec() } else { v.to_vec() }
            })
            .collect();
        if binary {
            for x in &flat {
                out.extend_from_slice(&x.to_le_bytes());
            }
        } else {
            let mut d = String::new();
            if even {
                for row in flat.chunks(4) {
                    row.iter().for_each(|x| d.push_str(&e(*x, 20, 11)));
                    d.push('\n');
                }
            } else {
                for row in flat.chunks(3) {
                    let _ = writeln!(d, "{}{}{}", e(row[0], 13, 5), e(row[1], 20, 11), e(row[2], 20, 11));
                }
            }
            out.extend_from_slice(d.as_bytes());
        }
        out.extend_from_slice(b"    -1\n");
    }
    out
}
