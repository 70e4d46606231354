//! The packaged MillingProcess.fmu through its C API (Rust master's importer): a NaN
//! displacement is discarded by fmi2SetReal (fmi2Discard, logged, naming the variable; the
//! instance keeps stepping), and an unphysical displacement makes fmi2DoStep return fmi2Discard
//! with a logged message.

use fmi_master::FmuError;
use fmi_master::import::Fmu;
use packaging::packaged;

#[test]
fn bad_displacements_into_the_process_fmu_are_refused_with_a_logged_message() {
    let fmu = Fmu::open(&packaged("MillingProcess.fmu")).unwrap();
    let vr = |name: &str| fmu.model_description().variable(name).unwrap().value_reference;
    let mut inst = fmu.instantiate("process", true, false).unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    inst.do_step(0.0, 1e-5).unwrap();
    // NaN: discarded by fmi2SetReal (the export layer checks every Real), logged
    let e = inst.set_real(&[vr("tool_x")], &[f64::NAN]).unwrap_err();
    assert!(format!("{e}").contains("fmi2SetReal"), "{e}");
    let FmuError::Call { status, .. } = &e else { panic!("{e}") };
    assert_eq!(*status, "fmi2Discard", "{e}");
    let logged = inst.log_lines().join("\n");
    assert!(logged.contains("tool_x") && logged.contains("not finite"), "{logged}");
    // the instance is still usable: the previous input stands and the next step runs
    inst.do_step(1e-5, 1e-5).unwrap();
    // a fresh instance: a finite but unphysical workpiece displacement reaches the model
    let mut inst = fmu.instantiate("process2", true, false).unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    inst.do_step(0.0, 1e-5).unwrap();
    inst.set_real(&[vr("workpiece_y")], &[5.0]).unwrap();
    let e = inst.do_step(1e-5, 1e-5).unwrap_err();
    let FmuError::Call { status, .. } = &e else { panic!("{e}") };
    assert_eq!(*status, "fmi2Discard", "{e}");
    let logged = inst.log_lines().join("\n");
    assert!(logged.contains("workpiece_y = 5 m"), "{logged}");
}
