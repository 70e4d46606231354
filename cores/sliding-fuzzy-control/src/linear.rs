//! Exact zero-order-hold discretisation of one axis `m ẍ + c ẋ + k x = u`.
//!
//! With `V = (x, ẋ)`, `A = [[0, 1], [−k/m, −c/m]]`, `B = (0, 1/m)` and `u` held over a sample
//! period `T`, `V(k+1) = A_d V(k) + B_d u(k)` with `A_d = e^{AT}` and `B_d = ∫₀ᵀ e^{As} ds B`
//! (seed 003, Eqs. 19–21). Both come from one exponential of the augmented matrix
//! `exp([[A, B], [0, 0]] T) = [[A_d, B_d], [0, 1]]`, computed by scaling and squaring with a
//! Taylor series ([`zoh`]); [`zoh_reference`] integrates the ODE with many RK4 steps (the slow
//! reference the fast path is tested against).

/// The discretised axis: `V(k+1) = a V(k) + b u(k)`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Discrete {
    /// `A_d`, row-major.
    pub a: [[f64; 2]; 2],
    /// `B_d`.
    pub b: [f64; 2],
}

fn mul3(p: &[[f64; 3]; 3], q: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|l| p[i][l] * q[l][j]).sum()))
}

/// Exact ZOH discretisation of `m ẍ + c ẋ + k x = u` over `t` (augmented matrix exponential).
pub fn zoh(m: f64, c: f64, k: f64, t: f64) -> Discrete {
    let mut g = [[0.0, t, 0.0], [-k / m * t, -c / m * t, t / m], [0.0; 3]];
    let norm = g.iter().map(|r| r.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max);
    let squarings = if norm > 0.5 { (norm / 0.5).log2().ceil() as i32 } else { 0 };
    let scale = 0.5f64.powi(squarings);
    for r in g.iter_mut() {
        for x in r.iter_mut() {
            *x *= scale;
        }
    }
    // Taylor series of exp(g), ‖g‖ ≤ 0.5: 20 terms are below rounding
    let mut e = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut term = e;
    for n in 1..=20 {
        term = mul3(&term, &g);
        for r in term.iter_mut() {
            for x in r.iter_mut() {
                *x /= n as f64;
            }
        }
        for (er, tr) in e.iter_mut().zip(&term) {
            for (x, t) in er.iter_mut().zip(tr) {
                *x += t;
            }
        }
    }
    for _ in 0..squarings {
        e = mul3(&e, &e);
    }
    Discrete { a: [[e[0][0], e[0][1]], [e[1][0], e[1][1]]], b: [e[0][2], e[1][2]] }
}

/// Slow reference: the same map by `n` classical RK4 steps of the ODE (columns of `A_d` from
/// unit initial states, `B_d` from a unit held input).
pub fn zoh_reference(m: f64, c: f64, k: f64, t: f64, n: usize) -> Discrete {
    let run = |v0: [f64; 2], u: f64| -> [f64; 2] {
        let f = |v: [f64; 2]| [v[1], (u - c * v[1] - k * v[0]) / m];
        let h = t / n as f64;
        let mut v = v0;
        for _ in 0..n {
            let k1 = f(v);
            let k2 = f([v[0] + 0.5 * h * k1[0], v[1] + 0.5 * h * k1[1]]);
            let k3 = f([v[0] + 0.5 * h * k2[0], v[1] + 0.5 * h * k2[1]]);
            let k4 = f([v[0] + h * k3[0], v[1] + h * k3[1]]);
            v = std::array::from_fn(|i| v[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
        }
        v
    };
    let c0 = run([1.0, 0.0], 0.0);
    let c1 = run([0.0, 1.0], 0.0);
    let b = run([0.0, 0.0], 1.0);
    Discrete { a: [[c0[0], c1[0]], [c0[1], c1[1]]], b }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrix_exponential_matches_fine_rk4() {
        // Table 1, x and y axes, at the sample period 1e-4 s and at a long period (squarings)
        for (m, c, k) in [(20.0, 1200.0, 7.2e6), (20.0, 4300.0, 6.48e7)] {
            for t in [1e-4, 5e-3] {
                let d = zoh(m, c, k, t);
                let r = zoh_reference(m, c, k, t, 20_000);
                // scales: a[0][1] in s, a[1][0] in 1/s; b = (T²/m, T/m) in size
                let tol = [[1e-10, 1e-10 * t], [1e-10 / t, 1e-10]];
                for ((dr, rr), tr) in d.a.iter().zip(&r.a).zip(&tol) {
                    for ((x, y), e) in dr.iter().zip(rr).zip(tr) {
                        assert!((x - y).abs() < *e, "A_d entry {x} vs {y}");
                    }
                }
                for ((x, y), s) in d.b.iter().zip(&r.b).zip([t * t / m, t / m]) {
                    assert!((x - y).abs() < 1e-10 * s, "B_d entry {x} vs {y}");
                }
            }
        }
    }

    #[test]
    fn small_period_limit() {
        // b ≈ (T²/2m, T/m) for T → 0
        let d = zoh(20.0, 1200.0, 7.2e6, 1e-7);
        assert!((d.b[0] / (1e-14 / 40.0) - 1.0).abs() < 1e-5);
        assert!((d.b[1] / (1e-7 / 20.0) - 1.0).abs() < 1e-5);
    }
}
