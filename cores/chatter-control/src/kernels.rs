//! The dense kernels of the Grünwald–Letnikov operator: the window dot product and the
//! block tail sums.
//!
//! A GL sample is a dot product of `L + 1` taps with the newest `L + 1` samples
//! ([`crate::grunwald`]); a block of [`BLOCK`] samples splits it into a head of `B` taps and a
//! tail that only reads samples older than the block,
//!
//! ```text
//! acc_q = Σ_{j=B..n−1} c_j p_{j−B+q}     (q = 0..B−1, p_m = x_{k−1−m}),
//! ```
//!
//! one Toeplitz matrix–vector product: each tap is broadcast over `B` consecutive samples, one
//! load per multiply–add instead of two. Each kernel has a scalar definition with a fixed
//! summation order ([`dot_fma`], [`block_tail_fma`]: one fused multiply–add per term) that the
//! AVX2 code computes bitwise (run-time detection, a test), and a portable variant without fused
//! multiply–add for other CPUs ([`dot_portable`], [`block_tail_portable`]). The tests compare all
//! of them with the plain sum.

/// Dot product `Σ a_i b_i` of the taps and the window (the whole cost of a GL sample).
///
/// On x86-64 processors with AVX2 and FMA (detected at run time) the sum is taken as defined by
/// [`dot_fma`] (32 fused multiply–add accumulators in eight 256-bit registers); elsewhere by
/// [`dot_portable`] (eight accumulators of `x·y + acc`, which the baseline SSE2 vectorises).
/// Both have a fixed summation order, so a run is reproducible on one machine; the two differ
/// in rounding only (relative 1e-16 per sum; the tests compare both with the direct sum). The
/// fused path is 1.7× faster on the project's machine (`cargo bench -p chatter-control --bench
/// gl_window` prints the ratio).
#[inline]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX2 and FMA (checked just above), the only requirement of
        // `dot_fma_avx2`'s target features.
        return unsafe { dot_fma_avx2(a, b) };
    }
    dot_portable(a, b)
}

/// [`dot`] without fused multiply–add: eight independent accumulators (vectorises on any x86-64).
#[inline]
pub fn dot_portable(a: &[f64], b: &[f64]) -> f64 {
    let ca = a.chunks_exact(8);
    let cb = b.chunks_exact(8);
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    let mut acc = [0.0f64; 8];
    for (x, y) in ca.zip(cb) {
        for i in 0..8 {
            acc[i] += x[i] * y[i];
        }
    }
    ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7])) + tail
}

/// Lanes of [`dot_fma`]: eight 4-wide accumulators (eight fused multiply–adds in flight cover
/// the instruction's latency on current x86-64 cores).
const FMA_LANES: usize = 32;

/// [`dot`] with fused multiply–add, the scalar definition of the AVX2 path: 32 independent
/// accumulators `acc_j = x·y + acc_j` (one rounding per term), reduced as eight 4-wide registers
/// `r_0..r_7` (lane j of register k is `acc_{4k+j}`): `((r0+r4) + (r2+r6)) + ((r1+r5) + (r3+r7))`,
/// then the lanes `(v0+v2) + (v1+v3)`, then the remainder's plain sum. Without hardware FMA
/// `mul_add` is a slow library call, so [`dot`] uses the AVX2 code (bitwise equal to this, a
/// test) only where the CPU has it; this function is for the tests and the bench.
pub fn dot_fma(a: &[f64], b: &[f64]) -> f64 {
    let ca = a.chunks_exact(FMA_LANES);
    let cb = b.chunks_exact(FMA_LANES);
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    let mut acc = [0.0f64; FMA_LANES];
    for (x, y) in ca.zip(cb) {
        for j in 0..FMA_LANES {
            acc[j] = x[j].mul_add(y[j], acc[j]);
        }
    }
    let r = |k: usize, j: usize| acc[4 * k + j];
    let v: [f64; 4] = std::array::from_fn(|j| {
        ((r(0, j) + r(4, j)) + (r(2, j) + r(6, j))) + ((r(1, j) + r(5, j)) + (r(3, j) + r(7, j)))
    });
    ((v[0] + v[2]) + (v[1] + v[3])) + tail
}

