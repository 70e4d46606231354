//! Tests of the case files: plan, run, verify, collect.

use super::*;
use std::io::Write;

/// A toy study: case k squares k; collect writes the sum. Each executed case appends its
/// ID to `runs.log` in the study directory, so the tests (which run in parallel, each in
/// its own directory) count their own runs.
struct Squares {
    spec: u32,
}

fn runs(dir: &Path) -> usize {
    std::fs::read_to_string(dir.join("runs.log")).map_or(0, |s| s.lines().count())
}

impl CaseStudy for Squares {
    const KIND: &'static str = "squares";
    type Spec = u32;
    type Case = u64;
    type Output = u64;
    fn spec(&self) -> &u32 {
        &self.spec
    }
    fn from_spec(spec: u32) -> Result<Self> {
        Ok(Squares { spec })
    }
    fn cases(&self) -> Result<Vec<(String, u64)>> {
        Ok((0..self.spec as u64).map(|k| (format!("k{k:02}"), k)).collect())
    }
    fn run_case(&self, dir: &Path, id: &str, k: &u64, _: &(dyn Fn(String) + Sync)) -> Result<u64> {
        let path = dir.join("runs.log");
        std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .and_then(|mut f| writeln!(f, "{id}"))
            .map_err(|e| StudyError::io(&path, e))?;
        if *k == 99 {
            return Err(StudyError::Invalid("boom".into()));
        }
        Ok(k * k)
    }
    fn collect(&self, dir: &Path, r: &[(String, u64, u64)]) -> Result<Collected> {
        let sum: u64 = r.iter().map(|x| x.2).sum();
        let path = dir.join("sum.txt");
        std::fs::write(&path, sum.to_string()).unwrap();
        Ok(Collected { text: sum.to_string(), written: vec![path] })
    }
}

#[test]
fn shards_cover_every_case_once_and_reruns_complete_only_what_is_missing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    assert_eq!(plan(&Squares { spec: 10 }, dir).unwrap(), 10);
    // planning the same study again is fine, another study is refused
    plan(&Squares { spec: 10 }, dir).unwrap();
    assert!(plan(&Squares { spec: 11 }, dir).is_err());
    // collect before running names the missing cases
    let e = collect::<Squares>(dir).unwrap_err().to_string();
    assert!(e.contains("10 of 10 cases") && e.contains("k00"), "{e}");
    let before = runs(dir);
    for i in 1..=3 {
        let s = run::<Squares>(dir, &Selection::Shard { index: i, count: 3 }).unwrap();
        assert!(s.failed.is_empty());
    }
    assert_eq!(runs(dir) - before, 10, "each case ran exactly once");
    // a re-run skips every case
    let s = run::<Squares>(dir, &Selection::All).unwrap();
    assert_eq!((s.ran.len(), s.skipped.len()), (0, 10));
    // a lost result is redone alone
    std::fs::remove_file(result_path(dir, "k04")).unwrap();
    let s = run::<Squares>(dir, &Selection::All).unwrap();
    assert_eq!(s.ran, vec!["k04".to_string()]);
    let c = collect::<Squares>(dir).unwrap();
    assert_eq!(c.text, (0..10u64).map(|k| k * k).sum::<u64>().to_string());
}

#[test]
fn a_truncated_result_counts_as_missing() {
    let tmp = tempfile::tempdir().unwrap();
    plan(&Squares { spec: 3 }, tmp.path()).unwrap();
    run::<Squares>(tmp.path(), &Selection::All).unwrap();
    std::fs::write(result_path(tmp.path(), "k02"), []).unwrap();
    let s = run::<Squares>(tmp.path(), &Selection::Index(2)).unwrap();
    assert_eq!(s.ran, vec!["k02".to_string()]);
}

/// A result with one flipped bit (byte 12 of `cases/pid-s01.result` made Table 5 print PID
/// as "133467.26 ± 188745.29 µm", exit 0) or copied under another case's name was used; it
/// is re-run with a warning now, and `collect` names it instead of using it.
#[test]
fn flipped_or_swapped_results_are_rerun_not_used() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    plan(&Squares { spec: 4 }, dir).unwrap();
    run::<Squares>(dir, &Selection::All).unwrap();
    let good = collect::<Squares>(dir).unwrap().text;
    // every single bit of a result file, flipped, is caught
    let bytes = std::fs::read(result_path(dir, "k03")).unwrap();
    for i in 0..bytes.len() * 8 {
        let mut b = bytes.clone();
        b[i / 8] ^= 1 << (i % 8);
        std::fs::write(result_path(dir, "k03"), &b).unwrap();
        let e = collect::<Squares>(dir).unwrap_err().to_string();
        assert!(e.contains("k03 (its result does not verify"), "bit {i}: {e}");
    }
    // k02's result under k03's name: the checksum holds, the case does not
    std::fs::copy(result_path(dir, "k02"), result_path(dir, "k03")).unwrap();
    let e = collect::<Squares>(dir).unwrap_err().to_string();
    assert!(e.contains("it is the result of case \"k02\""), "{e}");
    let before = runs(dir);
    let s = run::<Squares>(dir, &Selection::All).unwrap();
    assert_eq!(s.ran, vec!["k03".to_string()]);
    assert_eq!(s.rerun.len(), 1);
    assert_eq!(runs(dir) - before, 1);
    assert_eq!(collect::<Squares>(dir).unwrap().text, good);
}

#[test]
fn selections_parse_and_refuse_what_does_not_exist() {
    let ids: Vec<String> = (0..5).map(|k| format!("c{k}")).collect();
    assert_eq!("2/2".parse::<Selection>().unwrap().positions(&ids).unwrap(), vec![1, 3]);
    assert!("0/2".parse::<Selection>().is_err());
    assert!("3/2".parse::<Selection>().is_err());
    assert!("x".parse::<Selection>().is_err());
    assert!(Selection::Index(5).positions(&ids).is_err());
    assert!(Selection::Ids(vec!["nope".into()]).positions(&ids).is_err());
    assert_eq!(Selection::Ids(vec!["c4".into()]).positions(&ids).unwrap(), vec![4]);
}

#[test]
fn a_failed_case_is_reported_and_leaves_no_result() {
    struct Fails;
    impl CaseStudy for Fails {
        const KIND: &'static str = "fails";
        type Spec = ();
        type Case = u64;
        type Output = u64;
        fn spec(&self) -> &() {
            &()
        }
        fn from_spec(_: ()) -> Result<Self> {
            Ok(Fails)
        }
        fn cases(&self) -> Result<Vec<(String, u64)>> {
            Ok(vec![("ok".into(), 1), ("bad".into(), 99)])
        }
        fn run_case(&self, d: &Path, i: &str, k: &u64, s: &(dyn Fn(String) + Sync)) -> Result<u64> {
            Squares { spec: 0 }.run_case(d, i, k, s)
        }
        fn collect(&self, _: &Path, _: &[(String, u64, u64)]) -> Result<Collected> {
            Ok(Collected::default())
        }
    }
    let tmp = tempfile::tempdir().unwrap();
    plan(&Fails, tmp.path()).unwrap();
    let s = run::<Fails>(tmp.path(), &Selection::All).unwrap();
    assert_eq!(s.ran, vec!["ok".to_string()]);
    assert_eq!(s.failed.len(), 1);
    assert!(s.failed[0].1.contains("boom"));
    assert!(!result_path(tmp.path(), "bad").exists());
    assert!(collect::<Fails>(tmp.path()).unwrap_err().to_string().contains("bad"));
}
