//! Angle reduction to `[0, 2π)` without the software `fmod`.
//!
//! `x.rem_euclid(2π)` calls `fmod`, which on x86-64 without SSE4.1 is a bit-by-bit loop in
//! software (about 90 instructions for a tool angle of a few thousand radians, once per step
//! in the plant's outputs and once per tooth in the process). [`rem_two_pi`] gives the same
//! bits with a handful of multiplications:
//!
//! ```text
//! q = trunc(x / P)                     (P = 2π as f64; off by at most one for x < 10^15)
//! q·P = h + l exactly                  (Dekker's two-product, Veltkamp splitting, no FMA)
//! r = (x − h) − l                      (x − h exact by Sterbenz's lemma)
//! ```
//!
//! Why `r` is exact: `x ≥ P` is a multiple of `ulp(P)`, so is `x − qP`, and a multiple of
//! `ulp(P)` in `(−P, P)` is a double; the exact value `(x − h) − l` therefore rounds to itself.
//! When the estimate of `q` is one off, `r` lands in `(−P, 0)` or `[P, 2P)` with its sign and
//! its comparison with `P` still exact, and `q` is corrected by one.

use std::f64::consts::PI;

const P: f64 = 2.0 * PI;
/// Veltkamp's splitting constant `2^27 + 1`.
const SPLIT: f64 = 134_217_729.0;
/// Above this the estimate of the quotient may be off by more than one: `fmod` decides.
const LIMIT: f64 = 1e15;

/// The high and low halves of `a` (26 and 27 significant bits), `a = hi + lo` exactly.
#[inline(always)]
fn split(a: f64) -> (f64, f64) {
    let c = SPLIT * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

/// `x − q·P` exactly when that is a remainder of `x` in `(−P, 2P)` (see the module doc).
#[inline(always)]
fn minus_multiple(x: f64, q: f64) -> f64 {
    const PH: f64 = {
        let c = SPLIT * P;
        c - (c - P)
    };
    const PL: f64 = P - PH;
    let h = q * P;
    let (qh, ql) = split(q);
    let l = ((qh * PH - h) + qh * PL + ql * PH) + ql * PL;
    (x - h) - l
}

/// `x.rem_euclid(2π)`, bit for bit, for every `x` (finite `0 ≤ x < 10^15` without `fmod`).
#[inline]
pub fn rem_two_pi(x: f64) -> f64 {
    if !(P..LIMIT).contains(&x) {
        // below P (0 ≤ x < P is its own remainder), negative, huge or not finite
        return if (0.0..P).contains(&x) { x } else { x.rem_euclid(P) };
    }
    let mut q = (x / P) as u64 as f64;
    let mut r = minus_multiple(x, q);
    if r < 0.0 {
        q -= 1.0;
        r = minus_multiple(x, q);
    } else if r >= P {
        q += 1.0;
        r = minus_multiple(x, q);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(x: f64) {
        assert_eq!(rem_two_pi(x).to_bits(), x.rem_euclid(P).to_bits(), "x = {x:e} ({:#x})", x.to_bits());
    }

    /// Random angles over the range of runs (a 300 s run at 24 000 rpm is 7.5·10⁵ rad) and far
    /// beyond, the multiples of P and their neighbours (where the quotient estimate is off by
    /// one), below P, negative, huge and non-finite values: always the bits of `rem_euclid`.
    #[test]
    fn same_bits_as_rem_euclid() {
        let mut s = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..200_000 {
            check(next() * 1e6);
            check(next() * 10f64.powf(16.0 * next()));
        }
        let mut off_by_one = 0;
        for k in 1..20_000u64 {
            let m = k as f64 * P;
            for x in [m, m.next_up(), m.next_down(), m.next_up().next_up(), m.next_down().next_down()] {
                check(x);
                let r = minus_multiple(x, (x / P) as u64 as f64);
                off_by_one += usize::from(!(0.0..P).contains(&r));
            }
        }
        assert!(off_by_one > 100, "the quotient correction was exercised {off_by_one} times");
        for x in [0.0, -0.0, 1e-300, P.next_down(), P, 3.0, -1.0, -P, -1e20, 1e15, 1e15f64.next_down(), 1e300] {
            check(x);
        }
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(rem_two_pi(x).is_nan(), x.rem_euclid(P).is_nan());
        }
    }
}
