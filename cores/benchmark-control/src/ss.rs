//! Real state-space systems `ẋ = A x + B u`, `y = C x + D u`: frequency response, poles,
//! series connection, time scaling, the closed loop of a generalised plant with a controller,
//! and the controller as a `LinearController` parameter set.

use crate::DesignError;
use linear_control::{LinearControlParams, MAX_ORDER};
use nalgebra::DMatrix;
use num_complex::Complex64;

/// Complex matrix.
pub type CMat = DMatrix<Complex64>;

/// A real state-space system (continuous time).
#[derive(Clone, Debug, PartialEq)]
pub struct StateSpace {
    /// A (n × n).
    pub a: DMatrix<f64>,
    /// B (n × m).
    pub b: DMatrix<f64>,
    /// C (p × n).
    pub c: DMatrix<f64>,
    /// D (p × m).
    pub d: DMatrix<f64>,
}

/// `C (sI − A)⁻¹ B + D` of complex-valued matrices (used by the closed loops and the norm).
pub fn complex(m: &DMatrix<f64>) -> CMat {
    m.map(Complex64::from)
}

impl StateSpace {
    /// A system after checking the dimensions and finiteness.
    pub fn new(a: DMatrix<f64>, b: DMatrix<f64>, c: DMatrix<f64>, d: DMatrix<f64>) -> Result<Self, DesignError> {
        let n = a.nrows();
        if a.ncols() != n || b.nrows() != n || c.ncols() != n || d.nrows() != c.nrows() || d.ncols() != b.ncols() {
            return Err(DesignError::Invalid(format!(
                "state-space dimensions do not match: A {}×{}, B {}×{}, C {}×{}, D {}×{}",
                a.nrows(),
                a.ncols(),
                b.nrows(),
                b.ncols(),
                c.nrows(),
                c.ncols(),
                d.nrows(),
                d.ncols()
            )));
        }
        if ![&a, &b, &c, &d].iter().all(|m| m.iter().all(|x| x.is_finite())) {
            return Err(DesignError::Invalid("state-space matrices must be finite".into()));
        }
        Ok(StateSpace { a, b, c, d })
    }

    /// A static SISO gain.
    pub fn gain(k: f64) -> Self {
        StateSpace {
            a: DMatrix::zeros(0, 0),
            b: DMatrix::zeros(0, 1),
            c: DMatrix::zeros(1, 0),
            d: DMatrix::from_element(1, 1, k),
        }
    }

    /// The order n.
    pub fn order(&self) -> usize {
        self.a.nrows()
    }

    /// `C (sI − A)⁻¹ B + D` at a complex `s`.
    pub fn eval(&self, s: Complex64) -> CMat {
        let n = self.order();
        let mut g = complex(&self.d);
        if n == 0 {
            return g;
        }
        let m = CMat::from_fn(n, n, |i, j| if i == j { s - self.a[(i, j)] } else { Complex64::from(-self.a[(i, j)]) });
        match m.lu().solve(&complex(&self.b)) {
            Some(x) => g += complex(&self.c) * x,
            None => g.fill(Complex64::new(f64::INFINITY, 0.0)),
        }
        g
    }

    /// The (1, 1) entry at `s` (SISO systems).
    pub fn siso(&self, s: Complex64) -> Complex64 {
        self.eval(s)[(0, 0)]
    }

    /// The (1, 1) entry at `iω`.
    pub fn at(&self, omega: f64) -> Complex64 {
        self.siso(Complex64::new(0.0, omega))
    }

    /// The eigenvalues of A.
    pub fn poles(&self) -> Vec<Complex64> {
        if self.order() == 0 {
            return Vec::new();
        }
        self.a.complex_eigenvalues().iter().copied().collect()
    }

    /// The largest real part of the poles (−∞ for a static gain).
    pub fn spectral_abscissa(&self) -> f64 {
        self.poles().iter().map(|p| p.re).fold(f64::NEG_INFINITY, f64::max)
    }

