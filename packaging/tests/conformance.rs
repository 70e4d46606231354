//! Every product of `PRODUCTS`, as shipped: the linux64 binary inside its FMU (built by
//! `cargo run --release -p packaging`) is loaded with `libloading` and a table of hostile
//! calls goes through its C ABI: null component and arrays, calls in the wrong state, unknown
//! value references, NaN/Inf reals, out-of-range values and non-items of enumerations, h ≤ 0,
//! a huge h without a stop time, corrupted, truncated and foreign serialized states, state
//! handles of another product, of another instance, of a freed instance, and junk. Every row
//! must be refused (`fmi2Error` or `fmi2Discard`; never `fmi2OK`, `fmi2Fatal`, a crash or a
//! hang) with a message through the logger where there is one (a null or junk component has
//! no logger: `fmi2Error` alone). The variables each row uses come from the product's own
//! description, so a new product is covered by adding it to `PRODUCTS`.
//!
//! The model of this table is `fmi2-export/tests/bad_inputs.rs`, which runs in-process on the
//! layer's test model. `tests/run_all.sh` runs this test under valgrind too.
#![allow(missing_docs, clippy::type_complexity)]

mod common;
#[path = "conformance/host.rs"]
mod host;

use fmi2_abi::*;
use host::{Fmu, callbacks, errors_logged, last_message, load_all, refusal_logged};
use model_description::{Causality, ScalarType, Variability};
use std::ffi::CString;
use std::ptr;
use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

/// The state an instance is brought to before the row's call.
#[derive(Clone, Copy)]
enum Setup {
    Instantiated,
    Ready,
    Terminated,
}

type Call = Box<dyn Fn(&Fmu, fmi2Component) -> fmi2Status>;

fn row(
    name: impl Into<String>,
    setup: Setup,
    f: impl Fn(&Fmu, fmi2Component) -> fmi2Status + 'static,
) -> (String, Setup, Call) {
    (name.into(), setup, Box::new(f))
}

/// Handles made by another product and by other instances of this one, live for the table.
struct Foreign {
    /// Serialized state of the next product in `PRODUCTS`.
    bytes: Vec<fmi2Byte>,
    /// A live state of the next product (a handle of another library).
    state: usize,
    /// A live state of another instance of this product.
    other_instance: usize,
    /// A state of an instance of this product freed since (dangling).
    freed_instance: usize,
}

/// A huge step without a stop time (1e9 s) returns at once, whatever its status: the work of
/// one call is bounded (an FMU with an internal grid refuses it by its work bound; one that
/// integrates a step in closed form may accept it), never fmi2Fatal or a hang.
fn bounded_work_for_any_h(fmu: &Fmu, cb: &fmi2CallbackFunctions) {
    let name = format!("{}-huge-step", fmu.id);
    let c = fmu.ready(&name, cb);
    let started = Instant::now();
    // SAFETY: a live component.
    let s = unsafe { (fmu.api.do_step)(c, 0.0, 1e9, 1) };
    let took = started.elapsed();
    assert!(took < Duration::from_secs(2), "{} / DoStep h = 1e9 s: took {took:?}", fmu.id);
    assert!(s == fmi2OK || s == fmi2Error || s == fmi2Discard, "{} / DoStep h = 1e9 s: {}", fmu.id, status_name(s));
    if s != fmi2OK {
        assert!(refusal_logged(&name), "{} / DoStep h = 1e9 s refused without a message", fmu.id);
    }
    // SAFETY: a live component, freed once.
    unsafe { (fmu.api.free_instance)(c) };
}

