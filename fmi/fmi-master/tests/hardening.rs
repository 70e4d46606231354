//! Regression tests of the hardening issue, through the `cosim` command line
//! (each failed on the code before the `ssp`/`fmi-archive` crates):
//! a deeply nested SSD, a zip-bomb FMU, an `.ssp` missing a component's FMU,
//! two values for one SSP parameter, and an I/O error quoted twice.

mod common;

use common::{cosim, fmu_dir, packaged, rewrite_zip, run};
use std::path::Path;

fn closed_loop_ssd() -> String {
    ssp::read_ssd_from_ssp(&packaged("ClosedLoop.ssp")).unwrap()
}

/// 300 000 nested elements (2 MB) made `cosim info` abort with a stack overflow.
#[test]
fn info_on_a_deeply_nested_ssd_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let n = 300_000;
    // Exactly what aborted the old reader: a default namespace and 300 000 nested <a>, 2.1 MB.
    let xml = format!(
        "<SystemStructureDescription xmlns=\"{}\" version=\"1.0\" name=\"deep\">{}{}</SystemStructureDescription>",
        ssp::NS_SSD,
        "<a>".repeat(n),
        "</a>".repeat(n)
    );
    assert!(xml.len() > 2_000_000);
    let path = dir.path().join("deep.ssd");
    std::fs::write(&path, xml).unwrap();
    let (ok, _, err) = run(cosim().arg("info").arg(&path));
    assert!(!ok);
    assert!(
        err.starts_with("error: ") && err.contains("deep.ssd: line 1: elements are nested more than 64 levels deep"),
        "{err}"
    );
}

/// A 3 MB FMU could expand to 1 GiB: only the total (8 GiB) was limited.
#[test]
fn an_fmu_with_a_zip_bomb_entry_is_refused_before_extraction() {
    let dir = tempfile::tempdir().unwrap();
    let bomb = dir.path().join("MillingPlant.fmu");
    rewrite_zip(&packaged("MillingPlant.fmu"), &bomb, |_, data| Some(data));
    {
        use std::io::Write;
        let f = std::fs::OpenOptions::new().read(true).write(true).open(&bomb).unwrap();
        let mut z = zip::ZipWriter::new_append(f).unwrap();
        let opts = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
        z.start_file("resources/zeros.bin", opts).unwrap();
        z.write_all(&vec![0u8; 16 << 20]).unwrap();
        z.finish().unwrap();
    }
    let tmp = tempfile::tempdir().unwrap();
    let (ok, _, err) = run(cosim()
        .env("TMPDIR", tmp.path())
        .arg("run")
        .arg(&bomb)
        .args(["--stop-time", "0.001", "-o"])
        .arg(dir.path().join("x.csv")));
    assert!(!ok);
    assert!(err.contains("entry 'resources/zeros.bin' expands from") && err.contains("zip bomb"), "{err}");
    assert!(std::fs::read_dir(tmp.path()).unwrap().next().is_none(), "nothing extracted, nothing left");
}

/// An .ssp without a component's FMU used to fall back silently to `--fmu-dir`.
#[test]
fn an_ssp_missing_a_component_fmu_names_it_and_uses_no_other() {
    let dir = tempfile::tempdir().unwrap();
    let ssp_path = dir.path().join("NoPlant.ssp");
    let mut zip = fmi_archive::ZipBuilder::new();
    zip.file("SystemStructure.ssd", closed_loop_ssd(), fmi_archive::Compression::Deflated).directory("resources").file(
        "resources/ChatterController.fmu",
        std::fs::read(packaged("ChatterController.fmu")).unwrap(),
        fmi_archive::Compression::Stored,
    );
    zip.write_to(&ssp_path).unwrap();
    assert!(fmu_dir().join("MillingPlant.fmu").is_file(), "the fallback the old code used exists");
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&ssp_path)
        .arg("--fmu-dir")
        .arg(fmu_dir())
        .args(["--stop-time", "0.001", "-o"])
        .arg(dir.path().join("x.csv")));
    assert!(!ok, "must not run with target/fmu/MillingPlant.fmu");
    assert!(
        err.contains("component plant: FMU 'resources/MillingPlant.fmu' not found")
            && err.contains("NoPlant.ssp!resources/MillingPlant.fmu"),
        "{err}"
    );
}

#[test]
fn two_values_for_one_ssp_parameter_are_refused_with_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let ssd = closed_loop_ssd().replace(
        "<ssd:Elements>",
        r#"<ssd:ParameterBindings>
      <ssd:ParameterBinding>
        <ssd:ParameterValues>
          <ssv:ParameterSet version="1.0" name="twice">
            <ssv:Parameters>
              <ssv:Parameter name="plant.spindle_speed"><ssv:Real value="2000"/></ssv:Parameter>
              <ssv:Parameter name="plant.spindle_speed"><ssv:Real value="2500"/></ssv:Parameter>
            </ssv:Parameters>
          </ssv:ParameterSet>
        </ssd:ParameterValues>
      </ssd:ParameterBinding>
    </ssd:ParameterBindings>
    <ssd:Elements>"#,
    );
    let path = dir.path().join("Twice.ssd");
    std::fs::write(&path, ssd).unwrap();
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(&path)
        .arg("--fmu-dir")
        .arg(fmu_dir())
        .args(["--stop-time", "0.001", "-o"])
        .arg(dir.path().join("x.csv")));
    assert!(!ok);
    assert!(
        err.contains(
            "Twice.ssd: parameter plant.spindle_speed is given two values in one parameter binding (2000 and 2500)"
        ),
        "{err}"
    );
}

/// "File exists (os error 17): File exists (os error 17)": the cause was printed twice.
#[test]
fn an_io_error_is_stated_once() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, b"").unwrap();
    let (ok, _, err) = run(cosim()
        .arg("run")
        .arg(packaged("ClosedLoop.ssp"))
        .args(["--stop-time", "0.001", "-o"])
        .arg(file.join("x.csv")));
    assert!(!ok);
    assert!(err.contains(&format!("writing {}: File exists (os error 17)", file.display())), "{err}");
    assert_eq!(err.matches("os error 17").count(), 1, "{err}");
    assert!(Path::new(&file).is_file());
}
