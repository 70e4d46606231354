//! The SpindleStructure adapter: the shared adapter checks, and the Table I frequencies and tool
//! FRF measured through the FMU's own code path.

use fmi2_export::table::checks::{ready, stepped, vr};
use fmu_spindle_structure::SpindleStructure;
use model_description::{ScalarType, Value};
use num_complex::Complex64;
use spindle_structure::{Point, Spindle, SpindleParams};
use std::f64::consts::PI;

type M = SpindleStructure;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [SpindleParams { tool_mass: 0.02, actuator_damping_ratio: 0.3, ..Default::default() }],
    work: Work::Fixed,
    step: 1e-6,
    states: { stepped: stepped::<M>(10.0, 200, 1e-6), fresh: ready::<M>, seed: 0x51d1_e5ee_d002_0002, tries: 1000 },
}

/// The FMU's model (initialized from its start values) has the Table I modes.
#[test]
fn the_fmu_has_the_table_i_frequencies() {
    let inst = ready::<M>();
    let s = inst.model().unwrap().spindle();
    let d = s.damped_frequencies();
    let u = s.undamped_frequencies();
    println!("damped {d:?} Hz (paper 1296.7, 2517.7); undamped {u:?} Hz (1302.9, 2525.2)");
    for (got, want) in d.iter().zip([1296.7, 2517.7]).chain(u.iter().zip([1302.9, 2525.2])) {
        assert!((got / want - 1.0).abs() < 1e-3, "{got} vs {want}");
    }
}

/// Drive `tool_force_x` (or `_y`) with a unit sine through fmi2SetReal/fmi2DoStep, and fit the
/// steady tool displacement over whole periods: the measured FRF.
fn measured_frf(freq: f64, axis: usize) -> Complex64 {
    let mut inst = ready::<M>();
    let (fin, out) = if axis == 0 { ("tool_force_x", "tool_x") } else { ("tool_force_y", "tool_y") };
    let (vin, vout) = (vr::<M>(fin), vr::<M>(out));
    let h = 1e-6;
    let w = 2.0 * PI * freq;
    let period = 1.0 / freq;
    // settle 60 ms (slowest decay 1/(ζω) ≈ 4 ms), then fit over 20 whole periods
    let settle = (0.06 / period).ceil() * period;
    let fit = 20.0 * period;
    let n = ((settle + fit) / h).round() as usize;
    let start = (settle / h).round() as usize;
    let (mut sc, mut ss, mut cc, mut css, mut sss) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let mut got = Vec::new();
    for k in 0..n {
        let t = k as f64 * h;
        // the force held over the step is the sine at mid-step (second-order accurate in ωh)
        let f = (w * (t + 0.5 * h)).sin();
        inst.set("fmi2SetReal", ScalarType::Real, &[vin], &[Value::Real(f)]).unwrap();
        inst.do_step(t, h).unwrap();
        if k + 1 >= start {
            got.clear();
            inst.get("fmi2GetReal", ScalarType::Real, &[vout], &mut got).unwrap();
            let Value::Real(y) = got[0] else { panic!("not a Real") };
            let tt = t + h;
            let (s, c) = (w * tt).sin_cos();
            sc += y * c;
            ss += y * s;
            cc += c * c;
            css += s * s;
            sss += s * c;
        }
    }
    // y ≈ a sin + b cos (the cross term vanishes over whole periods; kept small by sss)
    assert!(sss.abs() < 1e-3 * css, "fit window not whole periods");
    let (a, b) = (ss / css, sc / cc);
    // sin response a sin + b cos = Im((a + i b) e^{iωt}) → FRF = a + i b
    Complex64::new(a, b)
}

#[test]
fn tool_frf_by_sine_sweep_matches_the_analytic_frf() {
    let s = Spindle::new(&SpindleParams::default()).unwrap();
    for (freq, axis) in [(300.0, 0), (1296.7, 0), (1900.0, 1), (2517.7, 1), (4000.0, 0)] {
        let want = s.frf(Point::Tool, Point::Tool, 2.0 * PI * freq)[axis][axis];
        let got = measured_frf(freq, axis);
        let err = (got - want).norm() / want.norm();
        println!(
            "{freq} Hz axis {axis}: |G| {:.4e} m/N, measured {:.4e}, rel. error {err:.2e}",
            want.norm(),
            got.norm()
        );
        assert!(err < 0.01, "{freq} Hz: {got} vs {want}");
    }
}
