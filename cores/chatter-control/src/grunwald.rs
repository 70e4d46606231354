//! Grünwald–Letnikov fractional operator with short memory.
//!
//! The Grünwald–Letnikov (GL) derivative of order α (α < 0: integral of order −α) of a
//! signal sampled at period `T` is
//!
//! ```text
//! D^α x(t_k) ≈ T^(−α) · Σ_{j=0..k} w_j · x_{k−j},   w_0 = 1,   w_j = w_{j−1} · (1 − (α + 1)/j)
//! ```
//!
//! (`w_j = (−1)^j · binom(α, j)`). Its discrete transfer function is exactly
//! `((1 − z⁻¹)/T)^α` when the sum runs over the whole history ("full memory"). The
//! *short-memory principle* (Podlubny) keeps only the last `L` samples:
//!
//! ```text
//! D^α x(t_k) ≈ T^(−α) · Σ_{j=0..L} w_j · x_{k−j}
//! ```
//!
//! i.e. an FIR filter with `L + 1` precomputed taps `c_j = T^(−α) w_j`. The samples are
//! kept in a ring buffer written twice (at `head` and `head + L + 1`), so that the newest
//! `L + 1` samples are always one contiguous slice.
//!
//! **Block-precomputed tail.** The taps `j ≥ B` of the outputs `y_k … y_{k+B−1}` of a block of
//! `B` = [`BLOCK`] samples only read samples older than `x_k`, so they are summed for the whole
//! block when it starts:
//!
//! ```text
//! y_{k+i} = Σ_{j<B} c_j x_{k+i−j}  +  T_i,     T_i = Σ_{j=B..L} c_j x_{k+i−j}   (i = 0..B−1)
//! ```
//!
//! The `B` tail sums are one Toeplitz matrix–vector product: for each tap one broadcast `c_j`
//! multiplies `B` consecutive samples, so a multiply–add costs one load instead of two (the
//! per-sample dot product of the whole window is bound by the L1 read bandwidth). Each `T_i` is
//! summed in order of `j` with one fused multiply–add per term (the scalar definition,
//! [`crate::kernels::block_tail_fma`], is bitwise what the AVX2 code computes); the head is the window dot
//! product of `B` taps. Same terms as the window sum, different rounding (1e-15 of the terms'
//! magnitudes; tests compare both with the direct sum). When the window holds two blocks
//! (`L + 1 ≥ 2B`) the tail sums are instead computed by uniformly partitioned FFT convolution
//! ([`crate::partitioned`]: `P·(B+1)` complex multiply–adds and two FFTs per block instead of
//! `B·(L+1−B)` multiply–adds); the direct tail stays selectable
//! ([`GrunwaldLetnikov::with_direct_tail`]) and the per-sample window sum as
//! [`GrunwaldLetnikov::step_window`], the references of the tests and the bench.
//!
//! For a sinusoid at ω the truncated tail relative to the full operator is about
//! `(ω L T)^(−(1+α)) / |Γ(−α)|` (summation by parts of `w_j ~ j^(−α−1)/Γ(−α)`). It is small
//! for derivatives but large for integrals (α ≈ −0.85 gives ~70 % at 143 Hz, L = 500),
//! which is why [`crate::fractional`] applies GL only to the non-integer part
//! `r = α − ⌊α⌋ ∈ [0, 1)` and realises the integer part exactly.
//!
//! The first-order accuracy of GL (error `O(T)` for smooth signals) is checked in the tests
//! on `D^0.5 1 = 1/√(πt)` and `D^0.5 t = 2√t/√π`.

use crate::kernels::{BLOCK, block_tail, dot, dot_head};
use crate::partitioned::PartitionedTail;
use num_complex::Complex64;
use serde::{Deserialize, Serialize};

/// The GL binomial weights `w_0..w_{n-1}` of order `alpha`.
pub fn gl_weights(alpha: f64, n: usize) -> Vec<f64> {
    let mut w = Vec::with_capacity(n);
    let mut wj = 1.0;
    for j in 0..n {
        if j > 0 {
            wj *= 1.0 - (alpha + 1.0) / j as f64;
        }
        w.push(wj);
    }
    w
}

