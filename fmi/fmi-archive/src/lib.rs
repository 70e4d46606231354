//! # fmi-archive — the zip layer of `.fmu` and `.ssp` files
//!
//! * [`extract`] / [`extract_with`]: safe extraction. Every entry is checked
//!   **before anything is written** (an archive with one bad entry extracts
//!   nothing): absolute paths, `..`, NUL bytes and symbolic links are refused,
//!   and so are archives over the [`Limits`] (entry count, size of one entry,
//!   total size, compression ratio: zip bombs).
//! * [`read_entry`]: one entry into memory, size-capped (e.g.
//!   `modelDescription.xml` or `SystemStructure.ssd` without extracting);
//!   [`read_file_capped`]: the same cap for a file already extracted.
//! * [`ZipBuilder`]: a deterministic zip writer (entries in the order given,
//!   fixed timestamps and permissions, written atomically) for packaging.
//!
//! Errors are [`ArchiveError`]s; each names the archive (and the entry) and
//! says what is wrong.

mod entry_path;
mod error;
mod extract;
mod write;

pub use entry_path::safe_entry_path;
pub use error::ArchiveError;
pub use extract::{Limits, extract, extract_with, read_entry, read_file_capped};
pub use write::{Compression, ZipBuilder};
