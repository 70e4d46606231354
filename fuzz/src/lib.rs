//! A fuzzing harness on stable Rust: a seeded, deterministic mutation loop
//! over seed corpora taken from the project's own artefacts, each input run
//! under `catch_unwind` and a per-input time limit.
//!
//! * [`targets`]: what is fuzzed — `modelDescription.xml` parsing, SSD
//!   parsing, FMU-state deserialisation followed by steps, and FMI call
//!   sequences through `fmi2-export`'s safe `Instance` — and their seeds.
//! * [`Rng`], [`mutate`]: the mutation engine (bit flips, byte and
//!   "interesting" value writes, insertions, deletions, duplicated chunks,
//!   splices between corpus entries, dictionary tokens).
//! * [`Campaign`]: runs one target for a number of inputs or a wall-time
//!   budget and reports panics and hangs ([`Finding`]); inputs that reach a
//!   new outcome class are kept in the corpus.
//!
//! The bounded campaign runs in `cargo test` (`tests/campaign.rs`); long
//! runs: `cargo run --release -p fuzz -- --minutes 10`. Findings
//! are written to `fuzz/regressions/<target>-<hash>.bin` and replayed by
//! `tests/regressions.rs`.

pub mod targets;

use std::collections::HashSet;
use std::panic::AssertUnwindSafe;
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// SplitMix64: small, seedable, deterministic.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

const INTERESTING: &[&[u8]] = &[
    b"0",
    b"-1",
    b"1e308",
    b"-1e308",
    b"nan",
    b"inf",
    b"-inf",
    b"4294967295",
    b"2147483648",
    b"-2147483649",
    b"1e-320",
    b"\xff\xff\xff\xff",
    b"\x00\x00\x00\x80",
    b"\x7f\xf0\x00\x00\x00\x00\x00\x00",
    b"\"",
    b"<",
    b">",
    b"&",
    b"&#0;",
    b"]]>",
    b"<!--",
    b"-->",
    b"<?",
    b"?>",
];

/// Mutate `data` in place: 1–4 stacked edits chosen by `rng`, using `other`
/// (another corpus entry) for splices and `dict` for tokens. At most
/// `max_len` bytes remain.
pub fn mutate(data: &mut Vec<u8>, other: &[u8], dict: &[&str], rng: &mut Rng, max_len: usize) {
    for _ in 0..1 + rng.below(4) {
        let len = data.len();
        match rng.below(9) {
            0 if len > 0 => {
                let i = rng.below(len);
                data[i] ^= 1 << rng.below(8);
            }
            1 if len > 0 => {
                let i = rng.below(len);
                data[i] = rng.next_u64() as u8;
            }
            2 => {
                let tok = INTERESTING[rng.below(INTERESTING.len())];
                let i = rng.below(len + 1);
                if rng.below(2) == 0 || i + tok.len() > len {
                    data.splice(i..i, tok.iter().copied());
                } else {
                    data[i..i + tok.len()].copy_from_slice(tok);
                }
            }
            3 if len > 0 => {
                let i = rng.below(len);
                let n = 1 + rng.below((len - i).min(64));
                data.drain(i..i + n);
            }
            4 if len > 0 => {
                let i = rng.below(len);
                let n = 1 + rng.below((len - i).min(256));
                let chunk = data[i..i + n].to_vec();
                let at = rng.below(len + 1);
                data.splice(at..at, chunk);
            }
            5 if !other.is_empty() => {
                let a = rng.below(other.len());
                let n = 1 + rng.below((other.len() - a).min(512));
                let at = rng.below(len + 1);
                let end = (at + rng.below(n + 1)).min(len);
                data.splice(at..end, other[a..a + n].iter().copied());
            }
            6 if !dict.is_empty() => {
                let tok = dict[rng.below(dict.len())].as_bytes();
                let at = rng.below(len + 1);
                data.splice(at..at, tok.iter().copied());
            }
            7 if len > 0 => data.truncate(rng.below(len)),
            _ if len > 0 => {
                // add a small number to a byte (numbers in text and in binary)
                let i = rng.below(len);
                data[i] = data[i].wrapping_add(1 + rng.below(8) as u8);
            }
            _ => data.push(rng.next_u64() as u8),
        }
    }
    data.truncate(max_len);
}

/// What running one input gave.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Outcome {
    /// Returned; the string classifies the result (coarse coverage signal).
    Done(String),
    /// Panicked, with the message.
    Panic(String),
}

/// A fuzz target: a name, seeds, a dictionary and a function of bytes that
/// must never panic or hang. It returns a short class of its result.
#[derive(Clone, Copy)]
pub struct Target {
    /// Name (used in file names of findings).
    pub name: &'static str,
    /// The seed corpus.
    pub seeds: fn() -> Vec<Vec<u8>>,
    /// Tokens to insert.
    pub dict: &'static [&'static str],
    /// Longest input.
    pub max_len: usize,
    /// Run one input.
    pub run: fn(&[u8]) -> String,
    /// Known defects not yet fixed (owned elsewhere): panics whose message
    /// contains one of these are counted in [`Report::known`], not reported
    /// as findings. Each has an ignored regression test.
    pub known_panics: &'static [&'static str],
    /// Hangs are a known defect of this target (counted in [`Report::known`]
    /// and [`Report::hangs`], not reported as findings).
    pub known_hangs: bool,
}

/// A panic or a hang found by a campaign.
#[derive(Clone, Debug)]
pub struct Finding {
    /// The target's name.
    pub target: &'static str,
    /// `panic: …` or `hang: > …`.
    pub what: String,
    /// The input.
    pub input: Vec<u8>,
}