/// `Σ_j c_j w^j` as eight interleaved Horner chains: `Σ_{r<8} w^r q_r(w^8)` with
/// `q_r(y) = Σ_k c_{8k+r} y^k`. The chains are independent, so the processor overlaps them
/// (plain Horner waits for each complex product: the frequency responses of the lobe
/// diagrams were 2/3 of its time); same terms, rounding differs at the 1e-15 level (a test
/// compares with [`GrunwaldLetnikov::response_reference`]).
pub fn polyval_interleaved(c: &[f64], w: Complex64) -> Complex64 {
    const K: usize = 8;
    let one = Complex64::new(1.0, 0.0);
    let mut pw = [one; K];
    for r in 1..K {
        pw[r] = pw[r - 1] * w;
    }
    let wk = pw[K - 1] * w;
    let mut acc = [Complex64::new(0.0, 0.0); K];
    let full = c.len() / K;
    let tail = &c[full * K..];
    for (r, a) in acc.iter_mut().enumerate().take(tail.len()) {
        *a = Complex64::new(tail[r], 0.0);
    }
    for row in c[..full * K].chunks_exact(K).rev() {
        for (a, &cr) in acc.iter_mut().zip(row) {
            *a = *a * wk + cr;
        }
    }
    acc.iter().zip(&pw).fold(Complex64::new(0.0, 0.0), |s, (a, p)| s + a * p)
}

/// Short-memory Grünwald–Letnikov operator of order `alpha` (an FIR filter of `L + 1` taps).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GrunwaldLetnikov {
    alpha: f64,
    ts: f64,
    /// `T^(−α) w_j`, j = 0..=L.
    coeffs: Vec<f64>,
    /// Ring buffer of length `2 (L + 1)`, each sample written twice.
    buf: Vec<f64>,
    head: usize,
    /// The current block's tail sums (`acc` of [`crate::kernels::block_tail_fma`]; unused when `L + 1 ≤ B`).
    tail: Vec<f64>,
    /// Index in the block of the next sample (the tail is summed when it is 0).
    phase: usize,
    /// The tail by partitioned FFT convolution (None: summed directly).
    partitioned: Option<PartitionedTail>,
}

impl GrunwaldLetnikov {
    /// Operator of order `alpha` at sample period `ts` keeping `memory_length` past samples
    /// (plus the current one).
    pub fn new(alpha: f64, ts: f64, memory_length: usize) -> Self {
        let n = memory_length + 1;
        let mut op = Self::with_direct_tail(alpha, ts, memory_length);
        if n >= 2 * BLOCK {
            op.partitioned = Some(PartitionedTail::new(&op.coeffs));
        }
        op
    }

    /// [`new`](Self::new) with the block's tail summed directly ([`block_tail`]) at every
    /// memory length: the reference of the partitioned tail in the tests and the bench.
    pub fn with_direct_tail(alpha: f64, ts: f64, memory_length: usize) -> Self {
        let n = memory_length + 1;
        // `libm::pow`, not `f64::powf` (the platform's libm): glibc and the Windows CRT may differ
        // in the last bit, and the FMUs compute the same bits on linux64 and win64
        let scale = libm::pow(ts, -alpha);
        let coeffs = gl_weights(alpha, n).into_iter().map(|w| w * scale).collect();
        GrunwaldLetnikov {
            alpha,
            ts,
            coeffs,
            buf: vec![0.0; 2 * n],
            head: 0,
            tail: vec![0.0; BLOCK],
            phase: 0,
            partitioned: None,
        }
    }

    /// Order α.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// Memory length `L` (number of past samples used).
    pub fn memory_length(&self) -> usize {
        self.coeffs.len() - 1
    }

    /// Sample period.
    pub fn ts(&self) -> f64 {
        self.ts
    }

