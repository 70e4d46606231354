//! The plant FMU's shared adapter checks, and regression tests against hostile calls: a bounded
//! amount of work per `fmi2DoStep`, and bounded memory for every input in its declared range.

use fmi2_export::instance::{CallError, Instance};
use fmi2_export::table::checks::{ready, ready_with, reseal, set_real};
use fmi2_export::{Fmi2Model, MAX_INTERNAL_STEPS_PER_CALL};
use fmu_plant::MillingPlant;
use milling_plant::PlantParams;
use model_description::Value;
use std::time::Instant;

type M = MillingPlant;

fmi2_export::adapter_tests! {
    model: M,
    // `distinct_value` would try 2 modes; the core takes 1 or 3
    valid: [("workpiece.modes", Value::Integer(3))],
    params: [{
        let mut p = PlantParams::default();
        p.cutting.axial_depth = 2.5e-3;
        p.workpiece.modes = 3;
        p.actuator.a[1][0] = 0.5;
        p
    }],
    work: Work::Bound("internal_step"),
    step: 1e-3,
    states: { stepped: cut_10_ms(), fresh: ready::<M>, seed: 0x2545_f491_4f6c_dd1d_u64, tries: 2000 },
}

#[test]
fn a_huge_step_without_stop_time_is_refused_at_once_not_run() {
    let mut inst = ready::<M>();
    let t = Instant::now();
    let err = inst.do_step(0.0, 1e6).unwrap_err();
    assert!(t.elapsed().as_secs_f64() < 1.0, "refused after {:?}", t.elapsed());
    let CallError::Error(m) = err else { panic!("expected fmi2Error, got {err:?}") };
    assert!(m.contains("internal steps") && m.contains("limit"), "{m}");
    // an ordinary step is still accepted
    let mut inst = ready::<M>();
    assert!(inst.do_step(0.0, 0.1).is_ok());
}

#[test]
fn the_bound_follows_the_internal_step_parameter() {
    // at a 0.1 ms grid a 100 s step is 1e6 internal steps: allowed; 1e4 s is 1e8: refused
    let inst = ready_with::<M>(&[("internal_step", Value::Real(1e-4))]);
    let m = inst.model().unwrap();
    assert!(m.internal_steps(100.0) <= MAX_INTERNAL_STEPS_PER_CALL);
    assert!(m.internal_steps(1e4) > MAX_INTERNAL_STEPS_PER_CALL);
}

/// (history samples, serialized FMU state bytes)
fn footprint(inst: &Instance<MillingPlant>) -> (usize, usize) {
    (inst.model().unwrap().plant().history_len(), inst.snapshot().serialize().unwrap().len())
}

#[test]
fn sixty_seconds_at_0_rpm_run_in_flat_memory() {
    let mut inst = ready::<M>();
    let h = 1e-3;
    // cut for 0.1 s at the default speed, then stop the spindle for 60 s
    for k in 0..100 {
        inst.do_step(k as f64 * h, h).unwrap();
    }
    set_real(&mut inst, "spindle_speed", 0.0);
    let mut at_5s = (0, 0);
    for k in 100..60_100 {
        inst.do_step(k as f64 * h, h).unwrap();
        if k == 5_100 {
            at_5s = footprint(&inst);
        }
    }
    let at_60s = footprint(&inst);
    println!("0 rpm: history samples / serialized state bytes after 5 s {at_5s:?}, after 60 s {at_60s:?}");
    // before the fix: +500 000 samples (16 MB of state) per 5 s
    assert_eq!(at_5s.0, at_60s.0, "the history grows at 0 rpm");
    // (the counters' variable-length encoding may add a few bytes)
    assert!(at_60s.1 <= at_5s.1 + 16, "the state grows at 0 rpm: {at_5s:?} -> {at_60s:?}");
    assert!(at_60s.0 < 1000 && at_60s.1 < 100_000, "{at_60s:?}");
    // and the spindle starts again on the surface it left
    set_real(&mut inst, "spindle_speed", 2000.0);
    assert!(inst.do_step(60.1, 0.01).is_ok());
}

#[test]
fn cutting_below_the_lowest_speed_is_refused_not_buffered_without_bound() {
    let mut inst = ready::<M>();
    let n_min = inst.model().unwrap().plant().min_cutting_speed_rpm();
    assert!(n_min > 1.0 && n_min < 20.0, "{n_min}");
    set_real(&mut inst, "spindle_speed", n_min / 2.0);
    let err = inst.do_step(0.0, 1e-3).unwrap_err();
    let CallError::Discard(m) = err else { panic!("expected fmi2Discard, got {err:?}") };
    assert!(m.contains("lowest cutting speed"), "{m}");
    let mut inst = ready::<M>();
    set_real(&mut inst, "spindle_speed", n_min * 1.01);
    assert!(inst.do_step(0.0, 1e-3).is_ok());
}

/// An instance after 10 ms of cutting at the default speed (noise on).
fn cut_10_ms() -> Instance<M> {
    let mut inst = ready::<M>();
    for k in 0..10 {
        inst.do_step(k as f64 * 1e-3, 1e-3).unwrap();
    }
    inst
}

/// The serialized state of [`cut_10_ms`].
fn saved_state() -> Vec<u8> {
    cut_10_ms().snapshot().serialize().unwrap()
}

/// Every occurrence of the double `from` replaced, one at a time, by `to`: each must be refused.
fn each_copy_refused(bytes: &[u8], from: f64, to: f64, what: &str) -> usize {
    let pat = from.to_le_bytes();
    let hits: Vec<usize> = bytes.windows(8).enumerate().filter(|(_, w)| *w == pat).map(|(i, _)| i).collect();
    for &at in &hits {
        let mut bad = bytes.to_vec();
        bad[at..at + 8].copy_from_slice(&to.to_le_bytes());
        reseal(&mut bad);
        match fmi2_export::instance::Snapshot::<MillingPlant>::deserialize(&bad) {
            Err(CallError::Error(m)) => assert!(m.contains("invalid state"), "{what}: {m}"),
            other => panic!("{what} at byte {at} accepted: {:?}", other.is_ok()),
        }
    }
    hits.len()
}

#[test]
fn a_valid_saved_state_passes_validation() {
    let bytes = saved_state();
    assert!(fmi2_export::instance::Snapshot::<MillingPlant>::deserialize(&bytes).is_ok());
}

#[test]
fn restored_states_with_a_zero_internal_step_or_negative_f_max_are_refused() {
    let bytes = saved_state();
    // before: internal_step = 0 hung the next step, f_max < 0 panicked in clamp
    assert!(each_copy_refused(&bytes, 1e-5, 0.0, "internal_step = 0") >= 2);
    assert!(each_copy_refused(&bytes, 27.0, -1.0, "f_max = -1") >= 2);
}

#[test]
fn a_restored_state_with_a_disordered_history_is_refused() {
    let bytes = saved_state();
    // history sample times are cell·T: the sample at 5 ms moved after the present
    assert_eq!(each_copy_refused(&bytes, 500.0 * 1e-5, 1.0, "history sample out of order"), 1);
    assert!(each_copy_refused(&bytes, 500.0 * 1e-5, f64::NAN, "history sample not finite") >= 1);
}
