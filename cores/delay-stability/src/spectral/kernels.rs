//! The element matrices of the exponential collocation (parent module docs): for an element of
//! length `h` with `N` Gauss–Legendre nodes `θ_i ∈ (0, 1)`,
//!
//! ```text
//! E_i = e^{A₀ h θ_i},    W_ij = h ∫₀^{θ_i} e^{A₀ h (θ_i − σ)} ℓ_j(σ) dσ · G,    (θ_{N+1} = 1: the element end)
//! ```
//!
//! `ℓ_j` the Lagrange polynomials on the nodes. The integrals are split at the nodes,
//! `W_{l} = e^{A₀ h Δ_l} W_{l−1} + J_l` with `J_l` the integral over `[θ_{l−1}, θ_l]` by
//! Gauss–Legendre with `⌈N/2⌉ + 10` points (exact for the polynomial, the exponential factor
//! spans a fraction of an oscillation), so every exponential is of a short interval.

use crate::quadrature::GaussLegendre;
use nalgebra::DMatrix;

/// Gauss–Legendre nodes on `[0, 1]` with their barycentric weights.
#[derive(Clone, Debug)]
pub(crate) struct Nodes {
    /// θ_1 < … < θ_N.
    pub theta: Vec<f64>,
    bary: Vec<f64>,
}

impl Nodes {
    pub fn new(n: usize) -> Nodes {
        let theta = GaussLegendre::new(n.max(1)).nodes().to_vec();
        let bary = (0..theta.len())
            .map(|j| {
                let p: f64 = (0..theta.len()).filter(|&k| k != j).map(|k| theta[j] - theta[k]).product();
                1.0 / p
            })
            .collect();
        Nodes { theta, bary }
    }

    pub fn len(&self) -> usize {
        self.theta.len()
    }

    /// `ℓ_j(σ)` for every j (barycentric formula of the second kind).
    pub fn lagrange(&self, sigma: f64, out: &mut [f64]) {
        #[allow(clippy::float_cmp)] // exactly on a node: the barycentric formula would divide by 0
        let on_node = self.theta.iter().position(|&t| t == sigma);
        if let Some(k) = on_node {
            out.iter_mut().enumerate().for_each(|(j, o)| *o = if j == k { 1.0 } else { 0.0 });
            return;
        }
        let mut sum = 0.0;
        for (j, o) in out.iter_mut().enumerate() {
            *o = self.bary[j] / (sigma - self.theta[j]);
            sum += *o;
        }
        out.iter_mut().for_each(|o| *o /= sum);
    }
}

/// The matrices of one element length (module docs), projected as the collocation needs them.
#[derive(Clone, Debug)]
pub(crate) struct Kernels {
    /// `[C₀ E_1; …; C₀ E_N]` (pN × n).
    pub ce0: DMatrix<f64>,
    /// `[C_d E_1; …; C_d E_N]` (rN × n).
    pub ced: DMatrix<f64>,
    /// `E_{N+1} = e^{A₀ h}` (n × n).
    pub eend: DMatrix<f64>,
    /// `[C₀ W_ij]` (pN × kN).
    pub cw0: DMatrix<f64>,
    /// `[C_d W_ij]` (rN × kN).
    pub cwd: DMatrix<f64>,
    /// `[W_{N+1, j}]` (n × kN).
    pub wend: DMatrix<f64>,
}

