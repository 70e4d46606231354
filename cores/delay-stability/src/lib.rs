//! Stability of linear time-periodic systems with one delay,
//!
//! ```text
//! ẋ(t) = A(t) x(t) + B(t) x(t − τ),      A(t + T) = A(t),  B(t + T) = B(t),  T = τ,
//! ```
//!
//! by the first-order semi-discretisation of Insperger & Stépán (Int. J. Numer. Meth. Engng 61,
//! 2004; *Semi-Discretization for Time-Delay Systems*, Springer 2011), with the milling
//! application (regenerative chatter of a multi-DOF structure under a multi-tooth cutter,
//! optionally with a delayed linear output-feedback controller) built in.
//!
//! * [`PeriodicDde`]: what a system must say: its dimension, period, the constant delayed output
//!   `y = C_d x` through which the delay acts (`B(t) = B_d(t) C_d`), and its matrices averaged
//!   over a sub-interval.
//! * [`sd`]: the discrete map over one period (the monodromy matrix Φ), its spectral radius and
//!   the classification of the critical multiplier ([`Bifurcation`]: Hopf, flip, fold).
//! * [`mod@lobes`]: the critical value of a parameter (the axial depth) by a bracketing scan and
//!   bisection of `ρ(Φ) = 1`, for many speeds in parallel (rayon) with a progress callback.
//! * [`milling`]: the milling model builder: a linear structure (modes with mass-normalised
//!   shapes, or any state-space model), the time-periodic directional matrix of the teeth
//!   (linear or power-law cutting, linearised), and a linear delayed controller.
//! * [`exact`]: the exact stability boundary of the time-invariant case (D-subdivision), the
//!   reference for the semi-discretisation.
//! * [`oscillator`]: the damped delayed Mathieu equation, the classic test problem.
//! * [`zero_order`]: the zero-order (Altintas–Budak) lobes of any receptance closure, exact
//!   critical depth per speed, b_min/b_max — the frequency-domain method beside the
//!   semi-discretisation.
//! * [`frequency`]: the same for a 2 × 2 receptance (modal or measured) under a milling
//!   [`milling::Cutter`]: the 2-D zero-order (Altintas–Budak) and the multi-frequency lobes.
//!
//! The crate is a core: plain types, `thiserror` errors, no FMI.

mod bracket;
pub mod exact;
pub mod frequency;
pub mod krylov;
pub mod lobes;
pub mod milling;
pub mod oscillator;
pub mod presets;
pub mod quadrature;
pub mod sd;
pub mod search;
pub mod spectral;
pub mod zero_order;

pub use lobes::{BisectionOptions, Critical, LobePoint, critical_value, lobes};
pub use sd::{Bifurcation, Multiplier, monodromy, monodromy_dense};
pub use search::{LobeOptions, Method, critical, lobes_with};
pub use spectral::{Spectral, SpectralOptions};

use nalgebra::DMatrix;

/// Errors of the stability computations.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StabilityError {
    /// A parameter is out of its range; the message says which.
    #[error("invalid parameter: {0}")]
    Invalid(String),
    /// The eigenvalue iteration did not converge.
    #[error("the eigenvalues of the {dim}×{dim} monodromy matrix did not converge")]
    Eigen {
        /// Dimension of the matrix.
        dim: usize,
    },
    /// The system is already unstable at the lower end of the parameter range.
    #[error("unstable at the lower end of the bracket (parameter {value}, spectral radius {rho})")]
    UnstableAtStart {
        /// The parameter value.
        value: f64,
        /// The spectral radius there.
        rho: f64,
    },
}

/// A linear `T`-periodic system with one delay `τ = T` whose delayed term acts through a
/// constant output: `ẋ = A(t) x + B_d(t) C_d x(t − τ)`.
///
/// Writing the delay through `y = C_d x` (r outputs) lets the semi-discretisation keep only the
/// last `m` outputs instead of `m` full states: the monodromy matrix has dimension `n + r m`
/// instead of `n (m + 1)` and the same nonzero eigenvalues (tested against [`monodromy_dense`]).
/// A system without such structure uses `C_d = I`.
pub trait PeriodicDde {
    /// State dimension n.
    fn dim(&self) -> usize;
    /// Period T = delay τ \[s\].
    fn period(&self) -> f64;
    /// The constant delayed output `C_d` (r × n).
    fn delayed_output(&self) -> DMatrix<f64>;
    /// `A(t)` and `B_d(t)` averaged over `[t0, t1] ⊂ [0, T]`: `(1/(t1−t0)) ∫ A dt` (n × n) and
    /// `(1/(t1−t0)) ∫ B_d dt` (n × r). With `t1 = t0` the values at `t0` (the limit), which the
    /// default [`PeriodicDde::at`] asks for.
    fn averaged(&self, t0: f64, t1: f64) -> (DMatrix<f64>, DMatrix<f64>);

    /// `A(t)` and `B_d(t)` at one instant `t ∈ (0, T)` (the spectral collocation's nodes, never a
    /// breakpoint). Default: [`PeriodicDde::averaged`] over `[t, t]`.
    fn at(&self, t: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        self.averaged(t, t)
    }

    /// The instants in `(0, T)` where `A` or `B_d` is not smooth (a jump, a kink, an integrable
    /// singularity): the spectral collocation ([`spectral`]) puts element ends there, so that
    /// every element sees smooth coefficients. Default: none (smooth coefficients).
    fn breakpoints(&self) -> Vec<f64> {
        Vec::new()
    }

    /// The instants in `[0, T)` where `A` or `B_d` is unbounded (an integrable singularity, like
    /// `(t − t_s)^{−1/4}` of the power-law cutting force where a tooth enters or leaves at zero
    /// chip; 0 stands for both ends of the period). The spectral collocation grades its elements
    /// geometrically towards them. Default: none.
    fn singularities(&self) -> Vec<f64> {
        Vec::new()
    }

    /// The constant part of the system, if it has one of low rank in the time-varying terms:
    /// `A(t) = A₀ + G P(t) C₀` and `B_d(t) = G Q(t)` ([`Splitting`]); the spectral collocation
    /// then integrates `A₀` exactly and collocates only the `k`-dimensional input `G v(t)`.
    /// Default `None`: `A₀` is the mean of `A` over the period and `G = C₀ = I`.
    fn splitting(&self) -> Option<Splitting> {
        None
    }

    /// `P(t)` (k × p) and `Q(t)` (k × r) of the [`Splitting`]; called only when
    /// [`PeriodicDde::splitting`] is `Some`. Default: the generic split (`P = A(t) − A₀`,
    /// `Q = B_d(t)` with `A₀` from `splitting`).
    fn gains(&self, t: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        let (a, b) = self.at(t);
        let a0 = self.splitting().map_or_else(|| DMatrix::zeros(a.nrows(), a.ncols()), |s| s.a0);
        (a - a0, b)
    }
}

/// The constant, low-rank structure of a [`PeriodicDde`]:
///
/// ```text
/// ẋ = A₀ x + G v(t),     v(t) = P(t) C₀ x(t) + Q(t) C_d x(t − τ),
/// ```
///
/// with constant `A₀` (n × n), `G` (n × k), `C₀` (p × n) and periodic `P(t)` (k × p), `Q(t)`
/// (k × r). A milling model has `A₀` = structure and controller, `G` = the force inputs,
/// `C₀` = the tool displacement, `P = a_p H(t)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Splitting {
    /// A₀ (n × n).
    pub a0: DMatrix<f64>,
    /// G (n × k).
    pub g: DMatrix<f64>,
    /// C₀ (p × n).
    pub c0: DMatrix<f64>,
}
