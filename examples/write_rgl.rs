//! Writes brdfkit's analytic RGL test materials (`brdfkit::brdf::rgl::samples`) as
//! `.bsdf` tensor files, for the Mitsuba comparison (scripts/peer/render_rgl_peer.py) and
//! for trying `--material FILE.bsdf` by hand.
//!
//! Usage: `cargo run --release --example write_rgl -- [--tiny] OUT_DIR [NAME...]` (default:
//! all of `blinn-rgb`, `aniso-rgb`, `blinn-spectral`); writes `OUT_DIR/NAME.bsdf`.
//! `--tiny` writes the same materials in the smallest grids the reader accepts (about a
//! kilobyte each: the seeds of the `rgl_file` fuzz target, fuzz/README.md).

use brdfkit::brdf::rgl::samples::{sample, tiny_sample, SAMPLE_NAMES};
use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let tiny = args.first().is_some_and(|a| a == "--tiny");
    if tiny {
        args.remove(0);
    }
    let Some(out) = args.first().map(PathBuf::from) else {
        eprintln!(
            "usage: write_rgl [--tiny] OUT_DIR [NAME...] (names: {})",
            SAMPLE_NAMES.join(", ")
        );
        return ExitCode::from(2);
    };
    let names: Vec<&str> = if args.len() > 1 {
        args[1..].iter().map(String::as_str).collect()
    } else {
        SAMPLE_NAMES.to_vec()
    };
    if let Err(e) = std::fs::create_dir_all(&out) {
        eprintln!("{}: cannot create directory: {e}", out.display());
        return ExitCode::FAILURE;
    }
    for name in names {
        let made = if tiny {
            tiny_sample(name)
        } else {
            sample(name)
        };
        let Some(s) = made else {
            eprintln!(
                "{name:?}: not a test material (names: {})",
                SAMPLE_NAMES.join(", ")
            );
            return ExitCode::from(2);
        };
        let path = out.join(format!("{name}.bsdf"));
        if let Err(e) = std::fs::write(&path, &s.bytes) {
            eprintln!("{}: cannot write: {e}", path.display());
            return ExitCode::FAILURE;
        }
        println!("{} ({} bytes)", path.display(), s.bytes.len());
    }
    ExitCode::SUCCESS
}
