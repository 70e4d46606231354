//! The milling model builder: a linear structure, a multi-tooth cutter and an optional delayed
//! linear controller, linearised about the periodic tool motion into a [`crate::PeriodicDde`].
//!
//! # Structure
//!
//! `ẋ = A x + B_t F + B_a F_a`, `v_t = C_t x` (tool-minus-workpiece displacement at the tool
//! point, x = feed, y = normal), `v_a = C_a x` (the actuator/sensor point). [`Structure::from_modes`]
//! builds it from modes with mass-normalised shapes (`q̈ + 2ζω q̇ + ω² q = u_tᵀF + u_aᵀF_a`,
//! `v_t = Σ u_t q`); a workpiece mode of mass `m` bending along `d` has `u_t = −d/√m` (the
//! workpiece moves the other way from the relative displacement). [`Structure::two_mass_per_axis`]
//! is seed 002's spindle (ground –(c_a, b_a)– m_a –(c_t, b_t)– m_t per axis, F_a and v_a at m_a).
//!
//! # Cutting (seed 002 Eqs. 1–3, 8–9; Altintas–Budak angles)
//!
//! Tooth `j` is at `φ_j(t) = Ω t + 2πj/z` from the `y` axis, engaged (`g_j = 1`) when
//! `φ_entry ≤ φ_j mod 2π ≤ φ_exit` and `sin φ_j > 0`. The chip is
//! `h_j = f_z sin φ_j + [sin φ_j, cos φ_j](v_t(t) − v_t(t − τ))` and the force on the tool
//! `F = a_p Σ g_j h_j^{x_F} S(φ_j) [K_t; K_r]`, `S = [[−cos, −sin], [sin, −cos]]`. Linearised about
//! the periodic motion,
//!
//! ```text
//! F̃ = a_p H(t) (ṽ_t(t) − ṽ_t(t − τ)),   H(t) = Σ_j g_j x_F (f_z sin φ_j)^{x_F − 1} S(φ_j)[K_t; K_r][sin φ_j, cos φ_j],
//! ```
//!
//! `τ = 60/(z n)`-periodic ([`Cutter::directional`]); for `x_F = 1` ([`ForceLaw::Linear`]) the
//! factor is 1. For `x_F < 1` the factor is singular (integrably) where `sin φ_j = 0` (entry at 0,
//! exit at π), so the semi-discretisation uses the exact sub-interval averages
//! [`Cutter::averaged`] computed with [`crate::quadrature`]. Edge coefficients (K_te, K_re) add
//! a constant force and no term to the linearisation, so they do not enter.
//!
//! # Controller (seed 002 Eq. 10)
//!
//! `ξ̇ = A_c ξ + B_c w`, `F_a = C_c ξ + D_c w`, `w = v_a − β v_a(t − τ)` (β = 1: Pyragas). The
//! closed loop in `X = (x, ξ)`:
//!
//! ```text
//! Ẋ = [[A + B_a D_c C_a, B_a C_c], [B_c C_a, A_c]] X + a_p B̂_t H(t) Ĉ_t (X − X(t − τ))
//!     − β [B_a D_c; B_c] C_a x(t − τ),
//! ```
//!
//! so the delayed output is `C_d = [Ĉ_t; Ĉ_a]` and `B_d(t) = [−a_p B̂_t H(t), −β [B_a D_c; B_c]]`.

use crate::StabilityError;
use crate::quadrature::GaussLegendre;
use nalgebra::{DMatrix, Matrix2};
use std::f64::consts::PI;

/// One mode with mass-normalised shapes at the tool and actuator points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeShape {
    /// Natural frequency \[rad/s\].
    pub omega: f64,
    /// Damping ratio \[-\].
    pub zeta: f64,
    /// Shape at the tool point, (x, y) \[1/√kg\].
    pub tool: [f64; 2],
    /// Shape at the actuator/sensor point, (x, y) \[1/√kg\].
    pub actuator: [f64; 2],
}

