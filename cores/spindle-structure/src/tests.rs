//! Unit tests of the spindle core against Table I and the RK4 reference.

use super::*;

fn table1() -> Spindle {
    Spindle::new(&SpindleParams::default()).unwrap()
}

#[test]
fn derived_constants_match_the_reading_guide() {
    let s = table1().params().structure();
    // m_t ẍ_t row: −c_t/m_t and −b_t/m_t
    let ct = -s.a[(3, 1)] * 0.015;
    let bt = -s.a[(3, 3)] * 0.015;
    let ca = -s.a[(2, 0)] * 0.14 - ct;
    let ba = -s.a[(2, 2)] * 0.14 - bt;
    for (got, want) in [(ct, 3.270e6), (ca, 1.083e7), (bt, 22.1), (ba, 295.6)] {
        // the guide prints three to four digits
        assert!((got / want - 1.0).abs() < 3e-3, "{got} vs {want}");
    }
}

#[test]
fn natural_frequencies_are_those_of_the_paper() {
    let s = table1();
    let d = s.damped_frequencies();
    let u = s.undamped_frequencies();
    println!("damped {d:?} Hz, undamped {u:?} Hz");
    for (got, want) in d.iter().zip([1296.7, 2517.7]).chain(u.iter().zip([1302.9, 2525.2])) {
        assert!((got / want - 1.0).abs() < 1e-3, "{got} vs {want}");
    }
    // every eigenvalue in the left half-plane, four per axis
    let e = s.eigenvalues();
    assert_eq!(e.len(), 8);
    assert!(e.iter().all(|l| l.re < 0.0));
}

#[test]
fn exact_step_matches_rk4() {
    let u = SpindleInputs { tool_force: [3.0, -1.0], actuator_force: [-2.0, 0.5] };
    let (mut a, mut b) = (table1(), table1());
    for k in 0..400 {
        // forces change every step (a coarse sine), as a master would set them
        let f = (k as f64 * 0.1).sin();
        let uk = SpindleInputs {
            tool_force: [u.tool_force[0] * f, u.tool_force[1]],
            actuator_force: [u.actuator_force[0], u.actuator_force[1] * f],
        };
        a.step(2e-6, &uk).unwrap();
        b.step_rk4(2e-6, &uk, 8).unwrap();
    }
    let scale = b.state().iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let err = a.state().iter().zip(b.state()).fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
    println!("max |exact − RK4| = {err:e} of {scale:e}");
    assert!(scale > 1e-8 && err < 1e-9 * scale, "{err} vs {scale}");
    // and RK4 with a too coarse step is measurably different (the test can fail)
    let mut c = table1();
    for _ in 0..40 {
        c.step_rk4(2e-5, &u, 1).unwrap();
    }
    let mut d = table1();
    for _ in 0..40 {
        d.step(2e-5, &u).unwrap();
    }
    assert!((c.state()[1] - d.state()[1]).abs() > 1e-6 * d.state()[1].abs());
}

#[test]
fn static_deflection_and_frf_at_zero_agree() {
    // a constant tool force: x_t = F (1/c_a + 1/c_t), x_a = F/c_a
    let mut s = table1();
    let u = SpindleInputs { tool_force: [10.0, 0.0], actuator_force: [0.0, -4.0] };
    for _ in 0..2000 {
        s.step(1e-5, &u).unwrap();
    }
    let g = s.frf(Point::Tool, Point::Tool, 0.0);
    let ga = s.frf(Point::Actuator, Point::Actuator, 0.0);
    let o = s.outputs();
    assert!((o.tool[0] / (10.0 * g[0][0].re) - 1.0).abs() < 1e-6, "{o:?} {g:?}");
    assert!((o.actuator[1] / (-4.0 * ga[1][1].re) - 1.0).abs() < 1e-6, "{o:?} {ga:?}");
    // axes decoupled
    assert!(g[0][1].norm() < 1e-30 && g[1][0].norm() < 1e-30);
    // the tool compliance at rest is 1/c_a + 1/c_t
    let want = 1.0 / 1.0833e7 + 1.0 / 3.2702e6;
    assert!((g[0][0].re / want - 1.0).abs() < 1e-3);
}

#[test]
fn bad_inputs_and_parameters_are_refused() {
    let mut s = table1();
    let bad = SpindleInputs { tool_force: [f64::NAN, 0.0], actuator_force: [0.0; 2] };
    assert!(matches!(s.step(1e-6, &bad), Err(SpindleError::Input(_))));
    assert!(matches!(s.step(0.0, &SpindleInputs::default()), Err(SpindleError::Input(_))));
    let p = SpindleParams { tool_mass: -1.0, ..SpindleParams::default() };
    assert!(Spindle::new(&p).is_err());
    // a huge force makes it diverge: refused, state unchanged
    let huge = SpindleInputs { tool_force: [1e12, 0.0], actuator_force: [0.0; 2] };
    let before = *s.state();
    assert!(matches!(s.step(1e-3, &huge), Err(SpindleError::Diverged { .. })));
    assert!(s.state().iter().zip(&before).all(|(a, b)| a.to_bits() == b.to_bits()));
}
