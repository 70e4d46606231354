//! The tail sums of a Grünwald–Letnikov block by uniformly partitioned convolution
//! (overlap-save with a frequency-domain delay line).
//!
//! [`crate::grunwald`] splits each output of a block of `B` samples starting at `x_k` into a
//! head of `B` taps and a tail `T_i = Σ_{j=B..L} c_j x_{k+i−j}` (`i = 0..B−1`) that only reads
//! samples older than `x_k`. Cut the taps into `P = ⌈(L + 1 − B)/B⌉` partitions of `B`,
//! `h_s[m] = c_{sB+m}` (`s = 1..P`, zero beyond `L`), and the tail is a sum of `P` block
//! convolutions:
//!
//! ```text
//! T_i = Σ_{s=1..P} Σ_{m<B} h_s[m] · x_{k−sB+i−m}
//!     = Σ_s (h_s ⊛ v_{b−s})[B + i],    v_{b'} = [X_{b'−1}, X_{b'}]  (2B samples, blocks of B)
//! ```
//!
//! where `⊛` is the circular convolution of length `N = 2B` (the taps padded with `B` zeros: the
//! outputs `B..2B−1` are free of wrap-around, overlap-save). With the real DFT `F` of size `N`,
//!
//! ```text
//! T = last B of  F⁻¹( Σ_{s=1..P} F(h_s) · F(v_{b−s}) )
//! ```
//!
//! `F(h_s)` is computed once; `F(v_{b'})` once per block, when block `b' = b − 1` is complete,
//! and kept for the next `P` blocks (the delay line). Per block: one real FFT, `P·(B + 1)`
//! complex multiply–adds, one inverse real FFT, instead of `B·(L + 1 − B)` multiply–adds.
//!
//! The real FFT of size `N = 2B` is a complex radix-2 FFT of size `B` on `z_n = v_{2n} + i v_{2n+1}`
//! with the split `X_k = E_k + W^k O_k`, `E_k = (Z_k + conj Z_{B−k})/2`,
//! `O_k = (Z_k − conj Z_{B−k})/(2i)`, `W = e^{−2πi/N}` (and its inverse). Twiddles come from the
//! pure-Rust `libm` and the arithmetic is plain IEEE multiply and add in a fixed order (no fused
//! multiply–add), so every platform computes the same bits; the compiler vectorises it (the
//! bit reversal is folded into the loads, the stages of length 2 and 4 use their exact twiddles
//! 1 and −i, the others contiguous per-stage twiddle tables; the partition sums of 8 bins at a
//! time stay in registers over all partitions).
//! Same terms as the direct tail in another order: the rounding differs by ~1e-15 of the terms'
//! magnitudes (tests compare both with the direct sum).

use crate::kernels::BLOCK;
use serde::{Deserialize, Serialize};
use std::sync::LazyLock;

/// Complex FFT size (`B`); the real transform has size `2B`.
const M: usize = BLOCK;
/// Non-redundant bins of the real transform of size `2B`.
pub const BINS: usize = BLOCK + 1;
/// Bins whose partition sums are kept in registers at once (two 4-wide registers per part).
const LANES: usize = 8;
const _: () = assert!(M.is_multiple_of(LANES));
// the FFT's first two stages are written out and the twiddle table starts at the stage of 8
const _: () = assert!(M.is_power_of_two() && M >= 8);

/// Twiddle and permutation tables (the same for every operator).
struct Tables {
    /// The twiddles `e^{−2πij/len}`, `j < len/2`, of the stages `len = 8, 16, …, M`, each stage's
    /// contiguous from offset `len/2 − 4` (real, imaginary parts); the stages 2 and 4 have the
    /// exact twiddles 1 and −i and need none.
    tw_re: [f64; M - 4],
    tw_im: [f64; M - 4],
    /// `e^{−2πik/(2M)}`, k ≤ M.
    s_re: [f64; M + 1],
    s_im: [f64; M + 1],
    /// Bit reversal of `0..M`.
    rev: [usize; M],
}