/// The hostile-call table of one product.
fn table(fmu: &Fmu, good: &[fmi2Byte], foreign: &Foreign) -> Vec<(String, Setup, Call)> {
    use Setup::*;
    use fmi2_abi::fmi2Byte as B;
    let mut rows = Vec::new();
    let real_out = fmu.var(ScalarType::Real, Causality::Output, None).or_else(|| fmu.any(ScalarType::Real));
    let real_in = fmu.var(ScalarType::Real, Causality::Input, None);
    let fixed = fmu.var(ScalarType::Real, Causality::Parameter, Some(Variability::Fixed));
    let any_int = fmu.any(ScalarType::Integer).map(|v| v.value_reference);
    let any_bool = fmu.any(ScalarType::Boolean).map(|v| v.value_reference);
    let any_str = fmu.any(ScalarType::String).map(|v| v.value_reference);
    let unknown =
        [ScalarType::Real, ScalarType::Integer, ScalarType::Boolean, ScalarType::String].map(|t| fmu.unknown_vr(t));
    let [ur, ui, ub, us] = unknown;

    rows.push(row("SetDebugLogging unknown category", Ready, |f, c| unsafe {
        (f.api.set_debug_logging)(c, 1, 1, &c"noSuchCategory".as_ptr())
    }));
    rows.push(row("SetDebugLogging null categories", Ready, |f, c| unsafe {
        (f.api.set_debug_logging)(c, 1, 2, ptr::null())
    }));
    rows.push(row("SetupExperiment NaN start", Instantiated, |f, c| unsafe {
        (f.api.setup_experiment)(c, 0, 0.0, f64::NAN, 0, 0.0)
    }));
    rows.push(row("SetupExperiment Inf stop", Instantiated, |f, c| unsafe {
        (f.api.setup_experiment)(c, 0, 0.0, 0.0, 1, f64::INFINITY)
    }));
    rows.push(row("SetupExperiment stop < start", Instantiated, |f, c| unsafe {
        (f.api.setup_experiment)(c, 0, 0.0, 1.0, 1, 0.5)
    }));
    rows.push(row("SetupExperiment NaN tolerance", Instantiated, |f, c| unsafe {
        (f.api.setup_experiment)(c, 1, f64::NAN, 0.0, 0, 0.0)
    }));
    rows.push(row("SetupExperiment wrong state", Ready, |f, c| unsafe {
        (f.api.setup_experiment)(c, 0, 0.0, 0.0, 0, 0.0)
    }));
    rows.push(row("EnterInitializationMode wrong state", Ready, |f, c| unsafe {
        (f.api.enter_initialization_mode)(c)
    }));
    rows.push(row("ExitInitializationMode wrong state", Instantiated, |f, c| unsafe {
        (f.api.exit_initialization_mode)(c)
    }));
    rows.push(row("Terminate wrong state", Instantiated, |f, c| unsafe { (f.api.terminate)(c) }));

    // get: unknown VRs, null arrays, wrong state
    rows.push(row("GetReal unknown VR", Ready, move |f, c| unsafe { (f.api.get_real)(c, &ur, 1, &mut 0.0) }));
    rows.push(row("GetInteger unknown VR", Ready, move |f, c| unsafe { (f.api.get_integer)(c, &ui, 1, &mut 0) }));
    rows.push(row("GetBoolean unknown VR", Ready, move |f, c| unsafe { (f.api.get_boolean)(c, &ub, 1, &mut 0) }));
    rows.push(row("GetString unknown VR", Ready, move |f, c| unsafe {
        (f.api.get_string)(c, &us, 1, &mut ptr::null())
    }));
    rows.push(row("GetReal VR u32::MAX", Ready, |f, c| unsafe { (f.api.get_real)(c, &u32::MAX, 1, &mut 0.0) }));
    if let Some(v) = real_out.map(|v| v.value_reference) {
        rows.push(row("GetReal null values", Ready, move |f, c| unsafe {
            (f.api.get_real)(c, &v, 1, ptr::null_mut())
        }));
        rows.push(row("GetReal null VRs", Ready, |f, c| unsafe { (f.api.get_real)(c, ptr::null(), 1, &mut 0.0) }));
        rows.push(row("GetReal wrong state", Instantiated, move |f, c| unsafe {
            (f.api.get_real)(c, &v, 1, &mut 0.0)
        }));
        rows.push(row("SetReal output", Ready, move |f, c| unsafe { (f.api.set_real)(c, &v, 1, &2.0) }));
    }
    if let Some(v) = any_int {
        rows.push(row("GetInteger null values", Ready, move |f, c| unsafe {
            (f.api.get_integer)(c, &v, 1, ptr::null_mut())
        }));
    }
    if let Some(v) = any_bool {
        rows.push(row("GetBoolean null values", Ready, move |f, c| unsafe {
            (f.api.get_boolean)(c, &v, 1, ptr::null_mut())
        }));
    }
    if let Some(v) = any_str {
        rows.push(row("GetString null values", Ready, move |f, c| unsafe {
            (f.api.get_string)(c, &v, 1, ptr::null_mut())
        }));
        rows.push(row("SetString null string", Instantiated, move |f, c| unsafe {
            (f.api.set_string)(c, &v, 1, &ptr::null())
        }));
    }

    // set: NaN/Inf, out of range, unknown VRs, null arrays, wrong state
    if let Some(v) = real_in.map(|v| v.value_reference) {
        for (what, x) in [("NaN", f64::NAN), ("+Inf", f64::INFINITY), ("-Inf", f64::NEG_INFINITY)] {
            rows.push(row(format!("SetReal input {what}"), Ready, move |f, c| unsafe {
                (f.api.set_real)(c, &v, 1, &x)
            }));
        }
        rows.push(row("SetReal null values", Ready, move |f, c| unsafe { (f.api.set_real)(c, &v, 1, ptr::null()) }));
        rows.push(row("SetReal wrong state", Terminated, move |f, c| unsafe { (f.api.set_real)(c, &v, 1, &0.0) }));
    }
    if let Some(v) = fixed.map(|v| v.value_reference) {
        rows.push(row("SetReal parameter NaN", Instantiated, move |f, c| unsafe {
            (f.api.set_real)(c, &v, 1, &f64::NAN)
        }));
        rows.push(row("SetReal fixed parameter after init", Ready, move |f, c| unsafe {
            let mut x = 0.0;
            (f.api.get_real)(c, &v, 1, &mut x);
            (f.api.set_real)(c, &v, 1, &x)
        }));
    }
    if let Some((v, x, name)) = fmu.out_of_range_real() {
        rows.push(row(format!("SetReal {name} out of range ({x:e})"), Instantiated, move |f, c| unsafe {
            (f.api.set_real)(c, &v, 1, &x)
        }));
    }
    if let Some((v, x)) = fmu.non_item() {
        rows.push(row("SetInteger not an enumeration item", Instantiated, move |f, c| unsafe {
            (f.api.set_integer)(c, &v, 1, &x)
        }));
    }
    rows.push(row("SetReal unknown VR", Ready, move |f, c| unsafe { (f.api.set_real)(c, &ur, 1, &1.0) }));
    rows.push(row("SetInteger unknown VR", Ready, move |f, c| unsafe { (f.api.set_integer)(c, &ui, 1, &1) }));
    rows.push(row("SetBoolean unknown VR", Ready, move |f, c| unsafe { (f.api.set_boolean)(c, &ub, 1, &1) }));
    rows.push(row("SetString unknown VR", Ready, move |f, c| unsafe { (f.api.set_string)(c, &us, 1, &c"x".as_ptr()) }));

    // steps
    rows.push(row("DoStep h = 0", Ready, |f, c| unsafe { (f.api.do_step)(c, 0.0, 0.0, 1) }));
    rows.push(row("DoStep h < 0", Ready, |f, c| unsafe { (f.api.do_step)(c, 0.0, -1e-3, 1) }));
    rows.push(row("DoStep h NaN", Ready, |f, c| unsafe { (f.api.do_step)(c, 0.0, f64::NAN, 1) }));
    rows.push(row("DoStep h Inf", Ready, |f, c| unsafe { (f.api.do_step)(c, 0.0, f64::INFINITY, 1) }));
    if let Some(w) = fmu.md.work_bound() {
        // an FMU that steps on an internal grid declares its work bound and refuses beyond it;
        // one that integrates a step in closed form may take any h (bounded_work_for_any_h)
        rows.push(row("DoStep huge h (1e9 s) without a stop time", Ready, |f, c| unsafe {
            (f.api.do_step)(c, 0.0, 1e9, 1)
        }));
        // the FMU refuses what its WorkBound annotation lets a master refuse in advance
        let p = match fmu.md.variable(&w.internal_step_parameter).and_then(|v| v.start_value()) {
            Some(model_description::Value::Real(p)) => p,
            other => {
                panic!("{}: work bound parameter {} without a Real start: {other:?}", fmu.id, w.internal_step_parameter)
            }
        };
        let h = 1.01 * w.max_step(p);
        rows.push(row(format!("DoStep 1 % beyond the declared work bound (h = {h:e} s)"), Ready, move |f, c| unsafe {
            (f.api.do_step)(c, 0.0, h, 1)
        }));
    }
    rows.push(row("DoStep t NaN", Ready, |f, c| unsafe { (f.api.do_step)(c, f64::NAN, 1e-3, 1) }));
    rows.push(row("DoStep wrong communication point", Ready, |f, c| unsafe { (f.api.do_step)(c, 5.0, 1e-3, 1) }));
    rows.push(row("DoStep wrong state", Instantiated, |f, c| unsafe { (f.api.do_step)(c, 0.0, 1e-3, 1) }));
    rows.push(row("DoStep after Terminate", Terminated, |f, c| unsafe { (f.api.do_step)(c, 0.0, 1e-3, 1) }));
    rows.push(row("CancelStep", Ready, |f, c| unsafe { (f.api.cancel_step)(c) }));

    // FMU states: handles
    let handles = [
        ("of another product", foreign.state),
        ("of another instance", foreign.other_instance),
        ("of a freed instance", foreign.freed_instance),
    ];
    for (what, s) in handles {
        rows.push(row(format!("SetFMUstate {what}"), Ready, move |f, c| unsafe {
            (f.api.set_fmu_state)(c, s as fmi2FMUstate)
        }));
        rows.push(row(format!("SerializedFMUstateSize {what}"), Ready, move |f, c| unsafe {
            (f.api.serialized_size)(c, s as fmi2FMUstate, &mut 0)
        }));
        rows.push(row(format!("FreeFMUstate {what}"), Ready, move |f, c| unsafe {
            let mut h = s as fmi2FMUstate;
            (f.api.free_fmu_state)(c, &mut h)
        }));
    }
    rows.push(row("GetFMUstate null", Ready, |f, c| unsafe { (f.api.get_fmu_state)(c, ptr::null_mut()) }));
    rows.push(row("SetFMUstate null", Ready, |f, c| unsafe { (f.api.set_fmu_state)(c, ptr::null_mut()) }));
    rows.push(row("SetFMUstate component as state", Ready, |f, c| unsafe { (f.api.set_fmu_state)(c, c) }));
    rows.push(row("SerializeFMUstate small buffer", Ready, |f, c| unsafe {
        let mut st: fmi2FMUstate = ptr::null_mut();
        (f.api.get_fmu_state)(c, &mut st);
        let mut buf = [0 as B; 4];
        let s = (f.api.serialize)(c, st, buf.as_mut_ptr(), 4);
        (f.api.reset)(c);
        (f.api.free_fmu_state)(c, &mut st);
        s
    }));
    // FMU states: bytes
    let mut corrupted: Vec<(String, Vec<B>)> = Vec::new();
    for (at, what) in [(0, "magic"), (good.len() / 2, "middle"), (good.len() - 1, "checksum")] {
        let mut b = good.to_vec();
        b[at] = !b[at];
        corrupted.push((format!("flipped byte ({what})"), b));
    }
    let mut every_8th = good.to_vec();
    every_8th.iter_mut().step_by(8).for_each(|b| *b ^= 0x55);
    corrupted.push(("every 8th byte flipped".into(), every_8th));
    corrupted.push(("truncated by one byte".into(), good[..good.len() - 1].to_vec()));
    corrupted.push(("one byte appended".into(), [good, &[0]].concat()));
    corrupted.push(("of another product".into(), foreign.bytes.clone()));
    corrupted.push(("all zero".into(), vec![0; good.len()]));
    for (what, bytes) in corrupted {
        rows.push(row(format!("DeSerializeFMUstate {what}"), Ready, move |f, c| unsafe {
            let mut st: fmi2FMUstate = ptr::null_mut();
            let s = (f.api.deserialize)(c, bytes.as_ptr(), bytes.len(), &mut st);
            assert!(st.is_null(), "{}: a refused state was returned", f.id);
            s
        }));
    }
    rows.push(row("DeSerializeFMUstate null bytes", Ready, |f, c| unsafe {
        (f.api.deserialize)(c, ptr::null(), 16, &mut ptr::null_mut())
    }));
    let g = good.to_vec();
    rows.push(row("DeSerializeFMUstate null state", Ready, move |f, c| unsafe {
        (f.api.deserialize)(c, g.as_ptr(), g.len(), ptr::null_mut())
    }));
    let g = good.to_vec();
    let other = foreign.other_instance;
    rows.push(row("DeSerializeFMUstate into a state of another instance", Ready, move |f, c| unsafe {
        let mut st = other as fmi2FMUstate;
        (f.api.deserialize)(c, g.as_ptr(), g.len(), &mut st)
    }));

    // optional functions the products do not provide, and status queries
    let v = real_out.map_or(0, |v| v.value_reference);
    rows.push(row("GetDirectionalDerivative", Ready, move |f, c| unsafe {
        (f.api.get_directional_derivative)(c, &v, 1, &v, 1, &1.0, &mut 0.0)
    }));
    rows.push(row("SetRealInputDerivatives", Ready, move |f, c| unsafe {
        (f.api.set_real_input_derivatives)(c, &v, 1, &1, &1.0)
    }));
    rows.push(row("GetRealOutputDerivatives", Ready, move |f, c| unsafe {
        (f.api.get_real_output_derivatives)(c, &v, 1, &1, &mut 0.0)
    }));
    rows.push(row("GetStatus pending", Ready, |f, c| unsafe { (f.api.get_status)(c, fmi2DoStepStatus, &mut 0) }));
    rows.push(row("GetStatus null value", Ready, |f, c| unsafe {
        (f.api.get_status)(c, fmi2DoStepStatus, ptr::null_mut())
    }));
    rows.push(row("GetRealStatus wrong kind", Ready, |f, c| unsafe {
        (f.api.get_real_status)(c, fmi2Terminated, &mut 0.0)
    }));
    rows.push(row("GetIntegerStatus", Ready, |f, c| unsafe {
        (f.api.get_integer_status)(c, fmi2DoStepStatus, &mut 0)
    }));
    rows.push(row("GetBooleanStatus null value", Ready, |f, c| unsafe {
        (f.api.get_boolean_status)(c, fmi2Terminated, ptr::null_mut())
    }));
    rows.push(row("GetStringStatus", Ready, |f, c| unsafe {
        (f.api.get_string_status)(c, fmi2PendingStatus, &mut ptr::null())
    }));
    rows
}

