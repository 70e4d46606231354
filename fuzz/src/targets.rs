//! The fuzz targets and their seed corpora (the project's own artefacts:
//! the FMUs' `modelDescription.xml` as packaged, `ClosedLoop.ssd`, FMU
//! states serialized by the FMUs themselves, well-formed call sequences).

use crate::Target;
use fmi2_export::instance::{Instance, LogLevel, LogSink, Snapshot};
use fmi2_export::{Environment, Fmi2Model};
use fmu_controller::ChatterController;
use fmu_plant::MillingPlant;
use model_description::{ModelDescription, ScalarType, Value};

/// Every target.
pub const ALL: &[Target] = &[MODEL_DESCRIPTION, SSD, FMU_STATE, CALL_SEQUENCE];

/// The target named `name`.
pub fn by_name(name: &str) -> Option<Target> {
    ALL.iter().copied().find(|t| t.name == name)
}

/// A coarse class of an error message: digits and quoted text removed, cut short.
fn class_of(prefix: &str, msg: &str) -> String {
    let mut out = String::from(prefix);
    let mut quoted = false;
    for c in msg.chars().take(60) {
        match c {
            '\'' | '"' => quoted = !quoted,
            _ if quoted || c.is_ascii_digit() => {}
            _ => out.push(c),
        }
    }
    out
}

const XML_DICT: &[&str] = &[
    "<ScalarVariable name=\"v\" valueReference=\"7\" causality=\"input\"><Real start=\"1\"/></ScalarVariable>",
    "<Unknown index=\"1\" dependencies=\"1 2\"/>",
    " valueReference=\"4294967295\"",
    " causality=\"parameter\" variability=\"tunable\"",
    "<Enumeration declaredType=\"E\" start=\"3\"/>",
    "<SimpleType name=\"E\"><Enumeration><Item name=\"a\" value=\"1\"/></Enumeration></SimpleType>",
    "<Unit name=\"m\"><BaseUnit m=\"1\"/></Unit>",
    " min=\"2\" max=\"1\"",
    " fmiVersion=\"2.0\"",
    "<![CDATA[x]]>",
    "<ssd:Component name=\"c\" source=\"resources/X.fmu\"/>",
    "<ssd:Connection startElement=\"a\" startConnector=\"y\" endElement=\"b\" endConnector=\"u\"/>",
    "<ssv:Parameter name=\"p\"><ssv:Real value=\"1e309\"/></ssv:Parameter>",
    "<ssd:Connector name=\"y\" kind=\"output\"><ssc:Real/></ssd:Connector>",
];

/// `ModelDescription::from_xml` on any text, then the checks a master makes.
pub const MODEL_DESCRIPTION: Target = Target {
    name: "model_description",
    seeds: || {
        let mut v = vec![
            MillingPlant::description().to_xml().expect("the plant's XML").into_bytes(),
            ChatterController::description().to_xml().expect("the controller's XML").into_bytes(),
        ];
        v.push(b"<fmiModelDescription fmiVersion=\"2.0\" modelName=\"m\" guid=\"g\"/>".to_vec());
        v
    },
    dict: XML_DICT,
    max_len: 1 << 17,
    known_panics: &[],
    known_hangs: false,
    run: |data| {
        let text = String::from_utf8_lossy(data);
        match ModelDescription::from_xml(&text) {
            Ok(md) => {
                let n = md.variables().len();
                let _ = md.model_identifier();
                for v in md.variables() {
                    let _ = (v.start_value(), v.unit(), v.scalar_type());
                    let _ = md.variable(&v.name);
                }
                let back = md.to_xml().map(|_| "xml").unwrap_or("no-xml");
                format!("ok/{}/{back}", n.min(8))
            }
            Err(e) => class_of("err/", &e.to_string()),
        }
    },
};

