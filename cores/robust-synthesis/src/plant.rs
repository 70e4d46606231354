//! Seed 002's generalised plant (Section 4, Eqs. 12–19), the controller parameterisations and
//! the closed loop `N = F_l(P̃, K)` with its gradients.
//!
//! # Uncertainty (Eq. 12)
//!
//! `a_p = ½ā_p(1 + δa)`, `|δa| ≤ 1` (complex), `τ = τ₀ + δτ`, `τ₀ = (τ̄ + τ̲)/2`,
//! `|δτ| ≤ δτ_max = (τ̄ − τ̲)/2`, with `τ = 60/(z n)` over the speed range. The time-invariant
//! model uses the averaged directional matrix `H̄` (Eq. 11; [`delay_stability::milling::Cutter::mean`]).
//!
//! # Generalised plant (Eqs. 14–16; the printed matrices are garbled, this reading reproduces
//! the physical equation)
//!
//! ```text
//! ẋ  = A x + ½ā B_t H̄ C_t (x − x(t−τ₀)) − ½ā B_t H̄ q₁ + ā B_t H̄ q₃ + B_a F_a
//! p₁ = C_t x(t−τ₀),  p₂ = C_a x(t−τ₀),  p₃ = ½(C_t x − C_t x(t−τ₀) − q₁)
//! q₁ = (D_δτ − 1) p₁, q₂ = (D_δτ − 1) p₂, q₃ = δa p₃
//! z  = W_KS F_a,     y = C_a x − β(C_a x(t−τ₀) + q₂) + r
//! ```
//!
//! Eliminating `q` gives back `ẋ = A x + a_p B_t H̄ C_t (x − x(t−τ)) + B_a F_a` and
//! `y = C_a(x − β x(t − τ)) + r` (tested). The seed's `p₃` carries the factor ½ā and `q₃` enters
//! with `B_t H̄`; here `p₃` is divided by ā and `q₃` enters with `ā B_t H̄`, a constant scaling
//! of that channel pair that leaves μ unchanged but keeps every channel in metres, so the
//! D-scalings start near 1. Scaled plant: the `p₁, p₂` rows are multiplied by
//! `Ω(ω) = 2 sin(δτ_max ω/2)` (`ω ≤ π/δτ_max`, else 2), the bound of `|e^{−iωδτ} − 1|` (Eq. 19).
//! Uncertainty structure: `diag(δτ-block I₄, δa I₂, Δ_perf 2×2)` → D-blocks `4 × 4`, `2 × 2`
//! full and `d I₂`.
//!
//! # Controller (Eq. 10)
//!
//! `K(s) = D_c + C_c (sI − A_c)⁻¹ B_c` on `y`; the parameters θ are scaled so that they are of
//! order one: `D_c = 10⁶ θ` N/m (θ in kN/mm), `A_c = 2π·1000 θ` rad/s, `B_c`, `C_c` by
//! `√(10⁶ · 2π·1000)`. [`Parameterisation::Structured`] is §6.1's `D_c = [[k₁, −k₂], [k₂, k₁]]`
//! (2 parameters), [`Parameterisation::Full`] `n_c` states with `A_c` block diagonal in 2 × 2
//! full blocks (the seed's parameter counts 4 / 16 / 28 for n_c = 0 / 2 / 4).

use crate::SynthError;
use crate::abscissa::DelaySystem;
use crate::mu::{self, Block, CMat};
use delay_stability::milling::{Controller, Structure};
use nalgebra::{DMatrix, DVector, Matrix2};
use num_complex::Complex64;
use std::f64::consts::PI;

/// Scale of D_c entries per unit θ \[N/m\].
pub const D_SCALE: f64 = 1e6;
/// Scale of A_c entries per unit θ \[rad/s\].
pub const A_SCALE: f64 = 2.0 * PI * 1000.0;

fn bc_scale() -> f64 {
    (D_SCALE * A_SCALE).sqrt()
}

/// The performance weight `W_KS` (SI: m/N).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Weight {
    /// A constant (§6.1: 1e-6 mm/N = 1e-9 m/N).
    Static(f64),
    /// Eq. 27: `K_p (s/ω_rl + 1)/(s/ω_pl + 1) · (s/ω_rh + 1)/(s/ω_ph + 1)`, frequencies in Hz.
    LeadLag {
        /// Gain K_p \[m/N\].
        kp: f64,
        /// f_r,l, f_p,l, f_r,h, f_p,h \[Hz\].
        hz: [f64; 4],
    },
}

