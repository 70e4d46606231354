//! The multipliers of largest modulus of a monodromy operator given only by its action on a
//! vector (the product form: one period of steps or elements), without forming the matrix.
//!
//! # Arnoldi
//!
//! The Krylov basis `V = [v₁ … v_j]` of `v₁, Φv₁, Φ²v₁, …` (modified Gram–Schmidt, repeated once)
//! and the Hessenberg matrix `H_j = Vᵀ Φ V` satisfy `Φ V_j = V_j H_j + h_{j+1,j} v_{j+1} e_jᵀ`.
//! Every few steps (from `j = 10`) the eigenvalues of `H_j` (dense Schur, small) are the Ritz
//! values; a Ritz pair `(μ, V y)` has the residual `‖Φ V y − μ V y‖ = |h_{j+1,j}| |y_j|` (‖y‖ = 1).
//! The iteration stops when every Ritz value of modulus `≥ 0.9 |μ₁|` has a residual below
//! `tol·|μ₁|`. A monodromy operator is compact with eigenvalues that decay fast (a delayed
//! second-order structure: like `1/k²`), so a few tens of steps give ρ to 1e-10 (tested against
//! the dense eigenvalues). If `max_basis` steps do not suffice the iteration restarts from the
//! real and imaginary parts of the wanted Ritz vectors, summed.
//!
//! An exact breakdown (`h_{j+1,j} ≈ 0`: an invariant subspace) continues from a fresh
//! pseudo-random direction; the Arnoldi relation still holds with that subdiagonal zero.
//!
//! # Warm start
//!
//! The leading Ritz vector of the last call (real plus imaginary part) is kept; the next call on
//! an operator of the same dimension (the next depth of a scan, the next speed) starts from it
//! plus a fixed pseudo-random vector of 30 % of its norm, so that an eigenvalue new at this
//! depth (a flip multiplier) still has a component to grow from. The pseudo-random vectors come
//! from a fixed seed: results depend only on the sequence of calls.
//!
//! # Workspace
//!
//! Basis vectors are kept in a pool and reused; a product `Φ v` writes into a pooled vector, so a
//! call allocates nothing per product once the pool is warm.

use crate::StabilityError;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// Settings and warm-start state of the Arnoldi iteration (module docs).
#[derive(Clone, Debug)]
pub struct Krylov {
    /// Largest basis before a restart.
    pub max_basis: usize,
    /// Relative residual tolerance (of `|μ₁|`).
    pub tol: f64,
    /// Products at most per call.
    pub max_products: usize,
    warm: Vec<f64>,
    v: Vec<Vec<f64>>,
    pool: Vec<Vec<f64>>,
}

/// The result: the Ritz values (largest modulus first) and the products used.
#[derive(Clone, Debug, PartialEq)]
pub struct Dominant {
    /// Ritz values, largest modulus first; the leading ones converged.
    pub values: Vec<Complex64>,
    /// Products `Φ v` computed.
    pub products: usize,
}

impl Default for Krylov {
    fn default() -> Self {
        Krylov { max_basis: 60, tol: 1e-10, max_products: 2000, warm: Vec::new(), v: Vec::new(), pool: Vec::new() }
    }
}

/// A fixed-seed generator of vectors with entries in (−½, ½).
struct Random(u64);

impl Random {
    fn fill(&mut self, x: &mut [f64]) {
        for v in x {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            *v = (self.0 >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        }
    }
}

impl Krylov {
    /// Forget the warm start.
    pub fn reset(&mut self) {
        self.warm.clear();
    }

    fn take(&mut self, dim: usize) -> Vec<f64> {
        let mut v = self.pool.pop().unwrap_or_default();
        v.clear();
        v.resize(dim, 0.0);
        v
    }

    fn recycle(&mut self) {
        let old = std::mem::take(&mut self.v);
        self.pool.extend(old);
    }

