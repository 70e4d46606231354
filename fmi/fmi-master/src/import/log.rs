//! The per-instance log: a ring buffer of the FMU's formatted log lines,
//! quoted by every error of that instance (safe code; the C logger shim and
//! the `extern "C"` sink it calls are in [`super::ffi`]).

use crate::error::LogExcerpt;
use std::collections::VecDeque;
use std::sync::Mutex;

/// How many log lines an instance keeps.
pub(crate) const LOG_CAPACITY: usize = 200;
/// How many of them an error quotes.
pub(crate) const LOG_QUOTED: usize = 20;

/// The log lines of one instance (filled from the FMU's logger callback,
/// possibly from threads the FMU starts, hence the mutex).
pub(crate) struct LogState {
    lines: Mutex<VecDeque<String>>,
    echo: bool,
    instance: String,
}

impl LogState {
    /// An empty log of `instance`; with `echo`, lines are also printed to stderr.
    pub(crate) fn new(instance: &str, echo: bool) -> Self {
        LogState { lines: Mutex::new(VecDeque::new()), echo, instance: instance.to_string() }
    }

    /// Keep one line (dropping the oldest beyond [`LOG_CAPACITY`]).
    pub(crate) fn push(&self, line: String) {
        if self.echo {
            eprintln!("[{}] {line}", self.instance);
        }
        let mut q = self.lines.lock().unwrap_or_else(|p| p.into_inner());
        if q.len() == LOG_CAPACITY {
            q.pop_front();
        }
        q.push_back(line);
    }

    /// The last `n` lines.
    pub(crate) fn excerpt(&self, n: usize) -> LogExcerpt {
        let q = self.lines.lock().unwrap_or_else(|p| p.into_inner());
        LogExcerpt(q.iter().skip(q.len().saturating_sub(n)).cloned().collect())
    }

    /// All lines kept.
    pub(crate) fn all(&self) -> Vec<String> {
        self.lines.lock().unwrap_or_else(|p| p.into_inner()).iter().cloned().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ring_buffer_keeps_the_last_lines() {
        let s = LogState::new("i", false);
        for i in 0..(LOG_CAPACITY + 5) {
            s.push(format!("line {i}"));
        }
        let all = s.all();
        assert_eq!(all.len(), LOG_CAPACITY);
        assert_eq!(all[0], "line 5");
        let ex = s.excerpt(3);
        assert_eq!(
            ex.0,
            vec![
                format!("line {}", LOG_CAPACITY + 2),
                format!("line {}", LOG_CAPACITY + 3),
                format!("line {}", LOG_CAPACITY + 4)
            ]
        );
    }
}
