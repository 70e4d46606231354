//! Replays every input kept in `fuzz/regressions/` (`<target>-<hash>.bin`):
//! each must now run to completion within the time limit.

use fmi2_export::Fmi2Model;
use fmi2_export::instance::Snapshot;
use fmu_controller::ChatterController;
use fmu_plant::MillingPlant;
use fuzz::{Executor, Outcome, TimedOut, targets};
use std::time::Duration;

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

/// Replace the trailing FNV-1a 64 checksum of a serialized state.
fn reseal(b: &mut [u8]) {
    let n = b.len() - 8;
    let sum = fmi2_export::fnv1a64(&b[..n]);
    b[n..].copy_from_slice(&sum.to_le_bytes());
}

/// A kept FMU state carries the GUID of the build that found it, and a GUID changes with any
/// change of a model's description: replayed as found, the state would stop at the GUID check
/// and test nothing. So each kept state is replayed as found and with its GUID replaced by each
/// current model's (checksum resealed), which reaches the models' validation.
fn restamped(input: &[u8]) -> Vec<Vec<u8>> {
    let mut out = vec![input.to_vec()];
    let header = 8 + 4 + 4;
    if input.len() < header + 8 || !input.starts_with(b"CHFMUST\0") {
        return out;
    }
    let n = u32::from_le_bytes(input[12..16].try_into().unwrap()) as usize;
    for guid in [&MillingPlant::description().guid, &ChatterController::description().guid] {
        if guid.len() == n && input.len() >= header + n + 8 {
            let mut b = input.to_vec();
            b[header..header + n].copy_from_slice(guid.as_bytes());
            reseal(&mut b);
            out.push(b);
        }
    }
    out
}

/// Does a restamped state get past the header and GUID checks of one of the models?
fn reaches_a_model(state: &[u8]) -> bool {
    let past = |e: String| !e.contains("GUID mismatch") && !e.contains("bad header") && !e.contains("checksum");
    [
        Snapshot::<MillingPlant>::deserialize(state).map(|_| ()).map_err(|e| format!("{e:?}")),
        Snapshot::<ChatterController>::deserialize(state).map(|_| ()).map_err(|e| format!("{e:?}")),
    ]
    .into_iter()
    .any(|r| r.map_or_else(past, |()| true))
}

fn replay(files: &[(String, Vec<u8>)]) -> Vec<String> {
    let mut failed = Vec::new();
    for (name, input) in files.iter().flat_map(|(n, b)| restamped(b).into_iter().map(move |b| (n, b))) {
        let input = &input;
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
    let files = kept();
    assert!(files.len() >= 8, "the kept findings are in fuzz/regressions/");
    let failed = replay(&files);
    assert!(failed.is_empty(), "{failed:#?}");
    for (name, input) in files.iter().filter(|(n, _)| n.starts_with("fmu_state-")) {
        assert!(restamped(input).iter().any(|b| reaches_a_model(b)), "{name}: stops at the header or GUID check");
    }
}
