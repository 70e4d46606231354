//! The tool FMU: the shared adapter checks, and through the instance state machine: the delay
//! line and the damper survive get/set and serialize/deserialize FMU state bitwise; a step that
//! is not a whole number of integration steps is discarded with a message; corrupted states are
//! refused or run safely.

use fmi2_export::instance::{CallError, Instance, Snapshot};
use fmi2_export::table::checks::{ready_with, real, vr};
use fmu_tool_xy_plant::ToolXyPlant;
use model_description::{ScalarType, Value};
use tool_xy::ToolParams;

type M = ToolXyPlant;

const H: f64 = 1e-4;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [ToolParams { cutting: false, teeth: 2, forcing_amplitude: [3.0, -4.0], ..Default::default() }],
    // the layer still refuses a step beyond 1e7 internal steps
    work: Work::Bound("max_step"),
    step: H,
    states: { stepped: damped(20), fresh: fresh, seed: 0x7001_0003_u64, tries: 300 },
}

fn fresh() -> Instance<M> {
    ready_with::<M>(&[("A_x", Value::Real(3.0)), ("A_y", Value::Real(20.0))])
}

/// A fresh instance after `steps` steps of [`run`].
fn damped(steps: usize) -> Instance<M> {
    let mut inst = fresh();
    run(&mut inst, 0, steps);
    inst
}

/// A velocity feedback through the inputs, so that the damper moves.
fn run(inst: &mut Instance<M>, from: usize, to: usize) {
    for j in from..to {
        let (vx, vy) = (real(inst, "vx"), real(inst, "vy"));
        inst.set(
            "fmi2SetReal",
            ScalarType::Real,
            &[vr::<M>("u_x"), vr::<M>("u_y")],
            &[Value::Real(-2e3 * vx), Value::Real(-2e3 * vy)],
        )
        .unwrap();
        inst.do_step(j as f64 * H, H).unwrap();
    }
}

const WATCH: [&str; 10] = ["x", "y", "vx", "vy", "deflection_x", "deflection_y", "F_x", "F_y", "damper_x", "damper_y"];

fn watched(inst: &mut Instance<M>) -> Vec<u64> {
    WATCH.iter().map(|n| real(inst, n).to_bits()).collect()
}

#[test]
fn the_delay_line_survives_get_set_and_serialize_bitwise() {
    // 70 steps: the 5 ms delay line (500 integration steps) is full of the run's history
    let mut a = fresh();
    run(&mut a, 0, 70);
    let snap = a.snapshot();
    let bytes = snap.serialize().unwrap();
    run(&mut a, 70, 160);
    let end = watched(&mut a);
    assert!(real(&mut a, "x").abs() > 0.0 && real(&mut a, "damper_x").abs() > 0.0);
    a.restore(&snap);
    run(&mut a, 70, 160);
    assert_eq!(watched(&mut a), end);
    let mut c = fresh();
    c.restore(&Snapshot::<M>::deserialize(&bytes).unwrap());
    run(&mut c, 70, 160);
    assert_eq!(watched(&mut c), end);
}

#[test]
fn bad_steps_and_inputs_are_refused_with_a_message() {
    let mut inst = fresh();
    let CallError::Discard(m) = inst.do_step(0.0, 1.5e-5).unwrap_err() else { panic!("expected fmi2Discard") };
    assert!(m.contains("whole number"), "{m}");
    for x in [f64::NAN, f64::NEG_INFINITY, 2e9] {
        let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("u_x")], &[Value::Real(x)]).unwrap_err();
        let (CallError::Error(m) | CallError::Discard(m)) = e;
        assert!(m.contains("u_x"), "{m}");
    }
}

/// `spindle_speed = 1` and `max_step = 1e-9`, both inside their declared ranges, asked the
/// allocator for 480 GB in fmi2ExitInitializationMode and the host died with SIGABRT (48 GB at
/// the declared minimum speed). Now initialization is an fmi2Error naming the parameters.
#[test]
fn a_delay_line_beyond_the_memory_budget_is_an_error_naming_the_parameters() {
    use fmi2_export::table::checks::{initializing, set};
    for (speed, step) in [(1.0, 1e-9), (1e-3, 1e-5)] {
        let mut inst = initializing::<M>();
        set(&mut inst, "spindle_speed", Value::Real(speed)).unwrap();
        set(&mut inst, "max_step", Value::Real(step)).unwrap();
        let CallError::Error(m) = inst.exit_initialization().unwrap_err() else { panic!("expected fmi2Error") };
        assert!(m.contains("spindle_speed") && m.contains("teeth") && m.contains("max_step"), "{m}");
        assert!(m.contains("more than the memory budget of 256.0 MiB"), "{m}");
    }
    // a stopped spindle is legal and does not cut
    let mut inst = ready_with::<M>(&[("spindle_speed", Value::Real(0.0))]);
    for k in 0..100 {
        inst.do_step(k as f64 * H, H).unwrap();
    }
    assert_eq!((real(&mut inst, "F_x"), real(&mut inst, "F_y")), (0.0, 0.0));
}

/// At 2900, 3100 or 3333 rpm the RK4 step was τ/⌈τ/max_step⌉ and the FMU refused its own
/// default communication step of 0.1 ms ("not a whole number of integration steps"). The step
/// is max_step now and the delay is interpolated: the default step runs at every speed, and the
/// interpolated delay converges to the on-grid one (RK4 with Hermite interpolation).
#[test]
fn the_default_step_runs_at_any_speed_and_the_interpolated_delay_converges() {
    let forced = |rpm: f64, max_step: f64| {
        let mut inst = ready_with::<M>(&[
            ("spindle_speed", Value::Real(rpm)),
            ("max_step", Value::Real(max_step)),
            ("A_x", Value::Real(10.0)),
            ("A_y", Value::Real(10.0)),
        ]);
        let h = <M as fmi2_export::Fmi2Model>::description().default_experiment.as_ref().unwrap().step_size.unwrap();
        assert_eq!(h, H);
        for k in 0..300 {
            inst.do_step(k as f64 * h, h).unwrap_or_else(|e| panic!("{rpm} rpm, step {k}: {e:?}"));
        }
        (real(&mut inst, "x"), real(&mut inst, "y"))
    };
    for rpm in [2900.0, 3100.0, 3333.0] {
        let (a, b) = (forced(rpm, 1e-5), forced(rpm, 0.5e-5));
        assert!(a.0 != 0.0 && a.1 != 0.0);
        assert!((a.0 - b.0).abs() < 1e-4 * a.0.abs() && (a.1 - b.1).abs() < 1e-4 * a.1.abs(), "{rpm}: {a:?} {b:?}");
    }
}
