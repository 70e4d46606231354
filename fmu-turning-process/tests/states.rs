//! The turning FMU: the shared adapter checks, and through the instance state machine: bitwise
//! equal to the core, bad inputs, restored states.

use fmi2_export::instance::{CallError, Instance, Snapshot};
use fmi2_export::table::checks::{ready, real, set_real, vr};
use fmu_turning_process::TurningProcessFmu;
use model_description::{ScalarType, Value};
use turning_process::{TurningInputs, TurningParams, TurningProcess};

type M = TurningProcessFmu;

const H: f64 = 5e-4;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [TurningParams { depth: 2.0, process_damping: 3.0, edge_angle: 60.0, ..Default::default() }],
    work: Work::Bound("max_step"),
    step: H,
    states: { stepped: driven(200), fresh: ready::<M>, seed: 0x5a17_3c9e_0b2d_4f61, tries: 300 },
}

/// A fresh instance after `steps` steps of [`drive`].
fn driven(steps: usize) -> Instance<M> {
    let mut inst = ready::<M>();
    drive(&mut inst, 0, steps);
    inst
}

fn inputs(j: usize) -> TurningInputs {
    TurningInputs { spindle_speed: 450.0 + 60.0 * (j as f64 * 0.01).sin(), feed: 0.1 + 0.02 * (j as f64 * 0.03).cos() }
}

/// Steps `from..to` (0.25 s for 500 steps: across the pulse and more than one revolution).
fn drive(inst: &mut Instance<M>, from: usize, to: usize) {
    for j in from..to {
        let i = inputs(j);
        set_real(inst, "spindle_speed", i.spindle_speed);
        set_real(inst, "feed", i.feed);
        inst.do_step(j as f64 * H, H).unwrap();
    }
}

#[test]
fn the_fmu_steps_the_core_bitwise() {
    let mut inst = ready::<M>();
    drive(&mut inst, 0, 500);
    let mut core = TurningProcess::new(&TurningParams::default()).unwrap();
    for j in 0..500 {
        core.set_time(j as f64 * H);
        core.step(H, &inputs(j)).unwrap();
    }
    let o = core.outputs();
    for (n, c) in [("x", o.x), ("v", o.v), ("q", o.force), ("chip", o.chip), ("delay", o.delay), ("angle", o.angle)] {
        assert_eq!(real(&mut inst, n).to_bits(), c.to_bits(), "{n}");
    }
    // the pulse has excited the tool and the delay is about one revolution
    assert!(o.x.abs() > 0.0 && o.delay > 0.1 && o.delay < 0.15, "{o:?}");
}

#[test]
fn state_survives_serialize_bitwise() {
    let mut a = ready::<M>();
    drive(&mut a, 0, 200);
    let bytes = a.snapshot().serialize().unwrap();
    drive(&mut a, 200, 500);
    let mut b = ready::<M>();
    b.restore(&Snapshot::<M>::deserialize(&bytes).unwrap());
    drive(&mut b, 200, 500);
    for n in ["x", "v", "q", "chip", "delay", "angle"] {
        assert_eq!(real(&mut a, n).to_bits(), real(&mut b, n).to_bits(), "{n}");
    }
}

#[test]
fn non_finite_or_out_of_range_inputs_are_refused_with_a_message() {
    let mut inst = ready::<M>();
    for x in [f64::NAN, f64::NEG_INFINITY, -1.0] {
        let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr::<M>("feed")], &[Value::Real(x)]).unwrap_err();
        let (CallError::Error(m) | CallError::Discard(m)) = e;
        assert!(m.contains("feed"), "{m}");
    }
    // a speed too slow for the history is a stopped spindle (issue 31: it was discarded, and
    // FMPy's simulate_ssp, which starts every connection at 0, failed at once): no cut
    set_real(&mut inst, "spindle_speed", 1.0);
    inst.do_step(0.0, H).unwrap();
    assert_eq!((real(&mut inst, "chip"), real(&mut inst, "angle")), (0.0, 0.0));
}