/// Calls without a valid component (null, junk): `fmi2Error`, nothing written, no crash.
fn without_component(fmu: &Fmu, c: fmi2Component) -> usize {
    let a = &fmu.api;
    let (mut r, mut i, mut b, mut s, mut st) = (0.0, 0, 0, ptr::null(), 0);
    // SAFETY: the functions must check `c` before touching anything; all other pointers are valid.
    let statuses = unsafe {
        [
            (a.set_debug_logging)(c, 1, 0, ptr::null()),
            (a.setup_experiment)(c, 0, 0.0, 0.0, 0, 0.0),
            (a.enter_initialization_mode)(c),
            (a.exit_initialization_mode)(c),
            (a.terminate)(c),
            (a.reset)(c),
            (a.get_real)(c, &0, 1, &mut r),
            (a.get_integer)(c, &0, 1, &mut i),
            (a.get_boolean)(c, &0, 1, &mut b),
            (a.get_string)(c, &0, 1, &mut s),
            (a.set_real)(c, &0, 1, &1.0),
            (a.set_integer)(c, &0, 1, &1),
            (a.set_boolean)(c, &0, 1, &1),
            (a.set_string)(c, &0, 1, &c"x".as_ptr()),
            (a.do_step)(c, 0.0, 1e-3, 1),
            (a.cancel_step)(c),
            (a.get_status)(c, fmi2DoStepStatus, &mut st),
            (a.get_real_status)(c, fmi2LastSuccessfulTime, &mut r),
            (a.get_integer_status)(c, fmi2DoStepStatus, &mut i),
            (a.get_boolean_status)(c, fmi2Terminated, &mut b),
            (a.get_string_status)(c, fmi2PendingStatus, &mut s),
            (a.get_fmu_state)(c, &mut ptr::null_mut()),
            (a.set_fmu_state)(c, ptr::null_mut()),
            (a.free_fmu_state)(c, &mut ptr::null_mut()),
            (a.serialized_size)(c, ptr::null_mut(), &mut 0),
            (a.serialize)(c, ptr::null_mut(), ptr::null_mut(), 0),
            (a.deserialize)(c, ptr::null(), 0, &mut ptr::null_mut()),
            (a.get_directional_derivative)(c, ptr::null(), 0, ptr::null(), 0, ptr::null(), ptr::null_mut()),
            (a.set_real_input_derivatives)(c, ptr::null(), 0, ptr::null(), ptr::null()),
            (a.get_real_output_derivatives)(c, ptr::null(), 0, ptr::null(), ptr::null_mut()),
        ]
    };
    for (k, s) in statuses.iter().enumerate() {
        assert_eq!(*s, fmi2Error, "{}: call {k} with component {c:p}", fmu.id);
    }
    assert_eq!((r.to_bits(), i, b, s, st), (0.0f64.to_bits(), 0, 0, ptr::null(), 0), "{}: written to", fmu.id);
    // SAFETY: null and junk are ignored by fmi2FreeInstance.
    unsafe { (a.free_instance)(c) };
    statuses.len()
}