/// [`dot_fma`] with AVX2 + FMA instructions (eight `ymm` accumulators), bitwise equal to it.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn dot_fma_avx2(a: &[f64], b: &[f64]) -> f64 {
    use std::arch::x86_64::*;
    let n = a.len().min(b.len());
    let blocks = n / FMA_LANES;
    let mut r = [_mm256_setzero_pd(); 8];
    for i in 0..blocks {
        let xa = &a[i * FMA_LANES..(i + 1) * FMA_LANES];
        let xb = &b[i * FMA_LANES..(i + 1) * FMA_LANES];
        for (k, rk) in r.iter_mut().enumerate() {
            // SAFETY: `xa` and `xb` hold 32 elements, so lanes 4k..4k+4 (k < 8) are in bounds;
            // unaligned loads need no alignment.
            let (va, vb) =
                unsafe { (_mm256_loadu_pd(xa.as_ptr().add(4 * k)), _mm256_loadu_pd(xb.as_ptr().add(4 * k))) };
            *rk = _mm256_fmadd_pd(va, vb, *rk);
        }
    }
    let tail: f64 = a[blocks * FMA_LANES..n].iter().zip(&b[blocks * FMA_LANES..n]).map(|(x, y)| x * y).sum();
    reduce_lanes(r) + tail
}

/// The reduction of [`dot_fma`]'s eight 4-wide accumulators: `((r0+r4) + (r2+r6)) +
/// ((r1+r5) + (r3+r7))`, then the lanes `(v0+v2) + (v1+v3)` (shared by the AVX2 paths).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn reduce_lanes(r: [std::arch::x86_64::__m256d; 8]) -> f64 {
    use std::arch::x86_64::*;
    let t = _mm256_add_pd(
        _mm256_add_pd(_mm256_add_pd(r[0], r[4]), _mm256_add_pd(r[2], r[6])),
        _mm256_add_pd(_mm256_add_pd(r[1], r[5]), _mm256_add_pd(r[3], r[7])),
    );
    let mut v = [0.0f64; 4];
    // SAFETY: `v` holds four f64, the width of the store.
    unsafe { _mm256_storeu_pd(v.as_mut_ptr(), t) };
    (v[0] + v[2]) + (v[1] + v[3])
}

/// The head of a GL sample: [`dot`]`(c, b)` of the first [`BLOCK`] taps with the newest
/// [`BLOCK`] samples, where `b_0 = x` is the sample just stored (`b` = `[x, older…]`, `older`
/// holding at least `BLOCK − 1` samples). The same sum as [`dot`] to the bit; the AVX2 path takes
/// `x` from its register instead of loading the vector that holds the fresh store (a 256-bit load
/// over a 64-bit store still in the store buffer cannot be forwarded and waits for it to reach
/// the cache: half of the head's cost).
#[inline]
pub fn dot_head(c: &[f64], x: f64, older: &[f64]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX2 and FMA (checked just above), the only requirement of
        // `dot_head_avx2`'s target features.
        return unsafe { dot_head_avx2(c, x, older) };
    }
    let mut b = [0.0; BLOCK];
    b[0] = x;
    b[1..].copy_from_slice(&older[..BLOCK - 1]);
    dot_portable(&c[..BLOCK], &b)
}

