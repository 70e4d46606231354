//! The studies' error type.

use std::path::{Path, PathBuf};

/// What can go wrong in a study.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// A run through the FMI master failed.
    #[error(transparent)]
    Sim(#[from] fmi_master::SimError),
    /// An FMU could not be opened.
    #[error(transparent)]
    Fmu(#[from] fmi_master::FmuError),
    /// A results CSV could not be written.
    #[error(transparent)]
    Csv(#[from] fmi_master::csv::CsvError),
    /// A figure could not be drawn.
    #[error(transparent)]
    Plot(#[from] fmi_master::plot::PlotError),
    /// A file could not be written or read.
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        error: std::io::Error,
    },
    /// The study's inputs do not make sense (the message says which and why).
    #[error("{0}")]
    Invalid(String),
    /// A step of a study failed; `context` says which.
    #[error("{context}: {source}")]
    In {
        /// Which step (e.g. "run fopid (seed 3)").
        context: String,
        /// Why.
        #[source]
        source: Box<StudyError>,
    },
}

impl StudyError {
    /// An I/O error on `path`.
    pub fn io(path: &Path, error: std::io::Error) -> StudyError {
        StudyError::Io { path: path.to_path_buf(), error }
    }

    /// This error inside `context`.
    pub fn within(self, context: impl Into<String>) -> StudyError {
        StudyError::In { context: context.into(), source: Box::new(self) }
    }
}
