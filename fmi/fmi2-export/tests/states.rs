//! Corrupted, foreign and junk FMU states and component handles through the C API: every one
//! is `fmi2Error` with a message (or, for a component handle, `fmi2Error` without a logger to
//! tell), never a panic, a hang or a crash.

mod common;
use common::{api, callbacks, messages, ready};
use fmi2_export::abi::*;
use fmi2_export::fnv1a64;
use std::ptr;

fn last_error(name: &str) -> String {
    messages(name).into_iter().filter(|m| m.0 >= fmi2Discard).map(|m| m.2).next_back().unwrap_or_default()
}

/// A serialized state of an instance that has stepped a little.
unsafe fn serialized(c: fmi2Component) -> Vec<u8> {
    unsafe {
        for k in 0..10 {
            assert_eq!(api::fmi2DoStep(c, k as f64 * 1e-2, 1e-2, 1), fmi2OK);
        }
        let mut st: fmi2FMUstate = ptr::null_mut();
        assert_eq!(api::fmi2GetFMUstate(c, &mut st), fmi2OK);
        let mut size = 0usize;
        assert_eq!(api::fmi2SerializedFMUstateSize(c, st, &mut size), fmi2OK);
        let mut bytes = vec![0 as fmi2Byte; size];
        assert_eq!(api::fmi2SerializeFMUstate(c, st, bytes.as_mut_ptr(), size), fmi2OK);
        api::fmi2FreeFMUstate(c, &mut st);
        bytes.into_iter().map(|b| b as u8).collect()
    }
}

/// Replace the trailing checksum so that only the content check can refuse the bytes.
fn reseal(bytes: &mut [u8]) {
    let n = bytes.len() - 8;
    let sum = fnv1a64(&bytes[..n]);
    bytes[n..].copy_from_slice(&sum.to_le_bytes());
}

unsafe fn deserialize(c: fmi2Component, bytes: &[u8]) -> (fmi2Status, fmi2FMUstate) {
    let mut st: fmi2FMUstate = ptr::null_mut();
    let s = unsafe { api::fmi2DeSerializeFMUstate(c, bytes.as_ptr() as *const fmi2Byte, bytes.len(), &mut st) };
    (s, st)
}