    /// A restored operator: the taps `fresh` has, a buffer of its length, the head inside it.
    pub(crate) fn check(&self, fresh: &Self) -> Result<(), String> {
        crate::restored::same(
            "Grünwald–Letnikov taps",
            &[&[self.alpha, self.ts], &self.coeffs[..]].concat(),
            &[&[fresh.alpha, fresh.ts], &fresh.coeffs[..]].concat(),
        )?;
        if self.buf.len() != fresh.buf.len() || self.head >= self.coeffs.len() {
            return Err("Grünwald–Letnikov buffer does not match the memory length".into());
        }
        if self.tail.len() != BLOCK || self.phase >= BLOCK {
            return Err("Grünwald–Letnikov block state is out of range".into());
        }
        crate::restored::finite("Grünwald–Letnikov buffer", &self.buf)?;
        crate::restored::finite("Grünwald–Letnikov tail sums", &self.tail)?;
        match (&self.partitioned, &fresh.partitioned) {
            (None, None) => Ok(()),
            (Some(a), Some(b)) => a.check(b),
            _ => Err("Grünwald–Letnikov tail method does not match the memory length".into()),
        }
    }

    /// Push sample `x_k` and return `D^α x (t_k)`: the head of `B` taps plus the block's tail
    /// sum, summed for the whole block at its first sample (module documentation).
    #[inline]
    pub fn step(&mut self, x: f64) -> f64 {
        let n = self.coeffs.len();
        if n <= BLOCK {
            return self.step_window(x);
        }
        if self.phase == 0 {
            let acc: &mut [f64; BLOCK] = (&mut self.tail[..]).try_into().expect("the tail holds one block");
            let window = &self.buf[self.head..self.head + n];
            match &mut self.partitioned {
                Some(p) => p.block(window, acc),
                None => block_tail(&self.coeffs, window, acc),
            }
        }
        self.push(x);
        let i = self.phase;
        self.phase = if i + 1 == BLOCK { 0 } else { i + 1 };
        dot_head(&self.coeffs, x, &self.buf[self.head + 1..self.head + BLOCK]) + self.tail[BLOCK - 1 - i]
    }

    /// [`step`](Self::step) as one dot product over the whole window per sample: the reference
    /// of the tests and the bench (the scheme of earlier releases). An operator is stepped by one
    /// of the two only (this one leaves the block's tail sums alone).
    #[inline]
    pub fn step_window(&mut self, x: f64) -> f64 {
        let n = self.coeffs.len();
        self.push(x);
        dot(&self.coeffs, &self.buf[self.head..self.head + n])
    }

    fn push(&mut self, x: f64) {
        let n = self.coeffs.len();
        self.head = if self.head == 0 { n - 1 } else { self.head - 1 };
        self.buf[self.head] = x;
        self.buf[self.head + n] = x;
    }

    /// Transfer function `Σ_j c_j z^(−j)` at `z` (the same taps [`step`](Self::step) uses).
    pub fn response(&self, z: Complex64) -> Complex64 {
        polyval_interleaved(&self.coeffs, z.inv())
    }

    /// [`response`](Self::response) by plain Horner (one dependent chain of 1001 complex
    /// multiply–adds): the slow reference of the tests.
    pub fn response_reference(&self, z: Complex64) -> Complex64 {
        let zinv = z.inv();
        self.coeffs.iter().rev().fold(Complex64::new(0.0, 0.0), |acc, &c| acc * zinv + c)
    }

