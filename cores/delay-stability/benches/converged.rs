//! The converged default ([`Method::Auto`]: spectral collocation, order raised until the boundary
//! moves by less than 0.1 %/3 to the next order) against the first-order semi-discretisation at
//! the same accuracy, all ratios measured in this run (wall time on the rayon pool, i.e. every
//! core of the machine, unless noted).
//!
//! 1. Converged 200-speed diagrams: the Insperger–Stépán 1-DOF benchmark (slotting and
//!    a/D = 0.05, down-milling, 5000–25000 rpm) and a 2-D, 4-mode machine (the "your own machine"
//!    end mill plus a 1250 Hz y mode, 3 teeth, slotting, 3000–20000 rpm). SD at the same
//!    accuracy: the smallest m of 40, 80, … 1280 whose boundary is within 0.1 % of the converged
//!    one at every one of 5 sampled speeds (the lowest, where SD is worst, included); its time
//!    per speed on those 5 speeds (serially, one core) is compared with the spectral time per
//!    speed on the same 5 (one core), and the 200-speed SD diagram time estimated from it.
//! 2. One spectral radius at SD's m = 160 and 320 (1-DOF, 5603 rpm slotting): the dense matrix
//!    and Schur (the reference) against the product form and Arnoldi.
//! 3. Cost per speed against the number of states (1, 2, 4, 8 modes, slotting, 10000 rpm, one
//!    core): the converged default and SD at m = 40.
//!
//! `cargo bench -p delay-stability --bench converged`

use delay_stability::milling::{Cutter, ForceLaw, Milling, MillingModel, ModeShape, Structure};
use delay_stability::sd::{SdOperator, eigenvalues};
use delay_stability::zero_order::speed_grid;
use delay_stability::{LobeOptions, Method, critical, lobes_with, monodromy};
use std::f64::consts::PI;
use std::time::Instant;

fn mode(hz: f64, k: f64, zeta: f64, dir: [f64; 2]) -> ModeShape {
    let m = k / (2.0 * PI * hz).powi(2);
    ModeShape { omega: 2.0 * PI * hz, zeta, tool: [dir[0] / m.sqrt(), dir[1] / m.sqrt()], actuator: [0.0; 2] }
}

fn model(modes: &[ModeShape], teeth: u32, kt: f64, kr: f64, immersion: f64) -> MillingModel {
    let (e, x) = Cutter::immersion(immersion, Milling::Down);
    let c = Cutter::new(teeth, e, x, kt, kr, ForceLaw::Linear).expect("cutter");
    MillingModel::new(&Structure::from_modes(modes).expect("structure"), c, None).expect("model")
}

fn one_dof(immersion: f64) -> MillingModel {
    let m = 0.03993f64;
    let mode = ModeShape { omega: 2.0 * PI * 922.0, zeta: 0.011, tool: [1.0 / m.sqrt(), 0.0], actuator: [0.0; 2] };
    model(&[mode], 2, 6e8, 2e8, immersion)
}

fn four_mode() -> MillingModel {
    let modes = [
        mode(600.0, 2e7, 0.03, [1.0, 0.0]),
        mode(1100.0, 5e7, 0.02, [1.0, 0.0]),
        mode(650.0, 2.5e7, 0.035, [0.0, 1.0]),
        mode(1250.0, 6e7, 0.025, [0.0, 1.0]),
    ];
    model(&modes, 3, 8e8, 2.4e8, 1.0)
}

fn options(method: Method) -> LobeOptions {
    LobeOptions { method, start: 1e-5, growth: 1.1, max: 0.05, rel_tol: 1e-5 }
}

fn serial<T>(f: impl FnOnce() -> T + Send) -> T
where
    T: Send,
{
    rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("pool").install(f)
}

