//! Reading the command line: clap parses and validates every argument (value enums, ranges,
//! `NUxNV` grids) before any work starts, and a rejected argument is reported the way every
//! other brdfkit error is: one line, `brdfkit: error: ...`, exit code 2.
//!
//! `--help` and `--version` print clap's own text and exit 0.

use super::Cli;
use clap::error::ErrorKind;
use clap::Parser;

/// The parsed command line of this process. Exits on `--help`/`--version` (code 0) and on a
/// rejected argument (code 2, one line on stderr naming the option and the problem).
pub fn parse_args() -> Cli {
    match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match e.kind() {
            ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => e.exit(),
            _ => {
                eprintln!("brdfkit: error: {}", one_line(&e.render().to_string()));
                std::process::exit(2);
            }
        },
    }
}

/// clap's multi-line report as one line: the message, then any "possible values" or tip
/// lines after a `; `, without the usage block and the "For more information" footer.
pub fn one_line(rendered: &str) -> String {
    let mut parts: Vec<String> = Vec::new();
    for line in rendered.lines() {
        let line = line.trim();
        if line.is_empty() || line.starts_with("For more information") {
            continue;
        }
        if line.starts_with("Usage:") {
            break;
        }
        let line = line.strip_prefix("error: ").unwrap_or(line);
        parts.push(line.to_string());
    }
    parts.join("; ")
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

    #[test]
    fn a_rejected_value_is_one_line_naming_option_and_choices() {
        let e = Cli::try_parse_from(["brdfkit", "render", "--cull", "sideways"]).unwrap_err();
        let line = one_line(&e.render().to_string());
        assert!(!line.contains('\n'), "{line}");
        assert!(
            line.contains("--cull") && line.contains("sideways"),
            "{line}"
        );
        assert!(line.contains("none") && line.contains("back"), "{line}");
        assert!(
            !line.contains("Usage") && !line.contains("For more"),
            "{line}"
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
