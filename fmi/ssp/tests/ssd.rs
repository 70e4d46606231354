//! Reading and writing `SystemStructure.ssd`: foreign prefixes, round trips,
//! clear errors, parameter bindings, and the hardening cases (deep nesting,
//! two values for one parameter).

use ssp::*;

const FOREIGN: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<SystemStructureDescription xmlns="http://ssp-standard.org/SSP1/SystemStructureDescription"
    xmlns:c="http://ssp-standard.org/SSP1/SystemStructureCommon"
    xmlns:v="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="Foreign">
  <System name="Root">
    <ParameterBindings>
      <ParameterBinding prefix="b.">
        <ParameterValues>
          <v:ParameterSet version="1.0" name="sys">
            <v:Parameters>
              <v:Parameter name="gain"><v:Real value="2.5" unit="1"/></v:Parameter>
            </v:Parameters>
          </v:ParameterSet>
        </ParameterValues>
      </ParameterBinding>
    </ParameterBindings>
    <Elements>
      <Component name="a" source="resources/A.fmu" implementation="CoSimulation">
        <Connectors>
          <Connector name="y" kind="output"><c:Real unit="m"/></Connector>
        </Connectors>
        <ParameterBindings>
          <ParameterBinding>
            <ParameterValues>
              <v:ParameterSet version="1.0" name="a">
                <v:Parameters>
                  <v:Parameter name="n"><v:Integer value="-3"/></v:Parameter>
                  <v:Parameter name="on"><v:Boolean value="true"/></v:Parameter>
                  <v:Parameter name="mode"><v:Enumeration value="fast"/></v:Parameter>
                  <v:Parameter name="label"><v:String value="a &amp; b"/></v:Parameter>
                </v:Parameters>
              </v:ParameterSet>
            </ParameterValues>
          </ParameterBinding>
        </ParameterBindings>
      </Component>
      <Component name="b" source="resources/B.fmu">
        <Connectors><Connector name="u" kind="input"/></Connectors>
      </Component>
    </Elements>
    <Connections>
      <Connection startElement="a" startConnector="y" endElement="b" endConnector="u">
        <c:LinearTransformation factor="1000" offset="0.5"/>
      </Connection>
    </Connections>
  </System>
  <DefaultExperiment startTime="0" stopTime="2.5">
    <Annotations>
      <c:Annotation type="com.example.other"><x:Settings xmlns:x="urn:other" stepSize="not ours"/></c:Annotation>
    </Annotations>
  </DefaultExperiment>
</SystemStructureDescription>"#;

fn foreign() -> SystemDescription {
    SystemDescription::from_xml(FOREIGN, "foreign.ssd", None).unwrap()
}

fn err(xml: &str) -> String {
    SystemDescription::from_xml(xml, "x.ssd", None).unwrap_err().to_string()
}

#[test]
fn parses_a_description_with_other_prefixes() {
    let d = foreign();
    assert_eq!(d.name, "Foreign");
    assert_eq!(d.system_name, "Root");
    assert_eq!(d.generation_tool, None);
    assert_eq!(d.components.len(), 2);
    let a = d.component("a").unwrap();
    assert_eq!(a.source, "resources/A.fmu");
    assert_eq!(
        a.connectors[0],
        Connector { name: "y".into(), kind: ConnectorKind::Output, ty: Some(ConnectorType::Real(Some("m".into()))) }
    );
    assert_eq!(
        a.parameters,
        vec![
            Parameter { name: "n".into(), value: ParamValue::Integer(-3) },
            Parameter { name: "on".into(), value: ParamValue::Boolean(true) },
            Parameter { name: "mode".into(), value: ParamValue::Enumeration("fast".into()) },
            Parameter { name: "label".into(), value: ParamValue::String("a & b".into()) },
        ]
    );
    assert_eq!(d.parameters, vec![Parameter { name: "b.gain".into(), value: ParamValue::Real(2.5, Some("1".into())) }]);
    assert_eq!(d.connections[0].linear, Some(Linear { factor: 1000.0, offset: 0.5 }));
    assert_eq!(d.connections[0].label(), "a.y → b.u");
    assert_eq!((d.start_time, d.stop_time), (Some(0.0), Some(2.5)));
    // Another tool's annotation is not ours: ignored.
    assert_eq!(d.master, MasterSettings::default());
}