/// The linear structure `ẋ = A x + B_t F + B_a F_a`, `v_t = C_t x`, `v_a = C_a x`.
#[derive(Clone, Debug, PartialEq)]
pub struct Structure {
    /// State matrix (n × n).
    pub a: DMatrix<f64>,
    /// Cutting-force input (n × 2).
    pub bt: DMatrix<f64>,
    /// Tool displacement output (2 × n).
    pub ct: DMatrix<f64>,
    /// Actuator force input (n × p).
    pub ba: DMatrix<f64>,
    /// Measured output (q × n).
    pub ca: DMatrix<f64>,
}

/// One axis of seed 002's spindle (Table I): two masses in series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoMassAxis {
    /// Tool mass m_t \[kg\].
    pub tool_mass: f64,
    /// Actuator (bearing) mass m_a \[kg\].
    pub actuator_mass: f64,
    /// ω_t = √(c_t/m_t) \[Hz\].
    pub tool_hz: f64,
    /// ω_a = √(c_a/m_a) \[Hz\].
    pub actuator_hz: f64,
    /// ζ_t = b_t/(2√(c_t m_t)).
    pub tool_zeta: f64,
    /// ζ_a = b_a/(2√(c_a m_a)).
    pub actuator_zeta: f64,
}

impl Structure {
    /// Modal structure, state `(q_1, q̇_1, q_2, q̇_2, …)`, two actuator inputs and outputs.
    pub fn from_modes(modes: &[ModeShape]) -> Result<Structure, StabilityError> {
        if modes.is_empty() {
            return Err(StabilityError::Invalid("a modal structure needs at least one mode".into()));
        }
        let n = 2 * modes.len();
        let mut s = Structure {
            a: DMatrix::zeros(n, n),
            bt: DMatrix::zeros(n, 2),
            ct: DMatrix::zeros(2, n),
            ba: DMatrix::zeros(n, 2),
            ca: DMatrix::zeros(2, n),
        };
        for (k, md) in modes.iter().enumerate() {
            if !(md.omega.is_finite() && md.omega > 0.0 && md.zeta.is_finite() && md.zeta >= 0.0) {
                return Err(StabilityError::Invalid(format!("mode {}: ω must be > 0 and ζ >= 0 (got {md:?})", k + 1)));
            }
            let (q, v) = (2 * k, 2 * k + 1);
            s.a[(q, v)] = 1.0;
            s.a[(v, q)] = -md.omega * md.omega;
            s.a[(v, v)] = -2.0 * md.zeta * md.omega;
            for d in 0..2 {
                s.bt[(v, d)] = md.tool[d];
                s.ct[(d, q)] = md.tool[d];
                s.ba[(v, d)] = md.actuator[d];
                s.ca[(d, q)] = md.actuator[d];
            }
        }
        Ok(s)
    }

    /// Seed 002's spindle: the same two-mass chain in x and y, state
    /// `(x_a, x_t, ẋ_a, ẋ_t)` of the x axis, then the y axis; F_t and v_t at m_t, F_a and v_a at m_a.
    pub fn two_mass_per_axis(p: &TwoMassAxis) -> Structure {
        let ct_ = p.tool_mass * (2.0 * PI * p.tool_hz).powi(2);
        let ca_ = p.actuator_mass * (2.0 * PI * p.actuator_hz).powi(2);
        let bt_ = 2.0 * p.tool_zeta * (ct_ * p.tool_mass).sqrt();
        let ba_ = 2.0 * p.actuator_zeta * (ca_ * p.actuator_mass).sqrt();
        let mut s = Structure {
            a: DMatrix::zeros(8, 8),
            bt: DMatrix::zeros(8, 2),
            ct: DMatrix::zeros(2, 8),
            ba: DMatrix::zeros(8, 2),
            ca: DMatrix::zeros(2, 8),
        };
        for ax in 0..2 {
            let o = 4 * ax;
            let (xa, xt, va, vt) = (o, o + 1, o + 2, o + 3);
            s.a[(xa, va)] = 1.0;
            s.a[(xt, vt)] = 1.0;
            // m_a ẍ_a = −c_a x_a − b_a ẋ_a − c_t (x_a − x_t) − b_t (ẋ_a − ẋ_t) + F_a
            s.a[(va, xa)] = -(ca_ + ct_) / p.actuator_mass;
            s.a[(va, xt)] = ct_ / p.actuator_mass;
            s.a[(va, va)] = -(ba_ + bt_) / p.actuator_mass;
            s.a[(va, vt)] = bt_ / p.actuator_mass;
            // m_t ẍ_t = −c_t (x_t − x_a) − b_t (ẋ_t − ẋ_a) + F_t
            s.a[(vt, xt)] = -ct_ / p.tool_mass;
            s.a[(vt, xa)] = ct_ / p.tool_mass;
            s.a[(vt, vt)] = -bt_ / p.tool_mass;
            s.a[(vt, va)] = bt_ / p.tool_mass;
            s.bt[(vt, ax)] = 1.0 / p.tool_mass;
            s.ct[(ax, xt)] = 1.0;
            s.ba[(va, ax)] = 1.0 / p.actuator_mass;
            s.ca[(ax, xa)] = 1.0;
        }
        s
    }

