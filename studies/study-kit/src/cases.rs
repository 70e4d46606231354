//! # Studies as independent cases: plan, run anywhere, collect
//!
//! A study that is a set of independent runs (the main job's controller × seed runs, a map's
//! cells, a robustness sample) implements [`CaseStudy`]. Then one directory holds everything:
//!
//! ```text
//! DIR/manifest.json        the study (its spec) and every case: stable ID + parameters
//! DIR/cases/<ID>.result    one finished case: its ID, its parameters and its result (postcard
//!                          bytes) with a checksum, written atomically
//! DIR/...                  what the cases stream (per-run CSVs) and what collect writes
//! ```
//!
//! * [`plan`] writes the manifest (again with the same study: no change; with another: an
//!   error). Case IDs and parameters come only from the spec, so every machine that reads the
//!   manifest sees the same cases, and any randomness of a case must derive from its
//!   parameters (seeds are parameters).
//! * [`run`] executes a [`Selection`] of the cases (all, shard `i/n`, one array index, given
//!   IDs) in parallel (rayon) and writes each result to a temporary file renamed into place,
//!   so a result file is complete or absent. Cases with a result are skipped: re-running after
//!   an interruption completes only what is missing, and two workers that run the same case
//!   (a retry after a lost worker) write the same bytes. A result is used only if it verifies
//!   ([`read_result`]): its checksum, its case ID and its parameters must match the manifest's,
//!   so a flipped bit or a result file copied under another case's name is re-run with a
//!   warning, never collected (one flipped bit made Table 5 print PID as 133467 µm).
//! * [`collect`] reads every result (an error names the missing cases) and lets the study
//!   write its tables and figures. Collected files contain no timings, so a study collected
//!   after a local run, a sharded run or a Dask/Slurm run is byte-identical.
//!
//! Which engine runs the cases is not this crate's business: `chatter run DIR --shard i/n`,
//! `--index K` (Slurm arrays: `--index $SLURM_ARRAY_TASK_ID`) or `--case ID` (one Dask task
//! per case, `python/chatter_dask.py`) all land here.

use crate::StudyError;
use rayon::prelude::*;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

type Result<T> = std::result::Result<T, StudyError>;

/// The manifest's format tag.
pub const FORMAT: &str = "chatter-study/1";

/// A study made of independent cases.
pub trait CaseStudy: Sync + Sized {
    /// The study's name in the manifest (`main-job`, …).
    const KIND: &'static str;
    /// Everything that defines the study (goes into the manifest; rebuilt with [`Self::from_spec`]).
    type Spec: Serialize + DeserializeOwned + Clone;
    /// The parameters of one case.
    type Case: Serialize + DeserializeOwned + Sync;
    /// The result of one case.
    type Output: Serialize + DeserializeOwned + Send;
    /// The study's spec.
    fn spec(&self) -> &Self::Spec;
    /// The study from its spec (on any machine that reads the manifest).
    fn from_spec(spec: Self::Spec) -> Result<Self>;
    /// Every case, with its stable ID (letters, digits, `-`, `_`, `.`), in a fixed order.
    fn cases(&self) -> Result<Vec<(String, Self::Case)>>;
    /// Run one case; `dir` is the study directory (for streamed files), `say` prints a line.
    fn run_case(&self, dir: &Path, id: &str, case: &Self::Case, say: &(dyn Fn(String) + Sync)) -> Result<Self::Output>;
    /// Write the study's tables and figures from every case's result (in manifest order).
    fn collect(&self, dir: &Path, results: &[(String, Self::Case, Self::Output)]) -> Result<Collected>;
}

/// What [`CaseStudy::collect`] produced.
#[derive(Debug, Default)]
pub struct Collected {
    /// Text to print (the main table).
    pub text: String,
    /// Files written.
    pub written: Vec<PathBuf>,
}

/// One case of a manifest.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ManifestCase<C> {
    /// Stable ID.
    pub id: String,
    /// Parameters.
    pub params: C,
}

/// `manifest.json`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Manifest<S, C> {
    /// [`FORMAT`].
    pub format: String,
    /// [`CaseStudy::KIND`].
    pub study: String,
    /// The study's spec.
    pub spec: S,
    /// The cases in order.
    pub cases: Vec<ManifestCase<C>>,
}

/// Which cases a `run` executes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Selection {
    /// Every case.
    All,
    /// Shard `index` of `count` (1-based): cases `k` with `k mod count = index − 1`.
    Shard {
        /// 1-based shard number.
        index: usize,
        /// Number of shards.
        count: usize,
    },
    /// The case at a 0-based position of the manifest (a Slurm array index).
    Index(usize),
    /// The cases with these IDs.
    Ids(Vec<String>),
}

