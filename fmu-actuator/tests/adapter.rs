//! The InertialActuator adapter: its table, parameter round trips, refusals and restored states.

use fmi2_export::instance::{CallError, Instance, LogLevel, LogSink};
use fmi2_export::table::checks;
use fmi2_export::{Environment, Fmi2Model};
use fmu_actuator::InertialActuator;
use model_description::{ScalarType, Value};

struct Quiet;
impl LogSink for Quiet {
    fn emit(&mut self, _level: LogLevel, _category: &str, _message: &str) {}
}

fn vr(name: &str) -> u32 {
    InertialActuator::description().variable(name).unwrap_or_else(|| panic!("no variable {name}")).value_reference
}

fn ready() -> Instance<InertialActuator> {
    let mut inst = Instance::<InertialActuator>::new(Environment::default(), false, Box::new(Quiet));
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization().unwrap();
    inst.exit_initialization().unwrap();
    inst
}

#[test]
fn the_xml_holds_exactly_the_table() {
    checks::description_matches_table::<InertialActuator>().unwrap();
}

#[test]
fn a_non_finite_input_is_refused_with_a_message() {
    let mut inst = ready();
    let name = fmu_actuator::TABLE.vars.inputs[0].attrs.name;
    let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr(name)], &[Value::Real(f64::INFINITY)]).unwrap_err();
    let CallError::Error(m) = e else { panic!("{e:?}") };
    assert!(m.contains(name), "{m}");
    inst.do_step(0.0, 1e-5).unwrap();
}

#[test]
fn randomly_corrupted_resealed_states_never_panic_or_hang() {
    let mut inst = ready();
    let name = fmu_actuator::TABLE.vars.inputs[0].attrs.name;
    inst.set("fmi2SetReal", ScalarType::Real, &[vr(name)], &[Value::Real(10.0)]).unwrap();
    for k in 0..200 {
        inst.do_step(k as f64 * 1e-5, 1e-5).unwrap();
    }
    let bytes = inst.snapshot().serialize().unwrap();
    let (refused, loaded) = checks::corrupted_states_never_panic_or_hang::<InertialActuator>(
        &bytes,
        0x2545_f491_4f6c_dd1d,
        1000,
        ready,
        1e-5,
    );
    println!("random corruptions: {refused} refused, {loaded} loaded and stepped without panic");
    assert!(refused > 0);
}

#[test]
fn parameters_round_trip_and_cover_every_field() {
    checks::parameter_round_trips::<InertialActuator>(&[]).unwrap();
    let mut p = machine_structure::ActuatorParams::default();
    checks::assignments_round_trip::<InertialActuator>(&p).unwrap();
    p.direction_angle = 0.5;
    p.a[1][0] = 0.7;
    checks::assignments_round_trip::<InertialActuator>(&p).unwrap();
    checks::parameter_coverage::<InertialActuator>().unwrap();
}
