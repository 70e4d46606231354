//! Replays every input kept in `fuzz/regressions/` (`<target>-<hash>.bin`):
//! each must now run to completion within the time limit.

use fuzz_targets::{Executor, Outcome, TimedOut, targets};
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
    let files = kept();
    assert!(files.len() >= 8, "the kept findings are in fuzz/regressions/");
    let failed = replay(&files);
    assert!(failed.is_empty(), "{failed:#?}");
}