impl Finding {
    /// A stable file name for the input: `<target>-<fnv64 hash>.bin`.
    pub fn file_name(&self) -> String {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for &b in &self.input {
            h = (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
        format!("{}-{h:016x}.bin", self.target)
    }
}

/// Figures of a campaign.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Inputs run.
    pub inputs: u64,
    /// Wall time.
    pub wall: Duration,
    /// Distinct outcome classes seen.
    pub classes: usize,
    /// Corpus size at the end.
    pub corpus: usize,
    /// Panics and hangs.
    pub findings: Vec<Finding>,
    /// Inputs that hit a known defect ([`Target::known_panics`]).
    pub known: u64,
    /// Inputs that exceeded the time limit (the campaign stops at [`MAX_HANGS`]).
    pub hangs: u64,
}

/// A campaign stops after this many hangs: each leaves a busy thread behind.
pub const MAX_HANGS: u64 = 3;

/// A panic message without its numbers (one defect, one finding).
fn defect_key(msg: &str) -> String {
    msg.chars().filter(|c| !c.is_ascii_digit() && !matches!(c, '.' | '-' | '+' | 'e')).collect()
}

type Job = (Vec<u8>, mpsc::Sender<Outcome>);

/// An input did not finish within the executor's time limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TimedOut;

/// Runs inputs of one target on a worker thread, each under a time limit.
/// A hung worker is abandoned (it keeps its thread) and replaced.
pub struct Executor {
    target: Target,
    limit: Duration,
    jobs: mpsc::Sender<Job>,
}

fn silence_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if std::thread::current().name() != Some("fuzz-worker") {
                default(info);
            }
        }));
    });
}

fn worker(target: Target) -> mpsc::Sender<Job> {
    let (tx, rx) = mpsc::channel::<Job>();
    std::thread::Builder::new()
        .name("fuzz-worker".into())
        .stack_size(64 << 20)
        .spawn(move || {
            for (input, reply) in rx {
                let r = std::panic::catch_unwind(AssertUnwindSafe(|| (target.run)(&input)));
                let out = match r {
                    Ok(class) => Outcome::Done(class),
                    Err(e) => Outcome::Panic(
                        e.downcast_ref::<String>()
                            .cloned()
                            .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                            .unwrap_or_else(|| "non-string panic".into()),
                    ),
                };
                if reply.send(out).is_err() {
                    return;
                }
            }
        })
        .expect("spawning the fuzz worker");
    tx
}

impl Executor {
    /// An executor of `target` with a per-input `limit`.
    pub fn new(target: Target, limit: Duration) -> Executor {
        silence_panics();
        Executor { target, limit, jobs: worker(target) }
    }

    /// Run one input: `Ok(outcome)`, or [`TimedOut`] if it did not finish in time.
    pub fn run(&mut self, input: &[u8]) -> Result<Outcome, TimedOut> {
        let (tx, rx) = mpsc::channel();
        if self.jobs.send((input.to_vec(), tx.clone())).is_err() {
            self.jobs = worker(self.target);
            self.jobs.send((input.to_vec(), tx)).expect("a fresh worker");
        }
        match rx.recv_timeout(self.limit) {
            Ok(o) => Ok(o),
            Err(_) => {
                self.jobs = worker(self.target);
                Err(TimedOut)
            }
        }
    }
}

/// One campaign: a target, a seed, and a budget.
pub struct Campaign {
    /// The target.
    pub target: Target,
    /// The random seed (same seed, same inputs).
    pub seed: u64,
    /// Stop after this many inputs…
    pub max_inputs: u64,
    /// …or this much wall time, whichever comes first.
    pub max_time: Duration,
    /// Per-input time limit (a longer run is a hang).
    pub limit: Duration,
}

impl Campaign {
    /// Run it.
    pub fn run(&self) -> Report {
        let t0 = Instant::now();
        let mut exec = Executor::new(self.target, self.limit);
        let mut rng = Rng::new(self.seed);
        let mut corpus = (self.target.seeds)();
        assert!(!corpus.is_empty(), "target {} has no seeds", self.target.name);
        let mut classes = HashSet::new();
        let mut report = Report::default();
        let mut seen_findings = HashSet::new();
        let mut queue: Vec<Vec<u8>> = corpus.clone();
        while report.inputs < self.max_inputs && t0.elapsed() < self.max_time {
            let input = queue.pop().unwrap_or_else(|| {
                let mut x = corpus[rng.below(corpus.len())].clone();
                let other = corpus[rng.below(corpus.len())].clone();
                mutate(&mut x, &other, self.target.dict, &mut rng, self.target.max_len);
                x
            });
            report.inputs += 1;
            match exec.run(&input) {
                Ok(Outcome::Done(class)) => {
                    if classes.insert(class) && corpus.len() < 4096 {
                        corpus.push(input);
                    }
                }
                Ok(Outcome::Panic(msg)) if self.target.known_panics.iter().any(|k| msg.contains(k)) => {
                    report.known += 1;
                }
                Ok(Outcome::Panic(msg)) => {
                    if seen_findings.insert(defect_key(&msg)) {
                        report.findings.push(Finding {
                            target: self.target.name,
                            what: format!("panic: {msg}"),
                            input,
                        });
                    }
                }
                Err(TimedOut) => {
                    report.hangs += 1;
                    if self.target.known_hangs {
                        report.known += 1;
                    } else if seen_findings.insert("hang".to_string()) {
                        report.findings.push(Finding {
                            target: self.target.name,
                            what: format!("hang: > {:?}", self.limit),
                            input,
                        });
                    }
                    if report.hangs >= MAX_HANGS {
                        break;
                    }
                }
            }
        }
        report.wall = t0.elapsed();
        report.classes = classes.len();
        report.corpus = corpus.len();
        report
    }
}
