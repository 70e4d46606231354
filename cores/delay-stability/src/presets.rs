//! Seed 002 (IJRNC 2015, Section 6, Table I): the two-axis two-mass spindle, its cutter and the
//! static delayed output feedback of Section 6.1.
//!
//! Units: the paper gives `K_t = 462`, `K_r = 38.6 N/mm^{1+x_F}` and `f_z = 0.2 mm`; in SI
//! (`F = K a_p h^{x_F}` with a_p, h in m) the coefficients are `K·1000^{1+x_F} N/m^{1+x_F}`. The
//! gains `k₁ = 697.1599`, `k₂ = −1071.058 N/mm` are `×1000` N/m, used as printed:
//! `F_a = +D_c (v_a − v_a(t − τ))`, `D_c = [[k₁, −k₂], [k₂, k₁]]` (β = 1).

use crate::StabilityError;
use crate::milling::{Controller, Cutter, ForceLaw, MillingModel, Structure, TwoMassAxis};
use nalgebra::DMatrix;
use std::f64::consts::PI;

/// Table I: m_t 0.015 kg, m_a 0.14 kg, ω_t 2350 Hz, ω_a 1400 Hz, ζ_t 0.05, ζ_a 0.12.
pub const SEED002_AXIS: TwoMassAxis = TwoMassAxis {
    tool_mass: 0.015,
    actuator_mass: 0.14,
    tool_hz: 2350.0,
    actuator_hz: 1400.0,
    tool_zeta: 0.05,
    actuator_zeta: 0.12,
};

/// Section 6.1 gains k₁, k₂ \[N/mm\].
pub const SEED002_GAINS: (f64, f64) = (697.1599, -1071.058);

/// Seed 002's structure.
pub fn seed002_structure() -> Structure {
    Structure::two_mass_per_axis(&SEED002_AXIS)
}

/// Seed 002's cutter: z = 4, full immersion (0, π), K_t 462, K_r 38.6 N/mm^{1+x_F},
/// `x_F = 1` (Section 6.1, linear law) or `x_F < 1` (Section 6.2: 0.744, with f_z = 0.2 mm).
pub fn seed002_cutter(x_f: f64) -> Result<Cutter, StabilityError> {
    let scale = 1000f64.powf(1.0 + x_f);
    let law =
        if (x_f - 1.0).abs() < 1e-12 { ForceLaw::Linear } else { ForceLaw::Power { x_f, feed_per_tooth: 0.2e-3 } };
    Cutter::new(4, 0.0, PI, 462.0 * scale, 38.6 * scale, law)
}

/// `D_c = [[k₁, −k₂], [k₂, k₁]]` in N/m from gains in N/mm.
pub fn seed002_gain(k1: f64, k2: f64) -> DMatrix<f64> {
    DMatrix::from_row_slice(2, 2, &[k1, -k2, k2, k1]) * 1000.0
}

/// Seed 002's model: open loop (`gain = None`) or with the static Pyragas feedback `D_c`.
pub fn seed002(x_f: f64, gain: Option<DMatrix<f64>>) -> Result<MillingModel, StabilityError> {
    let c = gain.map(|dc| Controller::static_gain(dc, 1.0));
    MillingModel::new(&seed002_structure(), seed002_cutter(x_f)?, c.as_ref())
}