#[test]
fn write_then_parse_round_trips() {
    let mut d = foreign();
    d.master =
        MasterSettings { step_size: Some(1e-5), order: Some(Order::Jacobi), sequence: vec!["b".into(), "a".into()] };
    d.description = Some("quote \" and <tag> & 'apostrophe'".into());
    d.generation_tool = Some("a test".into());
    let xml = d.to_xml().unwrap();
    let back = SystemDescription::from_xml(&xml, "written.ssd", None).unwrap();
    assert_eq!(back, d);
    // Canonical: writing again gives the same text.
    assert_eq!(back.to_xml().unwrap(), xml);
    assert!(xml.contains("stepSize=\"1e-5\""), "{xml}");
    assert!(xml.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<ssd:SystemStructureDescription"), "{xml}");
    assert!(xml.contains("<ssv:Parameter name=\"b.gain\">"), "{xml}");
    // A new description names this crate as its generation tool.
    let empty = SystemDescription::new("E");
    let text = empty.to_xml().unwrap();
    assert!(text.contains("generationTool=\"chatter-fmu ssp "), "{text}");
    assert_eq!(SystemDescription::from_xml(&text, "e.ssd", None).unwrap(), empty);
}

#[test]
fn numbers_are_written_to_read_back_exactly() {
    let mut d = SystemDescription::new("N");
    let values = [0.1, 1.0 / 3.0, -2.5e-300, 6.02214076e23, 30.0, f64::INFINITY, f64::NEG_INFINITY];
    d.parameters = values
        .iter()
        .enumerate()
        .map(|(i, x)| Parameter { name: format!("c.p{i}"), value: ParamValue::Real(*x, None) })
        .collect();
    let back = SystemDescription::from_xml(&d.to_xml().unwrap(), "n.ssd", None).unwrap();
    for (p, x) in back.parameters.iter().zip(values) {
        let ParamValue::Real(y, None) = p.value else { panic!("{p:?}") };
        assert_eq!(y.to_bits(), x.to_bits(), "{}", p.name);
    }
}

/// Writes `target/ssd-test/Full.ssd` (every construct the writer emits:
/// system and component bindings of all five types, typed connectors, a
/// linear transformation, the master annotation), which
/// `tests/python/test_ssd_schema.py` validates against the SSP 1.0 XSD.
#[test]
fn writes_a_full_description_for_schema_validation() {
    let mut d = foreign();
    d.master = MasterSettings {
        step_size: Some(1e-5),
        order: Some(Order::GaussSeidel),
        sequence: vec!["b".into(), "a".into()],
    };
    d.description = Some("all constructs".into());
    let b = &mut d.components[1];
    for (name, kind, ty) in [
        ("mode", ConnectorKind::Parameter, ConnectorType::Enumeration("Mode".into())),
        ("n", ConnectorKind::Input, ConnectorType::Integer),
        ("b", ConnectorKind::Output, ConnectorType::Boolean),
        ("s", ConnectorKind::Parameter, ConnectorType::String),
        ("r", ConnectorKind::CalculatedParameter, ConnectorType::Real(None)),
    ] {
        b.connectors.push(Connector { name: name.into(), kind, ty: Some(ty) });
    }
    let xml = d.to_xml().unwrap();
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target"));
    let dir = target.join("ssd-test");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("Full.ssd"), &xml).unwrap();
    assert_eq!(SystemDescription::from_xml(&xml, "Full.ssd", None).unwrap(), d);
}

