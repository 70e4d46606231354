//! The LinearController adapter: the shared adapter checks, the names the synthesis writes, and
//! the frequency response through the FMU's own stepping.

use fmi2_export::table::checks::{initializing, ready, set, stepped, vr};
use fmu_linear_controller::LinearController;
use linear_control::LinearControlParams;
use model_description::{ScalarType, Value};
use num_complex::Complex64;
use std::f64::consts::PI;

type M = LinearController;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [{
        let mut p = LinearControlParams { n_c: 3, discrete: true, ..Default::default() };
        p.ac[2][1] = -5.0;
        p.dc[1][0] = 1071.058e3;
        p
    }],
    work: Work::Bound("sample_period"),
    step: 1e-6,
    states: {
        stepped: stepped::<M>(40_000.0, 200, 1e-6),
        fresh: ready::<M>,
        seed: 0x11ea_c0de_0002_1313,
        tries: 1000,
    },
}

#[test]
fn the_names_the_synthesis_writes_are_variables() {
    for n in ["Ac[1,2]", "Ac[8,8]", "Bc[3,2]", "Cc[2,8]", "Dc[1,1]", "Dc[2,2]", "beta", "n_c"] {
        vr::<M>(n);
    }
}

/// Seed 002's static gain set through the FMU's parameters `Dc[i,j]`, a sine on `v_x` through
/// fmi2SetReal/fmi2DoStep: the fitted response is the FMU's `frequency_response`.
#[test]
fn the_fmu_steps_reproduce_its_frequency_response() {
    let (k1, k2) = (697.1599e3, -1071.058e3);
    let mut p = LinearControlParams { dc: [[k1, -k2], [k2, k1]], n_c: 1, ..Default::default() };
    p.ac[0][0] = -2.0 * PI * 3000.0;
    p.bc[0] = [2.0 * PI * 3000.0, 0.0];
    p.cc[1][0] = 5e5;
    // a 1 m sine asks for MN: lift the saturation out of the way
    p.saturation = [1e12; 2];
    let mut inst = initializing::<M>();
    for (name, value) in fmu_linear_controller::parameter_assignments(&p) {
        set(&mut inst, &name, value).unwrap();
    }
    inst.exit_initialization().unwrap();
    let rpm = 37_000.0;
    inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("spindle_speed")], &[Value::Real(rpm)]).unwrap();
    let tau = 60.0 / (4.0 * rpm);
    let h = 1e-6;
    let freq = 1300.0;
    let w = 2.0 * PI * freq;
    let per = 1.0 / freq;
    let n_set = ((0.01 / per).ceil() * per / h).round() as usize;
    let n_fit = (20.0 * per / h).round() as usize;
    let (mut acc, mut ss, mut cc) = ([(0.0, 0.0); 2], 0.0, 0.0);
    let mut got = Vec::new();
    for k in 0..n_set + n_fit {
        let t = k as f64 * h;
        inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("v_x")], &[Value::Real((w * t).sin())]).unwrap();
        inst.do_step(t, h).unwrap();
        if k >= n_set {
            got.clear();
            inst.get("fmi2GetReal", ScalarType::Real, &[vr::<M>("F_x"), vr::<M>("F_y")], &mut got).unwrap();
            let (s, c) = (w * t).sin_cos();
            for (i, a) in acc.iter_mut().enumerate() {
                let Value::Real(f) = got[i] else { panic!("not a Real") };
                a.0 += f * s;
                a.1 += f * c;
            }
            ss += s * s;
            cc += c * c;
        }
    }
    got.clear();
    inst.get("fmi2GetReal", ScalarType::Real, &[vr::<M>("tau"), vr::<M>("w_x")], &mut got).unwrap();
    println!("tau {:?} (want {tau}), w_x {:?}", got[0], got[1]);
    let want = fmu_linear_controller::frequency_response(&p, w, tau).unwrap();
    for (i, a) in acc.iter().enumerate() {
        let g = Complex64::new(a.0 / ss, a.1 / cc);
        let err = (g - want[i][0]).norm() / want[i][0].norm();
        println!("F{i}/v_x at {freq} Hz: measured {g:.5e}, response {:.5e}, rel. error {err:.1e}", want[i][0]);
        // w is held over the step: a phase lag of ω h/2 ≈ 4e-3 rad
        assert!(err < 1e-2, "{g} vs {}", want[i][0]);
    }
}

#[test]
fn a_spindle_speed_giving_no_valid_delay_is_discarded() {
    let mut inst = ready::<M>();
    inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("spindle_speed")], &[Value::Real(0.0)]).unwrap();
    let e = inst.do_step(0.0, 1e-6).unwrap_err();
    assert!(format!("{e:?}").contains("spindle_speed"), "{e:?}");
}
