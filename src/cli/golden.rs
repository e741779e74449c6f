//! `brdfkit golden check|bless`.

use super::GoldenAction;
use crate::error::Result;
use std::path::PathBuf;

pub fn run(action: GoldenAction) -> Result<bool> {
    match action {
        GoldenAction::Check { dir } => {
            let report = PathBuf::from("target/golden-failures");
            let outcomes = crate::golden::check(&dir, &report)?;
            let mut ok = true;
            for o in &outcomes {
                println!(
                    "{:<24} {}  max abs error {:.3e}  {}",
                    o.name,
                    if o.passed { "pass" } else { "FAIL" },
                    o.max_abs_error,
                    o.message
                );
                ok &= o.passed;
            }
            if !ok {
                println!(
                    "expected | difference | actual images and JSON reports: {}",
                    report.display()
                );
            }
            Ok(ok)
        }
        GoldenAction::Bless { names, dir } => {
            for p in crate::golden::bless(&dir, &names)? {
                println!("blessed {}", p.display());
            }
            Ok(true)
        }
    }
}
