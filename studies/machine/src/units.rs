//! Quantities with units, as a machine file writes them: an SI number (`2e7`) or a string with
//! a number and a unit (`"800 N/mm^2"`, `"600 Hz"`, `"12 mm"`, `"3 %"`).
//!
//! A unit is a product of powers of named units with SI prefixes: `N/mm^2`, `N·s/m`, `N/µm`,
//! `kg*m^2`, `MPa`, `rad/s`. The parser reduces it to a factor and a dimension (exponents of
//! kg, m, s); each field of the machine file says which dimension it takes, and a unit of
//! another dimension is refused with the field's accepted units.
//!
//! Angles and cycles: `rad` is 1 (dimensionless), `deg` is π/180, `rev` is 2π, `rpm` is
//! `rev/min`. A frequency field takes `Hz`, `kHz`, `rad/s`, `rpm`; since `Hz` counts cycles
//! and `rad/s` radians, frequencies are reduced to angular frequency (`Hz` = 2π rad/s), and a
//! bare `1/s` is refused as ambiguous. Percent `%` is 0.01.

use std::f64::consts::PI;

/// Exponents of kg, m and s.
pub type Dim = [f64; 3];

/// Dimensionless.
pub const ONE: Dim = [0.0, 0.0, 0.0];
/// Length (m).
pub const LENGTH: Dim = [0.0, 1.0, 0.0];
/// Mass (kg).
pub const MASS: Dim = [1.0, 0.0, 0.0];
/// Angular frequency (rad/s).
pub const FREQUENCY: Dim = [0.0, 0.0, -1.0];
/// Force (N).
pub const FORCE: Dim = [1.0, 1.0, -2.0];
/// Stiffness (N/m), also force per length (edge coefficients).
pub const STIFFNESS: Dim = [1.0, 0.0, -2.0];
/// Pressure (N/m², specific cutting force of the linear law).
pub const PRESSURE: Dim = [1.0, -1.0, -2.0];
/// Time (s).
pub const TIME: Dim = [0.0, 0.0, 1.0];

/// A parsed quantity: its SI value and dimension, and whether a unit was written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quantity {
    /// Value in SI (angles in rad, frequencies in rad/s).
    pub si: f64,
    /// Dimension.
    pub dim: Dim,
    /// Did the text name a unit (a bare number is SI)?
    pub had_unit: bool,
    /// Did the unit count cycles or angles (Hz, rev, rad, deg, rpm)?
    pub angular: bool,
}

/// One named unit: name, factor to SI, dimension, angular (cycles or radians).
const UNITS: &[(&str, f64, Dim, bool)] = &[
    ("m", 1.0, LENGTH, false),
    ("in", 0.0254, LENGTH, false),
    ("s", 1.0, TIME, false),
    ("min", 60.0, TIME, false),
    ("h", 3600.0, TIME, false),
    ("g", 1e-3, MASS, false),
    ("N", 1.0, FORCE, false),
    ("Pa", 1.0, PRESSURE, false),
    ("Hz", 2.0 * PI, FREQUENCY, true),
    ("rad", 1.0, ONE, true),
    ("deg", PI / 180.0, ONE, true),
    ("°", PI / 180.0, ONE, true),
    ("rev", 2.0 * PI, ONE, true),
    ("rpm", 2.0 * PI / 60.0, FREQUENCY, true),
    ("%", 0.01, ONE, false),
];

/// SI prefixes (`u` for micro as well as `µ`).
const PREFIXES: &[(&str, f64)] =
    &[("n", 1e-9), ("µ", 1e-6), ("μ", 1e-6), ("u", 1e-6), ("m", 1e-3), ("c", 1e-2), ("k", 1e3), ("M", 1e6), ("G", 1e9)];

/// Units that take a prefix.
const PREFIXABLE: &[&str] = &["m", "s", "g", "N", "Pa", "Hz"];

/// One named unit, with an optional prefix: (factor, dimension, angular).
fn atom(name: &str) -> Option<(f64, Dim, bool)> {
    if let Some(&(_, f, d, a)) = UNITS.iter().find(|(n, ..)| *n == name) {
        return Some((f, d, a));
    }
    for (p, pf) in PREFIXES {
        if let Some(rest) = name.strip_prefix(p)
            && PREFIXABLE.contains(&rest)
            && let Some(&(_, f, d, a)) = UNITS.iter().find(|(n, ..)| *n == rest)
        {
            return Some((pf * f, d, a));
        }
    }
    None
}

/// Parse a unit expression (`N/mm^2`, `N·s/m`, `kg*m^2`, `1/s`) into (factor, dimension, angular).
pub fn parse_unit(text: &str) -> Result<(f64, Dim, bool), String> {
    let t = text.trim().replace(['·', '*', '⋅'], " ").replace('²', "^2").replace('³', "^3");
    let (mut factor, mut dim, mut angular) = (1.0, ONE, false);
    // split at '/': the first part multiplies, every later part divides
    for (i, part) in t.split('/').enumerate() {
        let sign = if i == 0 { 1.0 } else { -1.0 };
        let part = part.trim().trim_start_matches('(').trim_end_matches(')');
        if part.is_empty() {
            return Err(format!("unit {text:?}: empty part"));
        }
        for word in part.split_whitespace() {
            let (name, power) = match word.split_once('^') {
                Some((n, p)) => {
                    let p = p.trim_start_matches('(').trim_end_matches(')');
                    (n, p.parse::<f64>().map_err(|_| format!("unit {text:?}: bad exponent {p:?}"))?)
                }
                None => (word, 1.0),
            };
            if name == "1" && (power - 1.0).abs() < f64::EPSILON {
                continue;
            }
            let (f, d, a) = atom(name).ok_or_else(|| format!("unit {text:?}: unknown unit {name:?}"))?;
            factor *= f.powf(sign * power);
            for k in 0..3 {
                dim[k] += sign * power * d[k];
            }
            angular |= a;
        }
    }
    Ok((factor, dim, angular))
}

