//! Streaming CSV results in FMPy's convention: a header of quoted names,
//! `"time"` first, then one row per output point; numbers in the shortest
//! form that reads back to the same double (integral values without a
//! fraction, booleans as 0/1).
//!
//! ## Crash safety and the completion marker
//! The header reaches the file as soon as the run starts, and rows are
//! flushed every [`FLUSH_ROWS`] rows and whenever [`FLUSH_INTERVAL`] has
//! passed since the last flush, so a run that dies (an FMU that segfaults
//! or calls `exit`) leaves every row up to the last flush.
//!
//! The CSV itself stays a plain numeric CSV (FMPy's `read_csv`, pandas and
//! numpy read it unchanged). Whether the run finished is told by a sidecar
//! file, [`incomplete_marker`] (`<csv>.incomplete`): [`CsvWriter::create`]
//! writes it, [`CsvWriter::complete`] (called only after a successful run)
//! removes it. A CSV with its `.incomplete` file beside it holds an
//! interrupted or failed run; the marker's text says why when the master
//! could still tell ([`CsvWriter::mark_failed`]).

use crate::error::SimError;
use crate::observer::Observer;
use std::io::{BufRead, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Format one value exactly (round-trips through `f64::from_str` and Python's `float`).
pub fn format_value(x: f64) -> String {
    if x.is_finite() && x.fract() == 0.0 && x.abs() < 1e15 {
        if x == 0.0 && x.is_sign_negative() {
            return "-0".into();
        }
        format!("{}", x as i64)
    } else if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{x:?}")
    }
}

/// Rows written between two flushes at most.
pub const FLUSH_ROWS: u64 = 256;
/// Longest time rows stay in the buffer (checked at every row).
pub const FLUSH_INTERVAL: Duration = Duration::from_millis(200);

/// The sidecar file that marks `csv` as the results of a run that has not
/// (yet, or ever) finished: `<csv>.incomplete`.
pub fn incomplete_marker(csv: &Path) -> PathBuf {
    let mut name = csv.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    name.push(".incomplete");
    csv.with_file_name(name)
}

/// Refuse an output path that would destroy what the run reads or what is not a results file:
/// one of `inputs` (the system file, its FMUs: `cosim run v.fmu -o v.fmu` replaced the FMU
/// with a CSV), a directory, or an existing zip archive (an FMU or SSP is never a results CSV).
/// [`CsvWriter::create`] checks the last two itself; this is for a check before the run starts.
pub fn check_output(path: &Path, inputs: &[&Path]) -> Result<(), SimError> {
    let refuse = |message: String| Err(SimError::OutputRefused { path: path.to_path_buf(), message });
    let same = |a: &Path, b: &Path| match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if let Some(input) = inputs.iter().find(|i| same(path, i)) {
        return refuse(format!(
            "is an input of this run ({}); writing the results there would destroy it: choose another -o",
            input.display()
        ));
    }
    if path.is_dir() {
        return refuse("is a directory; give a file name for the results CSV (e.g. DIR/results.csv)".into());
    }
    let mut head = [0u8; 4];
    if let Ok(mut f) = std::fs::File::open(path)
        && std::io::Read::read_exact(&mut f, &mut head).is_ok()
        && &head == b"PK\x03\x04"
    {
        return refuse(
            "is a zip archive (an FMU or SSP?), not a results CSV; refusing to overwrite it: choose another -o".into(),
        );
    }
    Ok(())
}

/// An [`Observer`] writing a CSV file as the run goes. Memory is constant;
/// the header is flushed at once, rows every [`FLUSH_ROWS`] rows or
/// [`FLUSH_INTERVAL`], and everything when the run ends (also when it
/// fails), so a failed or killed run keeps the rows it had. The sidecar
/// [`incomplete_marker`] exists until [`CsvWriter::complete`].
pub struct CsvWriter {
    path: PathBuf,
    out: BufWriter<std::fs::File>,
    /// The [`incomplete_marker`], locked (exclusive advisory lock) while this writer lives: a
    /// second run writing the same CSV is refused instead of truncating it under the first.
    marker: std::fs::File,
    last_flush: Instant,
    rows: u64,
    unflushed: u64,
    line: String,
}

impl CsvWriter {
    /// Create (truncate) the file and write its [`incomplete_marker`], which this writer holds
    /// locked until it is dropped. Refused ([`SimError::OutputRefused`]) before anything is
    /// written: a directory, a zip archive ([`check_output`]), and a CSV whose marker another
    /// live run holds (two runs writing one CSV left 17.8 MB of NUL bytes, both exiting 0).
    /// A marker left by a run that died is not locked and is taken over.
    pub fn create(path: &Path) -> Result<CsvWriter, SimError> {
        check_output(path, &[])?;
        if let Some(dir) = path.parent()
            && !dir.as_os_str().is_empty()
        {
            std::fs::create_dir_all(dir).map_err(|error| SimError::Output { path: dir.to_path_buf(), error })?;
        }
        let marker_path = incomplete_marker(path);
        let io = |p: &Path| {
            let p = p.to_path_buf();
            move |error| SimError::Output { path: p, error }
        };
        let mut marker = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&marker_path)
            .map_err(io(&marker_path))?;
        match marker.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                let holder = std::fs::read_to_string(&marker_path).unwrap_or_default();
                return Err(SimError::OutputRefused {
                    path: path.to_path_buf(),
                    message: format!(
                        "another run is writing this CSV now ({}): wait for it or choose another -o",
                        holder.trim()
                    ),
                });
            }
            Err(std::fs::TryLockError::Error(error)) => return Err(SimError::Output { path: marker_path, error }),
        }
        marker.set_len(0).map_err(io(&marker_path))?;
        writeln!(
            marker,
            "the run writing this CSV has not finished (it is running, failed or was killed); process {}",
            std::process::id()
        )
        .map_err(io(&marker_path))?;
        let f = std::fs::File::create(path).map_err(io(path))?;
        Ok(CsvWriter {
            path: path.to_path_buf(),
            out: BufWriter::with_capacity(1 << 16, f),
            marker,
            last_flush: Instant::now(),
            rows: 0,
            unflushed: 0,
            line: String::new(),
        })
    }

    /// The run finished: flush, and remove the [`incomplete_marker`].
    pub fn complete(&mut self) -> Result<(), SimError> {
        self.flush()?;
        let marker = incomplete_marker(&self.path);
        match std::fs::remove_file(&marker) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(SimError::Output { path: marker, error: e }),
            _ => Ok(()),
        }
    }

    /// The run failed: flush, and say why in the [`incomplete_marker`].
    pub fn mark_failed(&mut self, reason: &str) -> Result<(), SimError> {
        self.flush()?;
        let marker = incomplete_marker(&self.path);
        let text = format!("the run writing this CSV failed: {reason}\n");
        // through the locked handle: the file another run may be waiting on is this one
        let mut f = &self.marker;
        let r = f.set_len(0).and_then(|()| std::io::Seek::rewind(&mut f)).and_then(|()| f.write_all(text.as_bytes()));
        r.map_err(|error| SimError::Output { path: marker, error })
    }

    fn flush(&mut self) -> Result<(), SimError> {
        self.out.flush().map_err(|e| self.err(e))?;
        self.last_flush = Instant::now();
        self.unflushed = 0;
        Ok(())
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    fn err(&self, error: std::io::Error) -> SimError {
        SimError::Output { path: self.path.clone(), error }
    }
}