impl std::str::FromStr for Selection {
    type Err = StudyError;
    /// `i/n` for a shard.
    fn from_str(s: &str) -> Result<Selection> {
        let bad = || StudyError::Invalid(format!("--shard {s:?}: expected I/N with 1 ≤ I ≤ N"));
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) =
            (i.trim().parse::<usize>().map_err(|_| bad())?, n.trim().parse::<usize>().map_err(|_| bad())?);
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Selection::Shard { index, count })
    }
}

impl Selection {
    /// The positions of the selected cases among `ids`.
    pub fn positions(&self, ids: &[String]) -> Result<Vec<usize>> {
        match self {
            Selection::All => Ok((0..ids.len()).collect()),
            Selection::Shard { index, count } => Ok((0..ids.len()).filter(|k| k % count == index - 1).collect()),
            Selection::Index(k) if *k < ids.len() => Ok(vec![*k]),
            Selection::Index(k) => Err(StudyError::Invalid(format!(
                "case index {k} is out of range: the study has {} cases (0–{})",
                ids.len(),
                ids.len().saturating_sub(1)
            ))),
            Selection::Ids(wanted) => wanted
                .iter()
                .map(|w| {
                    ids.iter()
                        .position(|i| i == w)
                        .ok_or_else(|| StudyError::Invalid(format!("no case {w:?} in the manifest")))
                })
                .collect(),
        }
    }
}

fn manifest_path(dir: &Path) -> PathBuf {
    dir.join("manifest.json")
}

/// The result file of case `id`.
pub fn result_path(dir: &Path, id: &str) -> PathBuf {
    dir.join("cases").join(format!("{id}.result"))
}

fn valid_id(id: &str) -> bool {
    !id.is_empty() && id.chars().all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c)) && !id.starts_with('.')
}

/// Write `bytes` to `path` atomically (a temporary file in the same folder, renamed).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| StudyError::io(dir, e))?;
    let mut tmp = tempfile::NamedTempFile::new_in(dir).map_err(|e| StudyError::io(dir, e))?;
    std::io::Write::write_all(&mut tmp, bytes).map_err(|e| StudyError::io(path, e))?;
    tmp.as_file().sync_all().map_err(|e| StudyError::io(path, e))?;
    tmp.persist(path).map_err(|e| StudyError::io(path, e.error))?;
    Ok(())
}

/// The study kind of the manifest in `dir` (to choose the [`CaseStudy`] that reads it).
pub fn kind(dir: &Path) -> Result<String> {
    #[derive(Deserialize)]
    struct Head {
        format: String,
        study: String,
    }
    let path = manifest_path(dir);
    let text = std::fs::read_to_string(&path).map_err(|e| StudyError::io(&path, e))?;
    let head: Head = serde_json::from_str(&text)
        .map_err(|e| StudyError::Invalid(format!("{}: not a study manifest: {e}", path.display())))?;
    if head.format != FORMAT {
        return Err(StudyError::Invalid(format!("{}: format {:?}, expected {FORMAT:?}", path.display(), head.format)));
    }
    Ok(head.study)
}

/// Write the manifest of `study` into `dir`; returns the number of cases.
pub fn plan<S: CaseStudy>(study: &S, dir: &Path) -> Result<usize> {
    let cases = study.cases()?;
    let mut seen = std::collections::HashSet::new();
    for (id, _) in &cases {
        if !valid_id(id) || !seen.insert(id.clone()) {
            return Err(StudyError::Invalid(format!("case ID {id:?} is not a unique file-name-safe ID")));
        }
    }
    let manifest = Manifest {
        format: FORMAT.into(),
        study: S::KIND.into(),
        spec: study.spec().clone(),
        cases: cases.into_iter().map(|(id, params)| ManifestCase { id, params }).collect(),
    };
    let text =
        serde_json::to_string_pretty(&manifest).map_err(|e| StudyError::Invalid(format!("manifest: {e}")))? + "\n";
    let path = manifest_path(dir);
    if let Ok(old) = std::fs::read_to_string(&path) {
        if old == text {
            return Ok(manifest.cases.len());
        }
        return Err(StudyError::Invalid(format!(
            "{} holds another study (or other settings); plan into a new directory",
            path.display()
        )));
    }
    write_atomic(&path, text.as_bytes())?;
    Ok(manifest.cases.len())
}

/// Remove the manifest and the case results of `dir` (to plan and run it afresh); other files
/// stay and are overwritten by the new run.
pub fn forget_results(dir: &Path) -> Result<()> {
    let m = manifest_path(dir);
    if m.exists() {
        std::fs::remove_file(&m).map_err(|e| StudyError::io(&m, e))?;
    }
    let c = dir.join("cases");
    if c.exists() {
        std::fs::remove_dir_all(&c).map_err(|e| StudyError::io(&c, e))?;
    }
    Ok(())
}

