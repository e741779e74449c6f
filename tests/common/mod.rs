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
        let out = cmd
            .output()
            .expect("run brdfkit under timeout (coreutils) and prlimit (util-linux)");
        let run = Run {
            code: out.status.code(),
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
            elapsed: start.elapsed(),
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
