//! The ModalStructure adapter: the shared adapter checks, and the modal table file.

use fmi2_export::table::checks::{initializing, ready, set, stepped};
use fmu_modal_structure::{ModalStructure, StructureFmuParams};
use model_description::Value;

type M = ModalStructure;

fmi2_export::adapter_tests! {
    model: M,
    valid: [("modal_table", Value::String(modal_table_file())), ("n_modes", Value::Integer(3))],
    params: [{
        let mut p = StructureFmuParams::default();
        p.structure.n_modes = 4;
        p.structure.modes[2].tool = [0.1, -0.3];
        p.modal_table = "x.csv".into();
        p
    }],
    work: Work::Bound("internal_step"),
    step: 1e-5,
    states: { stepped: stepped::<M>(10.0, 200, 1e-5), fresh: ready::<M>, seed: 0x2545_f491_4f6c_dd1d, tries: 1000 },
}

/// A modal table file that exists, for the string parameter.
fn modal_table_file() -> String {
    let dir = std::env::temp_dir().join(format!("modal-table-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("modes.csv");
    std::fs::write(
        &file,
        "frequency,damping_ratio,modal_mass,tool_x,tool_y,actuator_x,actuator_y\n143,0.0088,30,1,0,1,0\n",
    )
    .unwrap();
    file.display().to_string()
}

#[test]
fn a_modal_table_file_replaces_the_mode_parameters() {
    let dir = std::env::temp_dir().join(format!("modal-table-b-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("modes.csv");
    std::fs::write(&file, "# two modes\n1000, 0.02, 1, 0.5, 0.1, 0.2, 0\n2500, 0.03, 1, -0.1, 0.4, 0, 0.3 # y mode\n")
        .unwrap();
    let mut inst = initializing::<M>();
    set(&mut inst, "modal_table", Value::String(file.display().to_string())).unwrap();
    inst.exit_initialization().unwrap();
    let p = inst.model().unwrap().structure().params();
    assert_eq!(p.n_modes, 2);
    assert!(p.modes[1].tool.iter().zip([-0.1, 0.4]).all(|(a, b)| (a - b).abs() < 1e-15));
    assert!((p.modes[0].frequency - 1000.0).abs() < 1e-12);
    // a broken table is refused at initialization with the file named
    std::fs::write(&file, "1000, 0.02\n").unwrap();
    let mut inst = initializing::<M>();
    set(&mut inst, "modal_table", Value::String(file.display().to_string())).unwrap();
    let e = inst.exit_initialization().unwrap_err();
    assert!(format!("{e:?}").contains("modes.csv"), "{e:?}");
}
