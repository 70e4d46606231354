//! The assembled milling model (parent module docs): structure, cutter and controller as one
//! periodic delay system at a given speed and depth.

use super::{Controller, Cutter, Structure};
use crate::exact::TimeInvariant;
use crate::{PeriodicDde, StabilityError};
use nalgebra::{DMatrix, Matrix2};
use std::f64::consts::PI;

/// Structure + cutter (+ controller), with the closed-loop matrices assembled once.
#[derive(Clone, Debug)]
pub struct MillingModel {
    /// The cutter.
    pub cutter: Cutter,
    /// `[[A + B_a D_c C_a, B_a C_c], [B_c C_a, A_c]]`.
    s0: DMatrix<f64>,
    /// `−β [B_a D_c; B_c]` (the delayed controller term acts on `C_a x(t − τ)`).
    e0: DMatrix<f64>,
    /// `[C_a, 0]`.
    ca: DMatrix<f64>,
    /// `[B_t; 0]`.
    bt: DMatrix<f64>,
    /// `[C_t, 0]`.
    ct: DMatrix<f64>,
    /// The rows of `C_t` that are not zero (a one-direction structure delays one output).
    keep: Vec<usize>,
}

fn dims(name: &str, m: &DMatrix<f64>, r: usize, c: usize) -> Result<(), StabilityError> {
    if m.shape() != (r, c) {
        return Err(StabilityError::Invalid(format!("{name} is {:?}, expected ({r}, {c})", m.shape())));
    }
    if m.iter().any(|v| !v.is_finite()) {
        return Err(StabilityError::Invalid(format!("{name} has non-finite entries")));
    }
    Ok(())
}

impl MillingModel {
    /// Assemble; the matrix dimensions are checked.
    pub fn new(s: &Structure, cutter: Cutter, controller: Option<&Controller>) -> Result<MillingModel, StabilityError> {
        let n = s.dim();
        dims("A", &s.a, n, n)?;
        dims("B_t", &s.bt, n, 2)?;
        dims("C_t", &s.ct, 2, n)?;
        let (p, q) = (s.ba.ncols(), s.ca.nrows());
        dims("B_a", &s.ba, n, p)?;
        dims("C_a", &s.ca, q, n)?;
        let keep: Vec<usize> = (0..2).filter(|&k| s.ct.row(k).iter().any(|&v| v != 0.0)).collect();
        if keep.is_empty() {
            return Err(StabilityError::Invalid("C_t is zero: the tool does not move".into()));
        }
        let Some(c) = controller else {
            return Ok(MillingModel {
                cutter,
                s0: s.a.clone(),
                e0: DMatrix::zeros(n, 0),
                ca: DMatrix::zeros(0, n),
                bt: s.bt.clone(),
                ct: s.ct.clone(),
                keep,
            });
        };
        let nc = c.ac.nrows();
        dims("A_c", &c.ac, nc, nc)?;
        dims("B_c", &c.bc, nc, q)?;
        dims("C_c", &c.cc, p, nc)?;
        dims("D_c", &c.dc, p, q)?;
        if !c.beta.is_finite() {
            return Err(StabilityError::Invalid("β must be finite".into()));
        }
        let nt = n + nc;
        let mut s0 = DMatrix::zeros(nt, nt);
        s0.view_mut((0, 0), (n, n)).copy_from(&(&s.a + &s.ba * &c.dc * &s.ca));
        s0.view_mut((0, n), (n, nc)).copy_from(&(&s.ba * &c.cc));
        s0.view_mut((n, 0), (nc, n)).copy_from(&(&c.bc * &s.ca));
        s0.view_mut((n, n), (nc, nc)).copy_from(&c.ac);
        let mut e0 = DMatrix::zeros(nt, q);
        if c.beta != 0.0 {
            e0.view_mut((0, 0), (n, q)).copy_from(&(&s.ba * &c.dc * -c.beta));
            e0.view_mut((n, 0), (nc, q)).copy_from(&(&c.bc * -c.beta));
        }
        let pad = |m: &DMatrix<f64>, rows: bool| {
            if rows {
                let mut o = DMatrix::zeros(nt, m.ncols());
                o.view_mut((0, 0), m.shape()).copy_from(m);
                o
            } else {
                let mut o = DMatrix::zeros(m.nrows(), nt);
                o.view_mut((0, 0), m.shape()).copy_from(m);
                o
            }
        };
        let (ca, e0) =
            if c.beta != 0.0 { (pad(&s.ca, false), e0) } else { (DMatrix::zeros(0, nt), DMatrix::zeros(nt, 0)) };
        Ok(MillingModel { cutter, s0, e0, ca, bt: pad(&s.bt, true), ct: pad(&s.ct, false), keep })
    }

