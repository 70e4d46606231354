//! A structure wired wrongly under the shipped process is refused by the Rust master before
//! any FMU is instantiated, with a message naming the connection: `DecomposedPlant.ssd` with
//! one connection changed (a velocity into a displacement input; a force into the structure's
//! displacement output). The unit rules themselves (scaled units, unknown units, conversions)
//! are unit-tested in `fmi-master/src/engine/assembly.rs`.

use fmi_master::SystemFile;
use packaging::{DECOMPOSED_PLANT_FMUS, DECOMPOSED_PLANT_SSD, fmu_dir, packaged};
use tests::{Short, run_short};

const SHIPPED: &str =
    r#"startElement="structure" startConnector="tool_x" endElement="process" endConnector="workpiece_x""#;

fn run_with(connection: &str) -> Result<(), String> {
    for f in DECOMPOSED_PLANT_FMUS {
        packaged(f);
    }
    assert!(DECOMPOSED_PLANT_SSD.contains(SHIPPED), "the shipped connection moved: update this test");
    let ssd = DECOMPOSED_PLANT_SSD.replace(SHIPPED, connection);
    let sys = SystemFile::from_text(&ssd, "DecomposedPlant (rewired)", &fmu_dir()).map_err(|e| e.to_string())?;
    let o = Short { stop: 1e-4, set: &[], record: &["process.force_x"], order: None };
    run_short(&sys, &o).map(|_| ()).map_err(|e| e.to_string())
}

#[test]
fn the_shipped_wiring_runs() {
    run_with(SHIPPED).unwrap();
}

#[test]
fn a_velocity_into_a_displacement_input_is_a_named_unit_mismatch() {
    let e = run_with(
        r#"startElement="structure" startConnector="tool_vx" endElement="process" endConnector="workpiece_x""#,
    )
    .unwrap_err();
    assert!(
        e.contains(
            "unit mismatch: connection structure.tool_vx → process.workpiece_x: structure.tool_vx is in m/s but \
             process.workpiece_x is in m (different physical dimensions)"
        ),
        "{e}"
    );
}

#[test]
fn a_connection_into_an_output_is_a_named_causality_error() {
    let e = run_with(
        r#"startElement="process" startConnector="workpiece_force_y" endElement="structure" endConnector="tool_x""#,
    )
    .unwrap_err();
    assert!(
        e.contains(
            "connection process.workpiece_force_y → structure.tool_x: the end structure.tool_x must be an input, it is Output"
        ),
        "{e}"
    );
}