    /// `next ∘ self`: the output of `self` drives `next` (states: self's, then next's).
    pub fn series(&self, next: &StateSpace) -> StateSpace {
        let (n1, n2) = (self.order(), next.order());
        let mut a = DMatrix::zeros(n1 + n2, n1 + n2);
        a.view_mut((0, 0), (n1, n1)).copy_from(&self.a);
        a.view_mut((n1, 0), (n2, n1)).copy_from(&(&next.b * &self.c));
        a.view_mut((n1, n1), (n2, n2)).copy_from(&next.a);
        let mut b = DMatrix::zeros(n1 + n2, self.b.ncols());
        b.view_mut((0, 0), (n1, self.b.ncols())).copy_from(&self.b);
        b.view_mut((n1, 0), (n2, self.b.ncols())).copy_from(&(&next.b * &self.d));
        let mut c = DMatrix::zeros(next.c.nrows(), n1 + n2);
        c.view_mut((0, 0), (next.c.nrows(), n1)).copy_from(&(&next.d * &self.c));
        c.view_mut((0, n1), (next.c.nrows(), n2)).copy_from(&next.c);
        StateSpace { a, b, c, d: &next.d * &self.d }
    }

    /// The system `G(s/w0)` from `G(s̃)` given in the time unit `1/w0`, with its input scaled by
    /// `input` and its output by `output`: `output · G(s/w0) · input`.
    pub fn rescaled(&self, w0: f64, input: f64, output: f64) -> StateSpace {
        StateSpace { a: &self.a * w0, b: &self.b * (w0 * input), c: &self.c * output, d: &self.d * (input * output) }
    }

    /// A diagonal similarity that makes each state's input and output coupling alike
    /// (`|B_i| = |C_i|`, where both are non-zero): the same transfer, better-scaled numbers.
    pub fn io_balanced(&self) -> StateSpace {
        let n = self.order();
        let mut t = self.clone();
        for i in 0..n {
            let bi = self.b.row(i).norm();
            let ci = self.c.column(i).norm();
            if bi > 0.0 && ci > 0.0 {
                let s = (bi / ci).sqrt(); // ξ_i → ξ_i / s
                for j in 0..n {
                    if i != j {
                        t.a[(i, j)] /= s;
                        t.a[(j, i)] *= s;
                    }
                }
                t.b.row_mut(i).scale_mut(1.0 / s);
                t.c.column_mut(i).scale_mut(s);
            }
        }
        t
    }

    /// The SISO controller `F_x = K(s) v_x` as a `LinearController` parameter set (`n_c` ≤ 8,
    /// β = 0 so that `w = v`, delay a parameter of 0, continuous form, `saturation` on both
    /// outputs; the y channel unused).
    pub fn to_linear_params(&self, saturation: f64) -> Result<LinearControlParams, DesignError> {
        let n = self.order();
        if n > MAX_ORDER || self.b.ncols() != 1 || self.c.nrows() != 1 {
            return Err(DesignError::Invalid(format!(
                "a LinearController holds a SISO controller of order ≤ {MAX_ORDER} (got order {n}, {}×{})",
                self.c.nrows(),
                self.b.ncols()
            )));
        }
        let mut p = LinearControlParams {
            n_c: n as u32,
            beta: 0.0,
            delay_from_speed: false,
            delay: 0.0,
            saturation: [saturation; 2],
            ..Default::default()
        };
        for i in 0..n {
            for j in 0..n {
                p.ac[i][j] = self.a[(i, j)];
            }
            p.bc[i][0] = self.b[(i, 0)];
            p.cc[0][i] = self.c[(0, i)];
        }
        p.dc[0][0] = self.d[(0, 0)];
        p.validate().map_err(DesignError::Invalid)?;
        Ok(p)
    }
}

/// A generalised plant `ẋ = A x + B₁ w + B₂ u`, `z = C₁ x + D₁₁ w + D₁₂ u`,
/// `y = C₂ x + D₂₁ w` (`D₂₂ = 0`), closed by `u = K y`.
#[derive(Clone, Debug, PartialEq)]
pub struct Generalized {
    /// A.
    pub a: DMatrix<f64>,
    /// B₁ (exogenous inputs w).
    pub b1: DMatrix<f64>,
    /// B₂ (control inputs u).
    pub b2: DMatrix<f64>,
    /// C₁ (performance outputs z).
    pub c1: DMatrix<f64>,
    /// C₂ (measurements y).
    pub c2: DMatrix<f64>,
    /// D₁₁.
    pub d11: DMatrix<f64>,
    /// D₁₂.
    pub d12: DMatrix<f64>,
    /// D₂₁.
    pub d21: DMatrix<f64>,
}

