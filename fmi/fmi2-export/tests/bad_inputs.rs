//! The bad-input table: every fmi2 function of the C API called in-process with a null
//! argument, in a wrong state, with unknown value references, NaN/Inf, out-of-range values,
//! h ≤ 0, a huge h, and corrupted or foreign states. Every row must be refused (`fmi2Error` or
//! `fmi2Discard`, never `fmi2Fatal`, a panic, a hang or a crash) with a message through the
//! host's logger; rows with a null or junk component cannot log (there is no logger without a
//! component) and must return `fmi2Error`.

mod common;
use common::{api, callbacks, instantiate, messages, ready, vr};
use fmi2_export::abi::*;
use std::ffi::CString;
use std::ptr;
use std::time::Instant;

/// The state an instance is brought to before the row's call.
#[derive(Clone, Copy)]
enum Setup {
    Instantiated,
    Ready,
    Terminated,
}

type Call = Box<dyn Fn(fmi2Component) -> fmi2Status>;

fn row(
    name: &'static str,
    setup: Setup,
    f: impl Fn(fmi2Component) -> fmi2Status + 'static,
) -> (&'static str, Setup, Call) {
    (name, setup, Box::new(f))
}

/// A serialized state of the test model.
fn state_bytes(cb: &fmi2CallbackFunctions) -> Vec<fmi2Byte> {
    let c = ready("bytes", cb);
    unsafe {
        let mut st: fmi2FMUstate = ptr::null_mut();
        api::fmi2GetFMUstate(c, &mut st);
        let mut n = 0usize;
        api::fmi2SerializedFMUstateSize(c, st, &mut n);
        let mut b = vec![0 as fmi2Byte; n];
        api::fmi2SerializeFMUstate(c, st, b.as_mut_ptr(), n);
        api::fmi2FreeFMUstate(c, &mut st);
        api::fmi2FreeInstance(c);
        b
    }
}

