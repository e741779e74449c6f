//! A render killed while it writes its output: after SIGTERM or SIGINT nothing of the write
//! is left (no `.NAME.*.tmp` beside the output, the previous output untouched) and the exit
//! status is `128 + signal` (`brdfkit::image_io::interrupt`).
//!
//! The child runs with the test hook `BRDFKIT_TEST_PAUSE_BEFORE_RENAME` on its own
//! `Command` (never `set_var` here): its writer records the temporary file's path in a
//! marker file once the image is written to it, then waits before the rename. The test
//! signals it in that window. The seeded fault is a signal that cannot be handled
//! (SIGKILL, what an absent handler amounts to): the same check must then find the
//! temporary file, and the next write of that output must remove it (its name holds the
//! dead process's id).

use brdfkit::image_io::interrupt::PAUSE_ENV;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// What a signalled render left.
struct Outcome {
    status: ExitStatus,
    stderr: String,
    /// The temporary file the writer was paused on (its directory is gone now).
    tmp: PathBuf,
    /// Whether it still existed after the process ended.
    tmp_left: bool,
    /// Names in the output directory afterwards.
    listing: Vec<String>,
    /// The output file's bytes afterwards.
    output: Vec<u8>,
    /// The output directory (kept for a second write).
    dir: tempfile::TempDir,
}

const PREVIOUS: &[u8] = b"the previous output, which an interrupted write must keep";

fn wait_until(what: &str, deadline: Duration, mut done: impl FnMut() -> bool) {
    let start = Instant::now();
    while !done() {
        assert!(
            start.elapsed() < deadline,
            "{what}: not within {deadline:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Renders the default scene at 512x384 into `out.exr` (which holds [`PREVIOUS`]), waits
/// until its writer is paused with the temporary file written, sends `signal`.
fn render_and_signal(signal: libc::c_int) -> Outcome {
    let out_dir = tempfile::tempdir().unwrap();
    let side = tempfile::tempdir().unwrap();
    let output = out_dir.path().join("out.exr");
    std::fs::write(&output, PREVIOUS).unwrap();
    let marker = side.path().join("paused");
    let mut child = Command::new(env!("CARGO_BIN_EXE_brdfkit"))
        .args(["render", "--width", "512", "--height", "384", "-o"])
        .arg(&output)
        .current_dir(side.path())
        .env(PAUSE_ENV, &marker)
        .env("BRDFKIT_CACHE_DIR", side.path().join("cache"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_until("the writer pauses", Duration::from_secs(60), || {
        if let Some(s) = child.try_wait().unwrap() {
            panic!("brdfkit ended before its writer paused: {s}");
        }
        std::fs::metadata(&marker).is_ok_and(|m| m.len() > 0)
    });
    let tmp = PathBuf::from(std::fs::read_to_string(&marker).unwrap());
    assert_eq!(tmp.parent(), Some(out_dir.path()), "beside the output");
    let name = tmp.file_name().unwrap().to_string_lossy().into_owned();
    assert!(
        name.starts_with(&format!(".out.exr.{}-", child.id())) && name.ends_with(".tmp"),
        "{name}"
    );
    // The image is in the temporary file, the rename not yet done.
    assert!(std::fs::metadata(&tmp).unwrap().len() > 100_000);
    assert_eq!(std::fs::read(&output).unwrap(), PREVIOUS);
    // SAFETY: kill(2) on our own child's pid.
    assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, signal) }, 0);
    wait_until(
        "brdfkit ends after the signal",
        Duration::from_secs(20),
        || child.try_wait().unwrap().is_some(),
    );
    let out = child.wait_with_output().unwrap();
    Outcome {
        status: out.status,
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        tmp_left: tmp.exists(),
        tmp,
        listing: listing(out_dir.path()),
        output: std::fs::read(&output).unwrap_or_default(),
        dir: out_dir,
    }
}

fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The check: the interrupted write left only the previous output, whole, and the run
/// failed. `Err` names what was left.
fn nothing_left(o: &Outcome) -> Result<(), String> {
    if o.listing != ["out.exr"] {
        return Err(format!("left in the output directory: {:?}", o.listing));
    }
    if o.output != PREVIOUS {
        return Err(format!(
            "out.exr changed ({} bytes, not the previous output)",
            o.output.len()
        ));
    }
    if o.status.success() {
        return Err("exit status 0".into());
    }
    Ok(())
}

#[test]
fn sigterm_during_a_write_removes_the_temporary_file_and_exits_143() {
    let o = render_and_signal(libc::SIGTERM);
    nothing_left(&o).unwrap();
    assert!(!o.tmp_left);
    assert_eq!(o.status.code(), Some(143), "{}", o.stderr);
    assert!(
        o.stderr
            .contains("interrupted (SIGTERM): 1 temporary file(s) removed"),
        "{}",
        o.stderr
    );
}

#[test]
fn sigint_during_a_write_removes_the_temporary_file_and_exits_130() {
    let o = render_and_signal(libc::SIGINT);
    nothing_left(&o).unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", o.stderr);
}

#[test]
fn seeded_fault_an_unhandled_kill_leaves_the_temporary_file_and_the_check_says_so() {
    // SIGKILL: no handler runs, as with the handler off. The check must fail, naming the
    // temporary file.
    use std::os::unix::process::ExitStatusExt;
    let o = render_and_signal(libc::SIGKILL);
    assert_eq!(o.status.signal(), Some(libc::SIGKILL));
    assert!(o.tmp_left);
    let err = nothing_left(&o).expect_err("the check must see the leftover");
    let name = o.tmp.file_name().unwrap().to_string_lossy().into_owned();
    assert!(err.contains(&name), "{err}");

    // The leftover names its dead process: the next write of out.exr removes it.
    let out = Command::new(env!("CARGO_BIN_EXE_brdfkit"))
        .args(["render", "--width", "64", "--height", "48", "-o", "out.exr"])
        .current_dir(o.dir.path())
        .env("BRDFKIT_CACHE_DIR", o.dir.path().join("cache"))
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(listing(o.dir.path()), ["out.exr"]);
}