impl Kernels {
    /// The kernels of an element of length `h` for `ẋ = A₀x + G v`, outputs `C₀`, `C_d`.
    pub fn new(
        a0: &DMatrix<f64>,
        g: &DMatrix<f64>,
        c0: &DMatrix<f64>,
        cd: &DMatrix<f64>,
        h: f64,
        nodes: &Nodes,
    ) -> Self {
        let (n, k) = g.shape();
        let (p, r) = (c0.nrows(), cd.nrows());
        let nn = nodes.len();
        let quad = GaussLegendre::new(nn / 2 + 10);
        let mut ell = vec![0.0; nn];
        let mut w = DMatrix::<f64>::zeros(n, k * nn); // W_l, l = 0: zero
        let mut e = DMatrix::<f64>::identity(n, n);
        let mut out = Kernels {
            ce0: DMatrix::zeros(p * nn, n),
            ced: DMatrix::zeros(r * nn, n),
            eend: DMatrix::zeros(n, n),
            cw0: DMatrix::zeros(p * nn, k * nn),
            cwd: DMatrix::zeros(r * nn, k * nn),
            wend: DMatrix::zeros(n, k * nn),
        };
        let mut prev = 0.0;
        for l in 0..=nn {
            let th = if l < nn { nodes.theta[l] } else { 1.0 };
            let delta = th - prev;
            let step = (a0 * (h * delta)).exp();
            let mut j_l = DMatrix::<f64>::zeros(n, k * nn);
            for (&s, &wq) in quad.nodes().iter().zip(quad.weights()) {
                let f = (a0 * (h * delta * (1.0 - s))).exp() * g;
                nodes.lagrange(prev + delta * s, &mut ell);
                for (j, &lj) in ell.iter().enumerate() {
                    let c = h * delta * wq * lj;
                    let mut block = j_l.columns_mut(k * j, k);
                    block += &f * c;
                }
            }
            w = &step * &w + j_l;
            e = &step * &e;
            if l < nn {
                out.ce0.rows_mut(p * l, p).copy_from(&(c0 * &e));
                out.ced.rows_mut(r * l, r).copy_from(&(cd * &e));
                out.cw0.rows_mut(p * l, p).copy_from(&(c0 * &w));
                out.cwd.rows_mut(r * l, r).copy_from(&(cd * &w));
            } else {
                out.eend = e.clone();
                out.wend = w.clone();
            }
            prev = th;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lagrange_basis_interpolates_and_sums_to_one() {
        let nodes = Nodes::new(9);
        let mut ell = vec![0.0; 9];
        for sigma in [0.0, 0.13, 0.5, 0.77, 1.0] {
            nodes.lagrange(sigma, &mut ell);
            assert!((ell.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            // degree 8 reproduced exactly
            let f = |x: f64| x.powi(8) - 3.0 * x.powi(3);
            let interp: f64 = (0..9).map(|j| ell[j] * f(nodes.theta[j])).sum();
            assert!((interp - f(sigma)).abs() < 1e-12, "{sigma}: {interp} vs {}", f(sigma));
        }
        nodes.lagrange(nodes.theta[3], &mut ell);
        assert!((ell[3] - 1.0).abs() < f64::EPSILON && ell[2].abs() < f64::EPSILON);
    }

    #[test]
    fn scalar_kernels_are_the_exact_integrals() {
        // a = −2, h = 0.7: W_{end, j} = h ∫₀¹ e^{a h (1 − σ)} ℓ_j(σ) dσ; with Σ_j ℓ_j = 1 their sum
        // is ∫₀^h e^{a(h − s)} ds = (e^{ah} − 1)/a, and with Σ_j θ_j ℓ_j = σ it is
        // ∫₀¹ e^{ah(1−σ)} σ h dσ = (e^{ah} − 1 − ah)/(a² h)
        let (a, h) = (-2.0, 0.7);
        let nodes = Nodes::new(6);
        let one = DMatrix::from_element(1, 1, 1.0);
        let kern = Kernels::new(&DMatrix::from_element(1, 1, a), &one, &one, &one, h, &nodes);
        let e = (a * h).exp();
        assert!((kern.eend[(0, 0)] - e).abs() < 1e-15);
        let sum: f64 = (0..6).map(|j| kern.wend[(0, j)]).sum();
        assert!((sum - (e - 1.0) / a).abs() < 1e-14, "{sum}");
        let lin: f64 = (0..6).map(|j| kern.wend[(0, j)] * nodes.theta[j]).sum();
        assert!((lin - (e - 1.0 - a * h) / (a * a * h)).abs() < 1e-14, "{lin}");
        // at node i: Σ_j W_ij = (e^{a h θ_i} − 1)/a
        for i in 0..6 {
            let s: f64 = (0..6).map(|j| kern.cw0[(i, j)]).sum();
            let ei = (a * h * nodes.theta[i]).exp();
            assert!((s - (ei - 1.0) / a).abs() < 1e-14);
            assert!((kern.ce0[(i, 0)] - ei).abs() < 1e-15);
        }
    }
}