/// [`dot_head`] with AVX2 + FMA: [`dot_fma_avx2`] over one block of 32 lanes, the first register
/// `[x, b_1, b_2, b_3]` built from `x` and `[b_1..b_4]` (permute and blend); bitwise [`dot_fma`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn dot_head_avx2(c: &[f64], x: f64, older: &[f64]) -> f64 {
    use std::arch::x86_64::*;
    assert!(c.len() >= BLOCK && older.len() >= BLOCK - 1, "dot_head needs a block of taps and samples");
    // SAFETY (all loads): `c` holds at least 32 taps and `older` at least 31 samples (asserted
    // above), so lanes 4k..4k+4 of `c` and `older[4k−1..4k+3]` (k ≥ 1), `older[0..4]` are in bounds.
    let first = unsafe { _mm256_loadu_pd(older.as_ptr()) }; // [b1, b2, b3, b4]
    let first = _mm256_permute4x64_pd::<0b10_01_00_11>(first); // [b4, b1, b2, b3]
    let first = _mm256_blend_pd::<0b0001>(first, _mm256_set1_pd(x)); // [x, b1, b2, b3]
    let mut r = [_mm256_setzero_pd(); 8];
    r[0] = _mm256_fmadd_pd(unsafe { _mm256_loadu_pd(c.as_ptr()) }, first, r[0]);
    for (k, rk) in r.iter_mut().enumerate().skip(1) {
        let (va, vb) =
            unsafe { (_mm256_loadu_pd(c.as_ptr().add(4 * k)), _mm256_loadu_pd(older.as_ptr().add(4 * k - 1))) };
        *rk = _mm256_fmadd_pd(va, vb, *rk);
    }
    reduce_lanes(r)
}

/// Samples per block of the precomputed tail sums (see the module documentation).
pub const BLOCK: usize = 32;

/// The tail sums of one block, scalar definition: with `p` the window before the block's first
/// sample (`p_m = x_{k−1−m}`, at least `c.len() − 1` samples), `acc_q = Σ_{j=B..n−1} c_j p_{j−B+q}`
/// summed in order of `j` with one fused multiply–add per term, for `q = 0..B−1`; the tail of the
/// block's sample `i` is `acc_{B−1−i}`. Without hardware FMA `mul_add` is a slow library call, so
/// [`block_tail`] runs the AVX2 code (bitwise equal, a test) where the CPU has it and
/// [`block_tail_portable`] elsewhere; this function is for the tests.
pub fn block_tail_fma(c: &[f64], p: &[f64], acc: &mut [f64; BLOCK]) {
    *acc = [0.0; BLOCK];
    for (j, &cj) in c.iter().enumerate().skip(BLOCK) {
        let w = &p[j - BLOCK..j];
        for q in 0..BLOCK {
            acc[q] = cj.mul_add(w[q], acc[q]);
        }
    }
}

/// [`block_tail_fma`] without fused multiply–add (`acc + c·p`, two roundings), the path of CPUs
/// without AVX2 + FMA (the inner loop vectorises on any x86-64).
pub fn block_tail_portable(c: &[f64], p: &[f64], acc: &mut [f64; BLOCK]) {
    *acc = [0.0; BLOCK];
    for (j, &cj) in c.iter().enumerate().skip(BLOCK) {
        let w = &p[j - BLOCK..j];
        for q in 0..BLOCK {
            acc[q] += cj * w[q];
        }
    }
}

/// The block's tail sums ([`block_tail_fma`] on CPUs with AVX2 + FMA, else [`block_tail_portable`]).
#[inline]
pub fn block_tail(c: &[f64], p: &[f64], acc: &mut [f64; BLOCK]) {
    assert!(p.len() + 1 >= c.len(), "the window holds the block's tail samples");
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX2 and FMA (checked just above), the only requirement of
        // `block_tail_avx2`'s target features.
        return unsafe { block_tail_avx2(c, p, acc) };
    }
    block_tail_portable(c, p, acc)
}

