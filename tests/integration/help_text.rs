//! The `--help` text of the binary and of every subcommand (nested ones included, found by
//! walking clap's command tree, so a new subcommand is checked without being listed here):
//! clap prints the doc comments of the arguments, so rustdoc syntax written there (links
//! such as [`crate::env::transfer`], paths, Markdown links) would reach the user. And
//! `view --help` lists only what `view` takes.

use clap::CommandFactory;
use std::path::Path;

use crate::common;

/// Every command path of the CLI: `[]` (the binary), `["render"]`, `["golden", "check"]`,
/// ... (clap's own `help` subcommand left out).
fn command_paths() -> Vec<Vec<String>> {
    fn walk(cmd: &clap::Command, prefix: Vec<String>, out: &mut Vec<Vec<String>>) {
        out.push(prefix.clone());
        for sub in cmd.get_subcommands().filter(|s| s.get_name() != "help") {
            let mut p = prefix.clone();
            p.push(sub.get_name().to_string());
            walk(sub, p, out);
        }
    }
    let mut out = Vec::new();
    walk(&brdfkit::cli::Cli::command(), Vec::new(), &mut out);
    out
}

/// `brdfkit PATH... FLAG`'s standard output; the run must succeed.
fn help(dir: &Path, path: &[String], flag: &str) -> String {
    let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
    args.push(flag);
    let r = common::brdfkit(dir).timeout(60).run(&args);
    assert_eq!(r.code, Some(0), "{args:?}: {}", r.stderr);
    assert!(!r.stdout.trim().is_empty(), "{args:?}: no help text");
    r.stdout
}

/// The rustdoc (and Markdown) syntax found in `text`, one entry per offending line.
fn rustdoc_syntax(text: &str) -> Vec<String> {
    const MARKERS: [&str; 6] = ["[`", "`]", "crate::", "super::", "](", "[crate"];
    text.lines()
        .filter(|l| MARKERS.iter().any(|m| l.contains(m)))
        .map(|l| l.trim().to_string())
        .collect()
}

#[test]
fn no_help_text_contains_rustdoc_syntax() {
    let d = tempfile::tempdir().unwrap();
    let paths = command_paths();
    // The tree walk found the nested subcommands (so it did not stop at the top).
    for nested in [
        &["golden", "check"][..],
        &["golden", "bless"],
        &["cache", "clean"],
    ] {
        assert!(
            paths.iter().any(|p| p == nested),
            "{nested:?} not among {paths:?}"
        );
    }
    let mut found = Vec::new();
    for path in &paths {
        // -h (the short help) and --help (the long one, with every value's description).
        for flag in ["-h", "--help"] {
            for line in rustdoc_syntax(&help(d.path(), path, flag)) {
                found.push(format!("brdfkit {} {flag}: {line}", path.join(" ")));
            }
        }
    }
    assert!(
        found.is_empty(),
        "rustdoc syntax in help text:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_check_finds_rustdoc_syntax() {
    for bad in [
        "  transfer table ([`crate::env::transfer`])",
        "see [the format](docs/scene-format.md)",
        "  --x  the super::lights_report module",
    ] {
        assert_eq!(rustdoc_syntax(bad).len(), 1, "{bad}");
    }
    assert!(rustdoc_syntax("values in [0, 1]; `[f32; 8]` lanes; `brdfkit materials`").is_empty());
}

/// The long options (and -o) a help text lists.
fn options(help: &str) -> Vec<String> {
    help.lines()
        .map(str::trim_start)
        .filter(|l| l.starts_with('-'))
        .flat_map(|l| {
            l.split([',', ' '])
                .filter(|w| w.starts_with('-'))
                .map(String::from)
        })
        .collect()
}

#[test]
fn view_help_lists_only_what_view_takes() {
    let d = tempfile::tempdir().unwrap();
    let render_only = [
        "-o",
        "--output",
        "--turntable",
        "--turntable-env",
        "--shard",
        "--assemble",
        "--fps",
        "--reference",
        "--device",
    ];
    let view = options(&help(d.path(), &["view".into()], "--help"));
    let render = options(&help(d.path(), &["render".into()], "--help"));
    for o in render_only {
        assert!(
            !view.contains(&o.to_string()),
            "view --help lists {o}: {view:?}"
        );
        assert!(
            render.contains(&o.to_string()),
            "render --help lacks {o}: {render:?}"
        );
    }
    // What both take is listed by both.
    for o in [
        "--env",
        "--material",
        "--aov",
        "--width",
        "--no-cache",
        "--stats",
    ] {
        assert!(view.contains(&o.to_string()), "view --help lacks {o}");
        assert!(render.contains(&o.to_string()), "render --help lacks {o}");
    }
    // And view's own options.
    for o in ["--script", "--screenshot", "--write-scene"] {
        assert!(view.contains(&o.to_string()), "view --help lacks {o}");
    }
    // `view` refuses render's options as usage errors (exit 2), before opening a window.
    for args in [
        &["view", "-o", "x.png"][..],
        &["view", "--turntable", "4"],
        &["view", "--reference"],
        &["view", "--fps", "10"],
    ] {
        let r = common::brdfkit(d.path()).timeout(60).run(args);
        assert_eq!(r.code, Some(2), "{args:?}: {}", r.stderr);
        assert!(
            r.stderr.starts_with("brdfkit: error: unexpected argument"),
            "{args:?}: {}",
            r.stderr
        );
    }
}