impl Generalized {
    /// The closed loop `w → z` with `u = K y` (lower linear fractional transformation):
    /// states (plant, controller).
    pub fn close(&self, k: &StateSpace) -> StateSpace {
        let (n, nk) = (self.a.nrows(), k.order());
        let mut a = DMatrix::zeros(n + nk, n + nk);
        a.view_mut((0, 0), (n, n)).copy_from(&(&self.a + &self.b2 * &k.d * &self.c2));
        a.view_mut((0, n), (n, nk)).copy_from(&(&self.b2 * &k.c));
        a.view_mut((n, 0), (nk, n)).copy_from(&(&k.b * &self.c2));
        a.view_mut((n, n), (nk, nk)).copy_from(&k.a);
        let mw = self.b1.ncols();
        let mut b = DMatrix::zeros(n + nk, mw);
        b.view_mut((0, 0), (n, mw)).copy_from(&(&self.b1 + &self.b2 * &k.d * &self.d21));
        b.view_mut((n, 0), (nk, mw)).copy_from(&(&k.b * &self.d21));
        let pz = self.c1.nrows();
        let mut c = DMatrix::zeros(pz, n + nk);
        c.view_mut((0, 0), (pz, n)).copy_from(&(&self.c1 + &self.d12 * &k.d * &self.c2));
        c.view_mut((0, n), (pz, nk)).copy_from(&(&self.d12 * &k.c));
        let d = &self.d11 + &self.d12 * &k.d * &self.d21;
        StateSpace { a, b, c, d }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn first_order(a: f64) -> StateSpace {
        StateSpace::new(
            DMatrix::from_element(1, 1, -a),
            DMatrix::from_element(1, 1, 1.0),
            DMatrix::from_element(1, 1, a),
            DMatrix::zeros(1, 1),
        )
        .unwrap()
    }

    #[test]
    fn series_multiplies_responses_and_rescaling_scales_frequency() {
        let (g1, g2) = (first_order(2.0), first_order(30.0));
        let s12 = g1.series(&g2);
        for w in [0.1, 3.0, 40.0] {
            let want = g1.at(w) * g2.at(w);
            assert!((s12.at(w) - want).norm() < 1e-14, "{w}");
            let r = g1.rescaled(10.0, 3.0, 0.5);
            assert!((r.at(10.0 * w) - 1.5 * g1.at(w)).norm() < 1e-14);
            let b = s12.io_balanced();
            assert!((b.at(w) - want).norm() < 1e-14);
        }
        assert!(
            StateSpace::new(DMatrix::zeros(2, 2), DMatrix::zeros(1, 1), DMatrix::zeros(1, 2), DMatrix::zeros(1, 1))
                .is_err()
        );
    }

    /// The lower LFT of `P = [[0, 1], [1, −G]]`-style loops: unit feedback around `G = a/(s+a)`
    /// with `u = −y` gives `a/(s + 2a)`.
    #[test]
    fn closing_a_generalised_plant_is_the_feedback_formula() {
        let a = 5.0;
        // plant state x: ẋ = −a x + a (w + u); z = x; y = x
        let p = Generalized {
            a: DMatrix::from_element(1, 1, -a),
            b1: DMatrix::from_element(1, 1, a),
            b2: DMatrix::from_element(1, 1, a),
            c1: DMatrix::from_element(1, 1, 1.0),
            c2: DMatrix::from_element(1, 1, 1.0),
            d11: DMatrix::zeros(1, 1),
            d12: DMatrix::zeros(1, 1),
            d21: DMatrix::zeros(1, 1),
        };
        let cl = p.close(&StateSpace::gain(-1.0));
        for w in [0.3, 7.0] {
            let want = Complex64::from(a) / Complex64::new(2.0 * a, w);
            assert!((cl.at(w) - want).norm() < 1e-14);
        }
        // a dynamic controller: K = first order, compare with G/(1 − G K)
        let k = first_order(50.0).rescaled(1.0, 1.0, -3.0);
        let cl = p.close(&k);
        let g = first_order(a);
        for w in [0.3, 7.0, 80.0] {
            let want = g.at(w) / (1.0 - g.at(w) * k.at(w));
            assert!((cl.at(w) - want).norm() < 1e-13);
        }
    }

    #[test]
    fn a_controller_becomes_a_linear_controller_with_the_same_response() {
        let k = first_order(50.0).series(&first_order(700.0)).rescaled(1.0, 2.0, -3.0);
        let p = k.to_linear_params(27.0).unwrap();
        let c = linear_control::LinearController::new(&p).unwrap();
        for w in [1.0, 100.0, 1e4] {
            assert!((c.frequency_response(w, 0.0)[0][0] - k.at(w)).norm() < 1e-12 * k.at(w).norm().max(1.0));
        }
        assert_eq!((p.n_c, p.beta, p.saturation), (2, 0.0, [27.0; 2]));
    }
}