    /// Clear the history.
    pub fn reset(&mut self) {
        self.buf.iter_mut().for_each(|b| *b = 0.0);
        self.tail.iter_mut().for_each(|b| *b = 0.0);
        self.head = 0;
        self.phase = 0;
        if let Some(p) = &mut self.partitioned {
            p.reset();
        }
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The interleaved polynomial evaluation against plain Horner, on and off the unit circle,
    /// for every length up to 40 and the default 1001 taps.
    #[test]
    fn interleaved_response_equals_horner() {
        for l in (0..40).chain([1000]) {
            let op = GrunwaldLetnikov::new(0.37, 1e-5, l);
            for k in 0..50 {
                let th = 0.0629 * k as f64;
                for r in [1.0, 0.97, 1.03] {
                    let z = Complex64::from_polar(r, th);
                    let (fast, slow) = (op.response(z), op.response_reference(z));
                    // the size of the terms Σ |c_j| |z|^(−j): the rounding scale of both sums
                    let scale: f64 = op.coeffs.iter().enumerate().map(|(j, c)| c.abs() * r.powi(-(j as i32))).sum();
                    assert!((fast - slow).norm() <= 1e-13 * scale, "L = {l}, z = {z}: {fast} vs {slow}");
                }
            }
        }
    }

    /// The block-precomputed step against the direct truncated sum and the per-sample window
    /// sum (1e-12 of the terms' magnitudes), for memories around the block size and the default,
    /// over several blocks; and a copy taken mid-block (serialised state) continues bitwise.
    #[test]
    fn block_tail_step_equals_direct_sum_and_window_sum() {
        let (alpha, ts) = (0.154, 1e-5);
        for l in [1, 30, 31, 32, 33, 62, 63, 64, 65, 100, 1000] {
            let mut fast = GrunwaldLetnikov::new(alpha, ts, l);
            assert_eq!(
                fast.partitioned.is_some(),
                l + 1 >= 2 * BLOCK,
                "L = {l}: the partitioned tail from two blocks on"
            );
            let mut direct = GrunwaldLetnikov::with_direct_tail(alpha, ts, l);
            let mut window = GrunwaldLetnikov::new(alpha, ts, l);
            let w = gl_weights(alpha, l + 1);
            let s = ts.powf(-alpha);
            let xs: Vec<f64> =
                (0..l + 5 * BLOCK + 7).map(|k| (0.07 * k as f64).sin() + 0.3 * (0.011 * k as f64).cos()).collect();
            let mut copy = None;
            for k in 0..xs.len() {
                let (got, reference, direct) = (fast.step(xs[k]), window.step_window(xs[k]), direct.step(xs[k]));
                let terms: Vec<f64> = (0..=l.min(k)).map(|j| w[j] * xs[k - j] * s).collect();
                let want: f64 = terms.iter().sum();
                let scale: f64 = terms.iter().map(|t| t.abs()).sum::<f64>().max(f64::MIN_POSITIVE);
                assert!((got - want).abs() <= 1e-12 * scale, "L = {l}, k = {k}: {got} vs direct {want}");
                assert!((got - reference).abs() <= 1e-12 * scale, "L = {l}, k = {k}: {got} vs window {reference}");
                assert!((direct - want).abs() <= 1e-12 * scale, "L = {l}, k = {k}: direct tail {direct} vs {want}");
                if k == xs.len() / 2 + 3 {
                    copy = Some(fast.clone());
                }
            }
            let mut copy = copy.unwrap();
            copy.check(&GrunwaldLetnikov::new(alpha, ts, l)).unwrap();
            let mut again = GrunwaldLetnikov::new(alpha, ts, l);
            for (k, &x) in xs.iter().enumerate() {
                let y = again.step(x);
                if k > xs.len() / 2 + 3 {
                    assert_eq!(copy.step(x).to_bits(), y.to_bits(), "L = {l}, k = {k}: the copy continues");
                }
            }
        }
    }

    #[test]
    fn weights_are_signed_binomials() {
        let w = gl_weights(0.5, 4);
        // (1 - z)^0.5 = 1 - z/2 - z^2/8 - z^3/16 ...
        assert_relative_eq!(w[0], 1.0);
        assert_relative_eq!(w[1], -0.5);
        assert_relative_eq!(w[2], -0.125);
        assert_relative_eq!(w[3], -0.0625);
        // integer order: backward difference
        let d = gl_weights(1.0, 4);
        assert_relative_eq!(d[0], 1.0);
        assert_relative_eq!(d[1], -1.0);
        assert!(d[2].abs() < 1e-15 && d[3].abs() < 1e-15);
    }

    #[test]
    fn ring_buffer_equals_direct_truncated_sum() {
        let (alpha, ts, l) = (0.37, 1e-3, 13);
        let mut op = GrunwaldLetnikov::new(alpha, ts, l);
        let w = gl_weights(alpha, l + 1);
        let xs: Vec<f64> = (0..60).map(|k| (0.3 * k as f64).sin() + 0.01 * k as f64).collect();
        for k in 0..xs.len() {
            let got = op.step(xs[k]);
            let want: f64 = (0..=l.min(k)).map(|j| w[j] * xs[k - j]).sum::<f64>() * ts.powf(-alpha);
            assert_relative_eq!(got, want, max_relative = 1e-12, epsilon = 1e-12);
        }
    }

    /// L = 1000 (the default memory): the contiguous-window sum equals the direct truncated
    /// sum to 1e-12 relative (of the sum of the terms' magnitudes), and for k ≤ L (where
    /// nothing is truncated yet) the full-memory reference.
    #[test]
    fn default_memory_window_equals_direct_sum_and_full_memory_reference() {
        let (alpha, ts, l) = (0.15, 1e-5, 1000);
        let mut fast = GrunwaldLetnikov::new(alpha, ts, l);
        let w = gl_weights(alpha, l + 1);
        let xs: Vec<f64> = (0..3000).map(|k| (0.013 * k as f64).sin() + 0.2 * (0.0021 * k as f64).cos()).collect();
        // full memory (every past sample, O(n²)) over the first L + 1 samples
        let wf = gl_weights(alpha, l + 1);
        let full: Vec<f64> =
            (0..=l).map(|k| ts.powf(-alpha) * (0..=k).map(|j| wf[j] * xs[k - j]).sum::<f64>()).collect();
        for k in 0..xs.len() {
            let got = fast.step(xs[k]);
            let terms: Vec<f64> = (0..=l.min(k)).map(|j| w[j] * xs[k - j] * ts.powf(-alpha)).collect();
            let want: f64 = terms.iter().sum();
            let scale: f64 = terms.iter().map(|t| t.abs()).sum();
            assert!((got - want).abs() <= 1e-12 * scale, "k = {k}: {got} vs {want}");
            if k <= l {
                assert!((got - full[k]).abs() <= 1e-12 * scale, "k = {k}: {got} vs full {}", full[k]);
            }
        }
    }

    /// D^0.5 of 1 and of t at t = 1: analytic 1/√π and 2/√π. GL is first-order accurate, so
    /// the error must be below C·h with the constant measured once (C = 0.15 leaves margin
    /// for both functions) and must halve when h halves.
    #[test]
    fn half_derivative_of_one_and_t() {
        let pi = std::f64::consts::PI;
        let exact = [1.0 / pi.sqrt(), 2.0 / pi.sqrt()];
        let mut errs = Vec::new();
        for &n in &[1000usize, 2000] {
            let h = 1.0 / n as f64;
            let mut one = GrunwaldLetnikov::new(0.5, h, n); // memory covers the whole history
            let mut lin = GrunwaldLetnikov::new(0.5, h, n);
            let (mut d1, mut dt) = (0.0, 0.0);
            for k in 0..=n {
                d1 = one.step(1.0);
                dt = lin.step(k as f64 * h);
            }
            let e = [(d1 - exact[0]).abs(), (dt - exact[1]).abs()];
            assert!(e[0] < 0.15 * h && e[1] < 0.15 * h, "h = {h}: errors {e:?}");
            errs.push(e);
        }
        for i in 0..2 {
            let ratio = errs[0][i] / errs[1][i];
            assert!((1.8..2.2).contains(&ratio), "not first order: ratio {ratio}");
        }
    }

    #[test]
    fn full_memory_response_is_power_of_backward_difference() {
        let (alpha, ts) = (0.6, 1e-5);
        let op = GrunwaldLetnikov::new(alpha, ts, 200_000);
        let w = 2.0 * std::f64::consts::PI * 143.0;
        let z = Complex64::from_polar(1.0, w * ts);
        let want = ((Complex64::new(1.0, 0.0) - z.inv()) / ts).powf(alpha);
        let got = op.response(z);
        assert!((got - want).norm() / want.norm() < 2e-3, "{got} vs {want}");
    }
}
