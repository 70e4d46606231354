//! Residues to modal parameters.
//!
//! For a mode with mass-normalised real shape φ and pole `λ = −ζω_n + iω_d`, the receptance
//! term `φ_p φ_q/(ω_n² − ω² + 2iζω_nω)` has the residue `A_pq = φ_p φ_q/(2iω_d)` at λ, so
//! `φ_p φ_q = 2iω_d A_pq`, real for proportional damping. With all four FRFs the shape is the best
//! rank-one fit `φφᵀ` of the symmetric 2×2 matrix of these products (the cross FRFs `xy`, `yx`
//! averaged); with one driving point and a cross FRF, the driving point gives its component and
//! the cross term the other; with both driving points and no cross FRF the coupling's sign is
//! unknown and taken as positive. The imaginary part of `2iω_d A` left over measures how
//! far the mode is from real (its complexity, 0 for a real mode).

use crate::lsfd::Residues;
use std::f64::consts::PI;

/// Which FRF an output is: (response direction, force direction), 0 = x, 1 = y.
pub type Pair = (usize, usize);

/// One identified mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode {
    /// Natural frequency \[Hz\].
    pub frequency_hz: f64,
    /// Damping ratio.
    pub damping: f64,
    /// Mass-normalised shape at the tool point (x, y) \[1/√kg\].
    pub shape: [f64; 2],
    /// Complexity: the imaginary share of `2iω_d A` at the driving point (0: a real mode).
    pub complexity: f64,
}

impl Mode {
    /// Unit direction of the shape.
    pub fn direction(&self) -> [f64; 2] {
        let n = self.shape[0].hypot(self.shape[1]);
        [self.shape[0] / n, self.shape[1] / n]
    }

    /// Modal mass along the unit direction, `1/|φ|²` \[kg\].
    pub fn mass(&self) -> f64 {
        1.0 / (self.shape[0] * self.shape[0] + self.shape[1] * self.shape[1])
    }

    /// Modal stiffness along the unit direction, `ω_n² / |φ|²` \[N/m\].
    pub fn stiffness(&self) -> f64 {
        (2.0 * PI * self.frequency_hz).powi(2) * self.mass()
    }
}

/// The modes of `res`, whose outputs are the FRFs `pairs`. A mode whose driving-point residues
/// give no positive `φ²` in any direction (a computational pole) is left out.
pub fn modes(res: &Residues, pairs: &[Pair]) -> Vec<Mode> {
    let find = |p: Pair| pairs.iter().position(|q| *q == p);
    let mut out = Vec::new();
    for (r, pole) in res.poles.iter().enumerate() {
        let wd = pole.0.im;
        let prod = |o: usize| num_complex::Complex64::new(0.0, 2.0 * wd) * res.residues[o][r];
        let driving = |d: usize| find((d, d)).map(&prod);
        let cross = {
            let v: Vec<_> = [(0, 1), (1, 0)].iter().filter_map(|&p| find(p)).map(|o| prod(o).re).collect();
            (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
        };
        let sq = [driving(0).map(|c| c.re), driving(1).map(|c| c.re)];
        let shape = match (sq, cross) {
            // the best rank-one fit φφᵀ of the 2×2 matrix [[xx, c], [c, yy]]: its leading
            // eigenvector times the square root of its eigenvalue (robust where one component
            // is small and the noise would make it a square root of noise)
            ([Some(a), Some(b)], Some(c)) => {
                let (mean, half) = (0.5 * (a + b), (0.25 * (a - b) * (a - b) + c * c).sqrt());
                let top = mean + half;
                if top <= 0.0 {
                    [0.0, 0.0]
                } else {
                    let v = if c.abs() > 0.0 {
                        [top - b, c]
                    } else if a >= b {
                        [1.0, 0.0]
                    } else {
                        [0.0, 1.0]
                    };
                    let n = v[0].hypot(v[1]);
                    let s = top.sqrt() / n;
                    [v[0] * s, v[1] * s]
                }
            }
            // one driving point and a cross FRF: the other component from the cross term
            ([Some(a), None], c) if a > 0.0 => [a.sqrt(), c.map_or(0.0, |c| c / a.sqrt())],
            ([None, Some(b)], c) if b > 0.0 => [c.map_or(0.0, |c| c / b.sqrt()), b.sqrt()],
            // both driving points, no cross FRF: the coupling's sign is unknown, taken as +
            ([a, b], _) => [a.map_or(0.0, |a| a.max(0.0).sqrt()), b.map_or(0.0, |b| b.max(0.0).sqrt())],
        };
        if shape == [0.0, 0.0] {
            continue;
        }
        let d = if shape[0].abs() >= shape[1].abs() { 0 } else { 1 };
        let complexity = driving(d).map_or(0.0, |c| (c.im / c.norm()).abs());
        out.push(Mode { frequency_hz: pole.frequency_hz(), damping: pole.damping(), shape, complexity });
    }
    out
}
