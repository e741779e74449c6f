//! Shared by the tests that drive the `brdfkit` binary: one way to run it.
//!
//! Every run is killed after a time limit (so a hang fails the test instead of stalling CI:
//! `timeout -s KILL` exits 137, which [`Cli::run`] turns into a panic naming the arguments),
//! and its light-set cache is a directory of the test's own (`BRDFKIT_CACHE_DIR`), never the
//! user's `~/.cache/brdfkit`.
#![allow(dead_code)] // each test file uses its own subset

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// What one run of the binary gave.
pub struct Run {
    /// The exit code; `None` when a signal ended it.
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
    /// Wall time of the run.
    pub elapsed: Duration,
    /// CPU time (user + system) of the run and every process it waited for, from
    /// `wait4(2)`: unlike the wall time, it does not grow when the machine is busy.
    pub cpu: Duration,
}

impl Run {
    /// True for exit code 0.
    pub fn success(&self) -> bool {
        self.code == Some(0)
    }
}

/// A `brdfkit` invocation being set up: working directory, cache, limits, environment.
pub struct Cli {
    cwd: PathBuf,
    cache: PathBuf,
    timeout_s: u32,
    address_space: Option<u64>,
    env: Vec<(String, String)>,
}

/// `brdfkit` run in `cwd`, with its cache in `cwd/cache` and a 120 s limit.
pub fn brdfkit(cwd: &Path) -> Cli {
    Cli {
        cwd: cwd.to_path_buf(),
        cache: cwd.join("cache"),
        timeout_s: 120,
        address_space: None,
        env: Vec::new(),
    }
}

impl Cli {
    /// The light-set cache directory (`BRDFKIT_CACHE_DIR`).
    pub fn cache(mut self, dir: &Path) -> Cli {
        self.cache = dir.to_path_buf();
        self
    }

    /// Seconds before the run is killed.
    pub fn timeout(mut self, seconds: u32) -> Cli {
        self.timeout_s = seconds;
        self
    }

    /// Runs under `prlimit --as=BYTES` (util-linux): allocation past it fails.
    pub fn address_space(mut self, bytes: u64) -> Cli {
        self.address_space = Some(bytes);
        self
    }

    /// One more environment variable for the child (never set in the test's own process).
    pub fn env(mut self, key: &str, value: impl AsRef<std::ffi::OsStr>) -> Cli {
        self.env.push((
            key.to_string(),
            value.as_ref().to_string_lossy().into_owned(),
        ));
        self
    }

    /// Runs `brdfkit args`. Panics if the run had to be killed at the time limit.
    pub fn run(&self, args: &[&str]) -> Run {
        let mut cmd = Command::new("timeout");
        cmd.args(["-s", "KILL", &self.timeout_s.to_string()]);
        if let Some(bytes) = self.address_space {
            cmd.arg("prlimit").arg(format!("--as={bytes}")).arg("--");
        }
        cmd.arg(env!("CARGO_BIN_EXE_brdfkit"))
            .args(args)
            .current_dir(&self.cwd)
            .env("BRDFKIT_CACHE_DIR", &self.cache);
        for (k, v) in &self.env {
            cmd.env(k, v);
        }
        let start = Instant::now();
        let (status, cpu, stdout, stderr) = spawn_and_wait(&mut cmd)
            .expect("run brdfkit under timeout (coreutils) and prlimit (util-linux)");
        let run = Run {
            code: status.code(),
            stdout: String::from_utf8_lossy(&stdout).into_owned(),
            stderr: String::from_utf8_lossy(&stderr).into_owned(),
            elapsed: start.elapsed(),
            cpu,
        };
        // `timeout` exits 128 + 9 when it had to kill the child.
        assert_ne!(
            run.code,
            Some(137),
            "{args:?}: killed after {} s (hung)",
            self.timeout_s
        );
        run
    }
}