    /// The leading multipliers of the operator `op` (`op(v, out)`: `out = Φ v`) of dimension
    /// `dim` (module docs).
    pub fn dominant(&mut self, dim: usize, op: &mut dyn FnMut(&[f64], &mut [f64])) -> Result<Dominant, StabilityError> {
        if dim == 0 {
            return Err(StabilityError::Invalid("empty operator".into()));
        }
        let mut rng = Random(0x2545_f491_4f6c_dd1d);
        let mut start = self.take(dim);
        rng.fill(&mut start);
        if self.warm.len() == dim {
            let (nw, nr) = (norm(&self.warm), norm(&start));
            if nw > 0.0 && nw.is_finite() {
                for (s, w) in start.iter_mut().zip(&self.warm) {
                    *s = 0.3 * *s / nr + w / nw;
                }
            }
        }
        let max_basis = self.max_basis.min(dim).max(2);
        let mut products = 0;
        let mut next = Some(start);
        while let Some(mut start) = next.take() {
            self.recycle();
            let ns = norm(&start);
            start.iter_mut().for_each(|x| *x /= ns);
            self.v.push(start);
            let mut h = DMatrix::<f64>::zeros(max_basis + 1, max_basis);
            let mut scale: f64 = 0.0;
            for j in 0..max_basis {
                let mut w = self.take(dim);
                op(&self.v[j], &mut w);
                products += 1;
                if w.iter().any(|x| !x.is_finite()) {
                    return Err(StabilityError::Invalid("the monodromy operator produced non-finite values".into()));
                }
                let nw0 = norm(&w);
                for _ in 0..2 {
                    for (i, b) in self.v.iter().enumerate() {
                        let c = dot(b, &w);
                        h[(i, j)] += c;
                        w.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
                    }
                }
                let mut nw = norm(&w);
                scale = scale.max(nw0);
                if nw <= 1e-12 * scale {
                    // invariant subspace: a fresh direction, the subdiagonal stays zero
                    rng.fill(&mut w);
                    for _ in 0..2 {
                        for b in &self.v {
                            let c = dot(b, &w);
                            w.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
                        }
                    }
                    nw = norm(&w);
                    h[(j + 1, j)] = 0.0;
                } else {
                    h[(j + 1, j)] = nw;
                }
                w.iter_mut().for_each(|x| *x /= nw);
                let m = j + 1;
                if m == dim || (m >= 10.min(dim) && (m % 4 == 2 || m == max_basis)) {
                    let hm = h.view((0, 0), (m, m)).into_owned();
                    let ev = crate::sd::eigenvalues_unshifted_first(&hm)?;
                    let mu1 = ev[0].norm();
                    let beta = if m == dim { 0.0 } else { h[(m, j)] };
                    let mut converged = true;
                    let mut lead: Option<DVector<Complex64>> = None;
                    for &mu in ev.iter().take_while(|z| z.norm() >= 0.9 * mu1) {
                        let y = ritz_vector(&hm, mu);
                        if lead.is_none() {
                            lead = Some(y.clone());
                        }
                        if beta * y[m - 1].norm() > self.tol * mu1 {
                            converged = false;
                        }
                    }
                    let lead = lead.expect("at least the leading Ritz value");
                    if converged || m == dim || products >= self.max_products {
                        if !converged && m < dim {
                            return Err(StabilityError::Eigen { dim });
                        }
                        self.pool.push(w);
                        self.warm = self.combine(&lead);
                        return Ok(Dominant { values: ev, products });
                    }
                    if m == max_basis {
                        // explicit restart from the leading Ritz vector
                        self.pool.push(w);
                        next = Some(self.combine(&lead));
                        break;
                    }
                }
                self.v.push(w);
            }
        }
        Err(StabilityError::Eigen { dim })
    }

