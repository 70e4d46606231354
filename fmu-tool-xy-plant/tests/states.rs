//! The tool FMU through the instance state machine: the delay line and the damper survive
//! get/set and serialize/deserialize FMU state bitwise; a step that is not a whole number of
//! integration steps is discarded with a message; corrupted states are refused or run safely.

use fmi2_export::instance::{CallError, Instance, LogLevel, LogSink, Snapshot};
use fmi2_export::table::checks;
use fmi2_export::{Environment, Fmi2Model};
use fmu_tool_xy_plant::ToolXyPlant;
use model_description::{ScalarType, Value};

struct NoLog;
impl LogSink for NoLog {
    fn emit(&mut self, _level: LogLevel, _category: &str, _message: &str) {}
}

fn vr(name: &str) -> u32 {
    ToolXyPlant::description().variable(name).unwrap_or_else(|| panic!("no variable {name}")).value_reference
}

const H: f64 = 1e-4;

fn fresh() -> Instance<ToolXyPlant> {
    let mut inst = Instance::<ToolXyPlant>::new(Environment::default(), false, Box::new(NoLog));
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization().unwrap();
    inst.set("fmi2SetReal", ScalarType::Real, &[vr("A_x"), vr("A_y")], &[Value::Real(3.0), Value::Real(20.0)]).unwrap();
    inst.exit_initialization().unwrap();
    inst
}

fn real(inst: &mut Instance<ToolXyPlant>, name: &str) -> f64 {
    let mut out = Vec::new();
    inst.get("fmi2GetReal", ScalarType::Real, &[vr(name)], &mut out).unwrap();
    match out[0] {
        Value::Real(x) => x,
        ref v => panic!("{v:?}"),
    }
}

/// A velocity feedback through the inputs, so that the damper moves.
fn run(inst: &mut Instance<ToolXyPlant>, from: usize, to: usize) {
    for j in from..to {
        let (vx, vy) = (real(inst, "vx"), real(inst, "vy"));
        inst.set(
            "fmi2SetReal",
            ScalarType::Real,
            &[vr("u_x"), vr("u_y")],
            &[Value::Real(-2e3 * vx), Value::Real(-2e3 * vy)],
        )
        .unwrap();
        inst.do_step(j as f64 * H, H).unwrap();
    }
}

const WATCH: [&str; 10] = ["x", "y", "vx", "vy", "deflection_x", "deflection_y", "F_x", "F_y", "damper_x", "damper_y"];

fn watched(inst: &mut Instance<ToolXyPlant>) -> Vec<u64> {
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
    c.restore(&Snapshot::<ToolXyPlant>::deserialize(&bytes).unwrap());
    run(&mut c, 70, 160);
    assert_eq!(watched(&mut c), end);
}

#[test]
fn bad_steps_and_inputs_are_refused_with_a_message() {
    let mut inst = fresh();
    let CallError::Discard(m) = inst.do_step(0.0, 1.5e-5).unwrap_err() else { panic!("expected fmi2Discard") };
    assert!(m.contains("whole number"), "{m}");
    for x in [f64::NAN, f64::NEG_INFINITY, 2e9] {
        let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr("u_x")], &[Value::Real(x)]).unwrap_err();
        let (CallError::Error(m) | CallError::Discard(m)) = e;
        assert!(m.contains("u_x"), "{m}");
    }
}

#[test]
fn randomly_corrupted_resealed_states_never_panic_or_hang() {
    let mut inst = fresh();
    run(&mut inst, 0, 20);
    let (refused, loaded) = checks::corrupted_states_never_panic_or_hang::<ToolXyPlant>(
        &inst.snapshot().serialize().unwrap(),
        0x7001_0003_u64,
        300,
        fresh,
        H,
    );
    println!("random corruptions: {refused} refused, {loaded} loaded and stepped without panic");
}