#[test]
fn malformed_descriptions_are_clear_errors() {
    let e = err("<a><b></a>");
    assert!(e.contains("x.ssd: XML error: line 1"), "{e}");
    let e = err("<root/>");
    assert!(e.contains("expected ssd:SystemStructureDescription"), "{e}");
    let e = err(&FOREIGN.replace(r#"<v:Real value="2.5" unit="1"/>"#, r#"<v:Real value="fast"/>"#));
    assert!(e.contains("x.ssd: parameter b.gain: 'fast' is not a number"), "{e}");
    let nested = FOREIGN.replace(
        r#"<Component name="b" source="resources/B.fmu">"#,
        r#"<System name="sub"/><Component name="b" source="resources/B.fmu">"#,
    );
    assert!(err(&nested).contains("nested ssd:System elements are not supported"), "{}", err(&nested));
    let e = err(&FOREIGN.replace(r#"kind="input""#, r#"kind="sideways""#));
    assert!(e.contains("connector b.u: missing or unknown kind"), "{e}");
    let e = err(&FOREIGN.replace(r#"version="1.0" name="Foreign""#, r#"version="2.0" name="Foreign""#));
    assert!(e.contains("SSD version '2.0'"), "{e}");
    let e = err(&FOREIGN.replace(r#"<Component name="b""#, r#"<Component name="a""#));
    assert!(e.contains("two components are named a"), "{e}");
    let e = err(&FOREIGN.replace(r#"stopTime="2.5""#, r#"stopTime="late""#));
    assert!(e.contains("stopTime: 'late' is not a number"), "{e}");
    let e =
        err(&FOREIGN.replace(r#"<ParameterBinding prefix="b.">"#, r#"<ParameterBinding prefix="b." type="text/csv">"#));
    assert!(e.contains("parameter binding of unsupported type text/csv"), "{e}");
    let e = err(&FOREIGN.replace(r#"implementation="CoSimulation""#, r#"implementation="ModelExchange""#));
    assert!(e.contains("component a: implementation ModelExchange"), "{e}");
    let e = err(&FOREIGN.replace("<v:Integer value=\"-3\"/>", ""));
    assert!(e.contains("parameter n has no value element"), "{e}");
    let e =
        err(&FOREIGN.replace(r#"<Connection startElement="a" startConnector="y""#, r#"<Connection startElement="a""#));
    assert!(e.contains("ssd:Connection without startConnector"), "{e}");
    let e = err(&FOREIGN.replace("<Elements>", r#"<Elements><Foo xmlns="urn:foo"/>"#));
    assert!(e.contains("{urn:foo}Foo is not in an SSP 1.0 namespace"), "{e}");
}

/// Regression (hardening issue): 300 000 nested elements (a 2 MB file) made
/// `cosim info` abort with a stack overflow; now a clear error naming the limit.
#[test]
fn a_deeply_nested_document_is_refused_not_a_stack_overflow() {
    let n = 300_000;
    // A default namespace and 300 000 nested <a> (2.1 MB): what aborted the old reader.
    let xml = format!(
        "<SystemStructureDescription xmlns=\"{NS_SSD}\" version=\"1.0\" name=\"deep\">\n{}{}</SystemStructureDescription>",
        "<a>".repeat(n),
        "</a>".repeat(n)
    );
    assert!(xml.len() > 2_000_000);
    let e = SystemDescription::from_xml(&xml, "deep.ssd", None).unwrap_err();
    assert!(matches!(e, SspError::TooDeep { limit: MAX_DEPTH, line: 2, .. }), "{e}");
    assert!(e.to_string().contains("deep.ssd: line 2: elements are nested more than 64 levels deep"), "{e}");
    // The same through a file and through an .ssv source.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("deep.ssd"), &xml).unwrap();
    assert!(matches!(SystemDescription::from_file(&dir.path().join("deep.ssd")), Err(SspError::TooDeep { .. })));
    let ssv = format!(
        "<ssv:ParameterSet xmlns:ssv=\"{NS_SSV}\" version=\"1.0\" name=\"x\">{}{}</ssv:ParameterSet>",
        "<ssv:Parameters>".repeat(n),
        "</ssv:Parameters>".repeat(n)
    );
    assert!(matches!(parse_ssv(&ssv, "deep.ssv", ""), Err(SspError::TooDeep { .. })));
}

/// Regression (hardening issue): one binding giving one parameter two values.
#[test]
fn two_values_for_one_parameter_in_one_binding_are_refused() {
    let two_elements =
        FOREIGN.replace(r#"<v:Real value="2.5" unit="1"/>"#, r#"<v:Real value="2.5" unit="1"/><v:Integer value="3"/>"#);
    let e = err(&two_elements);
    assert!(e.contains("parameter b.gain has 2 value elements (2.5, 3)"), "{e}");
    let twice = FOREIGN.replace(
        r#"<v:Parameter name="on"><v:Boolean value="true"/></v:Parameter>"#,
        r#"<v:Parameter name="on"><v:Boolean value="true"/></v:Parameter><v:Parameter name="n"><v:Integer value="4"/></v:Parameter>"#,
    );
    let e = err(&twice);
    assert!(e.contains("x.ssd: parameter n is given two values in one parameter binding (-3 and 4)"), "{e}");
    // Two bindings may bind the same name: the later one wins, and writing keeps that meaning.
    let mut d = foreign();
    d.parameters.push(Parameter { name: "b.gain".into(), value: ParamValue::Real(4.0, None) });
    let back = SystemDescription::from_xml(&d.to_xml().unwrap(), "w.ssd", None).unwrap();
    assert_eq!(back.parameters, vec![Parameter { name: "b.gain".into(), value: ParamValue::Real(4.0, None) }]);
}

#[test]
fn parameter_sources_are_read_through_the_callback() {
    let xml = FOREIGN
        .replace(r#"<ParameterBinding prefix="b.">"#, r#"<ParameterBinding prefix="b." source="resources/extra.ssv">"#);
    let ssv = r#"<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="x">
  <ssv:Parameters><ssv:Parameter name="k"><ssv:Real value="7"/></ssv:Parameter></ssv:Parameters></ssv:ParameterSet>"#;
    let read = |src: &str| -> Result<String, SspError> {
        assert_eq!(src, "resources/extra.ssv");
        Ok(ssv.to_string())
    };
    let d = SystemDescription::from_xml(&xml, "x.ssd", Some(&read)).unwrap();
    assert_eq!(d.parameters[0], Parameter { name: "b.k".into(), value: ParamValue::Real(7.0, None) });
    assert_eq!(d.parameters[1].name, "b.gain");
    let e = SystemDescription::from_xml(&xml, "x.ssd", None).unwrap_err().to_string();
    assert!(e.contains("refers to resources/extra.ssv, but this SSD has no location to read it from"), "{e}");
    // The source and the inline values are one binding: the same name in both is refused.
    let clash = ssv.replace(r#"name="k""#, r#"name="gain""#);
    let read = |_: &str| -> Result<String, SspError> { Ok(clash.clone()) };
    let e = SystemDescription::from_xml(&xml, "x.ssd", Some(&read)).unwrap_err().to_string();
    assert!(e.contains("parameter b.gain is given two values in one parameter binding (7 and 2.5)"), "{e}");
    // An .ssv file must be one.
    let read = |_: &str| -> Result<String, SspError> { Ok(FOREIGN.to_string()) };
    let e = SystemDescription::from_xml(&xml, "x.ssd", Some(&read)).unwrap_err().to_string();
    assert!(e.contains("resources/extra.ssv: root element is") && e.contains("expected ssv:ParameterSet"), "{e}");
}

#[test]
fn bare_ssd_files_read_their_sources_beside_them_and_not_outside() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sys");
    std::fs::create_dir_all(sub.join("params")).unwrap();
    let ssv = format!(
        r#"<ssv:ParameterSet xmlns:ssv="{NS_SSV}" version="1.0" name="x"><ssv:Parameters><ssv:Parameter name="k"><ssv:Integer value="5"/></ssv:Parameter></ssv:Parameters></ssv:ParameterSet>"#
    );
    std::fs::write(sub.join("params/p.ssv"), ssv).unwrap();
    let with = |src: &str| {
        FOREIGN
            .replace(r#"<ParameterBinding prefix="b.">"#, &format!(r#"<ParameterBinding prefix="b." source="{src}">"#))
    };
    std::fs::write(sub.join("ok.ssd"), with("params/p.ssv")).unwrap();
    let d = SystemDescription::from_file(&sub.join("ok.ssd")).unwrap();
    assert_eq!(d.parameters[0], Parameter { name: "b.k".into(), value: ParamValue::Integer(5) });
    std::fs::write(sub.join("escape.ssd"), with("../secret.ssv")).unwrap();
    let e = SystemDescription::from_file(&sub.join("escape.ssd")).unwrap_err().to_string();
    assert!(e.contains("parameter source '../secret.ssv' is not a relative path inside the system"), "{e}");
    std::fs::write(sub.join("missing.ssd"), with("params/none.ssv")).unwrap();
    let e = SystemDescription::from_file(&sub.join("missing.ssd")).unwrap_err().to_string();
    assert!(e.contains("cannot read") && e.contains("params/none.ssv"), "{e}");
    assert_eq!(e.matches("(os error 2)").count(), 1, "the io error once: {e}");
}