/// Runs `cmd` to its end with stdout and stderr collected: (exit status, CPU time of the
/// child and its waited-for descendants, stdout, stderr). Reaps the child with `wait4(2)`
/// for its resource usage, so the `Child` is never waited for by std.
fn spawn_and_wait(
    cmd: &mut Command,
) -> std::io::Result<(std::process::ExitStatus, Duration, Vec<u8>, Vec<u8>)> {
    use std::io::Read;
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()?;
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            r.read_to_end(&mut v).map(|_| v)
        })
    };
    let out = drain(Box::new(child.stdout.take().expect("piped")));
    let err = drain(Box::new(child.stderr.take().expect("piped")));
    let pid = child.id() as libc::pid_t;
    let mut status: libc::c_int = 0;
    // SAFETY: an all-zero rusage is a valid value of the plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: waits for our own child, writing into the two locals above.
        let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
        if r == pid {
            break;
        }
        let e = std::io::Error::last_os_error();
        if e.kind() != std::io::ErrorKind::Interrupted {
            return Err(e);
        }
    }
    let tv = |t: libc::timeval| Duration::new(t.tv_sec as u64, t.tv_usec as u32 * 1000);
    let cpu = tv(usage.ru_utime) + tv(usage.ru_stime);
    let stdout = out.join().expect("stdout reader")?;
    let stderr = err.join().expect("stderr reader")?;
    Ok((
        std::process::ExitStatus::from_raw(status),
        cpu,
        stdout,
        stderr,
    ))
}

/// Runs `brdfkit args` in `cwd` (the defaults of [`brdfkit`]), returning (success, stderr).
pub fn run_in(cwd: &Path, args: &[&str]) -> (bool, String) {
    let r = brdfkit(cwd).run(args);
    (r.success(), r.stderr)
}

/// One run of the binary in `dir` with a 120 s limit: (exit code, -1 for a signal; stdout;
/// stderr).
pub fn run_120s(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let r = brdfkit(dir).timeout(120).run(args);
    (r.code.unwrap_or(-1), r.stdout, r.stderr)
}

/// The shipped city probe's absolute path, as a string for command lines and scene files.
pub fn city_probe() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/probes/city.exr")
        .display()
        .to_string()
}

/// The shipped city probe box-downsampled 4x to 128 x 64 (each coarse texel's power is its
/// block's, [`brdfkit::env::probe::resample::downsample_box`]), written as an EXR into `dir`; returns
/// its absolute path. For tests of what a method does with a probe (turning it, caching
/// it), not of its accuracy: every preparation is 16x cheaper than on the 512 x 256 file.
pub fn small_city_probe(dir: &Path) -> String {
    let opts = brdfkit::env::LoadOptions::default();
    let (probe, _) = brdfkit::env::probe::load_probe(Path::new(&city_probe()), &opts).unwrap();
    let small = brdfkit::env::probe::resample::downsample_box(&probe, 4);
    let mut img = brdfkit::image_io::Image::new(small.width() as u32, small.height() as u32);
    for (p, t) in img.pixels.iter_mut().zip(small.texels()) {
        *p = glam::Vec3::from_array(*t);
    }
    let path = dir.join("city-128x64.exr");
    brdfkit::image_io::write_exr(&path, &img).unwrap();
    path.display().to_string()
}

/// Says, past libtest's capture (which takes only `print!`/`eprint!`, so a plain `cargo
/// test` shows the line), that `test` did not run and why; under `CI=true` it panics
/// instead: in CI a test that cannot run is a failure, not a pass.
pub fn cannot_run(test: &str, why: &str) {
    if std::env::var_os("CI").is_some_and(|v| v == "true") {
        panic!("{test} cannot run under CI=true: {why}");
    }
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "NOT RUN: {test}: {why}");
}

/// The kernel paths this CPU runs ([`brdfkit::lanes::KernelPath::available`]), after
/// printing past libtest's capture each path `test` therefore skips, by name (the AVX-512
/// path runs only on CPUs that have it, and a CI host may not). Never fails: no CPU has
/// every path.
pub fn kernel_paths(test: &str) -> Vec<brdfkit::lanes::KernelPath> {
    use brdfkit::lanes::KernelPath;
    use std::io::Write;
    // Said once per test name, however often a test asks.
    static SAID: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
    let mut said = SAID.lock().unwrap_or_else(|e| e.into_inner());
    if said.iter().any(|t| t == test) {
        return KernelPath::available();
    }
    said.push(test.to_string());
    for (path, needs) in KernelPath::unavailable() {
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED kernel path {}: {test}: this CPU lacks {needs}",
            path.name()
        );
    }
    KernelPath::available()
}