    /// State dimension.
    pub fn dim(&self) -> usize {
        self.a.nrows()
    }
}

/// The cutting-force law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ForceLaw {
    /// `F = a_p K h` (x_F = 1).
    Linear,
    /// `F = a_p K h^{x_F}`, linearised about the static chip `f_z sin φ`.
    Power {
        /// Exponent x_F ∈ (0, 1].
        x_f: f64,
        /// Feed per tooth f_z \[m\].
        feed_per_tooth: f64,
    },
}

/// Up- or down-milling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Milling {
    /// Up-milling: engaged on `[0, φ_c]`.
    Up,
    /// Down-milling: engaged on `[π − φ_c, π]`.
    Down,
}

/// A cutter with `z` equally spaced teeth.
#[derive(Clone, Debug)]
pub struct Cutter {
    /// Number of teeth z.
    pub teeth: u32,
    /// Entry angle φ_s \[rad\] from the y axis.
    pub entry: f64,
    /// Exit angle φ_e \[rad\].
    pub exit: f64,
    /// Tangential coefficient K_t \[N/m^{1+x_F}\].
    pub kt: f64,
    /// Radial coefficient K_r \[N/m^{1+x_F}\].
    pub kr: f64,
    /// Force law.
    pub law: ForceLaw,
    rule: GaussLegendre,
}

impl Cutter {
    /// A cutter; the angles must satisfy `0 ≤ entry < exit ≤ π`.
    pub fn new(teeth: u32, entry: f64, exit: f64, kt: f64, kr: f64, law: ForceLaw) -> Result<Cutter, StabilityError> {
        let bad = |m: String| Err(StabilityError::Invalid(m));
        if teeth == 0 {
            return bad("the cutter needs at least one tooth".into());
        }
        if !(entry.is_finite() && exit.is_finite() && 0.0 <= entry && entry < exit && exit <= PI) {
            return bad(format!("need 0 <= entry < exit <= π (got {entry}, {exit})"));
        }
        if !(kt.is_finite() && kr.is_finite()) {
            return bad("K_t and K_r must be finite".into());
        }
        if let ForceLaw::Power { x_f, feed_per_tooth } = law
            && !(x_f > 0.0 && x_f <= 1.0 && feed_per_tooth.is_finite() && feed_per_tooth > 0.0)
        {
            return bad(format!("power law: need 0 < x_F <= 1 and f_z > 0 (got {x_f}, {feed_per_tooth})"));
        }
        Ok(Cutter { teeth, entry, exit, kt, kr, law, rule: GaussLegendre::new(16) })
    }

    /// Entry and exit angles of a radial immersion `a_e/D ∈ (0, 1]`.
    pub fn immersion(radial_fraction: f64, milling: Milling) -> (f64, f64) {
        let phi_c = (1.0 - 2.0 * radial_fraction).clamp(-1.0, 1.0).acos();
        match milling {
            Milling::Up => (0.0, phi_c),
            Milling::Down => (PI - phi_c, PI),
        }
    }

    /// Tooth pitch 2π/z.
    pub fn pitch(&self) -> f64 {
        2.0 * PI / self.teeth as f64
    }

