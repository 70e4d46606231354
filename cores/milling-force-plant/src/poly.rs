//! # Polynomials (descending powers of z)
//!
//! Products, roots (closed form up to degree 2, companion-matrix eigenvalues above) and the
//! Diophantine equation of the pole-placement design,
//!
//! ```text
//! A R₁ + b₀ S = A_c,   A monic of degree n, A_c monic of degree n_c ≥ n,
//! R₁ monic of degree n_c − n,  deg S ≤ n − 1,
//! ```
//!
//! which is a square linear system in the `n_c − n` free coefficients of `R₁` and the `n`
//! coefficients of `S` (unique when `b₀ ≠ 0`: `b₀` is a constant, coprime with any `A`).

use crate::ForceError;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// `a · b`.
pub fn mul(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut c = vec![0.0; a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            c[i + j] += x * y;
        }
    }
    c
}

/// The roots of `p` (`p[0] ≠ 0`).
pub fn roots(p: &[f64]) -> Vec<Complex64> {
    let d = p.len() - 1;
    match d {
        0 => Vec::new(),
        1 => vec![Complex64::new(-p[1] / p[0], 0.0)],
        2 => {
            let (a, b, c) = (p[0], p[1], p[2]);
            let disc = b * b - 4.0 * a * c;
            if disc >= 0.0 {
                // the root of larger modulus without cancellation, the other by Vieta
                let q = -0.5 * (b + b.signum() * disc.sqrt());
                if q == 0.0 {
                    return vec![Complex64::new(0.0, 0.0); 2];
                }
                vec![Complex64::new(q / a, 0.0), Complex64::new(c / q, 0.0)]
            } else {
                let re = -b / (2.0 * a);
                let im = (-disc).sqrt() / (2.0 * a);
                vec![Complex64::new(re, im), Complex64::new(re, -im)]
            }
        }
        _ => {
            let mut m = DMatrix::<f64>::zeros(d, d);
            for j in 0..d {
                m[(0, j)] = -p[j + 1] / p[0];
            }
            for i in 1..d {
                m[(i, i - 1)] = 1.0;
            }
            m.complex_eigenvalues().iter().copied().collect()
        }
    }
}

/// Solves `A R₁ + b₀ S = A_c` for monic `R₁` (degree `deg A_c − deg A`) and `S` (degree
/// `deg A − 1`, returned with `deg A` coefficients).
pub fn diophantine(a: &[f64], b0: f64, ac: &[f64]) -> Result<(Vec<f64>, Vec<f64>), ForceError> {
    let n = a.len() - 1;
    let nc = ac.len() - 1;
    if nc < n || n == 0 {
        return Err(ForceError::Design(format!("degrees: deg A = {n}, deg A_c = {nc}")));
    }
    if !(b0.is_finite() && b0 != 0.0) {
        return Err(ForceError::Design(format!("b0 = {b0}")));
    }
    let nr = nc - n;
    // unknowns x = [r_1..r_nr, s_0..s_{n-1}], equations: coefficients of z^{nc-1} .. z^0
    let mut m = DMatrix::<f64>::zeros(nc, nc);
    let mut rhs = DVector::<f64>::zeros(nc);
    // A · z^{nr} (the monic part of R₁) moved to the right-hand side
    for e in 0..nc {
        let power_index = e + 1; // index into ac (descending): coefficient of z^{nc-1-e}
        let mut known = 0.0;
        // A R₁: coefficient index i+j with i in A, j in R₁ (R₁[0] = 1)
        if power_index < a.len() {
            known += a[power_index];
        }
        rhs[e] = ac[power_index] - known;
        for j in 1..=nr {
            // R₁[j] contributes a[power_index - j]
            if power_index >= j && power_index - j < a.len() {
                m[(e, j - 1)] = a[power_index - j];
            }
        }
        // b₀ S: S has n coefficients, S[k] multiplies z^{n-1-k}, i.e. index nc-(n-1-k) in A_c
        for k in 0..n {
            if power_index == nc - (n - 1 - k) {
                m[(e, nr + k)] = b0;
            }
        }
    }
    let x = m.lu().solve(&rhs).ok_or_else(|| ForceError::Design("singular Diophantine system".into()))?;
    let mut r1 = vec![1.0];
    r1.extend(x.iter().take(nr));
    let s = x.iter().skip(nr).copied().collect();
    Ok((r1, s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diophantine_solution_satisfies_the_equation() {
        let a = [1.0, -0.7, 0.1];
        let ac = [1.0, -1.2, 0.5, 0.03, -0.01];
        let b0 = 2.5;
        let (r1, s) = diophantine(&a, b0, &ac).unwrap();
        assert_eq!(r1.len(), 3);
        assert_eq!(s.len(), 2);
        let mut lhs = mul(&a, &r1);
        let off = lhs.len() - s.len();
        for (i, x) in s.iter().enumerate() {
            lhs[off + i] += b0 * x;
        }
        for (l, r) in lhs.iter().zip(ac.iter()) {
            assert!((l - r).abs() < 1e-13, "{lhs:?} vs {ac:?}");
        }
    }

    #[test]
    fn roots_of_known_polynomials() {
        let r = roots(&[2.0, -3.0, 1.0]); // 2(z − 1)(z − 0.5)
        let mut re: Vec<f64> = r.iter().map(|z| z.re).collect();
        re.sort_by(f64::total_cmp);
        assert!((re[0] - 0.5).abs() < 1e-15 && (re[1] - 1.0).abs() < 1e-15);
        let r = roots(&[1.0, -6.0, 11.0, -6.0]);
        let mut re: Vec<f64> = r.iter().map(|z| z.re).collect();
        re.sort_by(f64::total_cmp);
        for (x, e) in re.iter().zip([1.0, 2.0, 3.0]) {
            assert!((x - e).abs() < 1e-12);
        }
    }
}
