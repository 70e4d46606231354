//! UFF 58 round trips (ASCII and binary) and bad files.

use super::*;
use std::collections::BTreeMap;

fn sample(n: usize, step: f64) -> MeasuredFrf {
    let freq_hz: Vec<f64> = (0..n).map(|k| 10.0 + k as f64 * step).collect();
    let mut h = BTreeMap::new();
    for (i, p) in Pair::ALL.into_iter().enumerate() {
        h.insert(
            p,
            freq_hz.iter().map(|f| Complex64::new(1e-7 / (1.0 + f + i as f64), -3e-8 * (f / 97.0).sin())).collect(),
        );
    }
    MeasuredFrf { source: "synthetic".into(), freq_hz, h, notes: vec![] }
}

#[test]
fn ascii_and_binary_round_trip() {
    for (step, want_even) in [(1.0, true), (0.48828125, false)] {
        let m = sample(37, step);
        // binary: every bit
        let b = parse(&write(&m, "t", true), "t.uff").unwrap();
        assert_eq!((b.freq_hz.clone(), b.h.clone()), (m.freq_hz.clone(), m.h.clone()), "binary step {step}");
        // ASCII: 12 significant digits, the abscissa to 6 (E13.5)
        let text = write(&m, "t", false);
        let s = String::from_utf8(text.clone()).unwrap();
        assert_eq!(s.lines().nth(8).unwrap().as_bytes()[29], if want_even { b'1' } else { b'0' });
        assert!(s.lines().all(|l| l.len() <= 80), "80 columns");
        let a = parse(&text, "t.uff").unwrap();
        for (p, h) in &m.h {
            for (x, y) in h.iter().zip(&a.h[p]) {
                assert!((x - y).norm() <= 1e-11 * x.norm(), "{p:?} {x} {y}");
            }
        }
        for (x, y) in m.freq_hz.iter().zip(&a.freq_hz) {
            assert!((x - y).abs() <= 1e-5 * x, "{x} {y}");
        }
    }
}

#[test]
fn fortran_numbers_are_right_aligned() {
    assert_eq!(e(-1.5e-7, 20, 11), "  -1.50000000000e-07");
    assert_eq!(e(1234.0, 13, 5), "  1.23400e+03");
    assert!(fits_e13(1.0) && !fits_e13(0.48828125));
}

#[test]
fn bad_files_say_what_and_where() {
    let m = sample(12, 1.0);
    let good = String::from_utf8(write(&m, "t", false)).unwrap();
    let lines: Vec<&str> = good.lines().collect();
    let edit = |k: usize, new: &str| {
        let mut l = lines.clone();
        l[k] = new;
        l.join("\n") + "\n"
    };
    let rec7 = lines[8];
    let cases: Vec<(String, &str)> = vec![
        (
            edit(8, &rec7.replacen("        12", "        13", 1)),
            "t.uff:9: record 7 says 13 points, the data hold 24 values",
        ),
        (edit(8, &format!("         4{}", &rec7[10..])), "ordinate type 4 is real"),
        (
            edit(10, "        11    0    0    0 Velocity             m/s^2               "),
            "t.uff:11: record 9 says mobility but the units label \"m/s^2/N\" says accelerance",
        ),
        (
            edit(11, "         2    0    0    0 Stress               NONE                "),
            "t.uff:12: record 10: denominator data type 2 is not a force",
        ),
        (edit(13, &format!("{:>20}{}", "NaN", &lines[13][20..])), "t.uff:14: xx at 10 Hz is NaN"),
        (good.replacen("    -1\n", "    -2\n", 1), "expected a dataset start"),
        (lines[..lines.len() - 1].join("\n") + "\n", "dataset 58 has no closing"),
        (String::new(), "no dataset"),
    ];
    for (text, want) in cases {
        let e = parse(text.as_bytes(), "t.uff").unwrap_err().to_string();
        assert!(e.contains(want), "{e}\n  wanted: {want}");
    }
    // a repeated pair
    let twice = [good.as_bytes(), good.as_bytes()].concat();
    assert!(parse(&twice, "t.uff").unwrap_err().to_string().contains("a second xx FRF"));
    // binary: fewer bytes than record 7 says
    let b = write(&m, "t", true);
    let closing = b.windows(7).enumerate().filter(|(_, w)| *w == b"    -1\n").nth(1).unwrap().0;
    let e = parse(&b[..closing - 40], "t.uff").unwrap_err().to_string();
    assert!(e.contains("file ends before"), "{e}");
    // text: the header cut short
    let e = parse(&b[..b.len() / 3], "t.uff").unwrap_err().to_string();
    assert!(e.contains("ends inside its header"), "{e}");
}
