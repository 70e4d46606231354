//! Plant stepping speed: 30 s of simulated time at the 10 µs internal step (3·10⁶ RK4 steps),
//! time-domain cutting, all disturbances on, one mode and three modes.
#![allow(missing_docs)]
use criterion::{Criterion, criterion_group, criterion_main};
use milling_plant::{Plant, PlantInputs, PlantParams};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("plant");
    g.sample_size(10);
    for modes in [1, 3] {
        let mut p = PlantParams::default();
        p.workpiece.modes = modes;
        g.bench_function(format!("30s_at_10us_{modes}_modes"), |b| {
            b.iter(|| {
                let mut plant = Plant::new(&p).unwrap();
                for _ in 0..3_000_000 {
                    plant.step(1e-5, &PlantInputs::default()).unwrap();
                }
                black_box(plant.outputs().x)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
