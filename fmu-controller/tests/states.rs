//! The controller's shared adapter checks; restored FMU states of the controller are
//! validated: a corrupted sample period, buffer or gain is `fmi2Error` with a message, never a
//! hang or a panic on the next step.

use chatter_control::ControllerParams;
use fmi2_export::instance::{CallError, Instance, Snapshot};
use fmi2_export::table::checks::{ready_with, reseal, set_real};
use fmu_controller::ChatterController;
use model_description::Value;

type M = ChatterController;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [ControllerParams::paper_table2()],
    work: Work::Bound("Ts"),
    step: 1e-4,
    states: { stepped: stepped(), fresh: stepped, seed: 0x9e37_79b9_7f4a_7c15_u64, tries: 2000 },
}

/// An ADRC-FOPID (Grünwald–Letnikov) instance after 50 steps with a moving input.
fn stepped() -> Instance<M> {
    let mut inst = ready_with::<M>(&[("structure", Value::Integer(3))]);
    for k in 0..50 {
        set_real(&mut inst, "y", 1e-5 * (k as f64 * 0.3).sin());
        inst.do_step(k as f64 * 1e-4, 1e-4).unwrap();
    }
    inst
}

#[test]
fn a_valid_state_loads_and_a_zero_sample_period_is_refused() {
    let bytes = stepped().snapshot().serialize().unwrap();
    assert!(Snapshot::<ChatterController>::deserialize(&bytes).is_ok());
    // before: ts = 0 in the adapter's clock made the next fmi2DoStep loop forever
    let pat = 1e-5f64.to_le_bytes();
    let hits: Vec<usize> = bytes.windows(8).enumerate().filter(|(_, w)| *w == pat).map(|(i, _)| i).collect();
    assert!(hits.len() >= 3, "{}", hits.len());
    for at in hits {
        let mut bad = bytes.clone();
        bad[at..at + 8].copy_from_slice(&0.0f64.to_le_bytes());
        reseal(&mut bad);
        match Snapshot::<ChatterController>::deserialize(&bad) {
            Err(CallError::Error(m)) => assert!(m.contains("invalid state"), "{m}"),
            other => panic!("ts = 0 at byte {at} accepted: {}", other.is_ok()),
        }
    }
}

/// With `y` or `r` at ±1e308 (inside their declared ranges: none) the controller returned NaN
/// for u, z1, z2, z3 with status OK. The step is an fmi2Error naming the outputs now (at 1e200
/// the command still saturates correctly).
#[test]
fn an_input_of_1e308_is_an_error_not_nan_with_ok() {
    for structure in [2, 3, 4] {
        for (name, x) in [("y", 1e308), ("y", -1e308), ("r", 1e308), ("r", -1e308)] {
            let mut inst = ready_with::<M>(&[("structure", Value::Integer(structure))]);
            set_real(&mut inst, name, x);
            let mut outcome = Ok(());
            for k in 0..3 {
                outcome = inst.do_step(k as f64 * 1e-5, 1e-5);
                if outcome.is_err() {
                    break;
                }
                for out in ["u", "e", "z1", "z2", "z3"] {
                    let v = fmi2_export::table::checks::real(&mut inst, out);
                    assert!(v.is_finite(), "structure {structure}, {name} = {x}: {out} = {v} with status OK");
                }
            }
            if let Err(e) = outcome {
                let CallError::Error(m) = e else { panic!("{e:?}") };
                assert!(m.contains("non-finite output"), "{m}");
            }
        }
        let mut inst = ready_with::<M>(&[("structure", Value::Integer(structure))]);
        set_real(&mut inst, "y", 1e200);
        inst.do_step(0.0, 1e-5).unwrap();
        let u = fmi2_export::table::checks::real(&mut inst, "u");
        assert!(u.is_finite() && u.abs() <= ControllerParams::default().u_max, "{u}");
    }
}

/// `fractional.memory_length = 1e6`, `order = 50`, `Ts = 1e-9` were legal and needed ~2.2 s per
/// step (61 h per simulated second): the memory is bounded to 1e5 now and a sample counts
/// `SAMPLE_COST` internal steps, so the layer refuses a call that would run for long.
#[test]
fn the_longest_memory_at_the_shortest_sample_period_is_bounded_per_call() {
    use fmi2_export::table::checks::{initializing, set};
    let mut inst = initializing::<M>();
    let e = set(&mut inst, "fractional.memory_length", Value::Integer(1_000_000)).unwrap_err();
    assert!(matches!(&e, CallError::Error(m) if m.contains("outside [1, 100000]")), "{e:?}");
    let mut inst = ready_with::<M>(&[
        ("structure", Value::Integer(4)),
        ("fractional.memory_length", Value::Integer(100_000)),
        ("Ts", Value::Real(1e-9)),
    ]);
    // h/Ts = 1e6 samples: refused before the step runs
    let CallError::Error(m) = inst.do_step(0.0, 1e-3).unwrap_err() else { panic!() };
    assert!(m.contains("internal steps, more than the limit"), "{m}");
    // the largest accepted call: 1e7 / SAMPLE_COST − 1 samples
    let n = fmi2_export::MAX_INTERNAL_STEPS_PER_CALL / fmu_controller::SAMPLE_COST - 1.0;
    assert_eq!(n, 99_999.0);
}

/// Every parameter was `fixed`: a gain could not change during a run. The gains are tunable now
/// and a change between steps acts from the next sample on, with the controller's state kept
/// (a rebuilt controller would start from empty integrators: the two differ).
#[test]
fn a_gain_changed_between_steps_acts_at_the_next_sample_with_the_state_kept() {
    use fmi2_export::table::checks::real;
    let pid = [("structure", Value::Integer(2))];
    let (mut a, mut b) = (ready_with::<M>(&pid), ready_with::<M>(&pid));
    let kp = ControllerParams::default().pid.kp;
    for k in 0..40 {
        let y = 1e-9 * (k as f64 * 0.3).sin();
        set_real(&mut a, "y", y);
        set_real(&mut b, "y", y);
        if k == 20 {
            set_real(&mut b, "pid.kp", 2.0 * kp);
        }
        a.do_step(k as f64 * 1e-5, 1e-5).unwrap();
        b.do_step(k as f64 * 1e-5, 1e-5).unwrap();
        let (ua, ub) = (real(&mut a, "u"), real(&mut b, "u"));
        if k < 20 {
            assert_eq!(ua.to_bits(), ub.to_bits(), "step {k}");
        } else {
            // u = kp e + ki ∫e + kd ė: the change is kp e exactly (the state is the same)
            let e = real(&mut b, "e");
            assert!(ua.abs() < 0.5 * ControllerParams::default().u_max, "unsaturated: {ua}");
            assert!((ub - ua - kp * e).abs() <= 1e-9 * ua.abs().max(ub.abs()), "step {k}: {ua} {ub}");
        }
    }
    assert_eq!(b.model().unwrap().params().pid.kp, 2.0 * kp);
}