static TABLES: LazyLock<Tables> = LazyLock::new(|| {
    let bits = M.trailing_zeros();
    let tau = 2.0 * std::f64::consts::PI;
    // entry i belongs to the stage whose offset range holds it: half = the power of two ≤ i + 4
    let twiddle = |i: usize| {
        let half = 1usize << (usize::BITS - 1 - (i + 4).leading_zeros());
        tau * (i + 4 - half) as f64 / (2 * half) as f64
    };
    Tables {
        tw_re: std::array::from_fn(|i| libm::cos(twiddle(i))),
        tw_im: std::array::from_fn(|i| -libm::sin(twiddle(i))),
        s_re: std::array::from_fn(|k| libm::cos(tau * k as f64 / (2 * M) as f64)),
        s_im: std::array::from_fn(|k| -libm::sin(tau * k as f64 / (2 * M) as f64)),
        rev: std::array::from_fn(|k| k.reverse_bits() >> (usize::BITS - bits)),
    }
});

/// In-place forward complex FFT of size `M` of the bit-reversed input (radix 2, decimation in
/// time, split arrays): the stages of length 2 and 4 with their exact twiddles 1 and −i, the
/// others with each stage's twiddles contiguous, so that the butterflies vectorise.
#[inline(always)]
fn fft(re: &mut [f64; M], im: &mut [f64; M], t: &Tables) {
    // the butterfly of `a` and `b` with `x` the twiddled `b`: (a, b) ← (a + x, a − x)
    #[inline(always)]
    fn butterfly(re: &mut [f64; M], im: &mut [f64; M], a: usize, b: usize, (xr, xi): (f64, f64)) {
        re[b] = re[a] - xr;
        im[b] = im[a] - xi;
        re[a] += xr;
        im[a] += xi;
    }
    for a in (0..M).step_by(2) {
        butterfly(re, im, a, a + 1, (re[a + 1], im[a + 1]));
    }
    for a in (0..M).step_by(4) {
        butterfly(re, im, a, a + 2, (re[a + 2], im[a + 2]));
        // (re + i·im)·(−i) = im − i·re
        butterfly(re, im, a + 1, a + 3, (im[a + 3], -re[a + 3]));
    }
    let mut half = 4;
    while half < M {
        let (wr, wi) = (&t.tw_re[half - 4..2 * half - 4], &t.tw_im[half - 4..2 * half - 4]);
        for start in (0..M).step_by(2 * half) {
            let (lo_re, hi_re) = re[start..start + 2 * half].split_at_mut(half);
            let (lo_im, hi_im) = im[start..start + 2 * half].split_at_mut(half);
            for j in 0..half {
                let xr = hi_re[j] * wr[j] - hi_im[j] * wi[j];
                let xi = hi_re[j] * wi[j] + hi_im[j] * wr[j];
                hi_re[j] = lo_re[j] - xr;
                hi_im[j] = lo_im[j] - xi;
                lo_re[j] += xr;
                lo_im[j] += xi;
            }
        }
        half *= 2;
    }
}

