//! Benchmarks of the two analysis loops, each against its one-thread reference in the same run
//! (wall time, best of several rounds; the reference is the same code in a one-thread rayon
//! pool, so the ratio is the speed-up of parallelising over speeds and over particles):
//!
//! * one lobe diagram with 2001 speeds (seed plant, 1000–3000 rpm), open loop and the Table 2
//!   FOPID in closed loop;
//! * one PSO tuning run of the PID with the seed's settings (40 particles × 60 iterations =
//!   2440 evaluations, each with its time-domain saturation check).
//!
//! `cargo bench -p seed000 --bench lobes_and_pso` (`cargo test --benches`: a short run with 2
//! PSO iterations).

#![allow(missing_docs)]

use chatter_control::{ControllerParams, Structure};
use delay_stability::zero_order::speed_grid;
use seed000::loop_frf;
use seed000::tuning::TuningProblem;
use std::hint::black_box;
use std::time::Instant;
use study_kit::optim::pso::PsoConfig;

/// Best wall time of `rounds` calls of `f` \[s\].
fn best<R>(rounds: usize, mut f: impl FnMut() -> R) -> f64 {
    (0..rounds)
        .map(|_| {
            let t = Instant::now();
            black_box(f());
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// `f` in a one-thread rayon pool: the sequential reference of the parallel code.
fn one_thread<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a one-thread pool").install(f)
}

fn main() {
    let quick = !std::env::args().any(|a| a == "--bench");
    let (lobe_rounds, pso_rounds, iterations) = if quick { (1, 1, 2) } else { (5, 1, 60) };
    let threads = rayon::current_num_threads();
    println!("wall time, best of {lobe_rounds} (lobes) / {pso_rounds} (PSO); parallel = rayon with {threads} threads");
    println!("| what | parallel | one thread (reference) | ratio |");
    println!("|---|---|---|---|");
    let plant = loop_frf::seed_plant();
    let rpm = speed_grid(1000.0, 3000.0, 2001);
    for s in [Structure::Off, Structure::Fopid] {
        let ctrl = ControllerParams { structure: s, ..ControllerParams::paper_table2() };
        let diagram = || {
            let p = loop_frf::problem(&plant, Some(&ctrl), 1000.0).unwrap();
            let d = p.diagram(black_box(&rpm));
            p.extremes(&d).unwrap().min.depth
        };
        let par = best(lobe_rounds, diagram);
        let seq = one_thread(|| best(lobe_rounds, diagram));
        println!("| lobe diagram, 2001 speeds, {s:?} | {:.1} ms | {:.1} ms | {:.2} |", par * 1e3, seq * 1e3, seq / par);
    }
    let prob = TuningProblem::new(plant.clone(), Structure::Pid);
    let cfg = PsoConfig { iterations, ..Default::default() };
    let run = || prob.run(&cfg, |_, _| {}).breakdown.cost;
    let par = best(pso_rounds, run);
    let seq = one_thread(|| best(pso_rounds, run));
    println!(
        "| PSO run, PID, {} particles × {iterations} iterations | {par:.2} s | {seq:.2} s | {:.2} |",
        cfg.particles,
        seq / par
    );
}
