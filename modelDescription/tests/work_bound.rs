//! The work-bound vendor annotation: written before `ModelVariables` (FMI 2.0 schema order),
//! read back, checked when built, and other tools' annotations are skipped when parsing.
#![allow(missing_docs)]

use model_description::*;

fn model(bound: Option<WorkBound>) -> Result<ModelDescription, DescriptionError> {
    let mut b = ModelBuilder::new("Worker", "Worker")
        .unit("s", [0, 0, 1, 0, 0, 0, 0, 0])
        .var(
            ScalarVariable::real("dt", 0, Causality::Parameter, Variability::Fixed)
                .start(1e-5)
                .bounds(1e-8, 1e-3)
                .unit_of("s"),
        )
        .var(ScalarVariable::real("k", 1, Causality::Parameter, Variability::Fixed).start(1.0))
        .var(ScalarVariable::real("y", 2, Causality::Output, Variability::Continuous).depends_on(&[]));
    if let Some(w) = bound {
        b = b.work_bound(w);
    }
    b.build()
}

fn bound(parameter: &str) -> WorkBound {
    WorkBound {
        max_internal_steps_per_call: 1e7,
        internal_step_parameter: parameter.into(),
        extra_internal_steps_per_call: 2.0,
    }
}

#[test]
fn the_bound_round_trips_in_schema_order_and_changes_the_guid() {
    let md = model(Some(bound("dt"))).unwrap();
    let xml = md.to_xml().unwrap();
    let (va, mv) = (xml.find("<VendorAnnotations>").unwrap(), xml.find("<ModelVariables>").unwrap());
    assert!(va < mv, "VendorAnnotations must precede ModelVariables:\n{xml}");
    assert!(xml.contains("<Tool name=\"fmi2-export\">"), "{xml}");
    let back = ModelDescription::from_xml(&xml).unwrap();
    assert_eq!(back.work_bound(), Some(&bound("dt")));
    assert_ne!(md.guid, model(None).unwrap().guid, "the GUID covers the annotation");
    assert!(model(None).unwrap().work_bound().is_none());
    assert!(!model(None).unwrap().to_xml().unwrap().contains("VendorAnnotations"));
}

#[test]
fn cost_limit_and_largest_step() {
    let w = bound("dt");
    assert!((w.cost(1.0, 1e-5) - (1e5 + 2.0)).abs() < 1e-6);
    assert!(!w.exceeded(99.9, 1e-5));
    assert!(w.exceeded(100.1, 1e-5));
    assert!(w.exceeded(1e-3, 0.0) && w.exceeded(1e-3, f64::NAN) && w.exceeded(f64::NAN, 1e-5));
    let h = w.max_step(1e-5);
    assert!(!w.exceeded(h, 1e-5) && w.exceeded(h * (1.0 + 1e-9), 1e-5), "{h}");
}

#[test]
fn an_unusable_bound_is_refused_when_built() {
    for (w, why) in [
        (bound("nope"), "no variable nope"),
        (bound("y"), "must be a Real parameter"),
        (bound("k"), "positive min"),
        (WorkBound { max_internal_steps_per_call: f64::INFINITY, ..bound("dt") }, "finite"),
        (WorkBound { extra_internal_steps_per_call: -1.0, ..bound("dt") }, "finite"),
    ] {
        let e = model(Some(w)).unwrap_err().to_string();
        assert!(e.contains(why), "{e}");
    }
}

#[test]
fn other_tools_annotations_are_skipped() {
    let xml = model(Some(bound("dt"))).unwrap().to_xml().unwrap();
    let other = xml.replace(
        "<VendorAnnotations>",
        "<VendorAnnotations><Tool name=\"SomeTool\"><Settings a=\"1\"><Nested>text</Nested></Settings>\
         <WorkBound maxInternalStepsPerCall=\"1\" internalStepParameter=\"k\"/></Tool>",
    );
    let md = ModelDescription::from_xml(&other).unwrap();
    assert_eq!(md.vendor_annotations.as_ref().unwrap().tools.len(), 2);
    assert_eq!(md.work_bound(), Some(&bound("dt")), "only the fmi2-export tool's bound counts");
    let only_other = xml.replace("name=\"fmi2-export\"", "name=\"SomeTool\"");
    assert!(ModelDescription::from_xml(&only_other).unwrap().work_bound().is_none());
}
