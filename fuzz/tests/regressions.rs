//! Replays every input kept in `fuzz/regressions/` (`<target>-<hash>.bin`):
//! each must now run to completion within the time limit.

use fuzz_targets::{Executor, Outcome, TimedOut, targets};
use std::time::Duration;

/// Findings of the FMU-state target that need the FMU-state validation of
/// `fmi2-export`/the adapters (owned elsewhere): a deserialized state is
/// restored unchecked, and the next `fmi2DoStep` panics in a core or hangs.
/// Replayed by the ignored test below until fixed.
const KNOWN_EXPORT_PANICS: &[&str] = &[
    // milling-plant/src/plant.rs:286 `f64::clamp` with min > max (from a restored plant state)
    "fmu_state-0a3649917af9c17d.bin",
    "fmu_state-1dc7d0776757eacb.bin",
    // chatter-control/src/grunwald.rs:104 index out of bounds (len 121, index 1000) (restored controller)
    "fmu_state-602baf2b07960e57.bin",
    // chatter-control/src/controller.rs:126 `f64::clamp` with min > max (restored controller)
    "fmu_state-9f11ad122649d6c1.bin",
    // milling-plant/src/history.rs:71 "Out of bounds access" (restored plant history)
    "fmu_state-695f621c8a05febc.bin",
    // milling-plant/src/plant.rs:244 range end index 12 out of range for slice of length 3 (restored plant)
    "fmu_state-b4f1b2c284e9092a.bin",
    // fmi2DoStep on a restored state does not return within 10 s (no per-call work bound yet)
    "fmu_state-bde7e923b144b05b.bin",
    // controller: setup at start 2000 s after a first step; the next fmi2DoStep catches up
    // 20 million samples from the first step's time (chatter-control/src/grunwald.rs:56 via
    // fmu-controller/src/lib.rs:149): a hang (no per-call work bound yet)
    "call_sequence-61a61592860c3c8d.bin",
];

fn kept() -> Vec<(String, Vec<u8>)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("regressions");
    let mut v: Vec<_> = std::fs::read_dir(&dir)
        .map(|rd| {
            rd.flatten()
                .filter(|e| e.path().extension().is_some_and(|x| x == "bin"))
                .map(|e| (e.file_name().to_string_lossy().into_owned(), std::fs::read(e.path()).unwrap()))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

fn replay(files: &[(String, Vec<u8>)]) -> Vec<String> {
    let mut failed = Vec::new();
    for (name, input) in files {
        let target = name.rsplit_once('-').and_then(|(t, _)| targets::by_name(t));
        let Some(target) = target else {
            failed.push(format!("{name}: no target of that name"));
            continue;
        };
        match Executor::new(target, Duration::from_secs(5)).run(input) {
            Ok(Outcome::Done(_)) => {}
            Ok(Outcome::Panic(m)) => failed.push(format!("{name}: panic: {m}")),
            Err(TimedOut) => failed.push(format!("{name}: hang")),
        }
    }
    failed
}

#[test]
fn kept_fuzz_findings_run_clean() {
    let files: Vec<_> = kept().into_iter().filter(|(n, _)| !KNOWN_EXPORT_PANICS.contains(&n.as_str())).collect();
    let failed = replay(&files);
    assert!(failed.is_empty(), "{failed:#?}");
}

#[test]
#[ignore = "needs FMU-state validation in fmi2-export/the adapters (owned by the parallel hardening work)"]
fn known_export_layer_findings_run_clean() {
    let files: Vec<_> = kept().into_iter().filter(|(n, _)| KNOWN_EXPORT_PANICS.contains(&n.as_str())).collect();
    assert_eq!(files.len(), KNOWN_EXPORT_PANICS.len(), "every known finding is kept");
    let failed = replay(&files);
    assert!(failed.is_empty(), "{failed:#?}");
}