/// Parse `"<number> <unit>"` (or a bare number string).
pub fn parse_quantity(text: &str) -> Result<Quantity, String> {
    let t = text.trim();
    let split = t
        .char_indices()
        .find(|&(i, c)| {
            !(c.is_ascii_digit() || c == '.' || c == '+' || c == '-')
                && !((c == 'e' || c == 'E')
                    && t[i + 1..].starts_with(|n: char| n.is_ascii_digit() || n == '-' || n == '+'))
        })
        .map_or(t.len(), |(i, _)| i);
    let (num, unit) = t.split_at(split);
    let value: f64 = num.trim().parse().map_err(|_| format!("{text:?} does not start with a number"))?;
    let unit = unit.trim();
    if unit.is_empty() {
        return Ok(Quantity { si: value, dim: ONE, had_unit: false, angular: false });
    }
    let (factor, dim, angular) = parse_unit(unit)?;
    Ok(Quantity { si: value * factor, dim, had_unit: true, angular })
}

/// A dimension in words (for messages).
pub fn describe(dim: Dim) -> String {
    let known: [(Dim, &str); 8] = [
        (ONE, "a number without dimension"),
        (LENGTH, "a length"),
        (MASS, "a mass"),
        (FREQUENCY, "a frequency"),
        (FORCE, "a force"),
        (STIFFNESS, "a stiffness (force per length)"),
        (PRESSURE, "a pressure (force per area)"),
        (TIME, "a time"),
    ];
    known
        .iter()
        .find(|(d, _)| same_dim(*d, dim))
        .map_or_else(|| format!("kg^{} m^{} s^{}", dim[0], dim[1], dim[2]), |(_, w)| w.to_string())
}

/// Equal dimensions (to rounding of fractional exponents).
pub fn same_dim(a: Dim, b: Dim) -> bool {
    a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-9)
}

/// A short SI number for messages (`8e8`, `0.003`, `2.5e7`).
pub fn short(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-3..1e5).contains(&a) {
        let s = format!("{x:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        let s = format!("{x:.4e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn units_reduce_to_si_with_their_dimension() {
        let q = |t: &str| parse_quantity(t).unwrap();
        assert_relative_eq!(q("800 N/mm^2").si, 8e8);
        assert!(same_dim(q("800 N/mm^2").dim, PRESSURE));
        assert_relative_eq!(q("800 N/mm²").si, 8e8);
        assert_relative_eq!(q("800 MPa").si, 8e8);
        assert_relative_eq!(q("600 Hz").si, 2.0 * PI * 600.0);
        assert!(same_dim(q("600 Hz").dim, FREQUENCY) && q("600 Hz").angular);
        assert_relative_eq!(q("3769.9 rad/s").si, 3769.9);
        assert_relative_eq!(q("10000 rpm").si, 10000.0 * 2.0 * PI / 60.0);
        assert_relative_eq!(q("12 mm").si, 0.012);
        assert_relative_eq!(q("50 µm").si, 50e-6);
        assert_relative_eq!(q("50 um").si, 50e-6);
        assert_relative_eq!(q("2e7 N/m").si, 2e7);
        assert_relative_eq!(q("20 N/µm").si, 2e7);
        assert!(same_dim(q("20 N/um").dim, STIFFNESS));
        assert_relative_eq!(q("3 %").si, 0.03);
        assert_relative_eq!(q("90 deg").si, PI / 2.0);
        assert_relative_eq!(q("1.5 kg").si, 1.5);
        assert_relative_eq!(q("300 g").si, 0.3);
        assert_relative_eq!(q("15 N*s/m").si, 15.0);
        assert!(same_dim(q("15 N·s/m").dim, [1.0, 0.0, -1.0]));
        assert_relative_eq!(q("-2.5e-3").si, -2.5e-3);
        assert!(!q("7").had_unit);
        assert_relative_eq!(q("462 N/mm^1.744").si, 462.0 * 1e-3f64.powf(-1.744));
    }

    #[test]
    fn bad_units_are_named() {
        assert!(parse_quantity("800 N/mmm").unwrap_err().contains("unknown unit \"mmm\""));
        assert!(parse_quantity("Hz 600").unwrap_err().contains("does not start with a number"));
        assert!(parse_quantity("600 Hz^x").unwrap_err().contains("bad exponent"));
    }

    #[test]
    fn numbers_print_short() {
        assert_eq!(short(8e8), "8e8");
        assert_eq!(short(0.003), "0.003");
        assert_eq!(short(2.5e7), "2.5e7");
        assert_eq!(short(600.0), "600");
    }
}
