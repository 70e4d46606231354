//! [`SspError`]: what reading or writing a system description can fail with.

/// Errors of this crate. Messages start with the file they are about.
#[derive(Debug, thiserror::Error)]
pub enum SspError {
    /// Malformed XML (or XML the schema types cannot take).
    #[error("{file}: XML error: {message}")]
    Xml {
        /// The file (`archive.ssp!SystemStructure.ssd` for an entry).
        file: String,
        /// The parser's message, with the line where known.
        message: String,
    },
    /// Elements nested deeper than [`crate::MAX_DEPTH`].
    #[error(
        "{file}: line {line}: elements are nested more than {limit} levels deep \
         (this reader's limit; an SSD needs about a dozen)"
    )]
    TooDeep {
        /// The file.
        file: String,
        /// Line of the first element beyond the limit.
        line: usize,
        /// The limit.
        limit: usize,
    },
    /// Well-formed XML that is not a usable system description.
    #[error("{file}: {message}")]
    Invalid {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// Reading a file or an archive, or writing an archive, failed.
    #[error(transparent)]
    Archive(#[from] fmi_archive::ArchiveError),
    /// The XML writer failed.
    #[error("cannot write the system description {name}: {message}")]
    Write {
        /// The system's name.
        name: String,
        /// The serializer's message.
        message: String,
    },
}

/// An [`SspError::Invalid`] about `file`.
pub(crate) fn invalid(file: &str, message: impl Into<String>) -> SspError {
    SspError::Invalid { file: file.to_string(), message: message.into() }
}
