//! The controllers' cost per sample with the default Grünwald–Letnikov memory (L = 1000),
//! against the cost of one GL operator step measured in the same run (interleaved, best of 5,
//! thread CPU time): a ratio near 1 says the sample costs its two GL sums and nothing else. It
//! also times the two reference schemes and prints their ratios to the default one (tail sums
//! by partitioned FFT convolution): the block's tail summed directly (`with_direct_tail`) and
//! one dot product over the whole window per sample (`step_window`); and the window sum without
//! fused multiply–add (`dot_portable`, the path of CPUs without AVX2 + FMA).
//!
//! `cargo bench -p chatter-control --bench gl_window` (`cargo test --benches`: a short run).
#![allow(missing_docs)]

use chatter_control::grunwald::GrunwaldLetnikov;
use chatter_control::kernels::dot_portable;
use chatter_control::{Controller, ControllerParams, FractionalMethod, Structure};
use std::hint::black_box;

/// CPU time of this thread [s]: on a shared machine the wall time counts other processes' turns.
fn cpu_seconds() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: a valid, writable timespec; CLOCK_THREAD_CPUTIME_ID exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

fn ns_per<F: FnMut(f64) -> f64>(n: usize, mut f: F) -> f64 {
    let start = cpu_seconds();
    let mut acc = 0.0;
    for k in 0..n {
        acc += f(1e-7 * (0.009 * k as f64).sin());
    }
    black_box(acc);
    (cpu_seconds() - start) * 1e9 / n as f64
}

fn main() {
    let quick = !std::env::args().any(|a| a == "--bench");
    let (n, rounds) = if quick { (2_000, 1) } else { (200_000, 5) };
    let base = ControllerParams::default();
    let l = base.fractional.memory_length;
    println!(
        "controller sample, T = 10 µs, Grünwald–Letnikov L = {l}, best of {rounds} × {n} samples, thread CPU time"
    );
    let mut op = GrunwaldLetnikov::new(0.15, base.ts, l);
    let mut window_op = GrunwaldLetnikov::new(0.15, base.ts, l);
    let mut direct_op = GrunwaldLetnikov::with_direct_tail(0.15, base.ts, l);
    let mut ctrls: Vec<(Structure, Controller)> = [Structure::Fopid, Structure::AdrcFopid]
        .into_iter()
        .map(|s| {
            let mut p = ControllerParams { structure: s, ..base };
            p.fractional.method = FractionalMethod::GrunwaldLetnikov;
            (s, Controller::new(&p).unwrap())
        })
        .collect();
    // the same 1001-tap sum without fused multiply–add (the path of CPUs without AVX2 + FMA)
    let taps: Vec<f64> = (0..=l).map(|i| 1.0 / (1.0 + i as f64)).collect();
    let window: Vec<f64> = (0..2 * (l + 1)).map(|i| (0.01 * i as f64).sin()).collect();
    let mut head = 0;
    let mut portable_best = f64::INFINITY;
    let mut op_best = f64::INFINITY;
    let mut window_best = f64::INFINITY;
    let mut direct_best = f64::INFINITY;
    // the loop itself (the input sine and the accumulation), included in every figure
    let mut loop_best = f64::INFINITY;
    let mut best = vec![f64::INFINITY; ctrls.len()];
    for _ in 0..rounds {
        loop_best = loop_best.min(ns_per(n, black_box));
        op_best = op_best.min(ns_per(n, |y| op.step(black_box(y))));
        window_best = window_best.min(ns_per(n, |y| window_op.step_window(black_box(y))));
        direct_best = direct_best.min(ns_per(n, |y| direct_op.step(black_box(y))));
        portable_best = portable_best.min(ns_per(n, |y| {
            head = if head == 0 { l } else { head - 1 };
            y + dot_portable(black_box(&taps), &window[head..head + l + 1])
        }));
        for (b, (_, c)) in best.iter_mut().zip(&mut ctrls) {
            *b = b.min(ns_per(n, |y| c.sample(black_box(y), 0.0).u));
        }
    }
    println!("| what | ns per sample | ratio to two GL operator steps |");
    println!("|---|---|---|");
    println!("| one GL operator step (tail by partitioned FFT convolution, L = {l}) | {op_best:.1} | 0.50 |");
    println!(
        "| reference: tail summed directly per block (`with_direct_tail`) | {direct_best:.1} | {:.2} (direct / partitioned: {:.2}) |",
        direct_best / (2.0 * op_best),
        direct_best / op_best
    );
    println!(
        "| reference: window dot product per sample (`step_window`) | {window_best:.1} | {:.2} (window / partitioned: {:.2}) |",
        window_best / (2.0 * op_best),
        window_best / op_best
    );
    println!(
        "| the window sum without FMA (`dot_portable`) | {portable_best:.1} | {:.2} (portable / fused window: {:.2}) |",
        portable_best / (2.0 * op_best),
        portable_best / window_best
    );
    for (b, (s, _)) in best.iter().zip(&ctrls) {
        println!("| {s:?} sample (two GL operators) | {b:.1} | {:.2} |", b / (2.0 * op_best));
    }
    println!("| the loop alone (input sine, accumulation; included above) | {loop_best:.1} | |");
    for (b, (s, _)) in best.iter().zip(&ctrls) {
        println!("| {s:?} sample without the loop | {:.1} | |", b - loop_best);
    }
}
