//! `.ssp` archives: written deterministically, read back with and without
//! extraction, self-contained.

use ssp::*;
use std::path::Path;

const SSD: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="S">
  <ssd:System name="S">
    <ssd:Elements>
      <ssd:Component name="a" source="resources/A.fmu"/>
      <ssd:Component name="b" source="resources/B.fmu">
        <ssd:ParameterBindings><ssd:ParameterBinding source="resources/b.ssv"/></ssd:ParameterBindings>
      </ssd:Component>
    </ssd:Elements>
  </ssd:System>
</ssd:SystemStructureDescription>
"#;

fn fmus(dir: &Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let (a, b) = (dir.join("A.fmu"), dir.join("B.fmu"));
    std::fs::write(&a, b"fake A").unwrap();
    std::fs::write(&b, b"fake B").unwrap();
    (a, b)
}

#[test]
fn ssp_archive_is_written_deterministically_and_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = fmus(dir.path());
    let mut d = SystemDescription::from_xml(
        SSD.replace(
            "<ssd:ParameterBindings><ssd:ParameterBinding source=\"resources/b.ssv\"/></ssd:ParameterBindings>",
            "",
        )
        .as_str(),
        "s",
        None,
    )
    .unwrap();
    d.components[1].parameters.push(Parameter { name: "k".into(), value: ParamValue::Real(2.0, None) });
    let ssd = d.to_xml().unwrap();
    let out = dir.path().join("out/Sys.ssp");
    write_ssp(&out, &d, &[("A.fmu", &a), ("B.fmu", &b)]).unwrap();
    let first = std::fs::read(&out).unwrap();
    write_ssp_archive(&out, &ssd, &[("A.fmu", &a), ("B.fmu", &b)]).unwrap();
    assert_eq!(std::fs::read(&out).unwrap(), first, "same input, same bytes");
    assert_eq!(read_ssd_from_ssp(&out).unwrap(), ssd);
    assert_eq!(read_ssp(&out).unwrap(), d);
    let dest = tempfile::tempdir().unwrap();
    assert_eq!(extract_ssp(&out, dest.path()).unwrap(), d);
    assert_eq!(std::fs::read(dest.path().join("resources/B.fmu")).unwrap(), b"fake B");
    // A component whose FMU is not packed is refused.
    let e = write_ssp_archive(&out, &ssd, &[("A.fmu", &a)]).unwrap_err().to_string();
    assert!(e.contains("component b has source resources/B.fmu, which is not among the FMUs packed (A.fmu)"), "{e}");
    let e = write_ssp_archive(&out, &ssd, &[("../A.fmu", &a), ("B.fmu", &b)]).unwrap_err().to_string();
    assert!(e.contains("FMU name ../A.fmu must be a plain file name"), "{e}");
}

#[test]
fn ssv_sources_are_read_from_the_archive_with_or_without_extraction() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = fmus(dir.path());
    let ssv = format!(
        r#"<ssv:ParameterSet xmlns:ssv="{NS_SSV}" version="1.0" name="b"><ssv:Parameters><ssv:Parameter name="k"><ssv:Boolean value="false"/></ssv:Parameter></ssv:Parameters></ssv:ParameterSet>"#
    );
    let out = dir.path().join("S.ssp");
    let mut zip = fmi_archive::ZipBuilder::new();
    zip.file(SSD_ENTRY, SSD, fmi_archive::Compression::Deflated)
        .file("resources/A.fmu", std::fs::read(&a).unwrap(), fmi_archive::Compression::Stored)
        .file("resources/B.fmu", std::fs::read(&b).unwrap(), fmi_archive::Compression::Stored)
        .file("resources/b.ssv", ssv, fmi_archive::Compression::Deflated);
    zip.write_to(&out).unwrap();
    let want = vec![Parameter { name: "k".into(), value: ParamValue::Boolean(false) }];
    assert_eq!(read_ssp(&out).unwrap().components[1].parameters, want);
    let dest = tempfile::tempdir().unwrap();
    assert_eq!(extract_ssp(&out, dest.path()).unwrap().components[1].parameters, want);
}

#[test]
fn an_archive_without_an_ssd_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("Empty.ssp");
    let mut zip = fmi_archive::ZipBuilder::new();
    zip.directory("resources");
    zip.write_to(&out).unwrap();
    let e = read_ssp(&out).unwrap_err().to_string();
    assert!(e.contains("Empty.ssp: the archive has no SystemStructure.ssd"), "{e}");
    let dest = tempfile::tempdir().unwrap();
    let e = extract_ssp(&out, dest.path()).unwrap_err().to_string();
    assert!(e.contains("Empty.ssp: the archive has no SystemStructure.ssd"), "{e}");
}