impl Weight {
    /// §6.2's weight (Eq. 27): K_p = 1e-6 mm/N, 100 Hz, 0.01 Hz, 7500 Hz, 20 kHz.
    pub const SEED002_62: Weight = Weight::LeadLag { kp: 1e-9, hz: [100.0, 1e-2, 7500.0, 2e4] };

    /// `W(iω)`.
    pub fn at(&self, w: f64) -> Complex64 {
        match *self {
            Weight::Static(k) => Complex64::from(k),
            Weight::LeadLag { kp, hz } => {
                let s = Complex64::new(0.0, w);
                let f = |hz: f64| s / (2.0 * PI * hz) + 1.0;
                kp * f(hz[0]) / f(hz[1]) * f(hz[2]) / f(hz[3])
            }
        }
    }
}

/// How θ maps to the controller (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parameterisation {
    /// §6.1: `D_c = [[k₁, −k₂], [k₂, k₁]]`, θ = (k₁, k₂) in kN/mm.
    Structured,
    /// `n_c` states (even), `A_c` 2 × 2-block diagonal, full `B_c`, `C_c`, `D_c`.
    Full {
        /// Controller order.
        nc: usize,
    },
}

impl Parameterisation {
    /// Controller order.
    pub fn order(&self) -> usize {
        match *self {
            Parameterisation::Structured => 0,
            Parameterisation::Full { nc } => nc,
        }
    }

    /// For each θ_k, the entries `(row, col, scale)` of `K̂ = [[D_c, C_c], [B_c, A_c]]` it sets.
    pub fn entries(&self) -> Vec<Vec<(usize, usize, f64)>> {
        match *self {
            Parameterisation::Structured => {
                vec![vec![(0, 0, D_SCALE), (1, 1, D_SCALE)], vec![(0, 1, -D_SCALE), (1, 0, D_SCALE)]]
            }
            Parameterisation::Full { nc } => {
                let mut e = Vec::new();
                for b in 0..nc / 2 {
                    for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                        e.push(vec![(2 + 2 * b + i, 2 + 2 * b + j, A_SCALE)]);
                    }
                }
                for i in 0..nc {
                    for j in 0..2 {
                        e.push(vec![(2 + i, j, bc_scale())]);
                    }
                }
                for i in 0..2 {
                    for j in 0..nc {
                        e.push(vec![(i, 2 + j, bc_scale())]);
                    }
                }
                for i in 0..2 {
                    for j in 0..2 {
                        e.push(vec![(i, j, D_SCALE)]);
                    }
                }
                e
            }
        }
    }

    /// Number of parameters.
    pub fn len(&self) -> usize {
        self.entries().len()
    }

    /// Always false (a controller has parameters).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// `K̂(θ)`.
    pub fn khat(&self, theta: &[f64]) -> DMatrix<f64> {
        let k = 2 + self.order();
        let mut m = DMatrix::zeros(k, k);
        for (e, &t) in self.entries().iter().zip(theta) {
            for &(i, j, s) in e {
                m[(i, j)] += s * t;
            }
        }
        m
    }

    /// The controller `(A_c, B_c, C_c, D_c, β)` of θ.
    pub fn controller(&self, theta: &[f64], beta: f64) -> Controller {
        let nc = self.order();
        let k = self.khat(theta);
        Controller {
            dc: k.view((0, 0), (2, 2)).into_owned(),
            cc: k.view((0, 2), (2, nc)).into_owned(),
            bc: k.view((2, 0), (nc, 2)).into_owned(),
            ac: k.view((2, 2), (nc, nc)).into_owned(),
            beta,
        }
    }

    /// θ from a gradient in `K̂` entries: `∂/∂θ_k = Σ scale · ∂/∂K̂_ij`.
    pub fn chain(&self, g: &DMatrix<f64>) -> Vec<f64> {
        self.entries().iter().map(|e| e.iter().map(|&(i, j, s)| s * g[(i, j)]).sum()).collect()
    }
}

