//! What the master does when the process ends in a way Rust's destructors
//! do not see: an FMU calling `exit()` in the middle of a run, or a
//! `SIGINT`/`SIGTERM`/`SIGHUP`. The second (and last) module of the master
//! with `unsafe` code: `atexit`, `_exit`, `sigaction` and a self-pipe.
//!
//! * [`ScratchDir`]: a temporary directory (an FMU's or an `.ssp`'s
//!   extraction) registered in a process-wide list while it exists, so the
//!   paths below can remove it when destructors will not run.
//! * [`install_exit_guard`]: an `atexit` handler that removes every live
//!   [`ScratchDir`] and, if a run is in progress ([`RunInProgress`]), says
//!   so on stderr and ends the process with status [`EXIT_DURING_RUN`]
//!   instead of the status the FMU asked for — an FMU's `exit(0)` cannot
//!   make the master report success.
//! * [`install_signal_cleanup`]: `SIGINT`, `SIGTERM` and `SIGHUP` write
//!   their number into a pipe (the only thing the handler does:
//!   async-signal-safe); a thread reading it removes the live scratch
//!   directories and ends the process with `128 + signal`, as a shell does.
//!
//! A segfaulting FMU still takes the process down at once; its scratch
//! directory then stays in the temporary directory (`fmi-master-*`).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, Once};

/// The exit status when the process ends (an FMU called `exit`) during a run.
pub const EXIT_DURING_RUN: i32 = 3;

static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
static RUNNING: AtomicBool = AtomicBool::new(false);

/// A temporary directory removed when dropped, and by the exit and signal
/// paths of this module when the process ends without dropping it.
#[derive(Debug)]
pub struct ScratchDir {
    dir: tempfile::TempDir,
}

impl ScratchDir {
    /// Create `$TMPDIR/<prefix>XXXXXX` and register it.
    pub fn new(prefix: &str) -> std::io::Result<ScratchDir> {
        let dir = tempfile::Builder::new().prefix(prefix).tempdir()?;
        lock().push(dir.path().to_path_buf());
        Ok(ScratchDir { dir })
    }

    /// The directory.
    pub fn path(&self) -> &Path {
        self.dir.path()
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        let mut live = lock();
        if let Some(i) = live.iter().position(|p| p == self.dir.path()) {
            live.swap_remove(i);
        }
    }
}

fn lock() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Remove every registered scratch directory (best effort). Used only when
/// the process is ending: a thread holding the lock then is not waited for.
fn remove_live_dirs() {
    if let Ok(live) = LIVE.try_lock() {
        for p in live.iter() {
            let _ = std::fs::remove_dir_all(p);
        }
    }
}

/// Marks a run in progress while it lives (see [`install_exit_guard`]).
#[derive(Debug)]
pub struct RunInProgress(());

impl RunInProgress {
    /// A run starts.
    pub fn start() -> RunInProgress {
        RUNNING.store(true, Ordering::SeqCst);
        RunInProgress(())
    }
}

impl Drop for RunInProgress {
    fn drop(&mut self) {
        RUNNING.store(false, Ordering::SeqCst);
    }
}

fn write_stderr(msg: &str) {
    use std::io::Write;
    let _ = std::io::stderr().write_all(msg.as_bytes());
}

extern "C" fn at_exit() {
    remove_live_dirs();
    if RUNNING.load(Ordering::SeqCst) {
        write_stderr(
            "error: the process was ended (exit() called, probably by an FMU) while a run was in progress; \
             the results are incomplete\n",
        );
        // SAFETY: `_exit` ends the process at once without running further
        // handlers; it is the documented way to end from an atexit handler.
        unsafe { libc::_exit(EXIT_DURING_RUN) }
    }
}

/// Install the `atexit` handler (once per process; later calls do nothing).
pub fn install_exit_guard() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // SAFETY: `at_exit` is an `extern "C" fn()` that lives for the whole
        // program; registering it has no other precondition.
        unsafe {
            libc::atexit(at_exit);
        }
    });
}

static PIPE_WRITE: std::sync::atomic::AtomicI32 = std::sync::atomic::AtomicI32::new(-1);

extern "C" fn on_signal(sig: libc::c_int) {
    let fd = PIPE_WRITE.load(Ordering::SeqCst);
    let byte = sig as u8;
    // SAFETY: `write` is async-signal-safe; `byte` is a valid 1-byte buffer.
    unsafe {
        libc::write(fd, (&byte as *const u8).cast(), 1);
    }
}

/// Remove the live scratch directories and end with `128 + signal` on
/// `SIGINT`, `SIGTERM` and `SIGHUP` (once per process). Returns `false` if
/// the handlers could not be installed.
pub fn install_signal_cleanup() -> bool {
    static ONCE: Once = Once::new();
    static OK: AtomicBool = AtomicBool::new(false);
    ONCE.call_once(|| {
        let mut fds = [0 as libc::c_int; 2];
        // SAFETY: `fds` is a valid array of two ints for pipe(2) to fill.
        if unsafe { libc::pipe(fds.as_mut_ptr()) } != 0 {
            return;
        }
        PIPE_WRITE.store(fds[1], Ordering::SeqCst);
        let read_fd = fds[0];
        let spawned = std::thread::Builder::new().name("signal-cleanup".into()).spawn(move || {
            let mut byte = 0u8;
            // SAFETY: reading one byte into a valid 1-byte buffer from our pipe.
            let n = unsafe { libc::read(read_fd, (&mut byte as *mut u8).cast(), 1) };
            if n == 1 {
                remove_live_dirs();
                write_stderr(&format!("error: interrupted by signal {byte}; the results are incomplete\n"));
                // SAFETY: ends the process at once, as the default action of the signal would.
                unsafe { libc::_exit(128 + i32::from(byte)) }
            }
        });
        if spawned.is_err() {
            return;
        }
        for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            // SAFETY: a zeroed sigaction is a valid initial value; the handler
            // only calls write(2) on a pipe (async-signal-safe).
            unsafe {
                let mut sa: libc::sigaction = std::mem::zeroed();
                sa.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
                sa.sa_flags = libc::SA_RESTART;
                libc::sigemptyset(&mut sa.sa_mask);
                libc::sigaction(sig, &sa, std::ptr::null_mut());
            }
        }
        OK.store(true, Ordering::SeqCst);
    });
    OK.load(Ordering::SeqCst)
}
