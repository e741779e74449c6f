//! Atomic file replacement: the one "write to a temporary name, then rename" of the crate
//! ([`replace_via_temp`]), used by every writer (images, data sets, light sets, CSV,
//! manifests, caches), with one naming and one sync policy.

use super::interrupt::{pause_for_tests, LiveTemp};
use std::path::Path;

/// Runs `write` on a new temporary file beside `path`, syncs it to disk and renames it to
/// `path`; on any failure (or a panic in `write`) the temporary file is removed and nothing
/// appears under `path`. The one implementation of "write to a temporary name, then
/// rename" for every writer in the crate, whatever its error type: `io_err` turns a failure
/// to create, sync or rename the temporary file into that type.
///
/// The temporary file is created by [`tempfile::Builder`] in `path`'s directory (so the
/// rename stays on one filesystem) as `.<name>.<pid>-<random>.tmp`, exclusively (`O_EXCL`): two
/// threads or processes writing the same `path` never share a temporary file, and the
/// last rename wins. Unix permissions are those of [`std::fs::File::create`] (0666 less
/// the umask). `write` may reopen the path (`File::create` truncates the same file).
///
/// Interruption: the temporary file is registered while it exists
/// (`interrupt::LiveTemp`), and the binary's SIGINT/SIGTERM handler
/// ([`super::interrupt::remove_temporary_files_on_signals`]) deletes it before exiting, so
/// a killed write leaves neither the temporary file nor a partial `path`.
///
/// A process killed where no handler runs (SIGKILL, a crash) leaves its temporary file;
/// the next write of the same `path` removes every `.<name>.<pid>-*.tmp` whose process no
/// longer exists on this machine (`kill(pid, 0)` fails with `ESRCH`), so such leftovers
/// do not pile up. Files of live processes, and of this one, are kept.
///
/// Sync policy (every writer): the file's data is synced (`fsync`) before the rename, so
/// after a crash `path` holds the old or the new contents, never a part. The directory is
/// not synced: after a power loss the rename itself may be lost (the old file remains).
pub fn replace_via_temp<E>(
    path: &Path,
    write: impl FnOnce(&Path) -> std::result::Result<(), E>,
    io_err: impl Fn(std::io::Error) -> E,
) -> std::result::Result<(), E> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    remove_stale_temporaries(dir, &name);
    let prefix = format!(".{name}.{}-", std::process::id());
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    // The user gave `path`: an error names it (through `io_err`), never the temporary file.
    let io_err = |e: std::io::Error| io_err(without_temporary_path(e));
    // Dropped (and so removed) on every early return below.
    let tmp = LiveTemp::create(&builder, dir).map_err(io_err)?;
    write(tmp.path())?;
    pause_for_tests(tmp.path());
    std::fs::OpenOptions::new()
        .write(true)
        .open(tmp.path())
        .and_then(|f| f.sync_all())
        .map_err(io_err)?;
    tmp.persist(path).map_err(io_err)?;
    Ok(())
}

/// `e` without the temporary file's name: `tempfile` appends ` at path "DIR/.NAME.tmp"` to
/// the errors it returns (creating the file), which would show the user a name they never
/// gave; the kind and the system's message ("Permission denied (os error 13)") are kept.
/// Errors without that suffix are returned unchanged. Used for every temporary file
/// (this module's, and the writability probe of `check_output`).
pub(crate) fn without_temporary_path(e: std::io::Error) -> std::io::Error {
    if e.raw_os_error().is_some() {
        return e;
    }
    let text = e.to_string();
    match text.rfind(" at path ") {
        Some(i) => std::io::Error::new(e.kind(), text[..i].to_string()),
        None => e,
    }
}