/// The synthesis problem at one design depth ā_p (module docs).
#[derive(Clone, Debug)]
pub struct Problem {
    /// The spindle structure.
    pub structure: Structure,
    /// Averaged directional matrix H̄ \[N/m²\] (linearised).
    pub hbar: Matrix2<f64>,
    /// Design depth ā_p \[m\].
    pub abar: f64,
    /// Speed range \[rpm\].
    pub rpm: (f64, f64),
    /// Number of teeth.
    pub teeth: u32,
    /// Performance weight.
    pub weight: Weight,
    /// β of the Pyragas difference.
    pub beta: f64,
}

impl Problem {
    /// Checks the ranges.
    pub fn validate(&self) -> Result<(), SynthError> {
        let (lo, hi) = self.rpm;
        if !(lo.is_finite() && lo > 0.0 && hi > lo && hi.is_finite()) || self.teeth == 0 {
            return Err(SynthError::Invalid(format!("speed range {lo}–{hi} rpm, {} teeth", self.teeth)));
        }
        if !(self.abar.is_finite() && self.abar >= 0.0 && self.beta.is_finite()) {
            return Err(SynthError::Invalid(format!("ā_p = {}, β = {}", self.abar, self.beta)));
        }
        Ok(())
    }

    /// (τ₀, δτ_max) \[s\].
    pub fn delays(&self) -> (f64, f64) {
        let z = self.teeth as f64;
        let (t_lo, t_hi) = (60.0 / (z * self.rpm.1), 60.0 / (z * self.rpm.0));
        (0.5 * (t_hi + t_lo), 0.5 * (t_hi - t_lo))
    }

    /// Ω(ω) of Eq. 19.
    pub fn omega_bound(&self, w: f64) -> f64 {
        let (_, dt) = self.delays();
        if w * dt <= PI { 2.0 * (0.5 * w * dt).sin() } else { 2.0 }
    }

    /// The block structure of Δ̃ with performance.
    pub fn mu_structure() -> mu::Structure {
        mu::Structure(vec![Block::Scalar(4), Block::Scalar(2), Block::Full(2)])
    }

    /// The scaled generalised plant `P̃(iω)` (10 × 10): inputs `(q₁, q₂, q₃, r, F_a)`, outputs
    /// `(p₁, p₂, p₃, z, y)`, two each.
    pub fn generalized(&self, w: f64) -> Result<CMat, SynthError> {
        let st = &self.structure;
        let n = st.dim();
        let (tau0, _) = self.delays();
        let s = Complex64::new(0.0, w);
        let e = (-s * tau0).exp();
        let one = Complex64::from(1.0);
        let half = 0.5 * self.abar;
        let bh = &st.bt * DMatrix::from_fn(2, 2, |i, j| self.hbar[(i, j)]);
        let c = |m: &DMatrix<f64>| m.map(Complex64::from);
        let (bhc, ctc, cac) = (c(&bh), c(&st.ct), c(&st.ca));
        let m = CMat::identity(n, n) * s - c(&st.a) - &bhc * &ctc * ((one - e) * half);
        let lu = m.lu();
        let mut rhs = CMat::zeros(n, 6);
        rhs.columns_mut(0, 2).copy_from(&(&bhc * Complex64::from(-half)));
        rhs.columns_mut(2, 2).copy_from(&(&bhc * Complex64::from(self.abar)));
        rhs.columns_mut(4, 2).copy_from(&c(&st.ba));
        let x = lu.solve(&rhs).ok_or_else(|| SynthError::Singular(format!("sI − A − … at ω = {w}")))?;
        let om = Complex64::from(self.omega_bound(w));
        let mut p = CMat::zeros(10, 10);
        for (col, k) in [(0, 0), (4, 2), (8, 4)] {
            let xk = x.columns(k, 2);
            let ct_x = &ctc * xk;
            let ca_x = &cac * xk;
            p.view_mut((0, col), (2, 2)).copy_from(&(&ct_x * (om * e)));
            p.view_mut((2, col), (2, 2)).copy_from(&(&ca_x * (om * e)));
            p.view_mut((4, col), (2, 2)).copy_from(&(&ct_x * ((one - e) * 0.5)));
            p.view_mut((8, col), (2, 2)).copy_from(&(&ca_x * (one - e * self.beta)));
        }
        let wks = self.weight.at(w);
        for i in 0..2 {
            p[(4 + i, i)] -= Complex64::from(0.5);
            p[(8 + i, 2 + i)] -= Complex64::from(self.beta);
            p[(8 + i, 6 + i)] += one;
            p[(6 + i, 8 + i)] = wks;
        }
        Ok(p)
    }

