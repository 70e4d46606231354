//! The ModalStructure adapter: its table, parameter round trips, refusals and restored states.

use fmi2_export::instance::{Instance, LogLevel, LogSink};
use fmi2_export::table::checks;
use fmi2_export::{Environment, Fmi2Model};
use fmu_modal_structure::ModalStructure;
use model_description::{ScalarType, Value};

struct Quiet;
impl LogSink for Quiet {
    fn emit(&mut self, _level: LogLevel, _category: &str, _message: &str) {}
}

fn vr(name: &str) -> u32 {
    ModalStructure::description().variable(name).unwrap_or_else(|| panic!("no variable {name}")).value_reference
}

#[test]
fn the_xml_holds_exactly_the_table() {
    checks::description_matches_table::<ModalStructure>().unwrap();
}

#[test]
fn non_finite_inputs_are_refused_with_a_message() {
    checks::non_finite_inputs_are_refused::<ModalStructure>(1e-5).unwrap();
}

#[test]
fn randomly_corrupted_resealed_states_never_panic_or_hang() {
    let (refused, loaded) =
        checks::corrupted_states_after_steps::<ModalStructure>(10.0, 200, 1e-5, 0x2545_f491_4f6c_dd1d, 1000);
    println!("random corruptions: {refused} refused, {loaded} loaded and stepped without panic");
    assert!(refused > 0);
}

#[test]
fn parameters_round_trip_and_cover_every_field() {
    // a modal table file that exists, for the string parameter
    let dir = std::env::temp_dir().join(format!("modal-table-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("modes.csv");
    std::fs::write(
        &file,
        "frequency,damping_ratio,modal_mass,tool_x,tool_y,actuator_x,actuator_y\n143,0.0088,30,1,0,1,0\n",
    )
    .unwrap();
    checks::parameter_round_trips::<ModalStructure>(&[
        ("modal_table", Value::String(file.display().to_string())),
        ("n_modes", Value::Integer(3)),
    ])
    .unwrap();
    let mut p = fmu_modal_structure::StructureFmuParams::default();
    checks::assignments_round_trip::<ModalStructure>(&p).unwrap();
    p.structure.n_modes = 4;
    p.structure.modes[2].tool = [0.1, -0.3];
    p.modal_table = "x.csv".into();
    checks::assignments_round_trip::<ModalStructure>(&p).unwrap();
    checks::parameter_coverage::<ModalStructure>().unwrap();
}

#[test]
fn a_modal_table_file_replaces_the_mode_parameters() {
    let dir = std::env::temp_dir().join(format!("modal-table-b-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("modes.csv");
    std::fs::write(&file, "# two modes\n1000, 0.02, 1, 0.5, 0.1, 0.2, 0\n2500, 0.03, 1, -0.1, 0.4, 0, 0.3 # y mode\n")
        .unwrap();
    let mut inst = Instance::<ModalStructure>::new(Environment::default(), false, Box::new(Quiet));
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization().unwrap();
    inst.set("fmi2SetString", ScalarType::String, &[vr("modal_table")], &[Value::String(file.display().to_string())])
        .unwrap();
    inst.exit_initialization().unwrap();
    let p = inst.model().unwrap().structure().params();
    assert_eq!(p.n_modes, 2);
    assert!(p.modes[1].tool.iter().zip([-0.1, 0.4]).all(|(a, b)| (a - b).abs() < 1e-15));
    assert!((p.modes[0].frequency - 1000.0).abs() < 1e-12);
    // a broken table is refused at initialization with the file named
    std::fs::write(&file, "1000, 0.02\n").unwrap();
    let mut inst = Instance::<ModalStructure>::new(Environment::default(), false, Box::new(Quiet));
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization().unwrap();
    inst.set("fmi2SetString", ScalarType::String, &[vr("modal_table")], &[Value::String(file.display().to_string())])
        .unwrap();
    let e = inst.exit_initialization().unwrap_err();
    assert!(format!("{e:?}").contains("modes.csv"), "{e:?}");
}