/// The manifest in `dir`, which must be a study of kind `S`.
pub fn manifest<S: CaseStudy>(dir: &Path) -> Result<Manifest<S::Spec, S::Case>> {
    let k = kind(dir)?;
    if k != S::KIND {
        return Err(StudyError::Invalid(format!("{}: a {k} study, not {}", dir.display(), S::KIND)));
    }
    let path = manifest_path(dir);
    let text = std::fs::read_to_string(&path).map_err(|e| StudyError::io(&path, e))?;
    let m: Manifest<S::Spec, S::Case> =
        serde_json::from_str(&text).map_err(|e| StudyError::Invalid(format!("{}: {e}", path.display())))?;
    Ok(m)
}

/// Read the manifest of `dir` as study `S` and build the study from its spec.
pub fn open<S: CaseStudy>(dir: &Path) -> Result<(S, Vec<ManifestCase<S::Case>>)> {
    let m = manifest::<S>(dir)?;
    Ok((S::from_spec(m.spec)?, m.cases))
}

/// The first bytes of a result file (format 2: with the case and a checksum).
const RESULT_MAGIC: &[u8; 8] = b"CHCASE\0\x02";

/// A result file's bytes: [`RESULT_MAGIC`], the case ID and the postcard bytes of the case's
/// parameters (each as a u32 LE length and the bytes), the postcard bytes of the output, and
/// the FNV-1a 64 checksum (u64 LE) of everything before it.
pub fn result_bytes<C: Serialize, O: Serialize>(id: &str, case: &C, out: &O) -> Result<Vec<u8>> {
    let err = |e: postcard::Error| StudyError::Invalid(format!("case {id}: {e}"));
    let params = postcard::to_allocvec(case).map_err(err)?;
    let mut b = RESULT_MAGIC.to_vec();
    for part in [id.as_bytes(), params.as_slice()] {
        b.extend_from_slice(&(part.len() as u32).to_le_bytes());
        b.extend_from_slice(part);
    }
    let mut b = postcard::to_extend(out, b).map_err(err)?;
    let sum = fmi2_export::fnv1a64(&b);
    b.extend_from_slice(&sum.to_le_bytes());
    Ok(b)
}

/// What a case's result file holds.
#[derive(Debug)]
pub enum Stored<O> {
    /// No file.
    Missing,
    /// A file that does not verify, and why (re-run the case).
    Invalid(String),
    /// The verified result.
    Verified(O),
}

/// Read the result of case `id` with parameters `case` from `path`: [`Stored::Verified`] only if
/// the checksum holds and the file names this case with these parameters.
pub fn read_result<C: Serialize, O: DeserializeOwned>(path: &Path, id: &str, case: &C) -> Stored<O> {
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Stored::Missing,
        Err(e) => return Stored::Invalid(format!("cannot read it: {e}")),
    };
    match verify(&bytes, id, case) {
        Ok(out) => Stored::Verified(out),
        Err(why) => Stored::Invalid(why),
    }
}

fn verify<C: Serialize, O: DeserializeOwned>(bytes: &[u8], id: &str, case: &C) -> std::result::Result<O, String> {
    let body = bytes.strip_prefix(RESULT_MAGIC).ok_or("not a case result of this format (bad header)")?;
    if body.len() < 8 {
        return Err("truncated".into());
    }
    let (all, sum) = bytes.split_at(bytes.len() - 8);
    if fmi2_export::fnv1a64(all).to_le_bytes() != sum {
        return Err("checksum mismatch (the file was changed or damaged)".into());
    }
    let mut rest = &all[RESULT_MAGIC.len()..];
    let mut part = || -> std::result::Result<&[u8], String> {
        let n = rest.get(..4).ok_or("truncated")?;
        let n = u32::from_le_bytes([n[0], n[1], n[2], n[3]]) as usize;
        let p = rest.get(4..4 + n).ok_or("truncated")?;
        rest = &rest[4 + n..];
        Ok(p)
    };
    let (stored_id, stored_params) = (part()?, part()?);
    if stored_id != id.as_bytes() {
        return Err(format!("it is the result of case {:?}", String::from_utf8_lossy(stored_id)));
    }
    let params = postcard::to_allocvec(case).map_err(|e| e.to_string())?;
    if stored_params != params.as_slice() {
        return Err("it was computed with other parameters than the manifest's".into());
    }
    let (out, tail) = postcard::take_from_bytes::<O>(rest).map_err(|e| format!("unreadable result: {e}"))?;
    if !tail.is_empty() {
        return Err("trailing bytes after the result".into());
    }
    Ok(out)
}

