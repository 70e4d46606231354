//! The InertialActuator adapter: its table, parameter round trips, refusals and restored states.

use fmi2_export::table::checks;
use fmu_inertial_actuator::InertialActuator;

#[test]
fn the_xml_holds_exactly_the_table() {
    checks::description_matches_table::<InertialActuator>().unwrap();
}

#[test]
fn non_finite_inputs_are_refused_with_a_message() {
    checks::non_finite_inputs_are_refused::<InertialActuator>(1e-5).unwrap();
}

#[test]
fn randomly_corrupted_resealed_states_never_panic_or_hang() {
    let (refused, loaded) =
        checks::corrupted_states_after_steps::<InertialActuator>(10.0, 200, 1e-5, 0x2545_f491_4f6c_dd1d, 1000);
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