fn quote(name: &str) -> String {
    format!("\"{}\"", name.replace('"', "\"\""))
}

impl Observer for CsvWriter {
    fn start(&mut self, names: &[String]) -> Result<(), SimError> {
        let mut header = vec![quote("time")];
        header.extend(names.iter().map(|n| quote(n)));
        writeln!(self.out, "{}", header.join(",")).map_err(|e| self.err(e))?;
        self.flush()
    }

    fn sample(&mut self, t: f64, values: &[f64]) -> Result<(), SimError> {
        use std::fmt::Write as _;
        self.line.clear();
        self.line.push_str(&format_value(t));
        for v in values {
            self.line.push(',');
            let _ = write!(self.line, "{}", format_value(*v));
        }
        self.line.push('\n');
        self.out.write_all(self.line.as_bytes()).map_err(|e| self.err(e))?;
        self.rows += 1;
        self.unflushed += 1;
        if self.unflushed >= FLUSH_ROWS || self.last_flush.elapsed() >= FLUSH_INTERVAL {
            self.flush()?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), SimError> {
        self.flush()
    }
}

/// A CSV file read back: column names (without quotes) and columns.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Column names, `time` first.
    pub names: Vec<String>,
    /// Columns, same order.
    pub columns: Vec<Vec<f64>>,
}

