//! `brdfkit golden check|bless`.

use super::GoldenAction;
use crate::error::Result;
use std::path::PathBuf;

pub fn run(action: GoldenAction) -> Result<bool> {
    match action {
        GoldenAction::Check { names, dir } => {
            let report = PathBuf::from("target/golden-failures");
            let outcomes = crate::golden::check(&dir, &report, &names)?;
            let mut ok = true;
            for o in &outcomes {
                println!(
                    "{:<34} {}  max abs error {:.3e}  {}",
                    o.name,
                    if o.passed { "pass" } else { "FAIL" },
                    o.max_abs_error,
                    o.message
                );
                ok &= o.passed;
            }
            let failed = outcomes.iter().filter(|o| !o.passed).count();
            println!(
                "golden check: {} entries, {} passed, {} failed",
                outcomes.len(),
                outcomes.len() - failed,
                failed
            );
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