/// [`block_tail_fma`] with AVX2 + FMA: eight `ymm` accumulators (lanes `4r..4r+3`), one
/// broadcast tap and eight fused multiply–adds with memory operands per tap; bitwise equal to it.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn block_tail_avx2(c: &[f64], p: &[f64], acc: &mut [f64; BLOCK]) {
    use std::arch::x86_64::*;
    let mut r = [_mm256_setzero_pd(); BLOCK / 4];
    for (j, &cj) in c.iter().enumerate().skip(BLOCK) {
        let cv = _mm256_set1_pd(cj);
        let w = p[j - BLOCK..j].as_ptr();
        for (k, rk) in r.iter_mut().enumerate() {
            // SAFETY: `w` points at the B elements `p[j − B .. j]` (bounds-checked slice), and lanes
            // 4k..4k+4 ≤ B of them are read; unaligned loads need no alignment.
            *rk = _mm256_fmadd_pd(cv, unsafe { _mm256_loadu_pd(w.add(4 * k)) }, *rk);
        }
    }
    for (k, rk) in r.iter().enumerate() {
        // SAFETY: `acc[4k .. 4k + 4]` is in bounds (k < B/4).
        unsafe { _mm256_storeu_pd(acc.as_mut_ptr().add(4 * k), *rk) };
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    /// Both dot products (and the dispatched one) against the plain left-to-right sum, for every
    /// length up to 70 (all remainders of the 8- and 32-wide loops) and the default 1001 taps.
    #[test]
    fn dot_products_equal_the_plain_sum() {
        for n in (0..=70).chain([1001]) {
            let a: Vec<f64> = (0..n).map(|i| (-0.5f64).powi(i % 7) / (1.0 + i as f64)).collect();
            let b: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin() * 1e-6).collect();
            let plain: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            let scale: f64 = a.iter().zip(&b).map(|(x, y)| (x * y).abs()).sum::<f64>().max(f64::MIN_POSITIVE);
            for (name, got) in
                [("portable", dot_portable(&a, &b)), ("fma", dot_fma(&a, &b)), ("dispatched", dot(&a, &b))]
            {
                assert!((got - plain).abs() <= 1e-14 * scale, "{name}, n = {n}: {got} vs {plain}");
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
                assert_eq!(dot(&a, &b).to_bits(), dot_fma(&a, &b).to_bits(), "n = {n}: the AVX2 path is dot_fma");
            }
        }
    }

    /// The head with the newest sample from a register is [`dot`] of the stored window, to the
    /// bit (the AVX2 path against [`dot_fma`], the fallback against [`dot_portable`]).
    #[test]
    fn head_equals_the_window_dot_product() {
        for shift in 0..5 {
            let c: Vec<f64> = (0..BLOCK + shift).map(|j| (-0.7f64).powi(j as i32 % 3) / (1.0 + j as f64)).collect();
            let b: Vec<f64> = (0..BLOCK + shift).map(|i| (0.37 * (i + shift) as f64).sin() * 1e-3).collect();
            let got = dot_head(&c, b[0], &b[1..]);
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
                assert_eq!(got.to_bits(), dot_fma(&c[..BLOCK], &b[..BLOCK]).to_bits(), "shift {shift}");
                continue;
            }
            assert_eq!(got.to_bits(), dot_portable(&c[..BLOCK], &b[..BLOCK]).to_bits(), "shift {shift}");
        }
    }

    /// The dispatched tail sums are the scalar definition bitwise on AVX2 + FMA; the portable
    /// sums agree with it to rounding.
    #[test]
    fn block_tails_equal_their_scalar_definition() {
        for n in [BLOCK + 1, BLOCK + 2, 2 * BLOCK + 3, 1001] {
            // any taps: decaying with alternating signs, like the GL weights
            let c: Vec<f64> = (0..n).map(|j| (-0.7f64).powi(j as i32 % 3) / (1.0 + j as f64).powf(1.37)).collect();
            let p: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin() * 1e-6).collect();
            let (mut fma, mut portable, mut dispatched) = ([0.0; BLOCK], [0.0; BLOCK], [0.0; BLOCK]);
            block_tail_fma(&c, &p, &mut fma);
            block_tail_portable(&c, &p, &mut portable);
            block_tail(&c, &p, &mut dispatched);
            for q in 0..BLOCK {
                let terms: Vec<f64> = (BLOCK..n).map(|j| c[j] * p[j - BLOCK + q]).collect();
                let want: f64 = terms.iter().sum();
                let scale: f64 = terms.iter().map(|t| t.abs()).sum::<f64>().max(f64::MIN_POSITIVE);
                assert!((fma[q] - want).abs() <= 1e-14 * scale, "n = {n}, q = {q}");
                assert!((portable[q] - want).abs() <= 1e-14 * scale, "n = {n}, q = {q}");
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
                assert_eq!(
                    fma.map(f64::to_bits),
                    dispatched.map(f64::to_bits),
                    "n = {n}: the AVX2 path is block_tail_fma"
                );
            }
        }
    }
}