impl Table {
    /// The column named `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.names.iter().position(|n| n == name).map(|i| self.columns[i].as_slice())
    }
}

/// Errors reading a results CSV.
#[derive(Debug, thiserror::Error)]
pub enum CsvError {
    /// The file cannot be opened or read.
    #[error("cannot read {}: {error}", path.display())]
    Io {
        /// The CSV file.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// The content is not a numeric CSV with a header.
    #[error("{}: {message}", path.display())]
    Format {
        /// The CSV file.
        path: PathBuf,
        /// What is wrong, with the row.
        message: String,
    },
}

/// Read a CSV written by [`CsvWriter`] (or FMPy's `write_csv`, numeric columns).
pub fn read_csv(path: &Path) -> Result<Table, CsvError> {
    let io = |error| CsvError::Io { path: path.to_path_buf(), error };
    let format = |message: String| CsvError::Format { path: path.to_path_buf(), message };
    let f = std::fs::File::open(path).map_err(io)?;
    let mut lines = std::io::BufReader::new(f).lines();
    let header = lines.next().ok_or_else(|| format("empty CSV file".into()))?.map_err(io)?;
    let names: Vec<String> = header.split(',').map(|s| s.trim().trim_matches('"').to_string()).collect();
    let mut columns = vec![Vec::new(); names.len()];
    for (i, line) in lines.enumerate() {
        let line = line.map_err(io)?;
        if line.trim().is_empty() {
            continue;
        }
        let cells: Vec<&str> = line.split(',').collect();
        if cells.len() != names.len() {
            return Err(format(format!("row {} has {} cells, expected {}", i + 2, cells.len(), names.len())));
        }
        for (c, cell) in cells.iter().enumerate() {
            let v = match cell.trim() {
                "True" | "true" => 1.0,
                "False" | "false" => 0.0,
                s => s.parse::<f64>().map_err(|_| format(format!("row {}: '{s}' is not a number", i + 2)))?,
            };
            columns[c].push(v);
        }
    }
    Ok(Table { names, columns })
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // exact values are intended in these tests
mod tests {
    use super::*;

    #[test]
    fn values_are_written_exactly() {
        for x in [0.1, 1.0 / 3.0, -2.5e-300, 6.02214076e23, 1e-5, 123456.789, f64::MIN_POSITIVE, 2000.0, -7.0, 0.0] {
            let s = format_value(x);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{x} -> {s}");
        }
        assert_eq!(format_value(2000.0), "2000");
        assert_eq!(format_value(1e-5), "1e-5");
        assert_eq!(format_value(1.0 / 3.0), "0.3333333333333333");
        assert_eq!(format_value(f64::NAN), "nan");
    }

    #[test]
    fn writer_streams_fmpy_style_csv_and_reads_back() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("sub/r.csv");
        let mut w = CsvWriter::create(&p).unwrap();
        w.start(&["plant.x".into(), "controller.u".into()]).unwrap();
        w.sample(0.0, &[1e-6, 0.0]).unwrap();
        w.sample(1e-5, &[-3.25e-7, 27.0]).unwrap();
        // Before finish(), rows may still be buffered; after it they are on disk.
        w.finish().unwrap();
        assert!(incomplete_marker(&p).is_file(), "finish() alone does not say the run succeeded");
        w.complete().unwrap();
        assert!(!incomplete_marker(&p).exists());
        let text = std::fs::read_to_string(&p).unwrap();
        assert_eq!(text, "\"time\",\"plant.x\",\"controller.u\"\n0,1e-6,0\n1e-5,-3.25e-7,27\n");
        let t = read_csv(&p).unwrap();
        assert_eq!(t.names, vec!["time", "plant.x", "controller.u"]);
        assert_eq!(t.column("controller.u").unwrap(), &[0.0, 27.0]);
        assert_eq!(t.column("time").unwrap()[1], 1e-5);
    }

    /// The header waited in a 64 KiB buffer and rows were flushed only every
    /// 256th row after half a second: a crash early in a run left an empty file.
    #[test]
    fn header_and_rows_reach_the_file_without_finish() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.csv");
        let mut w = CsvWriter::create(&p).unwrap();
        assert_eq!(incomplete_marker(&p), dir.path().join("r.csv.incomplete"));
        assert!(incomplete_marker(&p).is_file());
        w.start(&["x".into()]).unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "\"time\",\"x\"\n");
        for i in 0..FLUSH_ROWS {
            w.sample(i as f64, &[1.0]).unwrap();
        }
        assert_eq!(read_csv(&p).unwrap().columns[0].len() as u64, FLUSH_ROWS, "flushed by count");
        w.sample(1e3, &[2.0]).unwrap();
        std::thread::sleep(FLUSH_INTERVAL + Duration::from_millis(20));
        w.sample(1e4, &[3.0]).unwrap();
        assert_eq!(read_csv(&p).unwrap().column("x").unwrap().last(), Some(&3.0), "flushed by time");
        w.mark_failed("an FMU failed").unwrap();
        assert!(std::fs::read_to_string(incomplete_marker(&p)).unwrap().contains("an FMU failed"));
        drop(w);
        assert!(incomplete_marker(&p).is_file(), "only complete() removes the marker");
    }

    /// Two runs writing the default `results.csv` both exited 0: the second truncated the file
    /// under the first, which then wrote at its old offset (17.8 MB of NUL bytes), and the first
    /// to finish deleted the marker of the other. The second is refused now, before it writes.
    #[test]
    fn a_second_writer_of_the_same_csv_is_refused_while_the_first_lives() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("results.csv");
        let mut first = CsvWriter::create(&p).unwrap();
        first.start(&["x".into()]).unwrap();
        first.sample(0.0, &[1.0]).unwrap();
        let e = CsvWriter::create(&p).err().expect("the second writer is refused").to_string();
        assert!(e.contains("another run is writing this CSV now") && e.contains("process"), "{e}");
        first.sample(1.0, &[2.0]).unwrap();
        first.finish().unwrap();
        first.complete().unwrap();
        assert_eq!(read_csv(&p).unwrap().column("x").unwrap(), &[1.0, 2.0], "the first run's rows are intact");
        drop(first);
        // a marker left behind by a run that died is not locked: the next run takes it over
        std::fs::write(incomplete_marker(&p), "left by a killed run\n").unwrap();
        let mut again = CsvWriter::create(&p).unwrap();
        again.mark_failed("test").unwrap();
        let marker = std::fs::read_to_string(incomplete_marker(&p)).unwrap();
        assert_eq!(marker, "the run writing this CSV failed: test\n", "rewritten from its start, no NUL bytes");
    }

    /// `-o <directory>` failed only after writing a stray `<directory>.incomplete`; `-o v.fmu`
    /// replaced the FMU with a CSV.
    #[test]
    fn directories_archives_and_inputs_are_refused_before_anything_is_written() {
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("out");
        std::fs::create_dir(&sub).unwrap();
        let e = CsvWriter::create(&sub).err().unwrap().to_string();
        assert!(e.contains("is a directory"), "{e}");
        assert!(!incomplete_marker(&sub).exists(), "no stray marker");
        let fmu = dir.path().join("v.fmu");
        std::fs::write(&fmu, b"PK\x03\x04 rest of an archive").unwrap();
        let e = CsvWriter::create(&fmu).err().unwrap().to_string();
        assert!(e.contains("is a zip archive"), "{e}");
        assert_eq!(std::fs::read(&fmu).unwrap(), b"PK\x03\x04 rest of an archive");
        let ssd = dir.path().join("s.ssd");
        std::fs::write(&ssd, "<xml/>").unwrap();
        let e = check_output(&dir.path().join("./s.ssd"), &[&ssd]).unwrap_err().to_string();
        assert!(e.contains("is an input of this run"), "{e}");
        check_output(&dir.path().join("r.csv"), &[&ssd]).unwrap();
    }

    #[test]
    fn ragged_rows_are_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("bad.csv");
        std::fs::write(&p, "\"time\",\"a\"\n0,1\n1\n").unwrap();
        assert!(read_csv(&p).unwrap_err().to_string().contains("row 3 has 1 cells"));
    }
}