    /// The nominal closed loop (`a_p = ½ā`, `τ = τ₀`) as `ẋ = A₀x + B_d C_d x(t − τ₀)` (Eq. 21).
    pub fn nominal(&self, c: &Controller) -> Result<DelaySystem, SynthError> {
        let st = &self.structure;
        let (n, nc) = (st.dim(), c.ac.nrows());
        let nt = n + nc;
        let half = 0.5 * self.abar;
        let bh = &st.bt * DMatrix::from_fn(2, 2, |i, j| self.hbar[(i, j)]);
        let mut a0 = DMatrix::zeros(nt, nt);
        a0.view_mut((0, 0), (n, n)).copy_from(&(&st.a + &bh * &st.ct * half + &st.ba * &c.dc * &st.ca));
        a0.view_mut((0, n), (n, nc)).copy_from(&(&st.ba * &c.cc));
        a0.view_mut((n, 0), (nc, n)).copy_from(&(&c.bc * &st.ca));
        a0.view_mut((n, n), (nc, nc)).copy_from(&c.ac);
        let mut bd = DMatrix::zeros(nt, 4);
        bd.view_mut((0, 0), (n, 2)).copy_from(&(&bh * -half));
        bd.view_mut((0, 2), (n, 2)).copy_from(&(&st.ba * &c.dc * -self.beta));
        bd.view_mut((n, 2), (nc, 2)).copy_from(&(&c.bc * -self.beta));
        let mut cd = DMatrix::zeros(4, nt);
        cd.view_mut((0, 0), (2, n)).copy_from(&st.ct);
        cd.view_mut((2, 0), (2, n)).copy_from(&st.ca);
        DelaySystem::new(a0, bd, cd, self.delays().0)
    }

    /// Spectral abscissa Ψ of the nominal loop times τ₀ (dimensionless: the growth per delay)
    /// and its gradient in θ (module docs of [`crate::abscissa`]).
    pub fn abscissa(&self, par: &Parameterisation, theta: &[f64], nodes: usize) -> Result<(f64, Vec<f64>), SynthError> {
        let c = par.controller(theta, self.beta);
        let sys = self.nominal(&c)?;
        let root = sys.rightmost(nodes, 3)?;
        let st = &self.structure;
        let (n, nc) = (st.dim(), c.ac.nrows());
        let k = 2 + nc;
        // A₀ = F₀ + G K̂ H₀, A₁ = F₁ + G K̂ H₁
        let mut g = DMatrix::zeros(n + nc, k);
        g.view_mut((0, 0), (n, 2)).copy_from(&st.ba);
        g.view_mut((n, 2), (nc, nc)).fill_with_identity();
        let e = (-root.lambda * sys.tau).exp();
        let mut h = CMat::zeros(k, n + nc);
        h.view_mut((0, 0), (2, n))
            .copy_from(&st.ca.map(|v| Complex64::from(v) * (Complex64::from(1.0) - e * self.beta)));
        h.view_mut((2, n), (nc, nc)).fill_with_identity();
        let row = root.left.adjoint() * g.map(Complex64::from);
        let col = h * &root.right;
        let den = sys.sensitivity_denominator(&root);
        let grad = DMatrix::from_fn(k, k, |i, j| (row[i] * col[j] / den).re);
        let tau = sys.tau;
        Ok((root.lambda.re * tau, par.chain(&grad).iter().map(|v| v * tau).collect()))
    }
}

