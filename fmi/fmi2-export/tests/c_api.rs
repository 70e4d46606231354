//! In-process tests of the exported C functions: every misuse returns the
//! right status, logs a message through the host's logger, and the process survives.
#![allow(missing_docs, clippy::float_cmp)]

mod common;
use common::{api, callbacks, get_real, instantiate, messages, ready, set_real, vr};
use fmi2_export::abi::*;
use std::ffi::{CStr, CString};
use std::ptr;

fn last_error(name: &str) -> String {
    messages(name).into_iter().filter(|m| m.0 >= fmi2Discard).map(|m| m.2).next_back().unwrap_or_default()
}

#[test]
fn null_component_is_an_error_everywhere() {
    let null = ptr::null_mut();
    unsafe {
        assert_eq!(api::fmi2DoStep(null, 0.0, 1e-3, 1), fmi2Error);
        assert_eq!(api::fmi2EnterInitializationMode(null), fmi2Error);
        assert_eq!(api::fmi2SetupExperiment(null, 0, 0.0, 0.0, 0, 0.0), fmi2Error);
        let mut x = 0.0;
        assert_eq!(api::fmi2GetReal(null, &0, 1, &mut x), fmi2Error);
        assert_eq!(api::fmi2Terminate(null), fmi2Error);
        assert_eq!(api::fmi2Reset(null), fmi2Error);
        api::fmi2FreeInstance(null); // tolerated
    }
}

#[test]
fn types_platform_and_version() {
    unsafe {
        assert_eq!(CStr::from_ptr(api::fmi2GetTypesPlatform()).to_str().unwrap(), "default");
        assert_eq!(CStr::from_ptr(api::fmi2GetVersion()).to_str().unwrap(), "2.0");
    }
}

#[test]
fn wrong_guid_and_wrong_type_are_refused_with_a_message() {
    let cb = callbacks(1);
    let name = CString::new("wrong-guid").unwrap();
    let c = unsafe {
        api::fmi2Instantiate(
            name.as_ptr(),
            fmi2CoSimulation,
            c"{00000000-0000-0000-0000-000000000000}".as_ptr(),
            ptr::null(),
            &cb,
            0,
            0,
        )
    };
    assert!(c.is_null());
    assert!(last_error("wrong-guid").contains("Wrong GUID"), "{:?}", messages("wrong-guid"));

    let name = CString::new("wrong-type").unwrap();
    let g = common::guid();
    let c = unsafe { api::fmi2Instantiate(name.as_ptr(), fmi2ModelExchange, g.as_ptr(), ptr::null(), &cb, 0, 0) };
    assert!(c.is_null());
    assert!(last_error("wrong-type").contains("Co-Simulation"));

    let c = unsafe { api::fmi2Instantiate(ptr::null(), fmi2CoSimulation, g.as_ptr(), ptr::null(), &cb, 0, 0) };
    assert!(c.is_null());
}

#[test]
fn null_logger_and_empty_name_do_not_crash_and_null_callbacks_are_refused() {
    let g = common::guid();
    let mut cb = callbacks(0);
    cb.logger = None;
    unsafe {
        let c = api::fmi2Instantiate(c"".as_ptr(), fmi2CoSimulation, g.as_ptr(), ptr::null(), &cb, 0, 1);
        assert!(!c.is_null());
        assert_eq!(api::fmi2DoStep(c, 0.0, 1e-3, 1), fmi2Error); // wrong state, logged to nobody
        api::fmi2FreeInstance(c);
        // `functions` is required (FMI 2.0): without it the instantiation is refused
        let c = api::fmi2Instantiate(c"x".as_ptr(), fmi2CoSimulation, g.as_ptr(), ptr::null(), ptr::null(), 0, 0);
        assert!(c.is_null());
        let c = api::fmi2Instantiate(c"x".as_ptr(), fmi2CoSimulation, g.as_ptr(), ptr::null(), &cb, 0, 0);
        assert!(!c.is_null());
        assert_eq!(api::fmi2SetDebugLogging(c, 1, 1, [ptr::null()].as_ptr()), fmi2Error);
        api::fmi2FreeInstance(c);
        let bad = api::fmi2Instantiate(c"y".as_ptr(), fmi2CoSimulation, ptr::null(), ptr::null(), ptr::null(), 0, 0);
        assert!(bad.is_null());
    }
}

