//! Timing of the 2-D frequency-domain solvers on the 3-mode machine of the "Your own machine"
//! issue (x: 600 Hz 2e7 N/m ζ 0.03 and 1100 Hz 5e7 N/m ζ 0.02; y: 650 Hz 2.5e7 N/m ζ 0.035;
//! 3 teeth, K_t = 8e8 N/m², K_r = 0.3 K_t), all on one thread (a rayon pool of one):
//!
//! * the 2-D zero-order lobes for 10,000 speeds (budget: < 1 s), slotting;
//! * the semi-discretisation (m = 40, bisection to 1e-5) per speed on fewer speeds, and the
//!   ratio of the per-speed times;
//! * the multi-frequency solver per speed at slotting and at a/D = 0.05 (automatic h), and on
//!   the 1-DOF Insperger–Stépán benchmark at a/D = 0.05.
//!
//! `cargo bench -p delay-stability --bench lobes_2d`

use delay_stability::frequency::{Lobes, ModalReceptance, MultiFrequency, ZeroOrder2d};
use delay_stability::milling::{Cutter, ForceLaw, Milling, MillingModel, ModeShape, Structure};
use delay_stability::zero_order::speed_grid;
use delay_stability::{BisectionOptions, critical_value};
use std::time::Instant;

fn machine() -> Vec<ModeShape> {
    vec![
        ModalReceptance::mode(600.0, 2e7, 0.03, [1.0, 0.0]),
        ModalReceptance::mode(1100.0, 5e7, 0.02, [1.0, 0.0]),
        ModalReceptance::mode(650.0, 2.5e7, 0.035, [0.0, 1.0]),
    ]
}

fn cutter(frac: f64) -> Cutter {
    let (e, x) = Cutter::immersion(frac, Milling::Down);
    Cutter::new(3, e, x, 8e8, 2.4e8, ForceLaw::Linear).expect("cutter")
}

fn main() {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("pool");
    pool.install(|| {
        let modes = machine();
        let (lo, hi) = (4000.0, 30000.0);
        let t = Instant::now();
        let zo = ZeroOrder2d::new(ModalReceptance::new(&modes).expect("modes"), &cutter(1.0), (10.0, 4000.0), lo)
            .expect("zero-order");
        let setup = t.elapsed().as_secs_f64();
        let speeds = speed_grid(lo, hi, 10_000);
        let t = Instant::now();
        let d = zo.diagram(&speeds);
        let zo_total = t.elapsed().as_secs_f64();
        let zo_each = zo_total / speeds.len() as f64;
        let bmin = d.iter().map(|c| c.depth).fold(f64::INFINITY, f64::min);
        println!(
            "zero-order 2-D: {} speeds in {:.3} s on one thread ({:.1} µs per speed; grid of {} points built in {:.1} ms); \
             b_min on the grid {:.4} mm",
            speeds.len(),
            zo_total,
            zo_each * 1e6,
            zo.grid_len(),
            setup * 1e3,
            bmin * 1e3
        );
        assert!(zo_total < 1.0, "10,000 speeds took {zo_total} s (budget 1 s)");

        let model = MillingModel::new(&Structure::from_modes(&modes).expect("structure"), cutter(1.0), None).expect("model");
        let o = BisectionOptions { m: 40, start: 1e-5, growth: 1.1, max: 0.2, rel_tol: 1e-5 };
        let sd_speeds = speed_grid(lo, hi, 20);
        let t = Instant::now();
        for &rpm in &sd_speeds {
            critical_value(|a| model.at(rpm, a), &o).expect("sd");
        }
        let sd_each = t.elapsed().as_secs_f64() / sd_speeds.len() as f64;
        println!(
            "semi-discretisation (m = 40): {:.1} ms per speed ({} speeds); zero-order is {:.0}× faster per speed",
            sd_each * 1e3,
            sd_speeds.len(),
            sd_each / zo_each
        );

        for frac in [1.0, 0.05] {
            let c = cutter(frac);
            let mf = MultiFrequency::new(ModalReceptance::new(&modes).expect("modes"), &c, (10.0, 4000.0), lo)
                .expect("multi-frequency");
            let mf_speeds = speed_grid(8000.0, 20000.0, 5);
            let hs: Vec<usize> = mf_speeds.iter().map(|&n| mf.harmonics_at(n)).collect();
            let t = Instant::now();
            for &rpm in &mf_speeds {
                mf.critical_depth(rpm);
            }
            let each = t.elapsed().as_secs_f64() / mf_speeds.len() as f64;
            println!(
                "multi-frequency a/D = {frac}: h = {hs:?} at {mf_speeds:?} rpm, grid {} points: {:.0} ms per speed ({:.1}× the SD time)",
                mf.grid_len(),
                each * 1e3,
                each / sd_each
            );
        }

        // the 1-DOF Insperger–Stépán benchmark at a/D = 0.05 (the flip lobes need h = 14)
        let m = 0.03993f64;
        let one = [ModeShape {
            omega: 2.0 * std::f64::consts::PI * 922.0,
            zeta: 0.011,
            tool: [1.0 / m.sqrt(), 0.0],
            actuator: [0.0, 0.0],
        }];
        let (e, x) = Cutter::immersion(0.05, Milling::Down);
        let c = Cutter::new(2, e, x, 6e8, 2e8, ForceLaw::Linear).expect("cutter");
        let mf = MultiFrequency::new(ModalReceptance::new(&one).expect("mode"), &c, (50.0, 5000.0), 12000.0)
            .expect("multi-frequency");
        let speeds = [14000.0, 16000.0, 19000.0];
        let t = Instant::now();
        for &rpm in &speeds {
            mf.critical_depth(rpm);
        }
        let each = t.elapsed().as_secs_f64() / speeds.len() as f64;
        let hs: Vec<usize> = speeds.iter().map(|&n| mf.harmonics_at(n)).collect();
        println!(
            "multi-frequency, 1-DOF benchmark a/D = 0.05: h = {hs:?} at {speeds:?} rpm, grid {} points: {:.0} ms per speed",
            mf.grid_len(),
            each * 1e3
        );
    });
}