    /// One tooth's `H` at angle `phi` if engaged (module docs), without the engagement test.
    fn tooth(&self, phi: f64) -> Matrix2<f64> {
        let (s, c) = phi.sin_cos();
        let factor = match self.law {
            ForceLaw::Linear => 1.0,
            // |sin|: a node rounded onto the far side of a zero of sin (pieces end there) must
            // not give NaN; the piece test in `averaged` keeps the sign right otherwise
            ForceLaw::Power { x_f, feed_per_tooth } => x_f * (feed_per_tooth * s.abs()).powf(x_f - 1.0),
        };
        let u = [-c * self.kt - s * self.kr, s * self.kt - c * self.kr];
        Matrix2::new(u[0] * s, u[0] * c, u[1] * s, u[1] * c) * factor
    }

    fn engaged(&self, phi: f64) -> bool {
        let p = phi.rem_euclid(2.0 * PI);
        p >= self.entry && p <= self.exit && p.sin() > 0.0
    }

    /// `H` at tool angle `phi` (tooth 0 at `phi`), summed over the engaged teeth.
    pub fn directional(&self, phi: f64) -> Matrix2<f64> {
        (0..self.teeth).map(|j| phi + j as f64 * self.pitch()).filter(|&p| self.engaged(p)).map(|p| self.tooth(p)).sum()
    }

    /// Exponent of the singularity-removing substitution for `h^{x_F − 1}`.
    fn k(&self) -> i32 {
        match self.law {
            ForceLaw::Linear => 1,
            ForceLaw::Power { x_f, .. } => crate::quadrature::exponent_for(x_f - 1.0),
        }
    }

    /// `(1/(φ1 − φ0)) ∫_{φ0}^{φ1} H dφ`: split at every entry, exit and zero of `sin` of every
    /// tooth, each engaged piece integrated with [`GaussLegendre::singular`].
    pub fn averaged(&self, phi0: f64, phi1: f64) -> Matrix2<f64> {
        if phi1 <= phi0 {
            return self.directional(phi0);
        }
        let mut sum = Matrix2::zeros();
        let k = self.k();
        for j in 0..self.teeth {
            let off = j as f64 * self.pitch();
            let (a, b) = (phi0 + off, phi1 + off);
            let mut cuts = vec![a, b];
            let first = (a / (2.0 * PI)).floor() as i64 - 1;
            let last = (b / (2.0 * PI)).ceil() as i64 + 1;
            for rev in first..=last {
                let base = rev as f64 * 2.0 * PI;
                for e in [0.0, PI, self.entry, self.exit] {
                    let x = base + e;
                    if x > a && x < b {
                        cuts.push(x);
                    }
                }
            }
            cuts.sort_by(f64::total_cmp);
            for w in cuts.windows(2) {
                // pieces narrower than rounding (a breakpoint met twice) carry nothing
                if w[1] - w[0] > 1e-12 * (1.0 + w[1].abs()) && self.engaged(0.5 * (w[0] + w[1])) {
                    sum += self.rule.singular(w[0], w[1], k, |p| self.tooth(p));
                }
            }
        }
        sum / (phi1 - phi0)
    }

    /// The mean over one tooth period, `H̄ = (z/2π) ∫_{φ_s}^{φ_e} H_tooth dφ` (zero-order term).
    pub fn mean(&self) -> Matrix2<f64> {
        self.averaged(0.0, self.pitch())
    }
}

/// The delayed linear controller of seed 002 Eq. 10.
#[derive(Clone, Debug, PartialEq)]
pub struct Controller {
    /// A_c (n_c × n_c; 0 × 0 for a static gain).
    pub ac: DMatrix<f64>,
    /// B_c (n_c × q).
    pub bc: DMatrix<f64>,
    /// C_c (p × n_c).
    pub cc: DMatrix<f64>,
    /// D_c (p × q).
    pub dc: DMatrix<f64>,
    /// β of `w = v_a − β v_a(t − τ)`.
    pub beta: f64,
}

impl Controller {
    /// A static gain `F_a = D_c (v_a − β v_a(t − τ))`.
    pub fn static_gain(dc: DMatrix<f64>, beta: f64) -> Controller {
        let (p, q) = dc.shape();
        Controller { ac: DMatrix::zeros(0, 0), bc: DMatrix::zeros(0, q), cc: DMatrix::zeros(p, 0), dc, beta }
    }
}

mod model;
pub use model::{MillingDde, MillingModel};
