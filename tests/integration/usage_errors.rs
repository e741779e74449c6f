//! Arguments clap rejects (an unknown option, a value outside a value enum, a missing
//! required argument): clap's first error line in the brdfkit form, then the usage line of
//! the subcommand typed, exit 2, nothing written; not a paragraph of clap's lines joined.

use std::path::{Path, PathBuf};

use crate::cli_errors::{brdfkit, list};

/// Asserts a usage error (an argument clap rejects): exit 2, two stderr lines (clap's
/// error line, containing every `needle`, and the usage line of the subcommand `usage`
/// names, e.g. "brdfkit render"), neither a `; `-joined paragraph, and nothing written.
pub(crate) fn assert_usage_error(dir: &Path, args: &[&str], needles: &[&str], usage: &str) {
    let before: Vec<PathBuf> = list(dir);
    let r = brdfkit(dir, args);
    assert_eq!(
        r.code,
        Some(2),
        "{args:?}: exit code {:?} ({})",
        r.code,
        r.stderr
    );
    let lines: Vec<&str> = r.stderr.lines().collect();
    assert_eq!(
        lines.len(),
        2,
        "{args:?}: expected two lines, got {lines:?}"
    );
    assert!(lines[0].starts_with("brdfkit: error: "), "{}", lines[0]);
    for n in needles {
        assert!(lines[0].contains(n), "{args:?}: {:?} lacks {n:?}", lines[0]);
    }
    assert!(
        lines[1].starts_with(&format!("Usage: {usage} ")) && lines[1].contains("--help"),
        "{args:?}: {:?} is not the usage line of {usage}",
        lines[1]
    );
    for l in &lines {
        assert!(!l.contains("; ") && !l.contains("tip:"), "{args:?}: {l:?}");
    }
    assert_eq!(list(dir), before, "{args:?}: files were written");
}

#[test]
fn rejected_arguments_are_clap_s_line_and_the_usage_line() {
    // clap rejects these before any work starts; the report is clap's first error line in
    // the brdfkit form, then the usage line (no tips, no footer), exit 2, nothing written.
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    assert_usage_error(
        dir,
        &["render", "--cull", "sideways", "-o", "x.png"],
        &["--cull", "sideways", "none", "back"],
        "brdfkit render",
    );
    assert_usage_error(
        dir,
        &[
            "acquire",
            "teal-paint",
            "--method",
            "fourier",
            "-o",
            "x.exr",
        ],
        &["--method", "fourier", "zero", "lsq", "even"],
        "brdfkit acquire",
    );
    assert_usage_error(
        dir,
        &["acquire", "teal-paint", "--grid", "16x0", "-o", "x.exr"],
        &["--grid", "16x0", "NUxNV"],
        "brdfkit acquire",
    );
    assert_usage_error(
        dir,
        &["fit-dbrdf", "teal-paint", "--grid", "big", "-o", "y.exr"],
        &["--grid", "big"],
        "brdfkit fit-dbrdf",
    );
    assert_usage_error(
        dir,
        &["render", "--no-such-flag"],
        &["--no-such-flag"],
        "brdfkit render",
    );
    assert_usage_error(
        dir,
        &["acquire", "teal-paint"],
        &["required", "--output"],
        "brdfkit acquire",
    );
    assert_usage_error(
        dir,
        &["golden", "check", "--kernel", "fast"],
        &["--kernel", "fast", "portable"],
        "brdfkit golden check",
    );
}