    /// State dimension of the closed loop.
    pub fn dim(&self) -> usize {
        self.s0.nrows()
    }

    /// Tooth period τ = 60/(z n) \[s\] at `rpm`.
    pub fn delay(&self, rpm: f64) -> f64 {
        60.0 / (self.cutter.teeth as f64 * rpm)
    }

    /// The periodic delay system at spindle speed `rpm` and axial depth `depth` \[m\].
    pub fn at(&self, rpm: f64, depth: f64) -> Result<MillingDde<'_>, StabilityError> {
        if !(rpm.is_finite() && rpm > 0.0 && depth.is_finite() && depth >= 0.0) {
            return Err(StabilityError::Invalid(format!("need speed > 0 and depth >= 0 (got {rpm} rpm, {depth} m)")));
        }
        Ok(MillingDde { model: self, rpm, depth })
    }

    /// The time-invariant (zero-order) model with the mean directional matrix `H̄`: exact for
    /// cases where `H(t)` is constant (e.g. full immersion with z ≥ 3 and the linear law).
    pub fn time_invariant(&self) -> TimeInvariant {
        self.time_invariant_with(self.cutter.mean())
    }

    /// The same with a given directional matrix.
    pub fn time_invariant_with(&self, hbar: Matrix2<f64>) -> TimeInvariant {
        TimeInvariant {
            s0: self.s0.clone(),
            t0: &self.e0 * &self.ca,
            bt: self.bt.clone(),
            ct: self.ct.clone(),
            hbar,
            teeth: self.cutter.teeth,
        }
    }

    /// Eigenvalues of the structure with the controller but without cutting, largest real part
    /// first (the controller's delayed term is *not* included).
    pub fn undelayed_poles(&self) -> Vec<num_complex::Complex64> {
        let mut ev: Vec<_> = self.s0.complex_eigenvalues().iter().copied().collect();
        ev.sort_by(|a, b| b.re.total_cmp(&a.re));
        ev
    }
}

/// The milling model at one speed and depth, as a [`PeriodicDde`].
#[derive(Clone, Copy, Debug)]
pub struct MillingDde<'a> {
    model: &'a MillingModel,
    rpm: f64,
    depth: f64,
}

