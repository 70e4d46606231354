//! Plant stepping speed, exact integrator (default) vs the RK4 reference, measured in the same
//! run: 10 µs steps (communication step = internal step, as the closed loop steps the FMU),
//! time-domain cutting at the nominal 2000 rpm / 1 mm, noise and drift on; one and three modes.
//!
//! `cargo bench -p milling-plant --bench plant_step` (best of 5 runs of 0.5 s simulated time
//! each, interleaved, so both integrators see the same machine load; thread CPU time, not wall
//! time; `cargo test --benches` runs a short version).
#![allow(missing_docs)]

use milling_plant::{Integrator, Plant, PlantInputs, PlantParams};
use std::hint::black_box;

/// CPU time of this thread [s]: on a shared machine the wall time counts other processes' turns.
fn cpu_seconds() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: a valid, writable timespec; CLOCK_THREAD_CPUTIME_ID exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// CPU nanoseconds per 10 µs step of one run of `steps` steps.
fn ns_per_step(p: &PlantParams, steps: usize) -> f64 {
    let inputs = PlantInputs::default();
    let mut plant = Plant::new(p).unwrap();
    let start = cpu_seconds();
    for _ in 0..steps {
        plant.step(1e-5, black_box(&inputs)).unwrap();
    }
    black_box(plant.outputs().x);
    (cpu_seconds() - start) * 1e9 / steps as f64
}

fn main() {
    let quick = !std::env::args().any(|a| a == "--bench");
    let (steps, rounds) = if quick { (2_000, 1) } else { (50_000, 5) };
    println!(
        "plant core step (10 µs, time-domain cutting, noise, drift), best of {rounds} × {steps} steps, thread CPU time"
    );
    println!("| modes | exact [ns/step] | reference RK4 [ns/step] | ratio reference/exact |");
    println!("|---|---|---|---|");
    for modes in [1, 3] {
        let mut p = PlantParams::default();
        p.workpiece.modes = modes;
        let fast = PlantParams { integrator: Integrator::Exact, ..p.clone() };
        let slow = PlantParams { integrator: Integrator::Reference, ..p };
        let (mut best_fast, mut best_slow) = (f64::INFINITY, f64::INFINITY);
        // PLANT_BENCH_ONLY=exact|reference runs one integrator (for profiling)
        let only = std::env::var("PLANT_BENCH_ONLY").unwrap_or_default();
        for _ in 0..rounds {
            if only != "reference" {
                best_fast = best_fast.min(ns_per_step(&fast, steps));
            }
            if only != "exact" {
                best_slow = best_slow.min(ns_per_step(&slow, steps));
            }
        }
        println!("| {modes} | {best_fast:.1} | {best_slow:.1} | {:.2} |", best_slow / best_fast);
    }
}
