//! Tooth angles by rotation recurrences and the time-domain cutting force of the fast
//! integrator (the same law as `Plant::cutting`, see [`crate::params`]).
//!
//! The tool angle advances by the same `Ω h` every cell at constant speed, so
//! `(sin, cos)(θ + Ω h)` is one 2×2 rotation of `(sin, cos)(θ)`, and tooth `j + 1` is tooth `j`
//! rotated by the pitch `2π/Z`. Rounding accumulates by about one ulp per rotation, so the
//! recurrence restarts from `sin_cos` every [`REANCHOR`] cells (error below 10⁻¹⁴).

use model_kit::rem_two_pi;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Rotations between two exact evaluations.
pub(crate) const REANCHOR: u32 = 64;

/// `(sin, cos)` of the tool angle reduced to `[0, 2π)`, by recurrence from cell to cell.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct ToothAngles {
    /// The angle these values are for (exact bits), and its reduction to `[0, 2π)`.
    theta: f64,
    base: f64,
    s: f64,
    c: f64,
    rotations: u32,
    /// The last increment and its `(sin, cos)`.
    step: f64,
    rs: f64,
    rc: f64,
}

/// An angle reduced to `[0, 2π)` with its sine and cosine.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Angle {
    pub base: f64,
    pub s: f64,
    pub c: f64,
}

impl ToothAngles {
    /// The values at `theta`, computed exactly.
    pub fn new(theta: f64) -> ToothAngles {
        let mut a = ToothAngles { rc: 1.0, ..ToothAngles::default() };
        a.exact(theta);
        a
    }

    /// Finite, on the unit circle, reduced angle in range (checked on a restored state).
    pub fn is_valid(&self) -> bool {
        let all = [self.theta, self.base, self.s, self.c, self.step, self.rs, self.rc];
        all.iter().all(|x| x.is_finite())
            && (self.s * self.s + self.c * self.c - 1.0).abs() < 1e-9
            && (self.rs * self.rs + self.rc * self.rc - 1.0).abs() < 1e-9
            && (0.0..2.0 * PI).contains(&self.base)
    }

    fn exact(&mut self, theta: f64) -> Angle {
        let base = rem_two_pi(theta);
        let (s, c) = base.sin_cos();
        (self.theta, self.base, self.s, self.c, self.rotations) = (theta, base, s, c, 0);
        Angle { base, s, c }
    }

    /// The values at `theta` (cached when `theta` is the last angle asked for).
    #[inline]
    pub fn at(&mut self, theta: f64) -> Angle {
        if theta.to_bits() == self.theta.to_bits() && self.s * self.s + self.c * self.c > 0.5 {
            return Angle { base: self.base, s: self.s, c: self.c };
        }
        self.exact(theta)
    }

    /// The values at `to = from + step` (a rotation when `from` is the last angle asked for).
    #[inline]
    pub fn advance(&mut self, from: f64, step: f64, to: f64) -> Angle {
        let continues = from.to_bits() == self.theta.to_bits() && self.s * self.s + self.c * self.c > 0.5;
        if !continues || self.rotations >= REANCHOR || !(0.0..2.0 * PI).contains(&step) {
            return self.exact(to);
        }
        if step.to_bits() != self.step.to_bits() || self.rs * self.rs + self.rc * self.rc < 0.5 {
            (self.rs, self.rc) = step.sin_cos();
            self.step = step;
        }
        let (s, c) = (self.s * self.rc + self.c * self.rs, self.c * self.rc - self.s * self.rs);
        let mut base = self.base + step;
        if base >= 2.0 * PI {
            base -= 2.0 * PI;
        }
        (self.theta, self.base, self.s, self.c) = (to, base, s, c);
        self.rotations += 1;
        Angle { base, s, c }
    }
}

/// What the cutting law needs of the geometry, derived once from the parameters.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Geometry {
    pub teeth: u32,
    pub pitch: f64,
    sp: f64,
    cp: f64,
    st: f64,
    ex: f64,
    ux: f64,
    uy: f64,
    kr: f64,
    apkt: f64,
}

impl Geometry {
    pub fn new(p: &crate::PlantParams) -> Geometry {
        let c = &p.cutting;
        let pitch = 2.0 * PI / c.teeth as f64;
        let (sp, cp) = pitch.sin_cos();
        let (st, ex) = p.engagement();
        let (ux, uy) = p.direction();
        Geometry {
            teeth: c.teeth,
            pitch,
            sp,
            cp,
            st,
            ex,
            ux,
            uy,
            kr: c.kr / c.kt.max(f64::MIN_POSITIVE),
            apkt: c.axial_depth * c.kt,
        }
    }

    /// Force along the beam and the largest chip for tooth 0 at `a`, feed `fz`, regenerative
    /// displacement `dx = x(t) − x(t − τ)`: the law of `Plant::cutting` with rotated angles.
    #[inline]
    pub fn force(&self, a: Angle, fz: f64, dx: f64) -> (f64, f64) {
        let (mut phi, mut s, mut c) = (a.base, a.s, a.c);
        let (mut force, mut chip) = (0.0, 0.0f64);
        for j in 0..self.teeth {
            if j > 0 {
                (s, c) = (s * self.cp + c * self.sp, c * self.cp - s * self.sp);
                phi += self.pitch;
                if phi >= 2.0 * PI {
                    phi -= 2.0 * PI;
                }
            }
            if phi < self.st || phi > self.ex {
                continue;
            }
            let h = fz * s - dx * (self.ux * s + self.uy * c);
            if h <= 0.0 {
                continue; // loss of contact
            }
            chip = chip.max(h);
            force += self.apkt * h * ((c + self.kr * s) * self.ux + (-s + self.kr * c) * self.uy);
        }
        (force, chip)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotations_follow_sin_cos_and_reanchor() {
        let mut a = ToothAngles::new(0.0);
        let step = 2000.0 * 2.0 * PI / 60.0 * 1e-5;
        let mut theta = 0.0;
        a.at(theta);
        let mut worst: f64 = 0.0;
        for _ in 0..10_000 {
            let to = theta + step;
            let got = a.advance(theta, step, to);
            let base = to.rem_euclid(2.0 * PI);
            worst = worst.max((got.s - base.sin()).abs()).max((got.c - base.cos()).abs());
            worst = worst.max((got.base - base).abs());
            theta = to;
            assert!(a.is_valid());
        }
        assert!(worst < 1e-13, "recurrence error {worst}");
        // a jump (another angle than the last) is evaluated exactly
        let j = a.advance(1.0, step, 1.0 + step);
        assert!((j.s - (1.0 + step).sin()).abs() < 1e-16);
    }
}