impl PeriodicDde for MillingDde<'_> {
    fn dim(&self) -> usize {
        self.model.dim()
    }
    fn period(&self) -> f64 {
        self.model.delay(self.rpm)
    }
    fn delayed_output(&self) -> DMatrix<f64> {
        let m = self.model;
        let r = m.keep.len();
        let mut cd = DMatrix::zeros(r + m.ca.nrows(), m.dim());
        for (i, &k) in m.keep.iter().enumerate() {
            cd.row_mut(i).copy_from(&m.ct.row(k));
        }
        cd.rows_mut(r, m.ca.nrows()).copy_from(&m.ca);
        cd
    }
    fn averaged(&self, t0: f64, t1: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        let m = self.model;
        let w = 2.0 * PI * self.rpm / 60.0;
        let h = m.cutter.averaged(w * t0, w * t1);
        let hd = DMatrix::from_fn(2, 2, |i, j| h[(i, j)]);
        let bh = &m.bt * hd * self.depth;
        let a = &m.s0 + &bh * &m.ct;
        let r = m.keep.len();
        let mut bd = DMatrix::zeros(m.dim(), r + m.e0.ncols());
        for (i, &k) in m.keep.iter().enumerate() {
            bd.column_mut(i).copy_from(&(-bh.column(k)));
        }
        bd.columns_mut(r, m.e0.ncols()).copy_from(&m.e0);
        (a, bd)
    }
    /// Where a tooth enters or leaves the cut or `sin φ` of a tooth changes sign.
    fn breakpoints(&self) -> Vec<f64> {
        let c = &self.model.cutter;
        let w = 2.0 * PI * self.rpm / 60.0;
        let period = self.period();
        let mut out = Vec::new();
        for j in 0..c.teeth {
            let off = j as f64 * c.pitch();
            for e in [0.0, PI, c.entry, c.exit] {
                let t = (e - off).rem_euclid(2.0 * PI) / w;
                if t > 1e-12 * period && t < period * (1.0 - 1e-12) {
                    out.push(t);
                }
            }
        }
        out.sort_by(f64::total_cmp);
        out.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * period);
        out
    }
    /// Power law only: where a tooth enters at `φ = 0` or leaves at `φ = π` (zero static chip,
    /// so `h^{x_F − 1}` is unbounded there).
    fn singularities(&self) -> Vec<f64> {
        let c = &self.model.cutter;
        if !matches!(c.law, super::ForceLaw::Power { x_f, .. } if x_f < 1.0) {
            return Vec::new();
        }
        let w = 2.0 * PI * self.rpm / 60.0;
        let period = self.period();
        let mut out = Vec::new();
        for j in 0..c.teeth {
            let off = j as f64 * c.pitch();
            // exactly 0 and π: the immersion's angles are set, not computed, at full immersion
            #[allow(clippy::float_cmp)]
            let ends = [(0.0, c.entry == 0.0), (PI, c.exit == PI)];
            for (e, at) in ends {
                if at {
                    let t = (e - off).rem_euclid(2.0 * PI) / w;
                    // a point within rounding of the period end is the period start
                    if t <= 1e-12 * period || (t - period).abs() <= 1e-12 * period {
                        out.push(0.0);
                    } else if t < period {
                        out.push(t);
                    }
                }
            }
        }
        out.sort_by(f64::total_cmp);
        out.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * period);
        out
    }
    /// `A₀ = S₀`, `G = [B̂_t, E₀]`, `C₀ = Ĉ_t` (kept rows): `P = [a_p H_keep; 0]`,
    /// `Q = [[−a_p H_keep, 0], [0, I]]` (module docs of [`crate::milling`]).
    fn splitting(&self) -> Option<crate::Splitting> {
        let m = self.model;
        let (n, q) = (m.dim(), m.e0.ncols());
        let mut g = DMatrix::zeros(n, 2 + q);
        g.columns_mut(0, 2).copy_from(&m.bt);
        g.columns_mut(2, q).copy_from(&m.e0);
        let mut c0 = DMatrix::zeros(m.keep.len(), n);
        for (i, &k) in m.keep.iter().enumerate() {
            c0.row_mut(i).copy_from(&m.ct.row(k));
        }
        Some(crate::Splitting { a0: m.s0.clone(), g, c0 })
    }
    fn gains(&self, t: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        let m = self.model;
        let w = 2.0 * PI * self.rpm / 60.0;
        let h = m.cutter.directional(w * t);
        let (p, q) = (m.keep.len(), m.e0.ncols());
        let mut pm = DMatrix::zeros(2 + q, p);
        let mut qm = DMatrix::zeros(2 + q, p + q);
        for (i, &k) in m.keep.iter().enumerate() {
            for d in 0..2 {
                pm[(d, i)] = self.depth * h[(d, k)];
                qm[(d, i)] = -self.depth * h[(d, k)];
            }
        }
        for i in 0..q {
            qm[(2 + i, p + i)] = 1.0;
        }
        (pm, qm)
    }
}