/// Instantiations with bad arguments: NULL, never a crash, a message where a logger exists.
fn bad_instantiations(fmu: &Fmu, cb: &fmi2CallbackFunctions) -> usize {
    let g = fmu.guid();
    let name = format!("{}-bad-inst", fmu.id);
    let n = CString::new(name.clone()).unwrap();
    let f = fmu.api.instantiate;
    // SAFETY: valid or null arguments, as each row says.
    let insts = unsafe {
        [
            f(ptr::null(), fmi2CoSimulation, g.as_ptr(), ptr::null(), cb, 0, 0),
            f(n.as_ptr(), fmi2ModelExchange, g.as_ptr(), ptr::null(), cb, 0, 0),
            f(n.as_ptr(), fmi2CoSimulation, c"{wrong-guid}".as_ptr(), ptr::null(), cb, 0, 0),
            f(n.as_ptr(), fmi2CoSimulation, ptr::null(), ptr::null(), cb, 0, 0),
            f(n.as_ptr(), fmi2CoSimulation, g.as_ptr(), ptr::null(), ptr::null(), 0, 0),
        ]
    };
    assert!(insts.iter().all(|c| c.is_null()), "{}: a bad instantiation returned a component", fmu.id);
    assert!(errors_logged(&name) >= 3, "{}: bad instantiations without messages", fmu.id);
    insts.len()
}

