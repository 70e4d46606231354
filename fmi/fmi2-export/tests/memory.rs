//! Memory of the export layer stays flat over 10 000 instantiate/step/state/free cycles
//! (alone in its test binary, so that no other test moves the resident set).

mod common;
use common::{api, callbacks, ready, vr};
use fmi2_export::abi::*;
use std::ptr;

/// Resident set size [bytes] from `/proc/self/statm` (Linux).
fn rss() -> usize {
    let statm = std::fs::read_to_string("/proc/self/statm").expect("/proc/self/statm");
    let pages: usize = statm.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * 4096
}

fn cycles(n: usize, cb: &fmi2CallbackFunctions) {
    for _ in 0..n {
        let c = ready("cycle", cb);
        let mut st: fmi2FMUstate = ptr::null_mut();
        unsafe {
            assert_eq!(api::fmi2DoStep(c, 0.0, 1e-3, 1), fmi2OK);
            assert_eq!(api::fmi2GetFMUstate(c, &mut st), fmi2OK);
            let mut size = 0usize;
            assert_eq!(api::fmi2SerializedFMUstateSize(c, st, &mut size), fmi2OK);
            let mut bytes = vec![0 as fmi2Byte; size];
            assert_eq!(api::fmi2SerializeFMUstate(c, st, bytes.as_mut_ptr(), size), fmi2OK);
            assert_eq!(api::fmi2DeSerializeFMUstate(c, bytes.as_ptr(), size, &mut st), fmi2OK);
            assert_eq!(api::fmi2FreeFMUstate(c, &mut st), fmi2OK);
            let mut p: fmi2String = ptr::null();
            assert_eq!(api::fmi2GetString(c, &vr::LABEL, 1, &mut p), fmi2OK);
            api::fmi2FreeInstance(c);
        }
    }
}

#[test]
#[cfg(target_os = "linux")]
fn ten_thousand_instantiate_free_cycles_keep_memory_flat() {
    let cb = callbacks(70);
    cycles(1_000, &cb); // warm-up: allocator pools, lazily built tables
    let before = rss();
    cycles(10_000, &cb);
    let after = rss();
    let growth = after as f64 - before as f64;
    println!("RSS over 10 000 cycles: {before} -> {after} bytes ({:+.1} KiB)", growth / 1024.0);
    // a leak of one component (> 1 KiB) per cycle would be > 10 MiB
    assert!(growth < 1024.0 * 1024.0, "memory grew by {growth} bytes");
}
