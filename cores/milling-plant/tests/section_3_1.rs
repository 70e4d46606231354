//! Seed 000, Section 3.1: the single-mode reduction of the cantilever, checked with the plant's
//! own modes (Table 1 first mode, k = 2.40e7 N/m; the higher modes from their published
//! frequencies, damping ratios and peak receptances).
//!
//! `G` is the 3-mode tip receptance, `G1` the first mode alone and `E = G − G1` the truncation
//! error; `R_stat = 1/k2 + 1/k3` is the static residual flexibility of the truncated modes.
//!
//! | quantity | seed | ours (this test) |
//! |---|---|---|
//! | max \|E\|/\|G\| over 67–200 Hz | < 2.96 % | 2.99 % at 200 Hz |
//! | \|E\|/\|G\| at f1 | 0.052 % | 0.051 % |
//! | R_stat | 1.187e-3 µm/N, "2.88 %" of 1/k1 | 1.1871e-3 µm/N, 2.85 % |
//! | band error with R_stat | < 0.1 % | 0.136 % |
//!
//! The seed's f1 = 143.2 Hz (and its 2.88 %) need k = 2.43e7 N/m, the Ozsoy stiffness, not its
//! Table 1's 2.40e7 N/m; the residual band error with the static correction is 0.136 %, not
//! "below 0.1 %". Both are reported as they come out of the seed's own numbers.

use milling_plant::{Mode, PlantParams};
use std::f64::consts::PI;

fn modes() -> (Mode, [Mode; 2]) {
    let p = PlantParams::default();
    (p.workpiece.first, p.workpiece.higher)
}

fn g_full(w: f64) -> num_complex::Complex64 {
    let (m1, [m2, m3]) = modes();
    m1.receptance(w) + m2.receptance(w) + m3.receptance(w)
}

fn band() -> impl Iterator<Item = f64> {
    (0..=1330).map(|i| 2.0 * PI * (67.0 + 0.1 * f64::from(i)))
}

#[test]
fn truncation_error_over_the_chatter_band_and_at_the_first_mode() {
    let (m1, _) = modes();
    let rel = |w: f64| (g_full(w) - m1.receptance(w)).norm() / g_full(w).norm();
    let (worst, at) = band().map(|w| (rel(w), w)).fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a });
    assert!((0.029..=0.031).contains(&worst), "max |E|/|G| = {:.4} %", worst * 100.0);
    assert!((at / (2.0 * PI) - 200.0).abs() < 0.2, "the worst point is the band edge, not {} Hz", at / (2.0 * PI));
    let at_f1 = rel(m1.omega_n());
    assert!((0.0004..0.0006).contains(&at_f1), "|E|/|G| at f1 = {:.4} %", at_f1 * 100.0);
}

#[test]
fn static_residual_flexibility_and_its_correction() {
    let (m1, [m2, m3]) = modes();
    let r_stat = 1.0 / m2.stiffness + 1.0 / m3.stiffness;
    assert!((r_stat * 1e6 - 1.1871e-3).abs() < 5e-8, "R_stat = {:.5e} µm/N", r_stat * 1e6);
    let share = r_stat * m1.stiffness;
    assert!((share - 0.0285).abs() < 5e-4, "R_stat k1 = {:.3} %", share * 100.0);
    let corrected = |w: f64| (g_full(w) - m1.receptance(w) - r_stat).norm() / g_full(w).norm();
    let worst = band().map(corrected).fold(0.0, f64::max);
    assert!((0.0013..0.0014).contains(&worst), "band error with R_stat = {:.4} %", worst * 100.0);
}