/// A case-count progress bar on a terminal (none when stderr is redirected: lines instead).
fn progress_bar(n: u64) -> Option<indicatif::ProgressBar> {
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        return None;
    }
    let b = indicatif::ProgressBar::new(n);
    b.set_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} cases, ETA {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    Some(b)
}

/// What [`run`] did.
#[derive(Debug, Default)]
pub struct RunSummary {
    /// Cases run now.
    pub ran: Vec<String>,
    /// Cases skipped (a verified result was there).
    pub skipped: Vec<String>,
    /// Cases whose result did not verify, with the reason (they are run again, in `ran`).
    pub rerun: Vec<(String, String)>,
    /// Cases that failed, with the error.
    pub failed: Vec<(String, String)>,
}

/// Run the `selection` of the study in `dir` (missing results only), in parallel.
pub fn run<S: CaseStudy>(dir: &Path, selection: &Selection) -> Result<RunSummary> {
    let (study, cases) = open::<S>(dir)?;
    run_opened(&study, &cases, dir, selection)
}

/// [`run`] with the study already built from the manifest's spec and the manifest's cases.
pub fn run_opened<S: CaseStudy>(
    study: &S,
    cases: &[ManifestCase<S::Case>],
    dir: &Path,
    selection: &Selection,
) -> Result<RunSummary> {
    let ids: Vec<String> = cases.iter().map(|c| c.id.clone()).collect();
    let picked = selection.positions(&ids)?;
    let mut summary = RunSummary::default();
    let mut todo: Vec<&ManifestCase<S::Case>> = Vec::new();
    for c in picked.iter().map(|&k| &cases[k]) {
        match read_result::<S::Case, S::Output>(&result_path(dir, &c.id), &c.id, &c.params) {
            Stored::Verified(_) => summary.skipped.push(c.id.clone()),
            Stored::Missing => todo.push(c),
            Stored::Invalid(why) => {
                eprintln!("warning: case {}: its result does not verify ({why}); running it again", c.id);
                summary.rerun.push((c.id.clone(), why));
                todo.push(c);
            }
        }
    }
    let bar = progress_bar(todo.len() as u64);
    let say = |line: String| match &bar {
        Some(b) => b.println(line),
        None => eprintln!("{line}"),
    };
    let outcomes: Vec<(String, Result<()>)> = todo
        .par_iter()
        .map(|c| {
            let r = study
                .run_case(dir, &c.id, &c.params, &say)
                .and_then(|out| write_atomic(&result_path(dir, &c.id), &result_bytes(&c.id, &c.params, &out)?));
            if let Some(b) = &bar {
                b.inc(1);
            }
            (c.id.clone(), r)
        })
        .collect();
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    for (id, r) in outcomes {
        match r {
            Ok(()) => summary.ran.push(id),
            Err(e) => summary.failed.push((id, e.to_string())),
        }
    }
    Ok(summary)
}

/// One finished case: its ID, parameters and result.
pub type CaseResult<S> = (String, <S as CaseStudy>::Case, <S as CaseStudy>::Output);

/// Every case of `cases` with its result, in manifest order; an error names the cases that
/// have none yet.
pub fn results<S: CaseStudy>(dir: &Path, cases: Vec<ManifestCase<S::Case>>) -> Result<Vec<CaseResult<S>>> {
    let mut results = Vec::with_capacity(cases.len());
    let mut missing = Vec::new();
    for c in cases {
        match read_result::<S::Case, S::Output>(&result_path(dir, &c.id), &c.id, &c.params) {
            Stored::Verified(out) => results.push((c.id, c.params, out)),
            Stored::Missing => missing.push(c.id),
            Stored::Invalid(why) => missing.push(format!("{} (its result does not verify: {why})", c.id)),
        }
    }
    if !missing.is_empty() {
        let shown: Vec<&str> = missing.iter().take(5).map(String::as_str).collect();
        return Err(StudyError::Invalid(format!(
            "{} of {} cases have no result yet ({}{}); run them first (`chatter run {}`)",
            missing.len(),
            missing.len() + results.len(),
            shown.join(", "),
            if missing.len() > shown.len() { ", …" } else { "" },
            dir.display()
        )));
    }
    Ok(results)
}

/// Read every result of the study in `dir` and let the study write its tables and figures.
pub fn collect<S: CaseStudy>(dir: &Path) -> Result<Collected> {
    let (study, cases) = open::<S>(dir)?;
    study.collect(dir, &results::<S>(dir, cases)?)
}

#[cfg(test)]
mod tests {
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
}
