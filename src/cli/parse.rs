//! Reading the command line: clap parses and validates every argument (value enums, ranges,
//! `NUxNV` grids) before any work starts.
//!
//! Design rule: a rejected argument is reported as clap words it, in the brdfkit form:
//! clap's first error line (`brdfkit: error: ...`, with the values or arguments clap lists
//! under it and its "a similar argument exists" suggestion), then the usage line of the
//! command that was typed, exit code 2. clap's other tips, blank lines and footer are
//! left out. `--help` and `--version` print clap's own text and exit 0.

use super::Cli;
use clap::error::ErrorKind;
use clap::{CommandFactory, Parser};

/// The parsed command line of this process. Exits on `--help`/`--version` (code 0) and on a
/// rejected argument (code 2: the error line, then the usage line; [`usage_error`]).
pub fn parse_args() -> Cli {
    match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match e.kind() {
            ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => e.exit(),
            _ => {
                let args: Vec<String> = std::env::args().collect();
                let (line, usage) = usage_error(&e.render().to_string(), &args);
                eprintln!("brdfkit: error: {line}");
                eprintln!("{usage}");
                std::process::exit(2);
            }
        },
    }
}

/// clap's report of a rejected command line `args` (`argv`, program name first) as two
/// lines: the error (the first paragraph of `rendered` on one line, without clap's
/// `error: ` prefix, plus a "similar argument" tip when clap gives one) and the usage line
/// of the (sub)command typed, with where to read more.
pub fn usage_error(rendered: &str, args: &[String]) -> (String, String) {
    let mut paragraphs = rendered
        .split("\n\n")
        .map(|p| p.lines().map(str::trim).filter(|l| !l.is_empty()))
        .map(|lines| lines.collect::<Vec<_>>())
        .filter(|p| !p.is_empty());
    let mut line = String::new();
    if let Some(first) = paragraphs.next() {
        let head = first[0].strip_prefix("error: ").unwrap_or(first[0]);
        line.push_str(head);
        // What clap lists under its first line: required arguments (after a colon), the
        // possible values (in brackets).
        let rest = &first[1..];
        if !rest.is_empty() {
            line.push(' ');
            line.push_str(&rest.join(if head.ends_with(':') { ", " } else { " " }));
        }
    }
    for p in paragraphs {
        for l in p {
            if let Some(tip) = l.strip_prefix("tip: ").filter(|t| t.contains("similar")) {
                line.push_str(&format!(" ({tip})"));
            }
        }
    }
    (line, usage_line(args))
}

/// The usage line of the deepest subcommand that `args` names (`brdfkit golden check ...`
/// gives golden check's), then where the full help is.
fn usage_line(args: &[String]) -> String {
    let mut cmd = Cli::command();
    cmd.build();
    let mut current = &mut cmd;
    let mut names = vec!["brdfkit".to_string()];
    for a in args.iter().skip(1) {
        if current.find_subcommand(a).is_none() {
            break;
        }
        names.push(a.clone());
        current = current.find_subcommand_mut(a).expect("found above");
    }
    let usage = current.render_usage().to_string();
    let usage = usage.lines().next().unwrap_or_default().trim().to_string();
    format!("{usage} (more: {} --help)", names.join(" "))
}

/// clap value parser for `NUxNV` grids (each side 1 to 1024), e.g. `16x8`.
pub fn grid(s: &str) -> Result<(usize, usize), String> {
    let bad = || format!("{s:?} is not NUxNV (e.g. 16x8, each 1 to 1024)");
    let (a, b) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (a, b): (usize, usize) = (a.parse().map_err(|_| bad())?, b.parse().map_err(|_| bad())?);
    if a == 0 || b == 0 || a > 1024 || b > 1024 {
        return Err(bad());
    }
    Ok((a, b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    /// [`usage_error`] of `argv` as clap rejects it.
    fn report(argv: &[&str]) -> (String, String) {
        let e = Cli::try_parse_from(argv).unwrap_err();
        let args: Vec<String> = argv.iter().map(|a| a.to_string()).collect();
        usage_error(&e.render().to_string(), &args)
    }

    #[test]
    fn a_rejected_value_is_clap_s_line_then_the_usage_line() {
        let (line, usage) = report(&["brdfkit", "render", "--cull", "sideways"]);
        for s in [&line, &usage] {
            assert!(!s.contains('\n') && !s.contains("; "), "{s}");
        }
        assert!(
            line.contains("--cull") && line.contains("sideways"),
            "{line}"
        );
        assert!(line.contains("none") && line.contains("back"), "{line}");
        assert!(
            !line.starts_with("error:") && !line.contains("Usage"),
            "{line}"
        );
        assert!(usage.starts_with("Usage: brdfkit render "), "{usage}");
        assert!(usage.contains("brdfkit render --help"), "{usage}");
    }

    #[test]
    fn required_arguments_similar_names_and_nested_subcommands() {
        let (line, usage) = report(&["brdfkit", "acquire", "teal-paint"]);
        assert!(
            line.contains("required") && line.contains("--output"),
            "{line}"
        );
        assert!(usage.starts_with("Usage: brdfkit acquire "), "{usage}");
        let (line, _) = report(&["brdfkit", "render", "--widht", "3"]);
        assert!(
            line.contains("'--widht'") && line.contains("'--width'"),
            "{line}"
        );
        let (line, usage) = report(&["brdfkit", "golden", "check", "--nope"]);
        assert!(line.contains("--nope"), "{line}");
        assert!(usage.starts_with("Usage: brdfkit golden check "), "{usage}");
        assert!(
            usage.contains("(more: brdfkit golden check --help)"),
            "{usage}"
        );
    }

    #[test]
    fn grids() {
        assert_eq!(grid("16x8"), Ok((16, 8)));
        assert_eq!(grid("3X5"), Ok((3, 5)));
        for bad in ["16", "0x8", "16x0", "1025x1", "ax8", "16x8x2", ""] {
            assert!(grid(bad).is_err(), "{bad}");
        }
    }
}