/// Removes `.<name>.<pid>-*.tmp` files in `dir` left by processes that no longer exist
/// (see [`replace_via_temp`]). Errors are ignored: a leftover only costs space.
fn remove_stale_temporaries(dir: &Path, name: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let prefix = format!(".{name}.");
    let own = std::process::id();
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(rest) = file_name
            .to_str()
            .and_then(|f| f.strip_prefix(&prefix))
            .and_then(|f| f.strip_suffix(".tmp"))
        else {
            continue;
        };
        let Some(pid) = rest
            .split_once('-')
            .and_then(|(p, _)| p.parse::<u32>().ok())
        else {
            continue;
        };
        if pid != own && !process_exists(pid) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Whether a process `pid` exists on this machine (`kill(pid, 0)`: only `ESRCH` means no).
#[cfg(unix)]
fn process_exists(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return true;
    };
    // SAFETY: signal 0 performs only the existence and permission checks.
    let r = unsafe { libc::kill(pid, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
}

#[cfg(not(unix))]
fn process_exists(_pid: u32) -> bool {
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn listing(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn interleaved_writers_of_one_path_never_share_a_temporary_file() {
        // A second write of the same path starts and finishes while the first is between
        // its write and its rename (what two threads of one process can do). With a
        // name made of the PID alone both would use one temporary file: the inner rename
        // would take the outer's file away and the outer rename would fail.
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.txt");
        replace_via_temp(
            &target,
            |outer| {
                std::fs::write(outer, "outer")?;
                replace_via_temp(
                    &target,
                    |inner| {
                        assert_ne!(inner, outer);
                        std::fs::write(inner, "inner")
                    },
                    |e| e,
                )?;
                assert_eq!(std::fs::read_to_string(&target)?, "inner");
                assert_eq!(std::fs::read_to_string(outer)?, "outer");
                Ok(())
            },
            |e| e,
        )
        .unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "outer");
        assert_eq!(listing(dir.path()), ["out.txt"]);
    }

    #[test]
    fn concurrent_threads_each_write_a_whole_file() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("t.bin");
        let contents: Vec<Vec<u8>> = (0..8u8).map(|t| vec![t; 4096 + t as usize]).collect();
        std::thread::scope(|s| {
            for c in &contents {
                let target = &target;
                s.spawn(move || {
                    for _ in 0..20 {
                        replace_via_temp(target, |tmp| std::fs::write(tmp, c), |e| e).unwrap();
                    }
                });
            }
        });
        let got = std::fs::read(&target).unwrap();
        assert!(
            contents.contains(&got),
            "a mixed file of {} bytes",
            got.len()
        );
        assert_eq!(listing(dir.path()), ["t.bin"]);
    }

    #[cfg(unix)]
    #[test]
    fn leftovers_of_dead_processes_are_removed_by_the_next_write_and_no_others() {
        let dir = tempfile::tempdir().unwrap();
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        let own = std::process::id();
        let names = [
            format!(".x.exr.{dead}-AbC123.tmp"), // dead: removed
            format!(".x.exr.{own}-AbC123.tmp"),  // this process: kept
            ".x.exr.1-AbC123.tmp".to_string(),   // init, alive: kept
            ".x.exr.AbC123.tmp".to_string(),     // no process id: kept
            format!(".y.exr.{dead}-AbC123.tmp"), // another target: kept
        ];
        for n in &names {
            std::fs::write(dir.path().join(n), "left").unwrap();
        }
        let target = dir.path().join("x.exr");
        replace_via_temp(&target, |tmp| std::fs::write(tmp, "new"), |e| e).unwrap();
        let mut expected: Vec<String> = names[1..].to_vec();
        expected.push("x.exr".into());
        expected.sort();
        assert_eq!(listing(dir.path()), expected);
    }

    #[test]
    fn an_error_creating_the_temporary_file_does_not_name_it() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("no/such/dir/x.exr");
        let e = replace_via_temp(&target, |tmp| std::fs::write(tmp, "x"), |e| e).unwrap_err();
        let text = e.to_string();
        assert_eq!(e.kind(), std::io::ErrorKind::NotFound, "{text}");
        assert!(!text.contains(".tmp") && !text.contains("x.exr"), "{text}");
        assert!(!text.is_empty());
        // The writability probe of check_output gets the same treatment.
        let e = tempfile::NamedTempFile::new_in(dir.path().join("gone")).unwrap_err();
        assert!(
            e.to_string().contains(".tmp"),
            "tempfile names its file: {e}"
        );
        let text = without_temporary_path(e).to_string();
        assert!(!text.contains(".tmp") && !text.is_empty(), "{text}");
    }

    #[test]
    fn a_failed_write_leaves_nothing_and_permissions_follow_file_create() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("x.exr");
        let r = replace_via_temp(
            &target,
            |tmp| {
                std::fs::write(tmp, "partial")?;
                Err(std::io::Error::other("seeded failure"))
            },
            |e| e,
        );
        assert!(r.is_err());
        assert!(listing(dir.path()).is_empty(), "{:?}", listing(dir.path()));
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            replace_via_temp(&target, |tmp| std::fs::write(tmp, "x"), |e| e).unwrap();
            let plain = dir.path().join("plain");
            std::fs::File::create(&plain).unwrap();
            let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode(&target), mode(&plain));
        }
    }
}
