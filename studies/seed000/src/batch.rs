//! Many short runs of the project's closed loop through the FMUs, in parallel (rayon; every run
//! opens its own FMU instances), with one progress bar over the runs and a results CSV that is
//! streamed row by row as runs finish.
//!
//! The CSV follows the crash-safety convention of [`fmi_master::csv`]: the header is written at
//! once, each row is flushed as soon as its run finishes, and the sidecar
//! [`fmi_master::csv::incomplete_marker`] (`<csv>.incomplete`) exists until every run has
//! finished ([`RowSink::complete`]); a failed study leaves the rows it had and says why in the
//! marker ([`RowSink::fail`]). A study writes its markdown table and figures only after the CSV
//! is complete, so nothing partial is presented as complete.
//!
//! Per run ([`Metrics`]), over the communication points `t ∈ (t_from, T]` of the measured tip
//! displacement `x`:
//!
//! * `rms = √(mean x²)` (raw, as the repo's Table 5), and the detrended `σ = √(mean x² − mean²)`;
//! * the detrended RMS of two growth windows `(a₀, a₁]` and `(b₀, b₁]` (the map's growth test);
//! * the fraction of samples with the controller's `saturated` output set.

use crate::scenario::Roles;
use chatter_control::Structure;
use fmi_master::{Observer, Override, Progress, RunConfig, SimError, Simulation, SystemFile};
use model_description::Value;
use model_kit::Choice;
use rayon::prelude::*;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use study_kit::StudyError;

/// The time windows of one run \[s\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Windows {
    /// Stop time.
    pub stop: f64,
    /// Start of the RMS window (to `stop`).
    pub rms_from: f64,
    /// First growth window.
    pub early: (f64, f64),
    /// Last growth window.
    pub late: (f64, f64),
}

impl Windows {
    /// RMS over `(from, stop]`, growth windows the first and the last second of the run.
    pub fn rms(stop: f64, from: f64) -> Windows {
        Windows { stop, rms_from: from, early: (0.0, 1.0_f64.min(stop)), late: ((stop - 1.0).max(0.0), stop) }
    }

    /// Check that every window holds time and lies in the run.
    pub fn validate(&self) -> Result<(), StudyError> {
        let ok = |(a, b): (f64, f64)| a.is_finite() && b.is_finite() && a >= 0.0 && b > a && b <= self.stop;
        if !(self.stop.is_finite()
            && self.stop > 0.0
            && ok((self.rms_from, self.stop))
            && ok(self.early)
            && ok(self.late))
        {
            return Err(StudyError::Invalid(format!("run windows {self:?}: every window must lie in (0, stop]")));
        }
        Ok(())
    }
}

/// One run's metrics (SI units).
#[derive(Clone, Copy, Debug, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Metrics {
    /// RMS of x over the RMS window \[m\].
    pub rms: f64,
    /// Standard deviation of x over the RMS window \[m\].
    pub rms_detrended: f64,
    /// Detrended RMS of the early growth window \[m\].
    pub early: f64,
    /// Detrended RMS of the late growth window \[m\].
    pub late: f64,
    /// Fraction of the RMS window's samples with the command saturated.
    pub saturation_duty: f64,
}

#[derive(Default, Clone, Copy)]
struct Acc {
    s1: f64,
    s2: f64,
    n: u64,
}

impl Acc {
    fn add(&mut self, x: f64) {
        self.s1 += x;
        self.s2 += x * x;
        self.n += 1;
    }
    fn rms(&self) -> f64 {
        (self.s2 / self.n.max(1) as f64).sqrt()
    }
    fn sigma(&self) -> f64 {
        let n = self.n.max(1) as f64;
        (self.s2 / n - (self.s1 / n).powi(2)).max(0.0).sqrt()
    }
}

struct Collect {
    w: Windows,
    main: Acc,
    early: Acc,
    late: Acc,
    saturated: u64,
}

impl Observer for Collect {
    fn start(&mut self, _names: &[String]) -> Result<(), SimError> {
        Ok(())
    }
    fn sample(&mut self, t: f64, v: &[f64]) -> Result<(), SimError> {
        let inside = |(a, b): (f64, f64)| t > a && t <= b;
        if inside((self.w.rms_from, self.w.stop)) {
            self.main.add(v[0]);
            self.saturated += u64::from(v[1] != 0.0);
        }
        if inside(self.w.early) {
            self.early.add(v[0]);
        }
        if inside(self.w.late) {
            self.late.add(v[0]);
        }
        Ok(())
    }
    fn finish(&mut self) -> Result<(), SimError> {
        Ok(())
    }
}

/// The overrides that select controller `structure` and noise seed `seed`.
pub fn select(roles: &Roles, structure: Structure, seed: i32) -> Vec<Override> {
    vec![
        Override::typed(format!("{}.structure", roles.controller), Value::Integer(structure.index())),
        Override::typed(format!("{}.seed", roles.plant), Value::Integer(seed)),
    ]
}

