//! The turning FMU through the instance state machine: bitwise equal to the core, bad inputs,
//! restored states.

use fmi2_export::instance::{CallError, Instance, LogLevel, LogSink, Snapshot};
use fmi2_export::table::checks;
use fmi2_export::{Environment, Fmi2Model};
use fmu_turning_process::TurningProcessFmu;
use model_description::{ScalarType, Value};
use turning_process::{TurningInputs, TurningParams, TurningProcess};

struct NoLog;
impl LogSink for NoLog {
    fn emit(&mut self, _level: LogLevel, _category: &str, _message: &str) {}
}

fn vr(name: &str) -> u32 {
    TurningProcessFmu::description().variable(name).unwrap_or_else(|| panic!("no variable {name}")).value_reference
}

fn fresh() -> Instance<TurningProcessFmu> {
    let mut inst = Instance::<TurningProcessFmu>::new(Environment::default(), false, Box::new(NoLog));
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization().unwrap();
    inst.exit_initialization().unwrap();
    inst
}

fn set(inst: &mut Instance<TurningProcessFmu>, name: &str, x: f64) {
    inst.set("fmi2SetReal", ScalarType::Real, &[vr(name)], &[Value::Real(x)]).unwrap();
}

fn real(inst: &mut Instance<TurningProcessFmu>, name: &str) -> f64 {
    let mut out = Vec::new();
    inst.get("fmi2GetReal", ScalarType::Real, &[vr(name)], &mut out).unwrap();
    match out[0] {
        Value::Real(x) => x,
        ref v => panic!("{v:?}"),
    }
}

const H: f64 = 5e-4;

fn inputs(j: usize) -> TurningInputs {
    TurningInputs { spindle_speed: 450.0 + 60.0 * (j as f64 * 0.01).sin(), feed: 0.1 + 0.02 * (j as f64 * 0.03).cos() }
}

/// Steps `from..to` (0.25 s for 500 steps: across the pulse and more than one revolution).
fn drive(inst: &mut Instance<TurningProcessFmu>, from: usize, to: usize) {
    for j in from..to {
        let i = inputs(j);
        set(inst, "spindle_speed", i.spindle_speed);
        set(inst, "feed", i.feed);
        inst.do_step(j as f64 * H, H).unwrap();
    }
}

#[test]
fn the_fmu_steps_the_core_bitwise() {
    let mut inst = fresh();
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
fn state_survives_serialize_bitwise_and_corruptions_never_panic() {
    let mut a = fresh();
    drive(&mut a, 0, 200);
    let bytes = a.snapshot().serialize().unwrap();
    drive(&mut a, 200, 500);
    let mut b = fresh();
    b.restore(&Snapshot::<TurningProcessFmu>::deserialize(&bytes).unwrap());
    drive(&mut b, 200, 500);
    for n in ["x", "v", "q", "chip", "delay", "angle"] {
        assert_eq!(real(&mut a, n).to_bits(), real(&mut b, n).to_bits(), "{n}");
    }
    let (refused, loaded) =
        checks::corrupted_states_never_panic_or_hang::<TurningProcessFmu>(&bytes, 0x5a17_3c9e_0b2d_4f61, 300, fresh, H);
    println!("random corruptions: {refused} refused, {loaded} loaded and stepped without panic");
}

#[test]
fn non_finite_or_out_of_range_inputs_are_refused_with_a_message() {
    checks::non_finite_inputs_are_refused::<TurningProcessFmu>(H).unwrap();
    let mut inst = fresh();
    for x in [f64::NAN, f64::NEG_INFINITY, -1.0] {
        let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr("feed")], &[Value::Real(x)]).unwrap_err();
        let (CallError::Error(m) | CallError::Discard(m)) = e;
        assert!(m.contains("feed"), "{m}");
    }
    // a speed too slow for the history: the step is discarded, the state stays at t = 0
    set(&mut inst, "spindle_speed", 1.0);
    let e = inst.do_step(0.0, H).unwrap_err();
    let CallError::Discard(m) = e else { panic!("expected fmi2Discard, got {e:?}") };
    assert!(m.contains("spindle_speed"), "{m}");
    assert_eq!(real(&mut inst, "x").to_bits(), 0.0f64.to_bits());
}
