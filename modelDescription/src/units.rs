//! The units the project's FMUs use, by name, as SI base-unit exponents.
//!
//! A variable table names its units (`"N/m"`); the description builder looks them up here and
//! writes the `UnitDefinitions` it needs, so no model repeats exponent vectors. Exponents are
//! in the order of FMI 2.0's `BaseUnit`: `kg, m, s, A, K, mol, cd, rad`.

use std::f64::consts::PI;

/// `(name, exponents [kg, m, s, A, K, mol, cd, rad], factor to SI)`.
pub const UNITS: &[(&str, [i32; 8], f64)] = &[
    // dimensionless (ratios, orders, normalised quantities): FMI's unit "1"
    ("1", [0, 0, 0, 0, 0, 0, 0, 0], 1.0),
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
    ("s/m", [0, -1, 1, 0, 0, 0, 0, 0], 1.0),
];

/// Units that no product of integer powers of SI base units expresses, declared by name only
/// (an FMI `Unit` without `BaseUnit`): `(name, what it is)`. A gain of a fractional-order
/// operator carries `s^λ` with the order λ a parameter; a state-space matrix whose meaning
/// changes with a parameter (continuous or discrete form); signals normalised by the model.
pub const NAMED_UNITS: &[(&str, &str)] = &[
    ("N/(m.s^lambda)", "FOPID integral gain: N/m per s^lambda, lambda the integral order"),
    ("N.s^mu/m", "FOPID derivative gain: N/m times s^mu, mu the derivative order"),
    ("s^(lambda-2)", "ADRC-FOPID integral gain (u0 in m/s2 per m per s^lambda)"),
    ("s^(mu-2)", "ADRC-FOPID derivative gain (u0 in m/s2 per m times s^mu)"),
    ("N/m^(1+x_F)", "power-law cutting coefficient: N per m of depth per m^x_F of chip (N/m2 for x_F = 1)"),
    ("1/s|1", "state-space matrix entry: 1/s in the continuous form, 1 (per sample) in the discrete form"),
    ("G", "AFrAC adaptation signal G = P12 z1 + P22 z2 (Lyapunov-weighted error, no SI product)"),
    ("lambda_2", "AFrAC feed adaptation gain (its unit follows G and the order beta)"),
    ("lambda_3", "AFrAC speed adaptation gain (its unit follows G and the order beta)"),
    ("e/m", "D-PID error units per metre of position (1000: the error in mm)"),
    ("N/e", "D-PID proportional gain: N per error unit"),
    ("N/(e.s)", "D-PID integral gain: N per error unit and second"),
    ("N.s/e", "D-PID derivative gain: N s per error unit"),
];

/// Is `name` a unit declared by name only ([`NAMED_UNITS`])?
pub fn named_unit(name: &str) -> bool {
    NAMED_UNITS.iter().any(|(n, _)| *n == name)
}

/// Exponents and factor of a known unit.
pub fn known_unit(name: &str) -> Option<([i32; 8], f64)> {
    UNITS.iter().find(|(n, _, _)| *n == name).map(|(_, e, f)| (*e, *f))
}

/// Values in SI that users often write in another unit: per SI unit, (factor to SI, the unit).
const SLIPS: &[(&str, &[(f64, &str)])] = &[
    ("m", &[(1e-3, "mm"), (1e-6, "µm")]),
    ("N/m2", &[(1e6, "N/mm²")]),
    ("Pa", &[(1e6, "N/mm²"), (1e6, "MPa")]),
    ("N/m", &[(1e3, "N/mm"), (1e6, "N/µm")]),
    ("kg", &[(1e-3, "g")]),
    ("s", &[(1e-3, "ms"), (1e-6, "µs")]),
    ("rad", &[(PI / 180.0, "deg")]),
    ("rad/s", &[(2.0 * PI, "Hz")]),
];

/// A hint for a value outside `[lo, hi]` of a variable in `unit`: if the number, read in a unit
/// people often mean instead (mm for m, N/mm² for N/m², deg for rad, …), lies inside, say so:
/// `values are SI (m): did you mean 3 mm = 0.003 m?`.
pub fn slip_hint(unit: &str, x: f64, lo: f64, hi: f64) -> Option<String> {
    let (_, slips) = SLIPS.iter().find(|(u, _)| *u == unit)?;
    let (factor, name) = slips.iter().find(|(f, _)| (lo..=hi).contains(&(x * f)))?;
    Some(format!("values are SI ({unit}): did you mean {x} {name} = {} {unit}?", x * factor))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slips_of_a_unit_are_named() {
        assert_eq!(slip_hint("m", 3.0, 0.0, 1.0).unwrap(), "values are SI (m): did you mean 3 mm = 0.003 m?");
        assert!(slip_hint("N/m2", 800.0, 1e6, 1e11).unwrap().contains("800 N/mm² = 800000000 N/m2"));
        assert_eq!(slip_hint("m", 3e9, 0.0, 1.0), None);
        assert_eq!(slip_hint("V", 3.0, 0.0, 1.0), None);
    }

    #[test]
    fn names_are_unique_and_rpm_is_scaled() {
        let mut names: Vec<_> = UNITS.iter().map(|u| u.0).chain(NAMED_UNITS.iter().map(|u| u.0)).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), UNITS.len() + NAMED_UNITS.len());
        assert_eq!(known_unit("1"), Some(([0; 8], 1.0)));
        assert!(named_unit("N.s^mu/m") && !named_unit("m"));
        let (e, f) = known_unit("rpm").unwrap();
        assert_eq!(e, known_unit("rad/s").unwrap().0);
        assert!((f * 60.0 - 2.0 * PI).abs() < 1e-15);
        assert!(known_unit("furlong").is_none());
    }
}
