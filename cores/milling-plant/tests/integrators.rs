//! The exact integrator (default) against the RK4 reference on the same scenarios, same seed.

use milling_plant::{CuttingModel, Integrator, Plant, PlantInputs, PlantParams};

/// Tip displacement every 10 µs over `seconds` (communication step = internal step).
fn run(p: &PlantParams, inputs: &PlantInputs, seconds: f64) -> Vec<f64> {
    let mut plant = Plant::new(p).unwrap();
    let n = (seconds / 1e-5).round() as usize;
    (0..n)
        .map(|_| {
            plant.step(1e-5, inputs).unwrap();
            plant.outputs().x
        })
        .collect()
}

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

fn with(p: &PlantParams, integrator: Integrator) -> PlantParams {
    PlantParams { integrator, ..p.clone() }
}

/// Nominal scenario (2000 rpm, 1 mm, noise, drift), 1 s: tip RMS within 1e-4 relative, and the
/// trajectories themselves close (the largest pointwise difference within 1 % of the RMS).
#[test]
fn exact_and_reference_agree_over_one_second_of_the_nominal_scenario() {
    for (modes, model) in [(1, CuttingModel::TimeDomain), (3, CuttingModel::TimeDomain), (1, CuttingModel::Averaged)] {
        let mut p = PlantParams::default();
        p.workpiece.modes = modes;
        p.cutting.model = model;
        let inputs = PlantInputs::default();
        let fast = run(&with(&p, Integrator::Exact), &inputs, 1.0);
        let slow = run(&with(&p, Integrator::Reference), &inputs, 1.0);
        let (rf, rs) = (rms(&fast), rms(&slow));
        let rel = (rf / rs - 1.0).abs();
        let worst = fast.iter().zip(&slow).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        println!(
            "{modes} mode(s), {model:?}: RMS exact {rf:.6e} reference {rs:.6e} (rel {rel:.2e}), max |dx| {worst:.2e} m"
        );
        assert!(rel < 1e-4, "{modes} modes {model:?}: tip RMS differs by {rel:.2e}");
        assert!(worst < 1e-2 * rs, "{modes} modes {model:?}: pointwise difference {worst:.2e} m");
    }
}

/// With a command that saturates and a sinusoidal disturbance (the terms the nominal scenario
/// leaves at zero), three modes, stepped with 2·10 µs, 0.2 s: still the reference's trajectory.
/// Over this shorter run the tooth-exit events (where both schemes are first order, with
/// different but unbiased errors) average out less: 1.2e-4 measured, 3e-4 allowed.
#[test]
fn exact_and_reference_agree_with_saturated_command_and_sine() {
    let mut p = PlantParams::default();
    p.workpiece.modes = 3;
    p.disturbance.sine_amplitude = 20.0;
    let mut fast = Plant::new(&with(&p, Integrator::Exact)).unwrap();
    let mut slow = Plant::new(&with(&p, Integrator::Reference)).unwrap();
    let (mut xf, mut xs) = (Vec::new(), Vec::new());
    for k in 0..10_000 {
        let u = 40.0 * (k as f64 * 0.01).sin();
        let inputs = PlantInputs { u, ..PlantInputs::default() };
        fast.step(2e-5, &inputs).unwrap();
        slow.step(2e-5, &inputs).unwrap();
        xf.push(fast.outputs().x);
        xs.push(slow.outputs().x);
        assert_eq!(fast.outputs().saturated, slow.outputs().saturated);
    }
    let rel = (rms(&xf) / rms(&xs) - 1.0).abs();
    assert!(rel < 3e-4, "tip RMS differs by {rel:.2e}");
}

/// Both integrators: communication steps that are multiples of the internal step give the
/// same trajectory bit for bit (the exact scheme's force evaluations and tooth-angle
/// recurrences depend only on the cells, not on where the communication points fall).
#[test]
fn both_integrators_are_independent_of_the_communication_step() {
    for integrator in [Integrator::Exact, Integrator::Reference] {
        let p = with(&PlantParams::default(), integrator);
        let inputs = PlantInputs { u: 3.0, ..PlantInputs::default() };
        let mut fine = Plant::new(&p).unwrap();
        let mut coarse = Plant::new(&p).unwrap();
        for k in 0..300 {
            for _ in 0..7 {
                fine.step(1e-5, &inputs).unwrap();
            }
            coarse.step(7e-5, &inputs).unwrap();
            let (a, b) = (fine.outputs(), coarse.outputs());
            for (name, x, y) in [("x", a.x, b.x), ("v", a.v, b.v), ("cutting_force", a.cutting_force, b.cutting_force)]
            {
                assert_eq!(x.to_bits(), y.to_bits(), "{integrator:?}: {name} differs at step {k}");
            }
        }
    }
}

/// A restored copy continues bit for bit (the tooth-angle recurrence is part of the state, the
/// derived matrices are rebuilt).
#[test]
fn a_serialized_copy_continues_identically() {
    let p = PlantParams::default();
    let inputs = PlantInputs::default();
    let mut a = Plant::new(&p).unwrap();
    a.step(0.0123, &inputs).unwrap();
    let bytes = postcard::to_allocvec(&a).unwrap();
    let mut b: Plant = postcard::from_bytes(&bytes).unwrap();
    assert_eq!(b.validate_state(), Ok(()));
    for _ in 0..1000 {
        a.step(1e-5, &inputs).unwrap();
        b.step(1e-5, &inputs).unwrap();
        assert_eq!(a.outputs().x.to_bits(), b.outputs().x.to_bits());
    }
}

/// Memory stays flat with run length: the regenerative history and the discretisations held
/// after 30 s and after 300 s of cutting are the same size.
#[test]
fn memory_is_flat_with_run_length() {
    let p = PlantParams::default();
    let inputs = PlantInputs::default();
    let mut plant = Plant::new(&p).unwrap();
    plant.step(30.0, &inputs).unwrap();
    let at_30 = plant.history_len();
    plant.step(270.0, &inputs).unwrap();
    let at_300 = plant.history_len();
    println!("history samples after 30 s: {at_30}, after 300 s: {at_300}");
    assert!(at_300 <= at_30 + 1 && at_30 < 1000, "{at_30} -> {at_300}");
}

/// Communication steps of one internal cell stay on the cell grid at any time: the step counts
/// its own remainder down instead of subtracting two times of size t (whose rounding, ≈ t·ε,
/// exceeded the grid tolerance after ~50 s and made every later step two partial cells, each
/// with a new discretisation: 4× slower at 120 s, 40× at 300 s). Both integrators, 1 and 3 modes.
#[test]
fn steps_stay_on_the_internal_grid_late_in_a_long_run() {
    for integrator in [Integrator::Exact, Integrator::Reference] {
        for modes in [1, 3] {
            let mut p = PlantParams { integrator, ..Default::default() };
            p.workpiece.modes = modes;
            for t0 in [0.0, 300.0, 1.0e4] {
                let mut plant = Plant::new_at(&p, t0).unwrap();
                let inputs = PlantInputs::default();
                for k in 0..2000 {
                    plant.step(p.internal_step, &inputs).unwrap();
                    assert_eq!(
                        plant.cell_offset().to_bits(),
                        0,
                        "{integrator:?}, {modes} modes, t0 = {t0}: off the grid at step {k}"
                    );
                }
                let t = plant.time() - t0;
                assert!((t - 2000.0 * p.internal_step).abs() < 1e-9, "t0 = {t0}: advanced {t} s");
            }
        }
    }
}
