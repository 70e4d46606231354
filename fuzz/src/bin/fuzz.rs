//! Long fuzzing runs: `cargo run --release -p fuzz -- --minutes 10`
//! [`--target NAME`] [`--seed N`] [`--limit-ms MS`], or `-- --replay FILE`
//! (one kept input, with its backtrace).
//!
//! Without `--target`, every target runs in a child process of its own (a
//! hung input's thread cannot be stopped; it ends with its process), one
//! after the other, sharing the time: a target that stops early (after
//! [`fuzz::MAX_HANGS`] hangs) starts again with another seed until
//! its share of the time is used.
//! Findings (panics, hangs) are written to `fuzz/regressions/` and the
//! process exits with status 1.

use fuzz::{Campaign, Target, targets};
use std::time::{Duration, Instant};

fn one(target: Target, seed: u64, time: Duration, limit: Duration) -> usize {
    let c = Campaign { target, seed, max_inputs: u64::MAX, max_time: time, limit };
    let r = c.run();
    println!(
        "{:<18} {:>9} inputs in {:>6.1} s ({:>6.0}/s), {} outcome classes, corpus {}, {} findings, {} hangs, {} known",
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
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("regressions");
    for f in &r.findings {
        let path = dir.join(f.file_name());
        std::fs::create_dir_all(&dir).expect("creating fuzz/regressions");
        std::fs::write(&path, &f.input).expect("writing a finding");
        println!("  {}: {}", path.display(), f.what);
    }
    r.findings.len()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| args.iter().position(|a| a == flag).and_then(|i| args.get(i + 1)).cloned();
    if let Some(file) = value("--replay") {
        // One kept input, on this thread: a panic prints its backtrace.
        let name = std::path::Path::new(&file).file_stem().and_then(|s| s.to_str()).unwrap_or_default();
        let target = name.rsplit_once('-').and_then(|(t, _)| targets::by_name(t)).expect("<target>-<hash>.bin");
        println!("{}", (target.run)(&std::fs::read(&file).expect("reading the input")));
        return;
    }
    let minutes: f64 = value("--minutes").map(|s| s.parse().expect("--minutes: a number")).unwrap_or(1.0);
    let seed: u64 = value("--seed").map(|s| s.parse().expect("--seed: an integer")).unwrap_or(1);
    let limit_ms: u64 = value("--limit-ms").map(|s| s.parse().expect("--limit-ms")).unwrap_or(2000);
    let total = Duration::from_secs_f64(minutes * 60.0);
    if let Some(n) = value("--target") {
        let target = targets::by_name(&n).unwrap_or_else(|| panic!("unknown target {n}"));
        let found = one(target, seed, total, Duration::from_millis(limit_ms));
        std::process::exit(i32::from(found > 0));
    }
    let t0 = Instant::now();
    let mut failed = false;
    for (k, target) in targets::ALL.iter().enumerate() {
        let slice = total.saturating_sub(t0.elapsed()) / (targets::ALL.len() - k) as u32;
        let end = Instant::now() + slice;
        // A target that stopped early (hangs) starts again with another seed until its time is up.
        let mut attempt = 0u64;
        while end.saturating_duration_since(Instant::now()) > Duration::from_secs(1) {
            let left = end.saturating_duration_since(Instant::now()).as_secs_f64();
            let seed = seed.wrapping_add(k as u64).wrapping_add(1000 * attempt);
            let status = std::process::Command::new(std::env::current_exe().expect("this program"))
                .args(["--target", target.name, "--minutes", &format!("{}", left / 60.0)])
                .args(["--seed", &seed.to_string(), "--limit-ms", &limit_ms.to_string()])
                .status()
                .expect("running a target");
            failed |= !status.success();
            attempt += 1;
        }
    }
    println!(
        "{:.1} min in all; {}",
        t0.elapsed().as_secs_f64() / 60.0,
        if failed { "findings" } else { "no findings" }
    );
    if failed {
        std::process::exit(1);
    }
}