#[test]
fn every_single_bit_corruption_of_a_serialized_state_is_refused() {
    let cb = callbacks(60);
    unsafe {
        let c = ready("bits", &cb);
        let bytes = serialized(c);
        let mut refused = 0;
        for i in 0..bytes.len() * 8 {
            let mut bad = bytes.clone();
            bad[i / 8] ^= 1 << (i % 8);
            let (s, st) = deserialize(c, &bad);
            assert_eq!(s, fmi2Error, "bit {i} flipped was accepted");
            assert!(st.is_null());
            assert!(last_error("bits").contains("fmi2DeSerializeFMUstate"));
            assert_eq!(api::fmi2Reset(c), fmi2OK);
            refused += 1;
        }
        println!("{refused} of {} single-bit corruptions refused", bytes.len() * 8);
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn a_resealed_state_with_non_finite_or_out_of_range_values_is_refused_by_validation() {
    let cb = callbacks(61);
    unsafe {
        let c = ready("reseal", &cb);
        let bytes = serialized(c);
        // the parameter k = 4.0 (bounds [0, 1e6]) is stored as 8 little-endian bytes
        let k = 4.0f64.to_le_bytes();
        let at = bytes.windows(8).position(|w| w == k).expect("k in the state");
        for (bad_k, what) in [(f64::NAN, "not finite"), (-1.0, "outside its bounds"), (2e6, "outside its bounds")] {
            let mut bad = bytes.clone();
            bad[at..at + 8].copy_from_slice(&bad_k.to_le_bytes());
            reseal(&mut bad);
            let (s, st) = deserialize(c, &bad);
            assert_eq!(s, fmi2Error, "k = {bad_k} accepted");
            assert!(st.is_null());
            let m = last_error("reseal");
            assert!(m.contains("invalid state") && m.contains(what), "{m}");
            assert_eq!(api::fmi2Reset(c), fmi2OK);
        }
        // the unchanged, resealed bytes still load
        let mut same = bytes.clone();
        reseal(&mut same);
        let (s, mut st) = deserialize(c, &same);
        assert_eq!(s, fmi2OK);
        api::fmi2FreeFMUstate(c, &mut st);
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn foreign_and_junk_state_handles_are_errors_with_a_message() {
    let cb = callbacks(62);
    unsafe {
        let c = ready("foreign", &cb);
        let mut junk = vec![0x5au64; 64];
        let j = junk.as_mut_ptr() as fmi2FMUstate;
        assert_eq!(api::fmi2SetFMUstate(c, j), fmi2Error);
        assert!(last_error("foreign").contains("not a live state of this instance"), "{}", last_error("foreign"));
        api::fmi2Reset(c);
        let mut size = 0usize;
        assert_eq!(api::fmi2SerializedFMUstateSize(c, j, &mut size), fmi2Error);
        api::fmi2Reset(c);
        let mut bytes = [0 as fmi2Byte; 16];
        assert_eq!(api::fmi2SerializeFMUstate(c, j, bytes.as_mut_ptr(), 16), fmi2Error);
        api::fmi2Reset(c);
        let mut jj = j;
        assert_eq!(api::fmi2GetFMUstate(c, &mut jj), fmi2Error);
        api::fmi2Reset(c);
        assert_eq!(api::fmi2FreeFMUstate(c, &mut jj), fmi2Error);
        assert_eq!(jj, j, "a foreign handle is not freed");
        api::fmi2Reset(c);
        // a component handle passed as a state, a state handle passed as a component
        assert_eq!(api::fmi2SetFMUstate(c, c as fmi2FMUstate), fmi2Error);
        api::fmi2Reset(c);
        let mut st: fmi2FMUstate = ptr::null_mut();
        assert_eq!(api::fmi2GetFMUstate(c, &mut st), fmi2OK);
        assert_eq!(api::fmi2DoStep(st as fmi2Component, 0.0, 1e-3, 1), fmi2Error);
        assert_eq!(api::fmi2FreeFMUstate(c, &mut st), fmi2OK);
        assert!(junk.iter().all(|&w| w == 0x5a), "the junk was written to");
        junk.clear();
        api::fmi2FreeInstance(c);
    }
}

#[test]
fn junk_component_handles_are_errors_not_crashes() {
    let mut junk = vec![0u64; 256];
    let j = junk.as_mut_ptr() as fmi2Component;
    let mut x = 0.0;
    unsafe {
        assert_eq!(api::fmi2DoStep(j, 0.0, 1e-3, 1), fmi2Error);
        assert_eq!(api::fmi2GetReal(j, &0, 1, &mut x), fmi2Error);
        assert_eq!(api::fmi2Reset(j), fmi2Error);
        api::fmi2FreeInstance(j); // ignored, not freed
    }
    assert!(junk.iter().all(|&w| w == 0));
}

/// FMI 2.0 §2.1.3: after `fmi2Error` "the simulation cannot be continued with this FMU
/// instance", but "it can be tried to restart the simulation from a formerly stored FMU state by
/// calling fmi2SetFMUstate" if it "was called before in non-erroneous state". An error of a
/// harmless call (an unknown value reference) therefore blocks stepping, with a message naming
/// that error and the ways out; a state stored before the error resumes stepping, one stored in
/// the error state does not, and `fmi2Reset` starts over.
#[test]
fn after_an_error_a_state_stored_before_it_resumes_stepping() {
    let cb = callbacks(63);
    let mut x = 0.0;
    unsafe {
        let c = ready("after-error", &cb);
        assert_eq!(api::fmi2DoStep(c, 0.0, 1e-2, 1), fmi2OK);
        let mut before: fmi2FMUstate = ptr::null_mut();
        assert_eq!(api::fmi2GetFMUstate(c, &mut before), fmi2OK);
        assert_eq!(api::fmi2GetReal(c, &9999, 1, &mut x), fmi2Error);
        assert_eq!(api::fmi2DoStep(c, 1e-2, 1e-2, 1), fmi2Error);
        let m = last_error("after-error");
        assert!(
            m.contains("not allowed after an fmi2Error (fmi2GetReal: unknown value reference 9999")
                && m.contains("fmi2SetFMUstate")
                && m.contains("fmi2Reset"),
            "{m}"
        );
        // outputs can still be read in the error state, and a state stored now keeps the error
        assert_eq!(api::fmi2GetReal(c, &common::vr::X, 1, &mut x), fmi2OK);
        let mut during: fmi2FMUstate = ptr::null_mut();
        assert_eq!(api::fmi2GetFMUstate(c, &mut during), fmi2OK);
        assert_eq!(api::fmi2SetFMUstate(c, before), fmi2OK);
        assert_eq!(api::fmi2DoStep(c, 1e-2, 1e-2, 1), fmi2OK, "{}", last_error("after-error"));
        assert_eq!(api::fmi2SetFMUstate(c, during), fmi2OK);
        assert_eq!(api::fmi2DoStep(c, 1e-2, 1e-2, 1), fmi2Error);
        assert!(last_error("after-error").contains("a state stored in the error state was restored"));
        assert_eq!(api::fmi2Reset(c), fmi2OK);
        assert_eq!(api::fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
        assert_eq!(api::fmi2EnterInitializationMode(c), fmi2OK);
        assert_eq!(api::fmi2ExitInitializationMode(c), fmi2OK);
        assert_eq!(api::fmi2DoStep(c, 0.0, 1e-2, 1), fmi2OK);
        api::fmi2FreeInstance(c); // frees both states
    }
}