/// Run `sys` with `overrides` (start 0, the system's step) and measure [`Metrics`].
pub fn run_one(sys: &SystemFile, roles: &Roles, overrides: Vec<Override>, w: &Windows) -> Result<Metrics, StudyError> {
    w.validate()?;
    let cfg = RunConfig {
        start: Some(0.0),
        stop: Some(w.stop),
        overrides,
        record: Some(vec![roles.measured(), format!("{}.saturated", roles.controller)]),
        ..RunConfig::default()
    };
    let mut sim = Simulation::new(sys, &cfg)?;
    let mut obs = Collect { w: *w, main: Acc::default(), early: Acc::default(), late: Acc::default(), saturated: 0 };
    sim.run(&mut obs, Progress::Off)?;
    if obs.main.n == 0 || obs.early.n == 0 || obs.late.n == 0 {
        return Err(StudyError::Invalid(format!("the run left no samples in one of the windows {w:?}")));
    }
    Ok(Metrics {
        rms: obs.main.rms(),
        rms_detrended: obs.main.sigma(),
        early: obs.early.sigma(),
        late: obs.late.sigma(),
        saturation_duty: obs.saturated as f64 / obs.main.n as f64,
    })
}

/// A results CSV written row by row (see the module documentation).
pub struct RowSink {
    path: PathBuf,
    file: Mutex<std::io::BufWriter<std::fs::File>>,
}

impl RowSink {
    /// Create `path` (and its directory) with `header`, and its `.incomplete` marker.
    pub fn create(path: &Path, header: &str) -> Result<RowSink, StudyError> {
        if let Some(d) = path.parent() {
            std::fs::create_dir_all(d).map_err(|e| StudyError::io(d, e))?;
        }
        let marker = fmi_master::csv::incomplete_marker(path);
        std::fs::write(&marker, "the study writing this CSV has not finished (running, failed or killed)\n")
            .map_err(|e| StudyError::io(&marker, e))?;
        let f = std::fs::File::create(path).map_err(|e| StudyError::io(path, e))?;
        let s = RowSink { path: path.to_path_buf(), file: Mutex::new(std::io::BufWriter::new(f)) };
        s.row(header)?;
        Ok(s)
    }

    /// Append one line and flush it.
    pub fn row(&self, line: &str) -> Result<(), StudyError> {
        let mut f = self.file.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        writeln!(f, "{line}").and_then(|()| f.flush()).map_err(|e| StudyError::io(&self.path, e))
    }

    /// Every run finished: remove the marker.
    pub fn complete(&self) -> Result<(), StudyError> {
        let marker = fmi_master::csv::incomplete_marker(&self.path);
        std::fs::remove_file(&marker).map_err(|e| StudyError::io(&marker, e))
    }

    /// The study failed: say why in the marker.
    pub fn fail(&self, why: &str) {
        let _ = std::fs::write(
            fmi_master::csv::incomplete_marker(&self.path),
            format!("the study writing this CSV failed: {why}\n"),
        );
    }

    /// The CSV's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// A progress bar over `n` runs on a terminal (hidden otherwise).
fn bar(n: usize, what: &str) -> indicatif::ProgressBar {
    let b = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        indicatif::ProgressBar::new(n as u64)
    } else {
        indicatif::ProgressBar::hidden()
    };
    b.set_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} {msg} runs, ETA {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    b.set_message(what.to_string());
    b
}

/// Run `f` on every job in parallel with a progress bar; `line(job, result)` is appended to
/// `sink` as each run finishes. On the first error the marker says why and the error returns
/// (with `label(job)` as context); on success the CSV is complete.
pub fn run_all<J: Sync, R: Send>(
    jobs: &[J],
    what: &str,
    sink: &RowSink,
    label: impl Fn(&J) -> String + Sync,
    f: impl Fn(&J) -> Result<R, StudyError> + Sync,
    line: impl Fn(&J, &R) -> String + Sync,
) -> Result<Vec<R>, StudyError> {
    let b = bar(jobs.len(), what);
    let out: Vec<Result<R, StudyError>> = jobs
        .par_iter()
        .map(|j| {
            let r = f(j).map_err(|e| e.within(label(j)))?;
            sink.row(&line(j, &r))?;
            b.inc(1);
            Ok(r)
        })
        .collect();
    b.finish_and_clear();
    match out.into_iter().collect::<Result<Vec<R>, StudyError>>() {
        Ok(v) => {
            sink.complete()?;
            Ok(v)
        }
        Err(e) => {
            sink.fail(&e.to_string());
            Err(e)
        }
    }
}

/// Mean, p90 (linear interpolation between order statistics, `h = 0.9·(n − 1)`), CV = σ/mean
/// with the population σ, and max.
pub fn table7_stats(v: &[f64]) -> (f64, f64, f64, f64) {
    if v.is_empty() {
        return (f64::NAN, f64::NAN, f64::NAN, f64::NAN);
    }
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let h = 0.9 * (n - 1.0);
    let (i, frac) = (h.floor() as usize, h - h.floor());
    let p90 = if i + 1 < s.len() { s[i] + frac * (s[i + 1] - s[i]) } else { s[i] };
    (mean, p90, sd / mean, s[s.len() - 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_of_a_known_sample() {
        let (m, p90, cv, max) = table7_stats(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0]);
        assert!((m - 6.0).abs() < 1e-12 && (p90 - 10.0).abs() < 1e-12 && (max - 11.0).abs() < 1e-12);
        assert!((cv - 10f64.sqrt() / 6.0).abs() < 1e-12, "{cv}");
        let (_, p90, ..) = table7_stats(&[0.0, 10.0]);
        assert!((p90 - 9.0).abs() < 1e-12);
    }

    #[test]
    fn windows_outside_the_run_are_refused() {
        assert!(Windows::rms(2.0, 1.0).validate().is_ok());
        assert!(Windows::rms(2.0, 3.0).validate().is_err());
        assert!(Windows { early: (-1.0, 0.5), ..Windows::rms(2.0, 1.0) }.validate().is_err());
    }
}