    /// `V (Re y + Im y)`.
    fn combine(&mut self, y: &DVector<Complex64>) -> Vec<f64> {
        let dim = self.v[0].len();
        let mut x = self.take(dim);
        for (k, yk) in y.iter().enumerate().take(self.v.len()) {
            let c = yk.re + yk.im;
            x.iter_mut().zip(&self.v[k]).for_each(|(a, b)| *a += c * b);
        }
        x
    }
}

/// A unit eigenvector of the small matrix `h` for its eigenvalue `mu` (two steps of inverse
/// iteration from a fixed vector, the shift moved off `mu` by a relative 1e-10).
fn ritz_vector(h: &DMatrix<f64>, mu: Complex64) -> DVector<Complex64> {
    let m = h.nrows();
    let shift = mu + Complex64::new(1e-10, 1e-10) * mu.norm().max(1e-300);
    let a = DMatrix::from_fn(m, m, |i, j| Complex64::from(h[(i, j)]) - if i == j { shift } else { 0.0.into() });
    let lu = a.lu();
    let mut y = DVector::from_fn(m, |i, _| Complex64::new(1.0 + 0.1 * i as f64, 0.3 - 0.01 * i as f64));
    y /= Complex64::from(y.norm());
    for _ in 0..2 {
        match lu.solve(&y) {
            Some(z) if z.iter().all(|c| c.re.is_finite() && c.im.is_finite()) && z.norm() > 0.0 => {
                let nz = z.norm();
                y = z / Complex64::from(nz);
            }
            _ => break,
        }
    }
    y
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dominant pair of modulus 0.98, a real −0.97, a tail decaying like 1/k², under a fixed
    /// non-orthogonal similarity.
    fn matrix(dim: usize) -> DMatrix<f64> {
        with_last(dim, None)
    }

    /// The same with the last diagonal entry (before the similarity) replaced.
    fn with_last(dim: usize, last: Option<f64>) -> DMatrix<f64> {
        let mut a = DMatrix::<f64>::zeros(dim, dim);
        let (r, t) = (0.98f64, 1.1f64);
        a[(0, 0)] = r * t.cos();
        a[(0, 1)] = -r * t.sin();
        a[(1, 0)] = r * t.sin();
        a[(1, 1)] = r * t.cos();
        a[(2, 2)] = -0.97;
        for k in 3..dim {
            a[(k, k)] = 0.9 / ((k - 1) as f64).powi(2) * if k % 2 == 0 { 1.0 } else { -1.0 };
        }
        if let Some(v) = last {
            a[(dim - 1, dim - 1)] = v;
        }
        let mut s = DMatrix::<f64>::identity(dim, dim);
        for k in 0..dim - 1 {
            s[(k, k + 1)] = 0.5;
        }
        let si = s.clone().try_inverse().unwrap();
        &s * a * si
    }

    fn solve(a: &DMatrix<f64>, k: &mut Krylov) -> Dominant {
        let mut op = |x: &[f64], y: &mut [f64]| {
            let r = a * DVector::from_column_slice(x);
            y.copy_from_slice(r.as_slice());
        };
        k.dominant(a.nrows(), &mut op).unwrap()
    }

    #[test]
    fn finds_the_dominant_multipliers_of_a_non_normal_matrix() {
        let a = matrix(200);
        let mut k = Krylov::default();
        let d = solve(&a, &mut k);
        assert!((d.values[0].norm() - 0.98).abs() < 1e-9, "{:?}", &d.values[..3]);
        assert!((d.values[0].arg().abs() - 1.1).abs() < 1e-9);
        assert!((d.values[2] + 0.97).norm() < 1e-9, "{:?}", &d.values[..3]);
        let dense = crate::sd::eigenvalues(&a).unwrap();
        assert!((dense[0].norm() - d.values[0].norm()).abs() < 1e-9);
        // the warm start: the same operator again needs no more products
        let again = solve(&a, &mut k);
        assert!(again.products <= d.products, "{} vs {}", again.products, d.products);
        assert!((again.values[0].norm() - 0.98).abs() < 1e-9);
    }

    #[test]
    fn a_new_dominant_eigenvalue_is_found_after_a_warm_start() {
        // warm start on a matrix whose leading pair is 0.98, then one where a real −1.05 (a flip
        // multiplier) appears in a direction the warm vector does not contain
        let a = matrix(150);
        let mut k = Krylov::default();
        solve(&a, &mut k);
        let b = with_last(150, Some(-1.05));
        let d = solve(&b, &mut k);
        assert!((d.values[0] + 1.05).norm() < 1e-9, "{:?}", &d.values[..3]);
    }

    #[test]
    fn a_small_operator_is_solved_exactly() {
        let a = matrix(12);
        let d = solve(&a, &mut Krylov::default());
        assert!((d.values[0].norm() - 0.98).abs() < 1e-10);
        assert!(d.products <= 12);
    }
}
