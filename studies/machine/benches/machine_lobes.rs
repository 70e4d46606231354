//! Speed of a user's machine's lobes (issue "your own machine"): the 2-D zero-order method over
//! 10,000 speeds on one thread, and the semi-discretisation of a 2-D, 4-mode machine over 200
//! speeds at m = 40 on every core against one thread (the single-thread baseline), each measured
//! in the same run.
//!
//! `cargo bench -p machine --bench machine_lobes`

use delay_stability::frequency::{Lobes, ZeroOrder2d};
use delay_stability::{BisectionOptions, lobes};
use machine::Machine;
use std::time::Instant;

const FOUR_MODES: &str = r#"
version = 1
name = "4-mode end mill"
[tool]
teeth = 3
diameter = "12 mm"
[structure]
x = [ { frequency = "600 Hz", damping = 0.03, stiffness = "2e7 N/m" },
      { frequency = "1100 Hz", damping = 0.02, stiffness = "5e7 N/m" } ]
y = [ { frequency = "650 Hz", damping = 0.035, stiffness = "2.5e7 N/m" },
      { frequency = "1250 Hz", damping = 0.025, stiffness = "6e7 N/m" } ]
[material]
kt = "800 N/mm^2"
kr_ratio = 0.3
[operation]
immersion = 0.5
milling = "down"
feed_per_tooth = "0.05 mm"
speed_range = ["3000 rpm", "20000 rpm"]
"#;

fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new().num_threads(n).build().expect("thread pool")
}

fn main() {
    let quick = std::env::args().any(|a| a == "--test");
    let m = Machine::from_toml(FOUR_MODES, "four_modes.toml").expect("valid machine");
    let (lo, hi) = m.operation.speed_range_rpm;
    // zero-order, one thread
    let n = if quick { 200 } else { 10_000 };
    let speeds = machine::workflow::speeds(lo, hi, n);
    let t = Instant::now();
    let d = pool(1).install(|| {
        let zo =
            ZeroOrder2d::new(|w: f64| m.receptance(w), &m.cutter().unwrap(), machine::lobes::band(&m), lo).unwrap();
        zo.diagram(&speeds)
    });
    let zo_s = t.elapsed().as_secs_f64();
    let min = d.iter().map(|p| p.depth).fold(f64::INFINITY, f64::min);
    println!(
        "2-D zero-order, 4 modes: {n} speeds in {zo_s:.3} s on one thread ({:.1} µs per speed), b_min {:.4} mm",
        zo_s / n as f64 * 1e6,
        min * 1e3
    );
    // semi-discretisation, all cores vs one
    let n = if quick { 4 } else { 200 };
    let speeds = machine::workflow::speeds(lo, hi, n);
    let model = m.sd_model().unwrap();
    let o = BisectionOptions { m: 40, start: 0.2e-3, growth: 1.1, max: 0.1, rel_tol: 1e-4 };
    let run = |threads: usize| {
        let t = Instant::now();
        let r = pool(threads).install(|| lobes(&speeds, |rpm, a| model.at(rpm, a), &o, &|_, _| {}).unwrap());
        (t.elapsed().as_secs_f64(), r)
    };
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (t_all, a) = run(cores);
    let (t_one, b) = run(1);
    assert!(
        a.iter().zip(&b).all(|(x, y)| x.critical.value == y.critical.value),
        "the same lobes on any number of threads"
    );
    println!(
        "semi-discretisation (m = 40), 4 modes: {n} speeds in {t_all:.2} s on {cores} threads, {t_one:.2} s on one thread: {:.2}x ({:.0} ms per speed on one thread)",
        t_one / t_all,
        t_one / n as f64 * 1e3
    );
}