/// `ssp::SystemDescription::from_xml` on any text.
pub const SSD: Target = Target {
    name: "ssd",
    seeds: || {
        vec![
            include_str!("../../packaging/scenarios/ClosedLoop.ssd").as_bytes().to_vec(),
            format!("<ssd:SystemStructureDescription xmlns:ssd=\"{}\" version=\"1.0\" name=\"s\"/>", ssp::NS_SSD)
                .into_bytes(),
        ]
    },
    dict: XML_DICT,
    max_len: 1 << 17,
    known_panics: &[],
    known_hangs: false,
    run: |data| {
        let text = String::from_utf8_lossy(data);
        match ssp::SystemDescription::from_xml(&text, "fuzz.ssd", None) {
            Ok(d) => {
                let _ = d.to_xml();
                for c in &d.connections {
                    let _ = c.label();
                }
                format!("ok/{}/{}", d.components.len().min(4), d.connections.len().min(4))
            }
            Err(e) => class_of("err/", &e.to_string()),
        }
    },
};

struct NoLog;

impl LogSink for NoLog {
    fn emit(&mut self, _: LogLevel, _: &str, _: &str) {}
}

fn instance<M: Fmi2Model>() -> Instance<M> {
    Instance::new(Environment { instance_name: "fuzz".into(), resources: None }, false, Box::new(NoLog))
}

fn initialized<M: Fmi2Model>() -> Instance<M> {
    let mut i = instance::<M>();
    i.setup_experiment(0.0, None).expect("setup");
    i.enter_initialization().expect("enter");
    i.exit_initialization().expect("exit");
    i
}

const H: f64 = 1e-4;

fn states_of<M: Fmi2Model>() -> Vec<Vec<u8>> {
    let mut out = vec![instance::<M>().snapshot().serialize().expect("serialize")];
    let mut i = initialized::<M>();
    out.push(i.snapshot().serialize().expect("serialize"));
    for _ in 0..5 {
        let t = i.time();
        i.do_step(t, H).expect("step");
    }
    out.push(i.snapshot().serialize().expect("serialize"));
    out
}

fn all_reals<M: Fmi2Model>(i: &mut Instance<M>) -> usize {
    let vrs: Vec<u32> = M::description()
        .variables()
        .iter()
        .filter(|v| v.scalar_type().api_type() == ScalarType::Real)
        .map(|v| v.value_reference)
        .collect();
    let mut out = Vec::new();
    let _ = i.get("fmi2GetReal", ScalarType::Real, &vrs, &mut out);
    out.len()
}

fn restore_and_step<M: Fmi2Model>(data: &[u8]) -> Option<String> {
    let snap = Snapshot::<M>::deserialize(data).ok()?;
    let mut i = instance::<M>();
    i.restore(&snap);
    let mut ok = 0;
    for _ in 0..3 {
        let t = i.time();
        if i.do_step(t, H).is_ok() {
            ok += 1;
        }
        all_reals(&mut i);
    }
    let _ = i.terminate();
    Some(format!("restored/{:?}/{ok}", i.state))
}

/// `Snapshot::deserialize` of any bytes (both FMUs), then three steps and reads.
pub const FMU_STATE: Target = Target {
    name: "fmu_state",
    seeds: || {
        let mut v = states_of::<MillingPlant>();
        v.extend(states_of::<ChatterController>());
        v
    },
    dict: &[],
    max_len: 1 << 16,
    // Restored states are validated (checksum, magic, the models' validate_state) and a step's
    // work is bounded: no panic or hang is expected; the findings that showed both before are
    // replayed by tests/regressions.rs.
    known_panics: &[],
    known_hangs: false,
    run: |data| {
        restore_and_step::<MillingPlant>(data)
            .or_else(|| restore_and_step::<ChatterController>(data))
            .unwrap_or_else(|| "rejected".into())
    },
};

/// Reads bytes of an input as call arguments (zeros when it runs out).
struct Cursor<'a>(&'a [u8]);

