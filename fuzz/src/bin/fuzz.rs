//! Long fuzzing runs: `cargo run --release -p fuzz-targets -- --minutes 10`
//! [`--target NAME`] [`--seed N`] [`--limit-ms MS`], or `-- --replay FILE` (one kept input, with its backtrace). The time is shared
//! equally by the targets; each input runs under the per-input limit.
//! Findings (panics, hangs) are written to `fuzz/regressions/` and the
//! process exits with status 1.

use fuzz_targets::{Campaign, targets};
use std::time::Duration;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| args.iter().position(|a| a == flag).and_then(|i| args.get(i + 1)).cloned();
    let minutes: f64 = value("--minutes").map(|s| s.parse().expect("--minutes: a number")).unwrap_or(1.0);
    let seed: u64 = value("--seed").map(|s| s.parse().expect("--seed: an integer")).unwrap_or(1);
    let limit = Duration::from_millis(value("--limit-ms").map(|s| s.parse().expect("--limit-ms")).unwrap_or(2000));
    if let Some(file) = value("--replay") {
        // One kept input, on this thread: a panic prints its backtrace.
        let name = std::path::Path::new(&file).file_stem().and_then(|s| s.to_str()).unwrap_or_default();
        let target = name.rsplit_once('-').and_then(|(t, _)| targets::by_name(t)).expect("<target>-<hash>.bin");
        println!("{}", (target.run)(&std::fs::read(&file).expect("reading the input")));
        return;
    }
    let chosen: Vec<_> = match value("--target") {
        Some(n) => vec![targets::by_name(&n).unwrap_or_else(|| panic!("unknown target {n}"))],
        None => targets::ALL.to_vec(),
    };
    let per_target = Duration::from_secs_f64(minutes * 60.0 / chosen.len() as f64);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("regressions");
    let mut total = 0;
    let mut inputs = 0;
    for (k, target) in chosen.into_iter().enumerate() {
        let c =
            Campaign { target, seed: seed.wrapping_add(k as u64), max_inputs: u64::MAX, max_time: per_target, limit };
        let r = c.run();
        inputs += r.inputs;
        println!(
            "{:<18} {:>9} inputs in {:>7.1} s ({:>7.0}/s), {} outcome classes, corpus {}, {} findings, {} hangs, {} known",
            target.name,
            r.inputs,
            r.wall.as_secs_f64(),
            r.inputs as f64 / r.wall.as_secs_f64().max(1e-9),
            r.classes,
            r.corpus,
            r.findings.len(),
            r.hangs,
            r.known
        );
        for f in &r.findings {
            let path = dir.join(f.file_name());
            std::fs::create_dir_all(&dir).expect("creating fuzz/regressions");
            std::fs::write(&path, &f.input).expect("writing a finding");
            println!("  {}: {}", path.display(), f.what);
        }
        total += r.findings.len();
    }
    println!("{inputs} inputs, {total} findings");
    if total > 0 {
        std::process::exit(1);
    }
}