#[test]
fn every_bad_input_is_refused_with_a_message_and_nothing_crashes() {
    use Setup::*;
    let cb = callbacks(80);
    let good = state_bytes(&cb);
    let mut flipped = good.clone();
    flipped[good.len() / 2] ^= 4;
    let truncated = good[..good.len() - 1].to_vec();
    let unknown = 9999u32;
    let junk: &'static mut [u64] = Box::leak(vec![0x77u64; 64].into_boxed_slice());
    let junk_ptr = junk.as_mut_ptr() as usize;
    let bad_cat = CString::new("noSuchCategory").unwrap();
    let cat = Box::leak(Box::new(bad_cat.as_ptr())) as *const fmi2String as usize;
    let (mut r, mut i, mut b) = (0.0f64, 0i32, 0 as fmi2Boolean);
    let (rp, ip, bp) = (&mut r as *mut f64 as usize, &mut i as *mut i32 as usize, &mut b as *mut fmi2Boolean as usize);
    let mut sp: fmi2String = ptr::null();
    let spp = &mut sp as *mut fmi2String as usize;
    let mut status = fmi2OK;
    let stp = &mut status as *mut fmi2Status as usize;
    // A state of another live instance, and one of an instance freed since (the export layer
    // freed the state with its instance: the handle dangles and must not be read).
    let other = ready("other-owner", &cb);
    let mut other_state: fmi2FMUstate = ptr::null_mut();
    let mut gone_state: fmi2FMUstate = ptr::null_mut();
    unsafe {
        assert_eq!(api::fmi2GetFMUstate(other, &mut other_state), fmi2OK);
        let gone = ready("gone-owner", &cb);
        assert_eq!(api::fmi2GetFMUstate(gone, &mut gone_state), fmi2OK);
        api::fmi2FreeInstance(gone);
    }
    let (other_state, gone_state) = (other_state as usize, gone_state as usize);
    unsafe {
        let g = good.clone();
        let f2 = flipped.clone();
        let t2 = truncated.clone();
        let rows: Vec<(&str, Setup, Call)> = vec![
            row("SetDebugLogging unknown category", Ready, move |c| {
                api::fmi2SetDebugLogging(c, 1, 1, cat as *const fmi2String)
            }),
            row("SetDebugLogging null categories", Ready, |c| api::fmi2SetDebugLogging(c, 1, 2, ptr::null())),
            row("SetupExperiment NaN start", Instantiated, |c| api::fmi2SetupExperiment(c, 0, 0.0, f64::NAN, 0, 0.0)),
            row("SetupExperiment Inf stop", Instantiated, |c| {
                api::fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, f64::INFINITY)
            }),
            row("SetupExperiment stop < start", Instantiated, |c| api::fmi2SetupExperiment(c, 0, 0.0, 1.0, 1, 0.5)),
            row("SetupExperiment NaN tolerance", Instantiated, |c| {
                api::fmi2SetupExperiment(c, 1, f64::NAN, 0.0, 0, 0.0)
            }),
            row("SetupExperiment tolerance <= 0", Instantiated, |c| api::fmi2SetupExperiment(c, 1, 0.0, 0.0, 0, 0.0)),
            row("SetupExperiment wrong state", Ready, |c| api::fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0)),
            row("EnterInitializationMode wrong state", Ready, |c| api::fmi2EnterInitializationMode(c)),
            row("ExitInitializationMode wrong state", Instantiated, |c| api::fmi2ExitInitializationMode(c)),
            row("Terminate wrong state", Instantiated, |c| api::fmi2Terminate(c)),
            row("GetReal unknown VR", Ready, move |c| api::fmi2GetReal(c, &unknown, 1, rp as *mut f64)),
            row("GetReal null values", Ready, |c| api::fmi2GetReal(c, &vr::X, 1, ptr::null_mut())),
            row("GetReal null VRs", Ready, move |c| api::fmi2GetReal(c, ptr::null(), 1, rp as *mut f64)),
            row("GetReal wrong state", Instantiated, move |c| api::fmi2GetReal(c, &vr::X, 1, rp as *mut f64)),
            row("GetInteger unknown VR", Ready, move |c| api::fmi2GetInteger(c, &unknown, 1, ip as *mut i32)),
            row("GetInteger null values", Ready, |c| api::fmi2GetInteger(c, &vr::STEPS, 1, ptr::null_mut())),
            row("GetBoolean unknown VR", Ready, move |c| api::fmi2GetBoolean(c, &unknown, 1, bp as *mut fmi2Boolean)),
            row("GetBoolean null values", Ready, |c| api::fmi2GetBoolean(c, &vr::POSITIVE, 1, ptr::null_mut())),
            row("GetString unknown VR", Ready, move |c| api::fmi2GetString(c, &unknown, 1, spp as *mut fmi2String)),
            row("GetString null values", Ready, |c| api::fmi2GetString(c, &vr::LABEL, 1, ptr::null_mut())),
            row("SetReal NaN", Ready, |c| api::fmi2SetReal(c, &vr::U, 1, &f64::NAN)),
            row("SetReal +Inf", Ready, |c| api::fmi2SetReal(c, &vr::U, 1, &f64::INFINITY)),
            row("SetReal -Inf", Ready, |c| api::fmi2SetReal(c, &vr::U, 1, &f64::NEG_INFINITY)),
            row("SetReal out of range", Instantiated, |c| api::fmi2SetReal(c, &vr::K, 1, &-1.0)),
            row("SetReal unknown VR", Ready, |c| api::fmi2SetReal(c, &9999, 1, &1.0)),
            row("SetReal null values", Ready, |c| api::fmi2SetReal(c, &vr::U, 1, ptr::null())),
            row("SetReal fixed after init", Ready, |c| api::fmi2SetReal(c, &vr::K, 1, &2.0)),
            row("SetReal output", Ready, |c| api::fmi2SetReal(c, &vr::X, 1, &2.0)),
            row("SetReal wrong state", Terminated, |c| api::fmi2SetReal(c, &vr::U, 1, &1.0)),
            row("SetInteger not an enum item", Instantiated, |c| api::fmi2SetInteger(c, &vr::MODE, 1, &7)),
            row("SetInteger unknown VR", Ready, |c| api::fmi2SetInteger(c, &9999, 1, &1)),
            row("SetInteger null values", Ready, |c| api::fmi2SetInteger(c, &vr::MODE, 1, ptr::null())),
            row("SetBoolean unknown VR", Ready, |c| api::fmi2SetBoolean(c, &9999, 1, &1)),
            row("SetBoolean null values", Ready, |c| api::fmi2SetBoolean(c, &vr::DAMPED, 1, ptr::null())),
            row("SetString unknown VR", Ready, |c| api::fmi2SetString(c, &9999, 1, &c"x".as_ptr())),
            row("SetString null values", Instantiated, |c| api::fmi2SetString(c, &vr::LABEL, 1, ptr::null())),
            row("SetString null string", Instantiated, |c| api::fmi2SetString(c, &vr::LABEL, 1, &ptr::null())),
            row("DoStep h = 0", Ready, |c| api::fmi2DoStep(c, 0.0, 0.0, 1)),
            row("DoStep h < 0", Ready, |c| api::fmi2DoStep(c, 0.0, -1e-3, 1)),
            row("DoStep h NaN", Ready, |c| api::fmi2DoStep(c, 0.0, f64::NAN, 1)),
            row("DoStep h Inf", Ready, |c| api::fmi2DoStep(c, 0.0, f64::INFINITY, 1)),
            row("DoStep huge h", Ready, |c| api::fmi2DoStep(c, 0.0, 1e6, 1)),
            row("DoStep t NaN", Ready, |c| api::fmi2DoStep(c, f64::NAN, 1e-3, 1)),
            row("DoStep wrong t", Ready, |c| api::fmi2DoStep(c, 5.0, 1e-3, 1)),
            row("DoStep wrong state", Instantiated, |c| api::fmi2DoStep(c, 0.0, 1e-3, 1)),
            row("CancelStep", Ready, |c| api::fmi2CancelStep(c)),
            row("GetFMUstate null", Ready, |c| api::fmi2GetFMUstate(c, ptr::null_mut())),
            row("SetFMUstate null", Ready, |c| api::fmi2SetFMUstate(c, ptr::null_mut())),
            row("SetFMUstate junk", Ready, move |c| api::fmi2SetFMUstate(c, junk_ptr as fmi2FMUstate)),
            row("SetFMUstate component as state", Ready, |c| api::fmi2SetFMUstate(c, c as fmi2FMUstate)),
            row("SetFMUstate of another instance", Ready, move |c| {
                api::fmi2SetFMUstate(c, other_state as fmi2FMUstate)
            }),
            row("SetFMUstate of a freed instance", Ready, move |c| api::fmi2SetFMUstate(c, gone_state as fmi2FMUstate)),
            row("GetFMUstate into a state of another instance", Ready, move |c| {
                let mut s = other_state as fmi2FMUstate;
                api::fmi2GetFMUstate(c, &mut s)
            }),
            row("FreeFMUstate of another instance", Ready, move |c| {
                let mut s = other_state as fmi2FMUstate;
                api::fmi2FreeFMUstate(c, &mut s)
            }),
            row("SerializedFMUstateSize of a freed instance", Ready, move |c| {
                let mut n = 0usize;
                api::fmi2SerializedFMUstateSize(c, gone_state as fmi2FMUstate, &mut n)
            }),
            row("FreeFMUstate junk", Ready, move |c| {
                let mut s = junk_ptr as fmi2FMUstate;
                api::fmi2FreeFMUstate(c, &mut s)
            }),
            row("SerializedFMUstateSize null", Ready, |c| {
                let mut n = 0usize;
                api::fmi2SerializedFMUstateSize(c, ptr::null_mut(), &mut n)
            }),
            row("SerializedFMUstateSize junk", Ready, move |c| {
                let mut n = 0usize;
                api::fmi2SerializedFMUstateSize(c, junk_ptr as fmi2FMUstate, &mut n)
            }),
            row("SerializeFMUstate junk", Ready, move |c| {
                let mut buf = [0 as fmi2Byte; 64];
                api::fmi2SerializeFMUstate(c, junk_ptr as fmi2FMUstate, buf.as_mut_ptr(), 64)
            }),
            row("SerializeFMUstate small buffer", Ready, |c| {
                let mut st: fmi2FMUstate = ptr::null_mut();
                api::fmi2GetFMUstate(c, &mut st);
                let mut buf = [0 as fmi2Byte; 4];
                let s = api::fmi2SerializeFMUstate(c, st, buf.as_mut_ptr(), 4);
                let _ = api::fmi2Reset(c);
                api::fmi2FreeFMUstate(c, &mut st);
                s
            }),
            row("DeSerializeFMUstate null bytes", Ready, |c| {
                let mut st: fmi2FMUstate = ptr::null_mut();
                api::fmi2DeSerializeFMUstate(c, ptr::null(), 16, &mut st)
            }),
            row("DeSerializeFMUstate null state", Ready, move |c| {
                api::fmi2DeSerializeFMUstate(c, g.as_ptr(), g.len(), ptr::null_mut())
            }),
            row("DeSerializeFMUstate flipped bit", Ready, move |c| {
                let mut st: fmi2FMUstate = ptr::null_mut();
                api::fmi2DeSerializeFMUstate(c, f2.as_ptr(), f2.len(), &mut st)
            }),
            row("DeSerializeFMUstate truncated", Ready, move |c| {
                let mut st: fmi2FMUstate = ptr::null_mut();
                api::fmi2DeSerializeFMUstate(c, t2.as_ptr(), t2.len(), &mut st)
            }),
            row("DeSerializeFMUstate empty", Ready, |c| {
                let mut st: fmi2FMUstate = ptr::null_mut();
                api::fmi2DeSerializeFMUstate(c, ptr::null(), 0, &mut st)
            }),
            row("DeSerializeFMUstate into junk", Ready, move |c| {
                let mut st = junk_ptr as fmi2FMUstate;
                let b = state_bytes_static();
                api::fmi2DeSerializeFMUstate(c, b.as_ptr(), b.len(), &mut st)
            }),
            row("GetDirectionalDerivative", Ready, move |c| {
                api::fmi2GetDirectionalDerivative(c, &vr::X, 1, &vr::U, 1, &1.0, rp as *mut f64)
            }),
            row("SetRealInputDerivatives", Ready, |c| api::fmi2SetRealInputDerivatives(c, &vr::U, 1, &1, &1.0)),
            row("GetRealOutputDerivatives", Ready, move |c| {
                api::fmi2GetRealOutputDerivatives(c, &vr::X, 1, &1, rp as *mut f64)
            }),
            row("GetStatus pending kind", Ready, move |c| {
                api::fmi2GetStatus(c, fmi2DoStepStatus, stp as *mut fmi2Status)
            }),
            row("GetStatus null value", Ready, |c| api::fmi2GetStatus(c, fmi2DoStepStatus, ptr::null_mut())),
            row("GetRealStatus wrong kind", Ready, move |c| api::fmi2GetRealStatus(c, fmi2Terminated, rp as *mut f64)),
            row("GetRealStatus null value", Ready, |c| {
                api::fmi2GetRealStatus(c, fmi2LastSuccessfulTime, ptr::null_mut())
            }),
            row("GetIntegerStatus", Ready, move |c| api::fmi2GetIntegerStatus(c, fmi2DoStepStatus, ip as *mut i32)),
            row("GetBooleanStatus null value", Ready, |c| {
                api::fmi2GetBooleanStatus(c, fmi2Terminated, ptr::null_mut())
            }),
            row("GetStringStatus", Ready, move |c| {
                api::fmi2GetStringStatus(c, fmi2PendingStatus, spp as *mut fmi2String)
            }),
            row("GetStatus wrong state", Instantiated, move |c| {
                api::fmi2GetStatus(c, fmi2DoStepStatus, stp as *mut fmi2Status)
            }),
        ];
        let mut refused_with_message = 0;
        for (k, (what, setup, call)) in rows.iter().enumerate() {
            let name = format!("bad-{k}");
            let c = match setup {
                Instantiated => instantiate(&name, &cb),
                Ready => ready(&name, &cb),
                Terminated => {
                    let c = ready(&name, &cb);
                    assert_eq!(api::fmi2Terminate(c), fmi2OK);
                    c
                }
            };
            assert!(!c.is_null());
            let started = Instant::now();
            let s = call(c);
            assert!(started.elapsed().as_secs_f64() < 2.0, "{what}: took {:?}", started.elapsed());
            assert!(s == fmi2Error || s == fmi2Discard, "{what}: status {s}");
            let logged = messages(&name).iter().any(|m| m.0 >= fmi2Discard && !m.2.is_empty());
            assert!(logged, "{what}: refused without a message");
            refused_with_message += 1;
            api::fmi2FreeInstance(c);
        }
        // without a component there is no logger: fmi2Error, no crash
        let j = junk_ptr as fmi2Component;
        let mut no_component = 0;
        for c in [ptr::null_mut(), j] {
            let statuses = [
                api::fmi2SetDebugLogging(c, 1, 0, ptr::null()),
                api::fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
                api::fmi2EnterInitializationMode(c),
                api::fmi2ExitInitializationMode(c),
                api::fmi2Terminate(c),
                api::fmi2Reset(c),
                api::fmi2GetReal(c, &vr::X, 1, rp as *mut f64),
                api::fmi2GetInteger(c, &vr::STEPS, 1, ip as *mut i32),
                api::fmi2GetBoolean(c, &vr::POSITIVE, 1, bp as *mut fmi2Boolean),
                api::fmi2GetString(c, &vr::LABEL, 1, spp as *mut fmi2String),
                api::fmi2SetReal(c, &vr::U, 1, &1.0),
                api::fmi2SetInteger(c, &vr::MODE, 1, &1),
                api::fmi2SetBoolean(c, &vr::DAMPED, 1, &1),
                api::fmi2SetString(c, &vr::LABEL, 1, &c"x".as_ptr()),
                api::fmi2DoStep(c, 0.0, 1e-3, 1),
                api::fmi2CancelStep(c),
                api::fmi2GetStatus(c, fmi2DoStepStatus, stp as *mut fmi2Status),
                api::fmi2GetRealStatus(c, fmi2LastSuccessfulTime, rp as *mut f64),
                api::fmi2GetIntegerStatus(c, fmi2DoStepStatus, ip as *mut i32),
                api::fmi2GetBooleanStatus(c, fmi2Terminated, bp as *mut fmi2Boolean),
                api::fmi2GetStringStatus(c, fmi2PendingStatus, spp as *mut fmi2String),
                api::fmi2GetFMUstate(c, &mut ptr::null_mut()),
                api::fmi2SetFMUstate(c, ptr::null_mut()),
                api::fmi2FreeFMUstate(c, &mut ptr::null_mut()),
                api::fmi2SerializedFMUstateSize(c, ptr::null_mut(), &mut 0),
                api::fmi2SerializeFMUstate(c, ptr::null_mut(), ptr::null_mut(), 0),
                api::fmi2DeSerializeFMUstate(c, ptr::null(), 0, &mut ptr::null_mut()),
                api::fmi2GetDirectionalDerivative(c, ptr::null(), 0, ptr::null(), 0, ptr::null(), ptr::null_mut()),
                api::fmi2SetRealInputDerivatives(c, ptr::null(), 0, ptr::null(), ptr::null()),
                api::fmi2GetRealOutputDerivatives(c, ptr::null(), 0, ptr::null(), ptr::null_mut()),
            ];
            for (k, s) in statuses.iter().enumerate() {
                assert_eq!(*s, fmi2Error, "call {k} with component {c:p}");
            }
            api::fmi2FreeInstance(c); // null and junk are ignored
            no_component += statuses.len();
        }
        // instantiation with bad arguments: null, never a crash, a message where a logger exists
        let g = CString::new(common::guid().to_str().unwrap()).unwrap();
        let n = c"bad-inst";
        let insts = [
            api::fmi2Instantiate(ptr::null(), fmi2CoSimulation, g.as_ptr(), ptr::null(), &cb, 0, 0),
            api::fmi2Instantiate(n.as_ptr(), fmi2ModelExchange, g.as_ptr(), ptr::null(), &cb, 0, 0),
            api::fmi2Instantiate(n.as_ptr(), fmi2CoSimulation, c"{wrong}".as_ptr(), ptr::null(), &cb, 0, 0),
            api::fmi2Instantiate(n.as_ptr(), fmi2CoSimulation, ptr::null(), ptr::null(), &cb, 0, 0),
            api::fmi2Instantiate(n.as_ptr(), fmi2CoSimulation, g.as_ptr(), ptr::null(), ptr::null(), 0, 0),
        ];
        assert!(insts.iter().all(|c| c.is_null()));
        assert!(messages("bad-inst").iter().filter(|m| m.0 == fmi2Error).count() >= 3);
        assert!(junk.iter().all(|&w| w == 0x77), "a junk handle was written to");
        // the other instance's state is still its own: usable there, freed with it
        assert_eq!(api::fmi2SetFMUstate(other, other_state as fmi2FMUstate), fmi2OK);
        api::fmi2FreeInstance(other);
        println!(
            "bad-input table: {} rows refused with a message, {no_component} calls without a valid component \
             answered fmi2Error, {} bad instantiations answered NULL; 0 crashes, 0 hangs, 0 fmi2Fatal",
            refused_with_message,
            insts.len()
        );
    }
}

/// A serialized state (valid bytes), built once.
fn state_bytes_static() -> &'static [fmi2Byte] {
    static B: std::sync::OnceLock<Vec<fmi2Byte>> = std::sync::OnceLock::new();
    B.get_or_init(|| state_bytes(&callbacks(81)))
}
