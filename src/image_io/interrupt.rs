//! Temporary files removed on SIGINT/SIGTERM: the registry of the live temporary files of
//! [`super::replace_via_temp`] (`LiveTemp`) and the handler that deletes them before the
//! process ends ([`remove_temporary_files_on_signals`]).
//!
//! Design rule: a temporary file is created *while the registry is locked* and registered
//! before the lock is released; the handler takes the lock, deletes every registered file
//! and ends the process (exit status `128 + signal`: 130 for SIGINT, 143 for SIGTERM)
//! without releasing it. So no temporary file can appear between the handler's deletion
//! and the exit, and a render killed during its write leaves neither a `.NAME.*.tmp` nor a
//! half-written `NAME` (the rename never happened; a finished rename leaves a whole file,
//! and deleting the already-renamed temporary name then fails harmlessly). SIGKILL cannot
//! be caught: a process killed that way leaves its temporary file, which the next write of
//! the same output removes (its name holds the dead process's id; see
//! [`super::replace_via_temp`]).
//!
//! The handler runs on its own thread ([`signal_hook::iterator::Signals`]), not in signal
//! context, so it may lock, delete and print. Only the binary installs it (`main.rs`);
//! library users keep their own signal dispositions.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// Paths of the temporary files that exist now (created, not yet renamed or removed).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Test hook (integration tests only): when this variable names a file, every
/// [`super::replace_via_temp`] writes the temporary file's path into it after the contents
/// are written and then waits [`PAUSE`] before the rename, so a test can signal the
/// process while a temporary file exists (tests/integration/interrupt.rs).
pub const PAUSE_ENV: &str = "BRDFKIT_TEST_PAUSE_BEFORE_RENAME";

/// How long the [`PAUSE_ENV`] hook waits before the rename.
pub const PAUSE: std::time::Duration = std::time::Duration::from_secs(30);

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    // A panic while holding the lock leaves the list itself consistent (push/retain).
    LIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// A temporary file that the signal handler deletes while it exists. Dropping it removes
/// the file, then forgets it; [`LiveTemp::persist`] renames it, then forgets it.
pub(crate) struct LiveTemp {
    file: Option<tempfile::NamedTempFile>,
    path: PathBuf,
}

impl LiveTemp {
    /// Creates a temporary file in `dir` with `builder`, registered before any signal
    /// handler can run again (see the module doc).
    pub(crate) fn create(builder: &tempfile::Builder, dir: &Path) -> io::Result<LiveTemp> {
        let mut live = live();
        let file = builder.tempfile_in(dir)?;
        let path = file.path().to_path_buf();
        live.push(path.clone());
        Ok(LiveTemp {
            file: Some(file),
            path,
        })
    }

    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// Renames the file to `target` (replacing it); on failure the file is removed.
    pub(crate) fn persist(mut self, target: &Path) -> io::Result<()> {
        let file = self
            .file
            .take()
            .expect("a LiveTemp holds its file until persisted");
        file.persist(target).map(drop).map_err(|e| e.error)
    }
}

impl Drop for LiveTemp {
    fn drop(&mut self) {
        // Removed (NamedTempFile's drop) before it is forgotten, so a signal in between
        // still finds it.
        drop(self.file.take());
        let mut live = live();
        if let Some(i) = live.iter().position(|p| *p == self.path) {
            live.swap_remove(i);
        }
    }
}

/// The [`PAUSE_ENV`] hook: records `tmp` in the named file and waits [`PAUSE`].
pub(crate) fn pause_for_tests(tmp: &Path) {
    if let Some(marker) = std::env::var_os(PAUSE_ENV) {
        let _ = std::fs::write(marker, tmp.as_os_str().as_encoded_bytes());
        std::thread::sleep(PAUSE);
    }
}

/// Installs the SIGINT/SIGTERM handler (module doc): on either signal, every live
/// temporary file is deleted, one line says so on stderr, and the process exits with
/// `128 + signal`. Call once, from the binary's `main`. Fails only if the signal thread
/// or the handler cannot be set up.
pub fn remove_temporary_files_on_signals() -> io::Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM])?;
    std::thread::Builder::new()
        .name("brdfkit-signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                // Held until the process ends: no temporary file is created after this.
                let live = live();
                let removed = live
                    .iter()
                    .filter(|p| std::fs::remove_file(p).is_ok())
                    .count();
                let name = if signal == SIGINT {
                    "SIGINT"
                } else {
                    "SIGTERM"
                };
                eprintln!(
                    "\nbrdfkit: interrupted ({name}){}",
                    match removed {
                        0 => String::new(),
                        n => format!(": {n} temporary file(s) removed"),
                    }
                );
                std::process::exit(128 + signal);
            }
        })?;
    Ok(())
}
