//! Cost of one `Controller::sample` per structure and fractional method (T = 10 µs defaults).
//!
//! `cargo bench -p chatter-control --bench controller_sample`
#![allow(missing_docs)]

use chatter_control::{Controller, ControllerParams, FractionalMethod, FractionalParams, Structure};
use criterion::{BenchmarkId, Criterion, Throughput, black_box, criterion_group, criterion_main};

const BATCH: usize = 1000;

fn bench(c: &mut Criterion) {
    let base = ControllerParams::default();
    let mut g = c.benchmark_group("controller_sample");
    g.throughput(Throughput::Elements(BATCH as u64));
    let mut cases: Vec<(String, ControllerParams)> = vec![
        ("off".into(), ControllerParams { structure: Structure::Off, ..base }),
        ("pid".into(), ControllerParams { structure: Structure::Pid, ..base }),
    ];
    for s in [Structure::Fopid, Structure::AdrcFopid] {
        for (m, l) in [
            (FractionalMethod::GrunwaldLetnikov, 250),
            (FractionalMethod::GrunwaldLetnikov, base.fractional.memory_length),
            (FractionalMethod::GrunwaldLetnikov, 4000),
            (FractionalMethod::Oustaloup, 0),
        ] {
            let name = match m {
                FractionalMethod::GrunwaldLetnikov => format!("{s:?}/GL_L{l}"),
                FractionalMethod::Oustaloup => format!("{s:?}/Oustaloup_N{}", base.fractional.order),
            };
            let fractional = FractionalParams { method: m, memory_length: l.max(1), ..base.fractional };
            cases.push((name, ControllerParams { structure: s, fractional, ..base }));
        }
    }
    for (name, p) in cases {
        let mut ctrl = Controller::new(&p).unwrap();
        let ys: Vec<f64> = (0..BATCH).map(|k| 1e-7 * (0.009 * k as f64).sin()).collect();
        g.bench_function(BenchmarkId::from_parameter(&name), |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for &y in &ys {
                    acc += ctrl.sample(black_box(y), 0.0).u;
                }
                acc
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
