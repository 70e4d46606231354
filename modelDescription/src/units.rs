//! The units the project's FMUs use, by name, as SI base-unit exponents.
//!
//! A variable table names its units (`"N/m"`); the description builder looks them up here and
//! writes the `UnitDefinitions` it needs, so no model repeats exponent vectors. Exponents are
//! in the order of FMI 2.0's `BaseUnit`: `kg, m, s, A, K, mol, cd, rad`.

use std::f64::consts::PI;

/// `(name, exponents [kg, m, s, A, K, mol, cd, rad], factor to SI)`.
pub const UNITS: &[(&str, [i32; 8], f64)] = &[
    ("m", [0, 1, 0, 0, 0, 0, 0, 0], 1.0),
    ("m/s", [0, 1, -1, 0, 0, 0, 0, 0], 1.0),
    ("m/s2", [0, 1, -2, 0, 0, 0, 0, 0], 1.0),
    ("kg", [1, 0, 0, 0, 0, 0, 0, 0], 1.0),
    ("1/kg", [-1, 0, 0, 0, 0, 0, 0, 0], 1.0),
    ("s", [0, 0, 1, 0, 0, 0, 0, 0], 1.0),
    ("Hz", [0, 0, -1, 0, 0, 0, 0, 0], 1.0),
    ("1/s", [0, 0, -1, 0, 0, 0, 0, 0], 1.0),
    ("1/s2", [0, 0, -2, 0, 0, 0, 0, 0], 1.0),
    ("rad", [0, 0, 0, 0, 0, 0, 0, 1], 1.0),
    ("rad/s", [0, 0, -1, 0, 0, 0, 0, 1], 1.0),
    ("rpm", [0, 0, -1, 0, 0, 0, 0, 1], 2.0 * PI / 60.0),
    ("N", [1, 1, -2, 0, 0, 0, 0, 0], 1.0),
    ("N/m", [1, 0, -2, 0, 0, 0, 0, 0], 1.0),
    ("N/m2", [1, -1, -2, 0, 0, 0, 0, 0], 1.0),
    ("N/m3", [1, -2, -2, 0, 0, 0, 0, 0], 1.0),
    ("N.s/m", [1, 0, -1, 0, 0, 0, 0, 0], 1.0),
    ("N/(m.s)", [1, 0, -3, 0, 0, 0, 0, 0], 1.0),
    ("N.s/m2", [1, -1, -1, 0, 0, 0, 0, 0], 1.0),
    ("m/N", [-1, 1, 2, 0, 0, 0, 0, 0], 1.0),
    ("m/rev", [0, 1, 0, 0, 0, 0, 0, -1], 1.0 / (2.0 * PI)),
    ("m3/s", [0, 3, -1, 0, 0, 0, 0, 0], 1.0),
    ("W", [1, 2, -3, 0, 0, 0, 0, 0], 1.0),
    ("J", [1, 2, -2, 0, 0, 0, 0, 0], 1.0),
    ("mm", [0, 1, 0, 0, 0, 0, 0, 0], 1e-3),
    ("mm/s", [0, 1, -1, 0, 0, 0, 0, 0], 1e-3),
    ("mm/s2", [0, 1, -2, 0, 0, 0, 0, 0], 1e-3),
    ("N/mm2", [1, -1, -2, 0, 0, 0, 0, 0], 1e6),
    ("N.s/mm", [1, 0, -1, 0, 0, 0, 0, 0], 1e3),
    ("mm/rev", [0, 1, 0, 0, 0, 0, 0, -1], 1e-3 / (2.0 * PI)),
    ("1/mm", [0, -1, 0, 0, 0, 0, 0, 0], 1e3),
    ("deg", [0, 0, 0, 0, 0, 0, 0, 1], PI / 180.0),
    ("rpm.s", [0, 0, 0, 0, 0, 0, 0, 1], 2.0 * PI / 60.0),
];

/// Exponents and factor of a known unit.
pub fn known_unit(name: &str) -> Option<([i32; 8], f64)> {
    UNITS.iter().find(|(n, _, _)| *n == name).map(|(_, e, f)| (*e, *f))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_rpm_is_scaled() {
        let mut names: Vec<_> = UNITS.iter().map(|u| u.0).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), UNITS.len());
        let (e, f) = known_unit("rpm").unwrap();
        assert_eq!(e, known_unit("rad/s").unwrap().0);
        assert!((f * 60.0 - 2.0 * PI).abs() < 1e-15);
        assert!(known_unit("furlong").is_none());
    }
}
