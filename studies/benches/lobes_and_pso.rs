//! Benchmarks: one lobe diagram with 2001 speeds (open loop and FOPID closed loop, seed plant,
//! 1000–3000 rpm), and one PSO tuning run of the PID (40 particles, 5 iterations = 240
//! evaluations; a full 60-iteration run makes 2440, so multiply by ≈ 10.2).

#![allow(missing_docs)] // criterion_group! generates undocumented functions

use chatter_control::{ControllerParams, Structure};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use studies::lobes::speed_grid;
use studies::loop_frf;
use studies::pso::PsoConfig;
use studies::tuning::TuningProblem;

fn lobes(c: &mut Criterion) {
    let plant = loop_frf::seed_plant();
    let rpm = speed_grid(1000.0, 3000.0, 2001);
    let mut g = c.benchmark_group("lobe_diagram_2001_speeds");
    g.sample_size(10);
    for s in [Structure::Off, Structure::Fopid] {
        let ctrl = ControllerParams { structure: s, ..ControllerParams::paper_table2() };
        g.bench_function(format!("{s:?}"), |b| {
            b.iter(|| {
                let p = loop_frf::problem(&plant, Some(&ctrl), 1000.0).unwrap();
                let d = p.diagram(black_box(&rpm));
                black_box(p.extremes(&d))
            })
        });
    }
    g.finish();
}

fn pso(c: &mut Criterion) {
    let prob = TuningProblem::new(loop_frf::seed_plant(), Structure::Pid);
    let mut g = c.benchmark_group("pso_run");
    g.sample_size(10);
    g.bench_function("pid_40x5", |b| {
        b.iter(|| {
            let cfg = PsoConfig { iterations: 5, ..Default::default() };
            black_box(prob.run(&cfg, |_, _| {}).breakdown.cost)
        })
    });
    g.finish();
}

criterion_group!(benches, lobes, pso);
criterion_main!(benches);
