//! The MillingProcess adapter: its table, parameter round trips, refusals and restored states.

use fmi2_export::instance::{CallError, Instance, LogLevel, LogSink};
use fmi2_export::table::checks;
use fmi2_export::{Environment, Fmi2Model};
use fmu_milling_process::MillingProcess;
use milling_process::ProcessParams;
use model_description::{ScalarType, Value};
use std::sync::{Arc, Mutex};

#[derive(Clone, Default)]
struct Log(Arc<Mutex<Vec<String>>>);
impl LogSink for Log {
    fn emit(&mut self, _level: LogLevel, _category: &str, message: &str) {
        self.0.lock().unwrap().push(message.to_string());
    }
}

fn vr(name: &str) -> u32 {
    MillingProcess::description().variable(name).unwrap_or_else(|| panic!("no variable {name}")).value_reference
}

fn ready() -> (Instance<MillingProcess>, Log) {
    let log = Log::default();
    let mut inst = Instance::<MillingProcess>::new(Environment::default(), true, Box::new(log.clone()));
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization().unwrap();
    inst.exit_initialization().unwrap();
    (inst, log)
}

#[test]
fn the_xml_holds_exactly_the_table() {
    checks::description_matches_table::<MillingProcess>().unwrap();
}

#[test]
fn every_parameter_set_through_the_api_reaches_the_core() {
    checks::parameter_round_trips::<MillingProcess>(&[
        // the window must stay in [0, pi] with entry < exit
        ("entry_angle", Value::Real(0.3)),
        ("exit_angle", Value::Real(2.0)),
    ])
    .unwrap();
}

#[test]
fn assignments_round_trip_and_cover_every_field() {
    checks::assignments_round_trip::<MillingProcess>(&ProcessParams::default()).unwrap();
    let mut p = ProcessParams::default();
    p.coefficients.law = milling_process::ForceLaw::Power;
    p.coefficients.exponent = 0.744;
    p.variable_pitch = true;
    p.tooth_angles[1] = 1.4;
    checks::assignments_round_trip::<MillingProcess>(&p).unwrap();
    checks::parameter_coverage::<MillingProcess>().unwrap();
}

#[test]
fn start_values_give_the_default_parameters() {
    let v = fmi2_export::Values::from_description(MillingProcess::description());
    assert_eq!(fmu_milling_process::TABLE.read_parameters(&v).unwrap(), ProcessParams::default());
}

#[test]
fn a_nan_or_an_out_of_range_displacement_is_discarded_with_a_message() {
    let (mut inst, log) = ready();
    // NaN: the export layer discards the value itself, naming the variable (fmi2SetReal -> fmi2Discard)
    let e = inst.set("fmi2SetReal", ScalarType::Real, &[vr("tool_x")], &[Value::Real(f64::NAN)]).unwrap_err();
    let CallError::Discard(m) = e else { panic!("expected fmi2Discard, got {e:?}") };
    assert!(m.contains("tool_x") && m.contains("not finite"), "{m}");
    // the instance is still usable: a step runs
    inst.do_step(0.0, 1e-5).unwrap();
    // a finite but unphysical displacement reaches the model: fmi2Discard with a logged message, no step
    inst.set("fmi2SetReal", ScalarType::Real, &[vr("workpiece_y")], &[Value::Real(5.0)]).unwrap();
    let e = inst.do_step(1e-5, 1e-5).unwrap_err();
    let CallError::Discard(m) = e else { panic!("expected fmi2Discard, got {e:?}") };
    assert!(m.contains("workpiece_y"), "{m}");
    // (the C boundary, fmi2-export's ffi, logs every refusal's message under logStatusDiscard /
    // logStatusError before returning the status; the messages are these)
    drop(log);
    assert!((inst.model().unwrap().process().time() - 1e-5).abs() < 1e-20, "the refused step was taken");
}

#[test]
fn randomly_corrupted_resealed_states_never_panic_or_hang() {
    let (mut inst, _) = ready();
    for k in 0..1000 {
        inst.do_step(k as f64 * 1e-5, 1e-5).unwrap();
    }
    let bytes = inst.snapshot().serialize().unwrap();
    let (refused, loaded) = checks::corrupted_states_never_panic_or_hang::<MillingProcess>(
        &bytes,
        0x9e37_79b9_7f4a_7c15,
        1000,
        || ready().0,
        1e-5,
    );
    println!("random corruptions: {refused} refused, {loaded} loaded and stepped without panic");
    assert!(refused > 0);
}