/// Real DFT of the `2M` samples `v` (bins `0..=M`).
#[inline(always)]
fn rfft(v: &[f64; 2 * M], out_re: &mut [f64], out_im: &mut [f64], t: &Tables) {
    // z_n = v_{2n} + i v_{2n+1}, loaded in bit-reversed order
    let mut zr: [f64; M] = std::array::from_fn(|n| v[2 * t.rev[n]]);
    let mut zi: [f64; M] = std::array::from_fn(|n| v[2 * t.rev[n] + 1]);
    fft(&mut zr, &mut zi, t);
    // bin k from Z_a, Z_b with a = k mod M, b = (M − k) mod M:
    // E = (Z_a + conj Z_b)/2, O = (Z_a − conj Z_b)/(2i), X_k = E + W^k O
    let bin = |k: usize, a: usize, b: usize| {
        let (er, ei) = (0.5 * (zr[a] + zr[b]), 0.5 * (zi[a] - zi[b]));
        let (or, oi) = (0.5 * (zi[a] + zi[b]), -0.5 * (zr[a] - zr[b]));
        (er + (t.s_re[k] * or - t.s_im[k] * oi), ei + (t.s_re[k] * oi + t.s_im[k] * or))
    };
    (out_re[0], out_im[0]) = bin(0, 0, 0);
    (out_re[M], out_im[M]) = bin(M, 0, 0);
    for k in 1..M {
        (out_re[k], out_im[k]) = bin(k, k, M - k);
    }
}

/// Inverse of [`rfft`]: the `2M` real samples of the Hermitian spectrum `x` (bins `0..=M`).
#[inline(always)]
fn irfft(x_re: &[f64], x_im: &[f64], v: &mut [f64; 2 * M], t: &Tables) {
    let mut zr = [0.0; M];
    let mut zi = [0.0; M];
    for k in 0..M {
        // E = (X_k + conj X_{M−k})/2, O = (X_k − conj X_{M−k}) · conj(W^k)/2, Z = E + iO,
        // conjugated for the inverse by the forward transform
        let (er, ei) = (0.5 * (x_re[k] + x_re[M - k]), 0.5 * (x_im[k] - x_im[M - k]));
        let (dr, di) = (0.5 * (x_re[k] - x_re[M - k]), 0.5 * (x_im[k] + x_im[M - k]));
        let (or, oi) = (dr * t.s_re[k] + di * t.s_im[k], di * t.s_re[k] - dr * t.s_im[k]);
        zr[t.rev[k]] = er - oi;
        zi[t.rev[k]] = -(ei + or);
    }
    fft(&mut zr, &mut zi, t);
    let scale = 1.0 / M as f64;
    for n in 0..M {
        v[2 * n] = zr[n] * scale;
        v[2 * n + 1] = -zi[n] * scale;
    }
}

/// The partitioned tail of one Grünwald–Letnikov operator: the taps' spectra and the delay line
/// of the input blocks' spectra.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PartitionedTail {
    /// `F(h_s)`, s = 1..P: `P` rows of `BINS` real parts then `BINS` imaginary parts.
    taps: Vec<f64>,
    /// `F(v_{b'})` of the last `P` blocks, same layout, newest at `newest`.
    line: Vec<f64>,
    newest: usize,
}

impl PartitionedTail {
    /// The tail of the taps `c` (`c.len() > B`).
    pub fn new(c: &[f64]) -> Self {
        assert!(c.len() > BLOCK, "a tail needs more than one block of taps");
        let p = (c.len() - BLOCK).div_ceil(BLOCK);
        let t = &*TABLES;
        let mut taps = vec![0.0; 2 * BINS * p];
        for (s, row) in taps.chunks_exact_mut(2 * BINS).enumerate() {
            let mut h = [0.0; 2 * M];
            for (m, hm) in h.iter_mut().take(BLOCK).enumerate() {
                *hm = c.get((s + 1) * BLOCK + m).copied().unwrap_or(0.0);
            }
            let (re, im) = row.split_at_mut(BINS);
            rfft(&h, re, im, t);
        }
        PartitionedTail { line: vec![0.0; taps.len()], taps, newest: 0 }
    }

    /// Partitions `P`.
    pub fn partitions(&self) -> usize {
        self.taps.len() / (2 * BINS)
    }

    /// A restored tail: the taps' spectra `fresh` has, a delay line of their size, finite.
    pub(crate) fn check(&self, fresh: &Self) -> Result<(), String> {
        crate::restored::same("partitioned tail spectra", &self.taps, &fresh.taps)?;
        if self.line.len() != fresh.line.len() || self.newest >= self.partitions() {
            return Err("partitioned tail delay line does not match the memory length".into());
        }
        crate::restored::finite("partitioned tail delay line", &self.line)
    }

