//! Shared by the tests that drive the `brdfkit` binary.

use std::path::Path;
use std::process::Command;

/// Runs `brdfkit args` in `cwd` (killed after 120 s; the light-set cache in `cwd/cache`,
/// never the user's), returning (success, stderr).
pub fn run_in(cwd: &Path, args: &[&str]) -> (bool, String) {
    let out = Command::new("timeout")
        .args(["-s", "KILL", "120", env!("CARGO_BIN_EXE_brdfkit")])
        .args(args)
        .current_dir(cwd)
        .env("BRDFKIT_CACHE_DIR", cwd.join("cache"))
        .output()
        .expect("run brdfkit under timeout (coreutils)");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