fn diagram(name: &str, m: &MillingModel, (lo, hi): (f64, f64)) {
    let speeds = speed_grid(lo, hi, 200);
    let t = Instant::now();
    let pts = lobes_with(&speeds, |r, a| m.at(r, a), &options(Method::default()), &|_, _| {}).expect("lobes");
    let wall = t.elapsed().as_secs_f64();
    let evals: usize = pts.iter().map(|p| p.critical.evaluations).sum();
    let worst = pts.iter().filter_map(|p| p.critical.error).fold(0.0, f64::max);
    let orders: Vec<usize> = pts
        .iter()
        .filter_map(|p| match p.critical.method {
            Method::Spectral(s) => Some(s.nodes),
            _ => None,
        })
        .collect();
    println!(
        "{name}: converged 200-speed diagram in {wall:.3} s on {} threads ({evals} operators; nodes per element {}–{}; largest error estimate {worst:.1e})",
        rayon::current_num_threads(),
        orders.iter().min().unwrap_or(&0),
        orders.iter().max().unwrap_or(&0)
    );
    // SD at the same accuracy on 5 sampled speeds, one core each side
    let sample = speed_grid(lo, hi, 5);
    let (spec, t_spec) = serial(|| {
        let t = Instant::now();
        let v: Vec<f64> = sample
            .iter()
            .map(|&r| critical(|a| m.at(r, a), &options(Method::default())).expect("auto").value.unwrap_or(f64::NAN))
            .collect();
        (v, t.elapsed().as_secs_f64() / sample.len() as f64)
    });
    let mut m_sd = 40;
    loop {
        let (sd, t_sd) = serial(|| {
            let t = Instant::now();
            let v: Vec<f64> = sample
                .iter()
                .map(|&r| {
                    critical(|a| m.at(r, a), &options(Method::Sd { m: m_sd })).expect("sd").value.unwrap_or(f64::NAN)
                })
                .collect();
            (v, t.elapsed().as_secs_f64() / sample.len() as f64)
        });
        let err = sd.iter().zip(&spec).map(|(a, b)| (a / b - 1.0).abs()).fold(0.0, f64::max);
        println!(
            "  SD m = {m_sd}: largest deviation from the converged boundary {:.3} % ({:.1} ms per speed; converged {:.1} ms per speed, one core each)",
            100.0 * err,
            t_sd * 1e3,
            t_spec * 1e3
        );
        if err <= 1e-3 || m_sd >= 1280 {
            println!(
                "  => SD at the same accuracy (0.1 %) needs m = {m_sd}: {:.1}× the converged default's time per speed; its 200-speed diagram ≈ {:.0} s on one core (converged: {:.2} s on one core)",
                t_sd / t_spec,
                200.0 * t_sd,
                200.0 * t_spec
            );
            break;
        }
        m_sd *= 2;
    }
}

fn main() {
    diagram("1-DOF benchmark, slotting", &one_dof(1.0), (5000.0, 25000.0));
    diagram("1-DOF benchmark, a/D = 0.05", &one_dof(0.05), (5000.0, 25000.0));
    diagram("2-D 4-mode machine, slotting", &four_mode(), (3000.0, 20000.0));

    // one spectral radius at large m: dense matrix + Schur (the reference) vs product form + Arnoldi
    let sys = one_dof(1.0);
    let s = sys.at(5603.0, 0.9e-3).expect("system");
    for m in [160usize, 320] {
        let t = Instant::now();
        let dense = eigenvalues(&monodromy(&s, m).expect("monodromy")).expect("eig")[0].norm();
        let t_dense = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let reps = 20;
        let mut rho = 0.0;
        for _ in 0..reps {
            let op = SdOperator::new(&s, m).expect("operator");
            let mut work = Vec::new();
            let mut k = delay_stability::krylov::Krylov::default();
            rho = k.dominant(op.dim(), &mut |z, o| op.apply(z, o, &mut work)).expect("arnoldi").values[0].norm();
        }
        let t_kr = t.elapsed().as_secs_f64() / reps as f64;
        println!(
            "SD m = {m} (dimension {}): dense monodromy + Schur {:.1} ms, product form + Arnoldi {:.2} ms ({:.0}×), ρ {dense:.12} vs {rho:.12}",
            m + 2,
            t_dense * 1e3,
            t_kr * 1e3,
            t_dense / t_kr
        );
    }

    // cost per speed against the number of states (one core)
    let all = [
        mode(600.0, 2e7, 0.03, [1.0, 0.0]),
        mode(650.0, 2.5e7, 0.035, [0.0, 1.0]),
        mode(1100.0, 5e7, 0.02, [1.0, 0.0]),
        mode(1250.0, 6e7, 0.025, [0.0, 1.0]),
        mode(1800.0, 9e7, 0.02, [0.8, 0.6]),
        mode(2100.0, 1.1e8, 0.02, [0.6, -0.8]),
        mode(2600.0, 1.5e8, 0.03, [1.0, 0.0]),
        mode(3000.0, 2e8, 0.03, [0.0, 1.0]),
    ];
    for modes in [1usize, 2, 4, 8] {
        let mdl = model(&all[..modes], 3, 8e8, 2.4e8, 1.0);
        let speeds = speed_grid(9000.0, 11000.0, 4);
        let time = |method: Method| {
            serial(|| {
                let t = Instant::now();
                let pts = lobes_with(&speeds, |r, a| mdl.at(r, a), &options(method), &|_, _| {}).expect("lobes");
                let evals: usize = pts.iter().map(|p| p.critical.evaluations).sum();
                (t.elapsed().as_secs_f64() / speeds.len() as f64, evals / speeds.len())
            })
        };
        let (t_auto, e_auto) = time(Method::default());
        let (t_sd, e_sd) = time(Method::Sd { m: 40 });
        println!(
            "{modes} mode(s), n = {}: converged {:.1} ms per speed ({e_auto} operators), SD m = 40 {:.1} ms per speed ({e_sd}); ratio SD(m = 40)/converged {:.2}",
            2 * modes,
            t_auto * 1e3,
            t_sd * 1e3,
            t_sd / t_auto
        );
    }
}
