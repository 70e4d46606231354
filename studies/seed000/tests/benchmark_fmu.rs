//! Table 8's benchmark controllers **through the FMUs**: `Benchmark.ssp` (MillingPlant with the
//! Ozsoy plant + LinearController) of `target/fmu` in the Rust master, each calibrated design
//! given as the LinearController's parameter set: 3 % below its lobe the cut decays, 3 % above
//! it grows, at the lobe minimum and at 2000 rpm. The designs' frequency response through the
//! FMU's own table and code path equals the design core's.

use benchmark_control::designs::dvf_at;
use delay_stability::zero_order::speed_grid;
use fmi_master::SystemFile;
use seed000::benchmark::{self, ALL, Benchmark, Response};
use seed000::closed_loop::AnyController;
use seed000::fmu_validation::FmuLoop;
use seed000::loop_frf;

/// The shipped `Benchmark.ssp` of `target/fmu` and the Ozsoy plant.
fn benchmark_system() -> (SystemFile, milling_plant::PlantParams) {
    let dir = packaging::fmu_dir();
    let ssp = dir.join("Benchmark.ssp");
    assert!(ssp.is_file(), "no {}: run `cargo run --release -p packaging` first", ssp.display());
    (SystemFile::open(&ssp, Some(&dir)).unwrap(), loop_frf::ozsoy_plant())
}

#[test]
fn benchmark_designs_decay_below_and_grow_above_their_lobes_through_the_fmus() {
    let (sys, plant) = benchmark_system();
    let fl = FmuLoop::linear(&sys, &plant).unwrap();
    let speeds = speed_grid(1000.0, 3000.0, 41);
    let mut failures = Vec::new();
    for kind in ALL {
        let target = match kind {
            Benchmark::Vpa => 2.5e-3,
            Benchmark::Hinf | Benchmark::Mu => 3.1e-3,
            _ => 3.2e-3,
        };
        let (_, d) = benchmark::calibrate(&plant, kind, target, &speeds, Response::Fmu).unwrap();
        let ctrl = AnyController::Linear(Box::new(d.params.clone()));
        let prob = loop_frf::problem_with(&plant, Some(&ctrl), 1000.0).unwrap();
        let rpm_min = prob.min_depth(&speeds).rpm;
        for rpm in [rpm_min, 2000.0] {
            let b = prob.critical_depth(rpm).depth;
            let below = fl.growth_ratio_with(Some(&ctrl), rpm, 0.97 * b, 1.5).unwrap();
            let above = fl.growth_ratio_with(Some(&ctrl), rpm, 1.03 * b, 1.5).unwrap();
            eprintln!(
                "{} at {rpm:.0} rpm, b = {:.4} mm: growth {below:.3} at 0.97, {above:.3} at 1.03",
                kind.label(),
                b * 1e3
            );
            if !(below < 1.0 && above > 1.0) {
                failures.push(format!("{} at {rpm} rpm: {below}, {above}", kind.label()));
            }
        }
        // the FMU's code path (the design's .ssv read through the FMU's table → core → frequency
        // response) equals the design core's controller to 1e-9
        let xml = seed000::benchmark_table::design_ssv("x", &d).unwrap();
        let mut r = study_kit::fmu_params::Resolved::default();
        for p in ssp::parse_ssv(&xml, "x.ssv", "").unwrap() {
            study_kit::fmu_params::apply_ssp::<fmu_linear_controller::LinearController>(&mut r, &p.name, &p.value)
                .unwrap();
        }
        for w in [50.0, 892.8, 5e3] {
            let fmu = fmu_linear_controller::frequency_response(&r.params, w, 0.0).unwrap()[0][0];
            let want = linear_control::LinearController::new(&d.params).unwrap().frequency_response(w, 0.0)[0][0];
            assert!((fmu - want).norm() <= 1e-9 * want.norm(), "{kind:?} at {w}: {fmu} vs {want}");
            if kind == Benchmark::Dvf {
                let f = dvf_at(&benchmark_control::designs::Dvf { gain: d.values[0], filter_hz: 5000.0 }, w);
                assert!((fmu - f).norm() <= 1e-9 * f.norm(), "DVF formula at {w}: {fmu} vs {f}");
            }
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// The DVF's inertial-actuator limit (`benchmark_control::designs::dvf_gain_limit`, the root
/// locus of the loop sampled at 10 µs: 1.1823e5 N·s/m) confirmed **through the FMUs**:
/// `Benchmark.ssp` with the cut at zero depth, released from 1 µm, saturation lifted, 4 s: at
/// 0.97 of the limit the actuator's 8.4 Hz suspension mode decays, at 1.03 it grows (the cores'
/// test `seed000::benchmark::tests::dvf_actuator_limit_in_the_time_domain` gives 0.587 / 1.673).
#[test]
fn dvf_actuator_limit_through_the_fmus() {
    let (sys, plant) = benchmark_system();
    let fl = FmuLoop::linear(&sys, &plant).unwrap();
    let dp = benchmark::design_plant(&plant);
    let limit = benchmark_control::designs::dvf_gain_limit(
        &dp,
        benchmark_control::designs::FILTER_HZ,
        Some(seed000::closed_loop::DEFAULT_STEP),
        (1e3, 1e7),
    )
    .unwrap();
    assert!((limit / 1.1823e5 - 1.0).abs() < 1e-3, "sampled limit {limit}");
    let ratio = |f: f64| {
        let d = benchmark::design(&plant, Benchmark::Dvf, &[f * limit]).unwrap();
        fl.growth_ratio_with(Some(&AnyController::Linear(Box::new(d.params))), 2000.0, 0.0, 4.0).unwrap()
    };
    let (below, above) = (ratio(0.97), ratio(1.03));
    eprintln!("DVF actuator limit {limit:.5e} N·s/m through the FMUs: growth {below:.3} at 0.97, {above:.3} at 1.03");
    assert!(below < 1.0 && above > 1.0, "{below}, {above}");
}