#[test]
fn calls_in_the_wrong_state_are_errors() {
    let cb = callbacks(2);
    let c = instantiate("wrong-state", &cb);
    unsafe {
        assert_eq!(api::fmi2DoStep(c, 0.0, 1e-3, 1), fmi2Error);
        assert!(last_error("wrong-state").contains("not allowed in state Instantiated"));
        api::fmi2FreeInstance(c);
        let c = ready("wrong-state-2", &cb);
        assert_eq!(api::fmi2EnterInitializationMode(c), fmi2Error);
        assert!(last_error("wrong-state-2").contains("fmi2EnterInitializationMode"));
        // after an error only get, reset and free are allowed
        assert_eq!(api::fmi2DoStep(c, 0.0, 1e-3, 1), fmi2Error);
        assert_eq!(get_real(c, vr::X).0, fmi2OK);
        assert_eq!(api::fmi2Reset(c), fmi2OK);
        assert_eq!(api::fmi2EnterInitializationMode(c), fmi2OK);
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn unknown_value_reference_and_null_arrays() {
    let cb = callbacks(3);
    let c = ready("unknown-vr", &cb);
    unsafe {
        let (s, _) = get_real(c, 999);
        assert_eq!(s, fmi2Error);
        assert!(last_error("unknown-vr").contains("unknown value reference 999"));
        api::fmi2Reset(c);
        let mut x = 0.0;
        assert_eq!(api::fmi2GetReal(c, ptr::null(), 1, &mut x), fmi2Error); // Instantiated: Get not allowed anyway
        let c2 = ready("null-array", &cb);
        assert_eq!(api::fmi2GetReal(c2, ptr::null(), 2, &mut x), fmi2Error);
        assert!(last_error("null-array").contains("NULL"));
        let c3 = ready("empty-array", &cb);
        assert_eq!(api::fmi2GetReal(c3, ptr::null(), 0, ptr::null_mut()), fmi2OK);
        for c in [c, c2, c3] {
            api::fmi2FreeInstance(c);
        }
    }
}

#[test]
fn nan_inputs_and_out_of_range_values_are_refused() {
    let cb = callbacks(4);
    let c = ready("nan", &cb);
    // a non-finite input is discarded (nothing stored, the instance stays usable) ...
    assert_eq!(set_real(c, vr::U, f64::NAN), fmi2Discard);
    assert!(last_error("nan").contains("not finite"));
    assert_eq!(set_real(c, vr::U, 0.5), fmi2OK);
    unsafe { api::fmi2FreeInstance(c) };
    // ... a non-finite parameter is an error
    let c = instantiate("inf-parameter", &cb);
    assert_eq!(set_real(c, vr::K, f64::INFINITY), fmi2Error);
    assert!(last_error("inf-parameter").contains("not finite"));
    unsafe { api::fmi2FreeInstance(c) };
    let c = instantiate("range", &cb);
    assert_eq!(set_real(c, vr::K, -1.0), fmi2Error);
    assert!(last_error("range").contains("outside"));
    unsafe { api::fmi2FreeInstance(c) };
    let c = instantiate("enum", &cb);
    unsafe {
        assert_eq!(api::fmi2SetInteger(c, &vr::MODE, 1, &7), fmi2Error);
        assert!(last_error("enum").contains("enumeration"));
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn step_size_and_communication_point_are_checked() {
    let cb = callbacks(5);
    unsafe {
        let c = ready("h0", &cb);
        assert_eq!(api::fmi2DoStep(c, 0.0, 0.0, 1), fmi2Error);
        assert!(last_error("h0").contains("communicationStepSize"));
        api::fmi2FreeInstance(c);
        let c = ready("hneg", &cb);
        assert_eq!(api::fmi2DoStep(c, 0.0, -1e-3, 1), fmi2Error);
        api::fmi2FreeInstance(c);
        let c = ready("tc", &cb);
        assert_eq!(api::fmi2DoStep(c, 0.5, 1e-3, 1), fmi2Error);
        assert!(last_error("tc").contains("currentCommunicationPoint"));
        api::fmi2FreeInstance(c);
        // a master accumulating t += h drifts; the tolerance accepts it
        let c = ready("drift", &cb);
        let mut t = 0.0;
        for _ in 0..1000 {
            assert_eq!(api::fmi2DoStep(c, t, 0.1, 1), fmi2OK);
            t += 0.1;
        }
        let mut last = 0.0;
        assert_eq!(api::fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &mut last), fmi2OK);
        assert_eq!(last, 100.0, "internal time is t0 + n·h, exact");
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn stop_time_is_enforced() {
    let cb = callbacks(6);
    let c = instantiate("stop", &cb);
    unsafe {
        assert_eq!(api::fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 0.01), fmi2OK);
        api::fmi2EnterInitializationMode(c);
        api::fmi2ExitInitializationMode(c);
        for i in 0..10 {
            assert_eq!(api::fmi2DoStep(c, i as f64 * 1e-3, 1e-3, 1), fmi2OK);
        }
        assert_eq!(api::fmi2DoStep(c, 0.01, 1e-3, 1), fmi2Error);
        assert!(last_error("stop").contains("stop time"));
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn fixed_parameter_after_initialization_is_refused_by_name() {
    let cb = callbacks(7);
    let c = ready("fixed", &cb);
    assert_eq!(set_real(c, vr::K, 2.0), fmi2Error);
    assert!(last_error("fixed").contains("\"k\""), "{}", last_error("fixed"));
    unsafe { api::fmi2FreeInstance(c) };
    // tunable parameter and input are fine after initialization
    let c = ready("tunable", &cb);
    assert_eq!(set_real(c, vr::GAIN, 2.0), fmi2OK);
    assert_eq!(set_real(c, vr::U, 1.0), fmi2OK);
    // outputs are never settable
    assert_eq!(set_real(c, vr::X, 1.0), fmi2Error);
    unsafe { api::fmi2FreeInstance(c) };
}

#[test]
fn model_initialization_error_is_reported() {
    let cb = callbacks(8);
    let c = instantiate("init-error", &cb);
    unsafe {
        let s = c"invalid";
        assert_eq!(api::fmi2SetString(c, &vr::LABEL, 1, &s.as_ptr()), fmi2OK);
        api::fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0);
        api::fmi2EnterInitializationMode(c);
        assert_eq!(api::fmi2ExitInitializationMode(c), fmi2Error);
        assert!(last_error("init-error").contains("refused"));
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn strings_stay_valid_until_the_next_get_string() {
    let cb = callbacks(9);
    let c = ready("strings", &cb);
    unsafe {
        let mut p: fmi2String = ptr::null();
        assert_eq!(api::fmi2GetString(c, &vr::LABEL, 1, &mut p), fmi2OK);
        let mut x = 0.0;
        api::fmi2GetReal(c, &vr::X, 1, &mut x); // other calls do not invalidate it
        assert_eq!(CStr::from_ptr(p).to_str().unwrap(), "osc");
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn injected_panic_is_fatal_not_an_abort() {
    let cb = callbacks(10);
    let c = ready("panic", &cb);
    assert_eq!(set_real(c, vr::PANIC_AT, 0.002), fmi2OK);
    unsafe {
        assert_eq!(api::fmi2DoStep(c, 0.0, 1e-3, 1), fmi2OK);
        assert_eq!(api::fmi2DoStep(c, 1e-3, 1e-3, 1), fmi2OK);
        assert_eq!(api::fmi2DoStep(c, 2e-3, 1e-3, 1), fmi2Fatal);
        let msgs = messages("panic");
        assert!(msgs.iter().any(|m| m.0 == fmi2Fatal && m.2.contains("injected panic")), "{msgs:?}");
        // only free is allowed now; everything else answers fmi2Fatal
        assert_eq!(api::fmi2DoStep(c, 2e-3, 1e-3, 1), fmi2Fatal);
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn discard_moves_to_step_failed() {
    let cb = callbacks(11);
    let c = ready("discard", &cb);
    unsafe {
        assert_eq!(api::fmi2DoStep(c, 0.0, 0.6, 1), fmi2Discard);
        assert!(last_error("discard").contains("too large"));
        let mut t = -1.0;
        assert_eq!(api::fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &mut t), fmi2OK);
        assert_eq!(t, 0.0);
        assert_eq!(api::fmi2DoStep(c, 0.0, 1e-3, 1), fmi2Error);
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn optional_functions_answer_honestly() {
    let cb = callbacks(12);
    let c = ready("optional", &cb);
    unsafe {
        let mut s = fmi2OK;
        assert_eq!(api::fmi2GetStatus(c, fmi2DoStepStatus, &mut s), fmi2Discard);
        let mut b = 1;
        assert_eq!(api::fmi2GetBooleanStatus(c, fmi2Terminated, &mut b), fmi2OK);
        assert_eq!(b, fmi2False);
        assert_eq!(api::fmi2SetRealInputDerivatives(c, &vr::U, 1, &1, &0.0), fmi2Error);
        assert!(last_error("optional").contains("canInterpolateInputs"));
        api::fmi2FreeInstance(c);
        let c = ready("optional-2", &cb);
        assert_eq!(api::fmi2CancelStep(c), fmi2Error);
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn debug_logging_categories() {
    let cb = callbacks(13);
    let c = ready("debug", &cb);
    unsafe {
        assert_eq!(api::fmi2SetDebugLogging(c, 1, 1, [c"logEvents".as_ptr()].as_ptr()), fmi2OK);
        api::fmi2DoStep(c, 0.0, 1e-3, 1);
        assert!(messages("debug").iter().any(|m| m.0 == fmi2OK && m.1 == "logEvents" && m.2 == "first step done"));
        assert_eq!(api::fmi2SetDebugLogging(c, 1, 1, [c"noSuchCategory".as_ptr()].as_ptr()), fmi2Error);
        assert!(last_error("debug").contains("noSuchCategory"));
        api::fmi2FreeInstance(c);
    }
    // with logging off, informational messages are not sent
    let c = ready("quiet", &cb);
    unsafe {
        api::fmi2DoStep(c, 0.0, 1e-3, 1);
        assert!(messages("quiet").iter().all(|m| m.0 != fmi2OK));
        api::fmi2FreeInstance(c);
    }
}

fn trajectory(c: fmi2Component, t0: f64, n: usize) -> Vec<u64> {
    (0..n)
        .map(|i| unsafe {
            set_real(c, vr::U, (i as f64 * 0.37).sin());
            assert_eq!(api::fmi2DoStep(c, t0 + i as f64 * 1e-3, 1e-3, 1), fmi2OK);
            get_real(c, vr::X).1.to_bits()
        })
        .collect()
}

#[test]
fn state_get_set_and_serialize_round_trip_bit_for_bit() {
    let cb = callbacks(14);
    let c = ready("state", &cb);
    unsafe {
        trajectory(c, 0.0, 50);
        let mut st: fmi2FMUstate = ptr::null_mut();
        assert_eq!(api::fmi2GetFMUstate(c, &mut st), fmi2OK);
        let reference = trajectory(c, 0.05, 100);
        // in-memory restore
        assert_eq!(api::fmi2SetFMUstate(c, st), fmi2OK);
        assert_eq!(trajectory(c, 0.05, 100), reference);
        // serialize, free, deserialize into another instance
        let mut size = 0usize;
        assert_eq!(api::fmi2SerializedFMUstateSize(c, st, &mut size), fmi2OK);
        let mut bytes = vec![0 as fmi2Byte; size];
        assert_eq!(api::fmi2SerializeFMUstate(c, st, bytes.as_mut_ptr(), size), fmi2OK);
        assert_eq!(api::fmi2FreeFMUstate(c, &mut st), fmi2OK);
        assert!(st.is_null());
        let c2 = ready("state-2", &cb);
        let mut st2: fmi2FMUstate = ptr::null_mut();
        assert_eq!(api::fmi2DeSerializeFMUstate(c2, bytes.as_ptr(), size, &mut st2), fmi2OK);
        assert_eq!(api::fmi2SetFMUstate(c2, st2), fmi2OK);
        assert_eq!(trajectory(c2, 0.05, 100), reference);
        api::fmi2FreeFMUstate(c2, &mut st2);
        // corrupted and truncated bytes are refused
        let mut bad = bytes.clone();
        let last = bad.len() - 1;
        bad.truncate(last);
        let mut st3: fmi2FMUstate = ptr::null_mut();
        assert_eq!(api::fmi2DeSerializeFMUstate(c2, bad.as_ptr(), bad.len(), &mut st3), fmi2Error);
        assert!(st3.is_null());
        assert!(last_error("state-2").contains("fmi2DeSerializeFMUstate"));
        api::fmi2Reset(c2);
        let mut garbage = bytes.clone();
        garbage[0] ^= 0x55;
        assert_eq!(api::fmi2DeSerializeFMUstate(c2, garbage.as_ptr(), garbage.len(), &mut st3), fmi2Error);
        api::fmi2FreeInstance(c);
        api::fmi2FreeInstance(c2);
    }
}

#[test]
fn many_instances_are_independent_across_threads() {
    let reference = {
        let cb = callbacks(15);
        let c = ready("ref", &cb);
        let r = trajectory(c, 0.0, 2000);
        unsafe { api::fmi2FreeInstance(c) };
        r
    };
    let handles: Vec<_> = (0..8)
        .map(|i| {
            std::thread::spawn(move || {
                let cb = callbacks(100 + i);
                let c = ready(&format!("thread-{i}"), &cb);
                let r = trajectory(c, 0.0, 2000);
                unsafe { api::fmi2FreeInstance(c) };
                r
            })
        })
        .collect();
    for h in handles {
        assert_eq!(h.join().unwrap(), reference);
    }
}

/// A thousand instantiate → step → state → string → free cycles, every call checked: the
/// statuses, the state handle made and nulled again, the string read, no message of the
/// instances above fmi2OK, and every model freed (the oscillators alive on this thread are
/// counted: a leaked instance or state fails here, not only under valgrind).
#[test]
fn thousand_instantiate_free_cycles() {
    let cb = callbacks(16);
    let live = common::live_models();
    for k in 0..1000 {
        let c = ready("cycle", &cb); // asserts non-null, setup, enter and exit fmi2OK
        assert_eq!(common::live_models(), live + 1, "cycle {k}: one model after initialization");
        let mut st: fmi2FMUstate = ptr::null_mut();
        let mut p: fmi2String = ptr::null();
        unsafe {
            assert_eq!(api::fmi2DoStep(c, 0.0, 1e-3, 1), fmi2OK, "cycle {k}: DoStep");
            assert_eq!(api::fmi2GetFMUstate(c, &mut st), fmi2OK, "cycle {k}: GetFMUstate");
            assert!(!st.is_null(), "cycle {k}: GetFMUstate gave no state");
            assert_eq!(common::live_models(), live + 2, "cycle {k}: the state holds a copy of the model");
            assert_eq!(api::fmi2FreeFMUstate(c, &mut st), fmi2OK, "cycle {k}: FreeFMUstate");
            assert!(st.is_null(), "cycle {k}: FreeFMUstate left the handle set");
            assert_eq!(common::live_models(), live + 1, "cycle {k}: FreeFMUstate freed no model");
            assert_eq!(api::fmi2GetString(c, &vr::LABEL, 1, &mut p), fmi2OK, "cycle {k}: GetString");
            assert!(!p.is_null(), "cycle {k}: GetString gave NULL");
            assert_eq!(CStr::from_ptr(p).to_str(), Ok("osc"), "cycle {k}: GetString");
            api::fmi2FreeInstance(c);
        }
        assert_eq!(common::live_models(), live, "cycle {k}: FreeInstance freed no model");
    }
    let refusals: Vec<_> = messages("cycle").into_iter().filter(|m| m.0 != fmi2OK).collect();
    assert!(refusals.is_empty(), "{refusals:?}");
}

#[test]
fn environment_pointer_is_passed_back() {
    let cb = callbacks(4242);
    let c = instantiate("env", &cb);
    unsafe {
        api::fmi2DoStep(c, 0.0, 1e-3, 1);
        api::fmi2FreeInstance(c);
    }
    let log = common::LOG.lock().unwrap();
    assert!(log.iter().any(|m| m.1 == "env" && m.0 == 4242));
}

#[test]
fn writes_the_test_model_description_for_external_validation() {
    // tests/python/test_export_layer.py validates this file with FMPy's XSD checks.
    use fmi2_export::Fmi2Model;
    let xml = common::Oscillator::description().to_xml().unwrap();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/fmu-test");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("Oscillator.modelDescription.xml"), xml).unwrap();
}

#[test]
fn a_step_costing_more_than_the_work_bound_is_an_error_with_the_limit() {
    let cb = callbacks(40);
    unsafe {
        let c = ready("huge", &cb);
        // 1e6 s at the test model's 1 ms substeps: 1e9 substeps, refused before the model runs
        assert_eq!(api::fmi2DoStep(c, 0.0, 1e6, 1), fmi2Error);
        let m = last_error("huge");
        assert!(m.contains("internal steps") && m.contains("1e7"), "{m}");
        api::fmi2FreeInstance(c);
    }
}

/// A master that counts time in integer nanoseconds (libcosim) passes `h_n = t_{n+1} − t_n`
/// computed in doubles, which wanders by an ulp around the nominal step. The instance treats
/// such an `h` as its current step, so the model integrates exactly the steps its clock counts
/// and the results are bitwise those of a master passing the nominal `h` every time.
#[test]
fn an_ulp_wandering_step_size_gives_the_nominal_steps_results() {
    let cb = callbacks(4);
    let (a, b) = (ready("h-nominal", &cb), ready("h-ns", &cb));
    let (h, h_ns) = (3e-4, 300_000_i64);
    let mut wandered = 0;
    for k in 0..400_i64 {
        let t_ns = |n: i64| (n * h_ns) as f64 * 1e-9;
        let h_k = t_ns(k + 1) - t_ns(k);
        wandered += usize::from(h_k != h);
        unsafe {
            assert_eq!(api::fmi2DoStep(a, k as f64 * h, h, 1), fmi2OK);
            assert_eq!(api::fmi2DoStep(b, t_ns(k), h_k, 1), fmi2OK, "step {k}: h = {h_k:e}");
        }
        assert_eq!(get_real(a, vr::X).1.to_bits(), get_real(b, vr::X).1.to_bits(), "step {k}");
    }
    assert!(wandered > 10, "the nanosecond steps must differ from the nominal one ({wandered} did)");
    unsafe {
        api::fmi2FreeInstance(a);
        api::fmi2FreeInstance(b);
    }
}