impl Cursor<'_> {
    fn byte(&mut self) -> Option<u8> {
        let (&b, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(b)
    }
    fn real(&mut self) -> f64 {
        const SPECIAL: [f64; 8] = [0.0, 1.0, -1.0, 1e-300, 1e300, f64::NAN, f64::INFINITY, 2000.0];
        let b = self.byte().unwrap_or(0);
        if b < 128 {
            return SPECIAL[b as usize % SPECIAL.len()];
        }
        let mut x = [0u8; 8];
        for v in &mut x {
            *v = self.byte().unwrap_or(0);
        }
        f64::from_le_bytes(x)
    }
}

fn call_sequence<M: Fmi2Model>(mut c: Cursor<'_>) -> String {
    let vars = M::description().variables();
    let mut i = instance::<M>();
    let mut saved: Option<Snapshot<M>> = None;
    let mut errors = 0u32;
    let mut out = Vec::new();
    let mut calls = 0;
    while let Some(op) = c.byte() {
        calls += 1;
        if calls > 256 {
            break;
        }
        let r = match op % 12 {
            0 => {
                let start = if c.byte().unwrap_or(0) < 200 { 0.0 } else { c.real() };
                let stop = if c.byte().unwrap_or(0) < 128 { None } else { Some(c.real()) };
                i.setup_experiment(start, stop)
            }
            1 => i.enter_initialization(),
            2 => i.exit_initialization(),
            3..=5 => {
                let v = &vars[c.byte().unwrap_or(0) as usize % vars.len()];
                let ty = v.scalar_type().api_type();
                let value = match ty {
                    ScalarType::Real => Value::Real(c.real()),
                    ScalarType::Boolean => Value::Boolean(c.byte().unwrap_or(0) & 1 == 1),
                    ScalarType::String => Value::String("x".into()),
                    _ => Value::Integer(i32::from(c.byte().unwrap_or(0) as i8)),
                };
                i.set("fmi2Set", ty, &[v.value_reference], &[value])
            }
            6 => {
                let v = &vars[c.byte().unwrap_or(0) as usize % vars.len()];
                i.get("fmi2Get", v.scalar_type().api_type(), &[v.value_reference], &mut out)
            }
            7 | 8 => {
                let t = i.time();
                // Step sizes a real master uses; huge steps are bounded by the
                // per-call work bound (owned by fmi2-export), not fuzzed here.
                let h = [1e-5, 1e-4, 5e-4, 0.0, -1e-4, f64::NAN][c.byte().unwrap_or(0) as usize % 6];
                let t = if c.byte().unwrap_or(0) < 240 { t } else { t + 1e-3 };
                i.do_step(t, h)
            }
            9 => i.terminate(),
            10 => i.reset(),
            _ => match (c.byte().unwrap_or(0) % 3, &saved) {
                (0, _) => {
                    saved = Some(i.snapshot());
                    Ok(())
                }
                (1, Some(s)) => {
                    i.restore(s);
                    Ok(())
                }
                _ => i.snapshot().serialize().and_then(|b| Snapshot::<M>::deserialize(&b)).map(|s| i.restore(&s)),
            },
        };
        if r.is_err() {
            errors += 1;
        }
    }
    format!("{:?}/{}", i.state, errors.min(4))
}

/// Sequences of FMI calls (with arguments) on a fresh instance of either FMU.
pub const CALL_SEQUENCE: Target = Target {
    name: "call_sequence",
    seeds: || {
        // model, setup, enter, set, exit, steps, get, save, step, restore, round trip, terminate, reset
        let base: &[u8] = &[0, 0, 0, 0, 1, 3, 2, 0, 2, 7, 0, 0, 7, 1, 0, 6, 3, 11, 0, 7, 0, 0, 11, 1, 11, 2, 9, 10];
        let mut plant = base.to_vec();
        plant[0] = 0;
        let mut controller = base.to_vec();
        controller[0] = 1;
        vec![plant, controller]
    },
    dict: &[],
    max_len: 4096,
    known_panics: &[],
    known_hangs: false,
    run: |data| {
        let mut c = Cursor(data);
        match c.byte().unwrap_or(0) % 2 {
            0 => format!("plant/{}", call_sequence::<MillingPlant>(c)),
            _ => format!("controller/{}", call_sequence::<ChatterController>(c)),
        }
    },
};