/// What one product's table counted.
struct Counts {
    rows: usize,
    no_component: usize,
    instantiations: usize,
}

fn run_product(fmus: &[Fmu], k: usize) -> Counts {
    use Setup::*;
    let fmu = &fmus[k];
    let next = &fmus[(k + 1) % fmus.len()];
    let cb = callbacks();
    let good = fmu.state_bytes(&cb);
    // handles made elsewhere: another product's live state, another instance's, a freed one's
    let other_product = next.ready(&format!("{}-foreign-{}", fmu.id, next.id), &cb);
    let other = fmu.ready(&format!("{}-other-owner", fmu.id), &cb);
    let gone = fmu.ready(&format!("{}-gone-owner", fmu.id), &cb);
    let (mut s1, mut s2, mut s3): (fmi2FMUstate, fmi2FMUstate, fmi2FMUstate) =
        (ptr::null_mut(), ptr::null_mut(), ptr::null_mut());
    // SAFETY: live components of their libraries.
    unsafe {
        assert_eq!((next.api.get_fmu_state)(other_product, &mut s1), fmi2OK);
        assert_eq!((fmu.api.get_fmu_state)(other, &mut s2), fmi2OK);
        assert_eq!((fmu.api.get_fmu_state)(gone, &mut s3), fmi2OK);
        (fmu.api.free_instance)(gone);
    }
    let foreign = Foreign {
        bytes: if fmus.len() > 1 { next.state_bytes(&cb) } else { vec![0x42; good.len()] },
        state: s1 as usize,
        other_instance: s2 as usize,
        freed_instance: s3 as usize,
    };
    bounded_work_for_any_h(fmu, &cb);
    let rows = table(fmu, &good, &foreign);
    for (n, (what, setup, call)) in rows.iter().enumerate() {
        let name = format!("{}-row-{n}", fmu.id);
        let c = match setup {
            Instantiated => fmu.instantiate(&name, &cb),
            Ready => fmu.ready(&name, &cb),
            Terminated => {
                let c = fmu.ready(&name, &cb);
                // SAFETY: a live component.
                assert_eq!(unsafe { (fmu.api.terminate)(c) }, fmi2OK);
                c
            }
        };
        let started = Instant::now();
        let s = call(fmu, c);
        let took = started.elapsed();
        assert!(took < Duration::from_secs(2), "{} / {what}: took {took:?}", fmu.id);
        assert!(
            s == fmi2Error || s == fmi2Discard,
            "{} / {what}: {} (expected fmi2Error or fmi2Discard); last message: {}",
            fmu.id,
            status_name(s),
            last_message(&name)
        );
        assert!(refusal_logged(&name), "{} / {what}: refused without a message", fmu.id);
        // SAFETY: a live component, freed once.
        unsafe { (fmu.api.free_instance)(c) };
    }
    // the handles made elsewhere are untouched: still usable where they belong
    // SAFETY: live components and their own states.
    unsafe {
        assert_eq!((next.api.set_fmu_state)(other_product, s1), fmi2OK, "{}", next.id);
        assert_eq!((fmu.api.set_fmu_state)(other, s2), fmi2OK, "{}", fmu.id);
        (next.api.free_instance)(other_product);
        (fmu.api.free_instance)(other);
    }
    let mut junk = vec![0x77u64; 64];
    let mut no_component = without_component(fmu, ptr::null_mut());
    no_component += without_component(fmu, junk.as_mut_ptr() as fmi2Component);
    assert!(junk.iter().all(|&w| w == 0x77), "{}: a junk handle was written to", fmu.id);
    Counts { rows: rows.len(), no_component, instantiations: bad_instantiations(fmu, &cb) }
}

