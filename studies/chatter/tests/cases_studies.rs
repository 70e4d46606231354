//! Every study of the `chatter` CLI as independent cases: `chatter <study> ARGS --out LOCAL`
//! and `chatter plan <study> ARGS --out DIR` + `run --shard k/n` for every k + `collect DIR`
//! write the same files (CSV rows in manifest order instead of completion order, titles without
//! the wall time); a deleted result is re-run alone and the collect is byte-identical again.

use std::path::{Path, PathBuf};
use std::process::Command;

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("chatter-cases-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn run(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_chatter")).args(args).output().expect("run chatter");
    assert!(out.status.success(), "chatter {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

fn read(d: &Path, f: &str) -> Vec<u8> {
    std::fs::read(d.join(f)).unwrap_or_else(|e| panic!("{}: {e}", d.join(f).display()))
}

/// `text` without the wall time a local title carries (`; 3 s wall` or ` — 3 s wall`).
fn without_wall(text: &str) -> String {
    let Some(end) = text.find(" s wall") else { return text.to_string() };
    let head = &text[..end];
    let digits = head.trim_end_matches(|c: char| c.is_ascii_digit() || c == '.');
    let cut = digits.strip_suffix("; ").or_else(|| digits.strip_suffix(" — ")).expect("a wall-time suffix");
    format!("{cut}{}", &text[end + " s wall".len()..])
}

/// How a local file and a collected one compare.
#[derive(Clone, Copy)]
enum How {
    /// The same lines in any order (CSVs streamed in completion order).
    Sorted,
    /// The same lines in the same order, titles without the wall time (tables).
    Exact,
    /// Byte-identical (figures, JSON, CSVs written in order).
    Bytes,
    /// Every line with its last CSV column dropped (a timing column), then sorted.
    SortedWithoutLast,
}

fn normalised(bytes: &[u8], how: How) -> Vec<String> {
    if matches!(how, How::Bytes) {
        return bytes.iter().map(|b| b.to_string()).collect();
    }
    let text = String::from_utf8_lossy(bytes);
    let mut v: Vec<String> = match how {
        How::SortedWithoutLast => text.lines().map(|l| l.rsplit_once(',').map_or(l, |(a, _)| a).to_string()).collect(),
        _ => text.lines().map(without_wall).collect(),
    };
    if matches!(how, How::Sorted | How::SortedWithoutLast) {
        v.sort();
    }
    v
}

/// Local vs sharded cases (see the module documentation); returns the number of cases.
fn cases_match_local(name: &str, study: &[&str], args: &[&str], shards: usize, files: &[(&str, How)]) -> usize {
    let (local, cases) = (out_dir(&format!("{name}-local")), out_dir(&format!("{name}-cases")));
    let (l, c) = (local.to_str().unwrap(), cases.to_str().unwrap());
    run(&[study, args, &["--out", l]].concat());
    let planned = run(&[&["plan"], study, args, &["--out", c]].concat());
    let n: usize = planned.split_whitespace().nth(1).and_then(|w| w.parse().ok()).expect("planned N cases");
    for k in 1..=shards {
        run(&["run", c, "--shard", &format!("{k}/{shards}")]);
    }
    run(&["collect", c]);
    for (f, how) in files {
        let (l, c) = (normalised(&read(&local, f), *how), normalised(&read(&cases, f), *how));
        assert!(l == c, "{name}: {f} differs: local {:.200?} / collected {:.200?}", l.join("\n"), c.join("\n"));
    }
    // a lost result is redone alone, and the collect is byte-identical
    let first: Vec<Vec<u8>> = files.iter().map(|(f, _)| read(&cases, f)).collect();
    let results: Vec<PathBuf> = std::fs::read_dir(cases.join("cases")).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(results.len(), n, "{name}: one result per case");
    std::fs::remove_file(&results[results.len() / 2]).unwrap();
    let again = run(&["run", c]);
    assert!(again.contains(&format!("1 cases run, {} already done", n - 1)), "{name}: {again}");
    run(&["collect", c]);
    for ((f, how), before) in files.iter().zip(&first) {
        let after = read(&cases, f);
        // a timing column is the re-run's own; everything else is byte-identical
        let same = match how {
            How::SortedWithoutLast => normalised(&after, *how) == normalised(before, *how),
            _ => &after == before,
        };
        assert!(same, "{name}: {f} after the re-run differs");
    }
    std::fs::remove_dir_all(&local).unwrap();
    std::fs::remove_dir_all(&cases).unwrap();
    n
}

#[test]
fn wall_times_are_removed_from_titles_only() {
    assert_eq!(without_wall("Sweep (a; 2 s runs; 12 s wall)"), "Sweep (a; 2 s runs)");
    assert_eq!(without_wall("Map (x) — 3 s wall"), "Map (x)");
    assert_eq!(without_wall("| off | 1 |"), "| off | 1 |");
}

#[test]
fn the_feed_sweep_as_cases_collects_the_local_sweep() {
    let args = ["feed", "--quick", "--controllers", "off,pid", "--values", "0.05,0.1", "--quiet"];
    let files = [("sweep_feed.csv", How::Sorted), ("sweep_feed.md", How::Exact)];
    assert_eq!(cases_match_local("sweep-feed", &["sweep"], &args, 3, &files), 4);
}

#[test]
fn the_engagement_sweep_as_cases_collects_the_local_sweep() {
    let args = ["engagement", "--quick", "--controllers", "off", "--values", "6,10"];
    let files = [("sweep_engagement.csv", How::Sorted), ("sweep_engagement.md", How::Exact)];
    assert_eq!(cases_match_local("sweep-eng", &["sweep"], &args, 2, &files), 2);
}

#[test]
fn the_depth_study_as_cases_collects_the_local_study() {
    let args = ["--quick", "--controllers", "off,fopid", "--depths", "1,2"];
    let files = [("depth_study.csv", How::Sorted), ("depth_study.md", How::Exact)];
    assert_eq!(cases_match_local("depth", &["depth-study"], &args, 3, &files), 4);
}

#[test]
fn the_lobes_as_speed_chunks_collect_the_local_lobes_byte_for_byte() {
    let args = ["--controllers", "off,fopid", "--points", "101"];
    let files = [("lobes.csv", How::Bytes), ("lobes.png", How::Bytes)];
    let n = cases_match_local("lobes", &["lobes"], &[&args[..], &["--rpm-min", "1500"]].concat(), 2, &files);
    assert_eq!(n, 1, "one chunk of the default 200 speeds");
    // chunks of 30 speeds: 4 cases, the same files
    let plan = ["--controllers", "off,fopid", "--points", "101", "--chunk", "30"];
    let (local, cases) = (out_dir("lobes30-local"), out_dir("lobes30-cases"));
    run(&[&["lobes"], &plan[..4], &["--out", local.to_str().unwrap()]].concat());
    let c = cases.to_str().unwrap();
    assert!(run(&[&["plan", "lobes"], &plan[..], &["--out", c]].concat()).contains("planned 4 cases of lobes"));
    run(&["run", c, "--index", "3"]);
    run(&["run", c, "--shard", "1/2"]);
    run(&["run", c, "--shard", "2/2"]);
    let collected = run(&["collect", c]);
    assert!(collected.contains("fopid: b_min"), "{collected}");
    for f in ["lobes.csv", "lobes.png"] {
        assert!(read(&local, f) == read(&cases, f), "lobes in chunks of 30: {f} differs");
    }
    std::fs::remove_dir_all(&local).unwrap();
    std::fs::remove_dir_all(&cases).unwrap();
}

#[test]
fn pso_runs_as_cases_collect_the_local_table_a1() {
    let args = ["--structures", "pid,fopid", "--runs", "2", "--particles", "6", "--iterations", "3", "--quiet"];
    let files = [
        ("table_a1.md", How::Bytes),
        ("tuned_pid.json", How::Bytes),
        ("tuned_fopid.json", How::Bytes),
        ("tuning_runs.csv", How::SortedWithoutLast),
    ];
    assert_eq!(cases_match_local("tune", &["tune"], &args, 3, &files), 4);
}