/// `K(iω)` (2 × 2) and, for the gradient, `C_c R` and `R B_c` with `R = (iωI − A_c)⁻¹`.
pub fn controller_frf(c: &Controller, w: f64) -> Result<(CMat, CMat, CMat), SynthError> {
    let nc = c.ac.nrows();
    let cx = |m: &DMatrix<f64>| m.map(Complex64::from);
    let dc = cx(&c.dc);
    if nc == 0 {
        return Ok((dc, CMat::zeros(2, 0), CMat::zeros(0, 2)));
    }
    let r = (CMat::identity(nc, nc) * Complex64::new(0.0, w) - cx(&c.ac))
        .try_inverse()
        .ok_or_else(|| SynthError::Singular(format!("controller pole on the imaginary axis at ω = {w}")))?;
    let cr = cx(&c.cc) * &r;
    let rb = &r * cx(&c.bc);
    Ok((dc + &cr * cx(&c.bc), cr, rb))
}

/// The closed loop at one frequency: `N = P₁₁ + P₁₂ K (I − P₂₂ K)⁻¹ P₂₁` and the two factors
/// needed for the gradient.
pub struct Loop {
    /// N (8 × 8).
    pub n: CMat,
    /// `P₁₂ (I − K P₂₂)⁻¹` (8 × 2).
    left: CMat,
    /// `(I − P₂₂ K)⁻¹ P₂₁` (2 × 8).
    right: CMat,
}

/// `(I − P₂₂K)⁻¹P₂₁` and `N = P₁₁ + P₁₂ K (I − P₂₂K)⁻¹P₂₁`.
fn right_and_n(p: &CMat, k: &CMat) -> Result<(CMat, CMat), SynthError> {
    let p11 = p.view((0, 0), (8, 8));
    let p12 = p.view((0, 8), (8, 2));
    let p21 = p.view((8, 0), (2, 8));
    let p22 = p.view((8, 8), (2, 2));
    let a = (CMat::identity(2, 2) - p22 * k).try_inverse().ok_or_else(|| SynthError::Singular("I − P₂₂K".into()))?;
    let right = a * p21;
    let n = p11 + p12 * k * &right;
    Ok((right, n))
}

/// [`Loop`] of `P̃` (from [`Problem::generalized`]) and `K(iω)`.
pub fn close(p: &CMat, k: &CMat) -> Result<Loop, SynthError> {
    let (right, n) = right_and_n(p, k)?;
    let p12 = p.view((0, 8), (8, 2));
    let p22 = p.view((8, 8), (2, 2));
    let b = (CMat::identity(2, 2) - k * p22).try_inverse().ok_or_else(|| SynthError::Singular("I − KP₂₂".into()))?;
    let left = p12 * b;
    Ok(Loop { n, left, right })
}

/// `N` of [`close`] alone (the same operations, without the gradient's other factor).
pub fn close_n(p: &CMat, k: &CMat) -> Result<CMat, SynthError> {
    Ok(right_and_n(p, k)?.1)
}

/// `σ̄(D N D⁻¹)` and its gradient in θ (module docs of [`crate::mu`]):
/// `∂σ̄/∂K = (u* D P₁₂(I − KP₂₂)⁻¹)ᵀ ∘ ((I − P₂₂K)⁻¹P₂₁ D⁻¹ v)`, then through `K(iω)` to `K̂`.
pub fn scaled_gain(
    l: &Loop,
    d: &CMat,
    dinv: &CMat,
    c: &Controller,
    w: f64,
    par: &Parameterisation,
) -> Result<(f64, Vec<f64>), SynthError> {
    let m = d * &l.n * dinv;
    let (sigma, u, v) = mu::top_singular(&m);
    let alpha: DVector<Complex64> = (u.adjoint() * d * &l.left).transpose();
    let beta: DVector<Complex64> = &l.right * dinv * v;
    let gk = &alpha * beta.transpose(); // dσ = Re Σ G_ij dK_ij
    let (_, cr, rb) = controller_frf(c, w)?;
    let nc = c.ac.nrows();
    let mut g = DMatrix::zeros(2 + nc, 2 + nc);
    g.view_mut((0, 0), (2, 2)).copy_from(&gk.map(|z| z.re));
    if nc > 0 {
        g.view_mut((0, 2), (2, nc)).copy_from(&(&gk * rb.transpose()).map(|z| z.re));
        g.view_mut((2, 0), (nc, 2)).copy_from(&(cr.transpose() * &gk).map(|z| z.re));
        g.view_mut((2, 2), (nc, nc)).copy_from(&(cr.transpose() * &gk * rb.transpose()).map(|z| z.re));
    }
    Ok((sigma, par.chain(&g)))
}
