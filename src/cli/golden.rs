//! `brdfkit golden check|bless`.

use super::GoldenAction;
use crate::error::{Error, Result};
use crate::golden::CheckOptions;
use crate::kernel::lanes::Dispatch;
use std::path::PathBuf;

pub fn run(action: GoldenAction) -> Result<bool> {
    match action {
        GoldenAction::Check {
            names,
            dir,
            kernel,
            bounds,
        } => {
            let report = PathBuf::from("target/golden-failures");
            if Dispatch::choose(kernel).is_none() {
                return Err(Error::field(
                    "--kernel",
                    format!("'{}' is not available on this CPU", kernel.name()),
                ));
            }
            let opts = CheckOptions { kernel };
            let outcomes = crate::golden::check(&dir, &report, &names, &opts)?;
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
            if bounds {
                let measured = crate::golden::check_bounds(&dir, &names)?;
                for b in &measured {
                    println!(
                        "{:<34} {}  fast vs reference at 1/{}: max abs {:.3e} (stored {:.3e})  rel RMSE {:.3e} ({:.3e})  FLIP mean {:.4} ({:.4})",
                        b.name,
                        if b.passed { "pass" } else { "FAIL" },
                        crate::golden::BOUND_CHECK_SCALE,
                        b.measured.max_abs,
                        b.stored.max_abs,
                        b.measured.rel_rmse,
                        b.stored.rel_rmse,
                        b.measured.flip_mean,
                        b.stored.flip_mean
                    );
                    ok &= b.passed;
                }
                let failed = measured.iter().filter(|b| !b.passed).count();
                println!(
                    "golden bounds: {} entries, {} passed, {} failed",
                    measured.len(),
                    measured.len() - failed,
                    failed
                );
            }
            Ok(ok)
        }
        GoldenAction::Bless { names, dir, kernel } => {
            if Dispatch::choose(kernel).is_none() {
                return Err(Error::field(
                    "--kernel",
                    format!("'{}' is not available on this CPU", kernel.name()),
                ));
            }
            for p in crate::golden::bless(&dir, &names, &CheckOptions { kernel })? {
                println!("blessed {}", p.display());
            }
            Ok(true)
        }
    }
}