    /// Clear the delay line.
    pub fn reset(&mut self) {
        self.line.iter_mut().for_each(|x| *x = 0.0);
        self.newest = 0;
    }

    /// At the start of a block: take in the newest two blocks `p[0..2B]` (`p_m = x_{k−1−m}`, the
    /// window before the block's first sample) and write the block's tail sums into `acc` in the
    /// order of [`crate::kernels::block_tail_fma`] (`acc_{B−1−i}` is sample `i`'s).
    pub fn block(&mut self, p: &[f64], acc: &mut [f64; BLOCK]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above), the only requirement of the
            // function's target feature; the arithmetic is the same (no FMA), so are the bits.
            return unsafe { self.block_avx2(p, acc) };
        }
        self.block_portable(p, acc)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn block_avx2(&mut self, p: &[f64], acc: &mut [f64; BLOCK]) {
        self.block_body(p, acc)
    }

    fn block_portable(&mut self, p: &[f64], acc: &mut [f64; BLOCK]) {
        self.block_body(p, acc)
    }

    #[inline(always)]
    fn block_body(&mut self, p: &[f64], acc: &mut [f64; BLOCK]) {
        let t = &*TABLES;
        let np = self.partitions();
        // v = [X_{b−2}, X_{b−1}] in time order
        let v: [f64; 2 * M] = std::array::from_fn(|i| p[2 * M - 1 - i]);
        self.newest = if self.newest + 1 == np { 0 } else { self.newest + 1 };
        let row = &mut self.line[2 * BINS * self.newest..2 * BINS * (self.newest + 1)];
        let (re, im) = row.split_at_mut(BINS);
        rfft(&v, re, im, t);
        // Σ_s F(h_s)·F(v_{b−s}): partition s (0-based) meets the spectrum s blocks older. Each
        // bin sums over s in order; the bins go in groups of `LANES` whose sums stay in registers
        // over all partitions (one pass over the spectra per group instead of a load and a store
        // of every sum per partition).
        let (mut ar, mut ai) = ([0.0; BINS], [0.0; BINS]);
        for g in (0..M).step_by(LANES) {
            let (mut sr, mut si) = ([0.0; LANES], [0.0; LANES]);
            let mut slot = self.newest;
            for s in 0..np {
                let h = &self.taps[2 * BINS * s..2 * BINS * (s + 1)];
                let x = &self.line[2 * BINS * slot..2 * BINS * (slot + 1)];
                let hr: &[f64; LANES] = h[g..g + LANES].try_into().expect("a group of bins");
                let hi: &[f64; LANES] = h[BINS + g..BINS + g + LANES].try_into().expect("a group of bins");
                let xr: &[f64; LANES] = x[g..g + LANES].try_into().expect("a group of bins");
                let xi: &[f64; LANES] = x[BINS + g..BINS + g + LANES].try_into().expect("a group of bins");
                for q in 0..LANES {
                    sr[q] += hr[q] * xr[q] - hi[q] * xi[q];
                    si[q] += hr[q] * xi[q] + hi[q] * xr[q];
                }
                slot = if slot == 0 { np - 1 } else { slot - 1 };
            }
            ar[g..g + LANES].copy_from_slice(&sr);
            ai[g..g + LANES].copy_from_slice(&si);
        }
        // the Nyquist bin (M)
        let mut slot = self.newest;
        for s in 0..np {
            let (h, x) = (&self.taps[2 * BINS * s..], &self.line[2 * BINS * slot..]);
            ar[M] += h[M] * x[M] - h[BINS + M] * x[BINS + M];
            ai[M] += h[M] * x[BINS + M] + h[BINS + M] * x[M];
            slot = if slot == 0 { np - 1 } else { slot - 1 };
        }
        let mut y = [0.0; 2 * M];
        irfft(&ar, &ai, &mut y, t);
        for i in 0..BLOCK {
            acc[BLOCK - 1 - i] = y[BLOCK + i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The real FFT against the direct DFT, and its inverse against the samples.
    #[test]
    fn real_fft_is_the_dft_and_inverts() {
        let t = &*TABLES;
        let v: [f64; 2 * M] = std::array::from_fn(|i| (0.37 * i as f64).sin() + 0.1 * (i % 5) as f64);
        let (mut re, mut im) = ([0.0; BINS], [0.0; BINS]);
        rfft(&v, &mut re, &mut im, t);
        let n = 2 * M;
        for k in 0..BINS {
            let (mut dr, mut di) = (0.0, 0.0);
            for (j, x) in v.iter().enumerate() {
                let a = -2.0 * std::f64::consts::PI * (k * j) as f64 / n as f64;
                dr += x * a.cos();
                di += x * a.sin();
            }
            assert!(
                (re[k] - dr).abs() < 1e-12 && (im[k] - di).abs() < 1e-12,
                "bin {k}: {} {} vs {dr} {di}",
                re[k],
                im[k]
            );
        }
        let mut back = [0.0; 2 * M];
        irfft(&re, &im, &mut back, t);
        for (a, b) in back.iter().zip(&v) {
            assert!((a - b).abs() < 1e-14, "{a} vs {b}");
        }
    }

    /// Block tails against the direct tails ([`crate::kernels::block_tail_fma`]) over a stream
    /// of blocks, for partition counts 1, 2, 3 and the default memory, to 1e-13 of the tail's
    /// bound `Σ|c_j|·max|x|`; and the AVX2 and portable paths give the same bits.
    #[test]
    fn partitioned_tails_equal_direct_tails() {
        use crate::kernels::block_tail_fma;
        for n in [BLOCK + 1, 2 * BLOCK, 2 * BLOCK + 1, 3 * BLOCK + 7, 1001] {
            // any taps: decaying with alternating signs, like the GL weights
            let c: Vec<f64> = (0..n).map(|j| (-0.8f64).powi(j as i32 % 4) / (1.0 + j as f64).powf(1.154)).collect();
            let mut fast = PartitionedTail::new(&c);
            let mut portable = fast.clone();
            let len = n.max(2 * BLOCK);
            let xs: Vec<f64> =
                (0..len + 9 * BLOCK).map(|k| (0.05 * k as f64).sin() + 0.2 * (0.013 * k as f64).cos()).collect();
            for b in 0..xs.len() / BLOCK {
                // the window before the block starting at k = bB: p_m = x_{k−1−m} (zeros before 0)
                let k = b * BLOCK;
                let p: Vec<f64> = (0..len).map(|m| if m < k { xs[k - 1 - m] } else { 0.0 }).collect();
                let (mut got, mut want, mut other) = ([0.0; BLOCK], [0.0; BLOCK], [0.0; BLOCK]);
                fast.block(&p, &mut got);
                portable.block_portable(&p, &mut other);
                block_tail_fma(&c, &p, &mut want);
                // the FFT's rounding scales with the norms of the taps and the samples it
                // transforms (the overlap block included), not with one output's terms
                let scale = c[BLOCK..].iter().map(|x| x.abs()).sum::<f64>()
                    * p[..2 * BLOCK].iter().fold(0.0f64, |a, x| a.max(x.abs()));
                for q in 0..BLOCK {
                    assert!(
                        (got[q] - want[q]).abs() <= 1e-13 * scale,
                        "n = {n}, block {b}, q = {q}: {} vs {}",
                        got[q],
                        want[q]
                    );
                    assert_eq!(got[q].to_bits(), other[q].to_bits(), "n = {n}: AVX2 and portable differ");
                }
            }
        }
    }
}
