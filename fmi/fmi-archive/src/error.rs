//! [`ArchiveError`]: what reading, extracting or writing an archive can fail with.

use std::path::PathBuf;

/// Errors of this crate. Every message names the archive or file involved.
///
/// The underlying I/O error is part of the message (and not also exposed as
/// [`std::error::Error::source`], so that printing an error chain does not
/// repeat it).
#[derive(Debug, thiserror::Error)]
pub enum ArchiveError {
    /// A file-system operation failed.
    #[error("{context} {}: {error}", path.display())]
    Io {
        /// What was being done (`"cannot open"`, `"cannot create"` …).
        context: &'static str,
        /// The path involved.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// Not a readable zip archive (or a damaged entry).
    #[error("{} is not a valid zip archive: {reason}", path.display())]
    NotZip {
        /// The archive.
        path: PathBuf,
        /// The zip reader's message.
        reason: String,
    },
    /// An entry that would escape the extraction directory, or a link.
    #[error("refusing to extract {}: unsafe entry '{entry}' ({reason})", path.display())]
    UnsafeEntry {
        /// The archive.
        path: PathBuf,
        /// The entry's name as stored.
        entry: String,
        /// Why it is unsafe.
        reason: &'static str,
    },
    /// The archive exceeds one of the [`crate::Limits`] (a zip bomb or simply too big).
    #[error("refusing to extract {}: {message}", path.display())]
    Limit {
        /// The archive.
        path: PathBuf,
        /// Which limit, with the numbers.
        message: String,
    },
    /// An entry or file read into memory is larger than allowed.
    #[error("{}: {what} is {size} bytes, more than the {max} bytes this reader accepts", path.display())]
    TooLarge {
        /// The archive or file.
        path: PathBuf,
        /// The entry (or `"the file"`).
        what: String,
        /// Its (declared) size.
        size: u64,
        /// The cap.
        max: u64,
    },
    /// An entry ended before its declared size.
    #[error("{}: entry {entry} is truncated ({got} of {size} bytes)", path.display())]
    Truncated {
        /// The archive.
        path: PathBuf,
        /// The entry.
        entry: String,
        /// Bytes actually read.
        got: u64,
        /// Declared size.
        size: u64,
    },
    /// An entry name given to [`crate::ZipBuilder`] that is unsafe or repeated.
    #[error("cannot write {}: entry name '{entry}' {reason}", path.display())]
    BadEntryName {
        /// The archive being written.
        path: PathBuf,
        /// The entry name.
        entry: String,
        /// What is wrong with it.
        reason: String,
    },
    /// The zip writer failed.
    #[error("cannot write {}: {reason}", path.display())]
    Write {
        /// The archive being written.
        path: PathBuf,
        /// The zip writer's message.
        reason: String,
    },
}