#[test]
fn every_product_refuses_every_hostile_call_with_a_message() {
    let fmus = Arc::new(load_all());
    let mut summary = Vec::new();
    for k in 0..fmus.len() {
        let id = fmus[k].id.clone();
        // A hang fails the test instead of blocking it: the table runs on a thread with a deadline.
        let (tx, rx) = mpsc::channel();
        let shared = Arc::clone(&fmus);
        let worker = std::thread::spawn(move || {
            let counts = run_product(&shared, k);
            let _ = tx.send(());
            counts
        });
        match rx.recv_timeout(Duration::from_secs(120)) {
            Ok(()) | Err(mpsc::RecvTimeoutError::Disconnected) => {}
            Err(mpsc::RecvTimeoutError::Timeout) => panic!("{id}: the hostile-call table hangs"),
        }
        let c = worker.join().unwrap_or_else(|e| std::panic::resume_unwind(e));
        println!(
            "{id}: {} hostile calls refused with a message, {} calls without a valid component answered \
             fmi2Error, {} bad instantiations answered NULL; 0 crashes, 0 hangs, 0 fmi2Fatal",
            c.rows, c.no_component, c.instantiations
        );
        summary.push((id, c.rows));
    }
    assert!(summary.len() >= 2, "PRODUCTS lists the plant and the controller at least");
    println!("conformance table: {summary:?}");
}
