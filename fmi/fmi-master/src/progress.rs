//! Progress display of a run: off, an automatic bar on a terminal, or a bar
//! shared by several runs (the main job). [`Tracker`] is what the stepping
//! loop talks to; it updates every [`CHUNK`] steps and at the last step.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Progress display.
#[derive(Clone, Debug, Default)]
pub enum Progress {
    /// None.
    #[default]
    Off,
    /// A bar on stderr if it is a terminal, shown once the run has taken 1 s.
    Auto,
    /// Increment this (shared) bar by the number of steps taken.
    Shared(indicatif::ProgressBar),
}

/// Steps between two progress updates.
pub const CHUNK: u64 = 4096;

/// The progress of one run of `total` steps.
pub(crate) struct Tracker {
    progress: Progress,
    total: u64,
    began: Instant,
    tty: bool,
    bar: Option<indicatif::ProgressBar>,
    reported: u64,
}

impl Tracker {
    /// Start tracking now.
    pub(crate) fn new(progress: Progress, total: u64) -> Self {
        let tty = matches!(progress, Progress::Auto) && std::io::stderr().is_terminal();
        Tracker { progress, total, began: Instant::now(), tty, bar: None, reported: 0 }
    }

    /// Time since [`Tracker::new`].
    pub(crate) fn elapsed(&self) -> Duration {
        self.began.elapsed()
    }

    /// `done` steps are finished.
    #[inline]
    pub(crate) fn update(&mut self, done: u64) {
        if !(done.is_multiple_of(CHUNK) || done == self.total) {
            return;
        }
        match &self.progress {
            Progress::Off => {}
            Progress::Shared(b) => {
                b.inc(done - self.reported);
                self.reported = done;
            }
            Progress::Auto => {
                if self.bar.is_none() && self.tty && self.began.elapsed() > Duration::from_secs(1) {
                    let b = indicatif::ProgressBar::new(self.total);
                    b.set_style(
                        indicatif::ProgressStyle::with_template(
                            "{elapsed_precise} [{bar:40}] {percent:>3}% {human_pos}/{human_len} steps, ETA {eta}",
                        )
                        .expect("valid template")
                        .progress_chars("=> "),
                    );
                    self.bar = Some(b);
                }
                if let Some(b) = &self.bar {
                    b.set_position(done);
                }
            }
        }
    }

    /// The run is over: clear the bar of [`Progress::Auto`].
    pub(crate) fn finish(self) {
        if let Some(b) = self.bar {
            b.finish_and_clear();
        }
    }
}
