//! Tests of the modal structure: exact maps against closed forms and the RK4 reference.
use super::*;

fn quiet() -> ModalParams {
    let mut p = ModalParams::default();
    p.disturbance.noise = false;
    p.disturbance.drift = false;
    p
}

#[test]
fn a_held_force_gives_the_exact_step_response() {
    // m q̈ + c q̇ + k q = F from rest: q(t) = F/k (1 − e^{−σt}(cos ω_d t + σ/ω_d sin ω_d t))
    let p = quiet();
    let mut s = ModalStructure::new(&p).unwrap();
    let f = StructureInputs { tool_force: [100.0, 0.0], ..Default::default() };
    for _ in 0..1234 {
        s.step(1e-5, &f).unwrap();
    }
    let m = p.modes[0];
    let (w, z) = (m.omega(), m.damping_ratio);
    let (sg, wd, t) = (z * w, w * (1.0 - z * z).sqrt(), s.time());
    let q = 100.0 / m.stiffness() * (1.0 - (-sg * t).exp() * ((wd * t).cos() + sg / wd * (wd * t).sin()));
    assert!((s.outputs().tool[0] - q).abs() < 1e-12 * q.abs().max(1e-9), "{} vs {q}", s.outputs().tool[0]);
    assert!(s.outputs().tool[1] == 0.0);
}

#[test]
fn exact_and_rk4_agree_with_modes_in_both_axes_drift_and_noise() {
    let mut p = ModalParams { n_modes: 4, ..Default::default() };
    p.modes[1].tool = [0.3, 0.8];
    p.modes[3].actuator = [0.5, -0.2];
    p.disturbance.sine_amplitude = 20.0;
    p.disturbance.direction_angle = 0.4;
    p.disturbance.drift_frequency = 50.0; // faster than seed 000 to exercise it
    let mut a = ModalStructure::new(&p).unwrap();
    let mut b = a.clone();
    let inputs = StructureInputs { tool_force: [30.0, -10.0], actuator_force: [5.0, 7.0] };
    let mut worst: f64 = 0.0;
    let mut scale: f64 = 0.0;
    for k in 0..20_000 {
        // odd communication steps: partial cells too
        let h = if k % 3 == 0 { 0.7e-5 } else { 1e-5 };
        a.step(h, &inputs).unwrap();
        b.step_rk4(h, &inputs, 8).unwrap();
        for i in 0..2 {
            worst = worst.max((a.outputs().tool[i] - b.outputs().tool[i]).abs());
            scale = scale.max(b.outputs().tool[i].abs());
        }
    }
    assert!(a.time().to_bits() == b.time().to_bits());
    assert!(worst < 1e-7 * scale, "exact vs RK4: {worst} of {scale}");
    assert!(scale > 1e-7);
}

#[test]
fn rk4_converges_to_the_exact_map_at_fourth_order() {
    let p = quiet();
    let m = p.modes[0];
    let d = discretise(m.modal_mass, m.damping(), m.stiffness(), 1e-3);
    let errs: Vec<f64> = [10usize, 20]
        .iter()
        .map(|&n| {
            let mut s = ModalStructure::new(&p).unwrap();
            s.q[0] = 1e-6;
            let h = 1e-3 / n as f64;
            let mut r = s.clone();
            r.p.internal_step = h;
            for _ in 0..n {
                r.step_rk4(h, &StructureInputs::default(), 1).unwrap();
            }
            (r.q[0] - d.phi[0][0] * 1e-6).abs()
        })
        .collect();
    let order = (errs[0] / errs[1]).log2();
    assert!(order > 3.7 && order < 4.3, "order {order} ({errs:?})");
}

#[test]
fn mode_shapes_route_forces_and_outputs() {
    let mut p = quiet();
    p.modes[0].tool = [0.0, 1.0];
    p.modes[0].actuator = [2.0, 0.0];
    let mut s = ModalStructure::new(&p).unwrap();
    // a force along x at the tool point does not excite a mode that moves the tool along y
    s.step(1e-3, &StructureInputs { tool_force: [100.0, 0.0], ..Default::default() }).unwrap();
    assert!(s.outputs().tool.iter().all(|x| x.abs() < 1e-30));
    s.step(1e-3, &StructureInputs { actuator_force: [100.0, 0.0], ..Default::default() }).unwrap();
    let o = s.outputs();
    assert!(o.tool[1] > 0.0 && (o.actuator[0] - 2.0 * o.tool[1]).abs() < 1e-20);
}

#[test]
fn bad_inputs_and_parameters_are_refused() {
    let mut s = ModalStructure::new(&quiet()).unwrap();
    let e = s.step(1e-5, &StructureInputs { tool_force: [f64::NAN, 0.0], ..Default::default() }).unwrap_err();
    assert!(matches!(e, StructureError::Input(_)));
    let mut p = quiet();
    p.n_modes = 5;
    assert!(ModalStructure::new(&p).is_err());
    p.n_modes = 1;
    p.modes[0].damping_ratio = 1.0;
    assert!(ModalStructure::new(&p).is_err());
    assert!(s.validate_state().is_ok());
}

/// A communication step of one internal cell stays on the cell grid late in a long run (the
/// step counts its remainder down; `t_end − time()` lost the grid once t·ε exceeded the
/// tolerance, after ~50 s at 10 µs), for the exact maps and the RK4 reference.
#[test]
fn steps_stay_on_the_internal_grid_late_in_a_long_run() {
    let p = ModalParams::default();
    for t0 in [0.0, 300.0, 1.0e4] {
        let mut exact = ModalStructure::new_at(&p, t0).unwrap();
        let mut rk4 = ModalStructure::new_at(&p, t0).unwrap();
        for k in 0..2000 {
            exact.step(p.internal_step, &StructureInputs::default()).unwrap();
            rk4.step_rk4(p.internal_step, &StructureInputs::default(), 1).unwrap();
            assert_eq!(exact.cell_offset().to_bits(), 0, "exact, t0 = {t0}: off the grid at step {k}");
            assert_eq!(rk4.cell_offset().to_bits(), 0, "rk4, t0 = {t0}: off the grid at step {k}");
        }
    }
}
