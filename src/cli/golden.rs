//! `brdfkit golden check|list|bless`.

use super::{GoldenAction, GoldenDevice};
use crate::error::{Error, Result};
use crate::golden::CheckOptions;
use crate::lanes::Dispatch;
use crate::shard::Shard;
use std::path::PathBuf;

pub fn run(action: GoldenAction) -> Result<bool> {
    match action {
        GoldenAction::Check {
            names,
            dir,
            kernel,
            bounds,
            device,
            gpu_fault,
            shard,
            json,
            merge,
        } => {
            if !merge.is_empty() {
                let (outcomes, bounds_failed, passed) =
                    crate::golden::shard::merge_check_reports(&merge)?;
                print_outcomes(&outcomes);
                for b in &bounds_failed {
                    println!("{b:<34} FAIL  fast vs reference bound");
                }
                println!("golden check: {} shard reports merged", merge.len());
                return Ok(passed);
            }
            if device == GoldenDevice::Gpu {
                if shard.is_some() || json.is_some() {
                    return Err(Error::field(
                        "--shard/--json",
                        "shard the CPU check only: not with --device gpu",
                    ));
                }
                if bounds {
                    return Err(Error::field(
                        "--bounds",
                        "measures the CPU's fast path: not with --device gpu",
                    ));
                }
                return check_gpu(&names, &dir, gpu_fault.as_deref());
            }
            if gpu_fault.is_some() {
                return Err(Error::field("--gpu-fault", "needs --device gpu"));
            }
            let report = PathBuf::from("target/golden-failures");
            if Dispatch::choose(kernel).is_none() {
                return Err(Error::field(
                    "--kernel",
                    format!("'{}' is not available on this CPU", kernel.name()),
                ));
            }
            let opts = CheckOptions { kernel };
            let stamp = crate::golden::shard::stamp(
                &dir,
                &names,
                match &shard {
                    Some(s) => Shard::parse(s)?,
                    None => Shard::ALL,
                },
                crate::golden::shard::CHECK_REPORT_FORMAT,
            )?;
            if let Some(j) = &json {
                crate::image_io::check_output(j, &["json"], "--json")?;
            }
            // A shard with no entry checks nothing (an empty list would mean every entry).
            let outcomes = if stamp.entries.is_empty() {
                Vec::new()
            } else {
                crate::golden::check(&dir, &report, &stamp.entries, &opts)?
            };
            let mut ok = outcomes.iter().all(|o| o.passed);
            print_outcomes(&outcomes);
            if !ok {
                println!(
                    "expected | difference | actual images and JSON reports: {}",
                    report.display()
                );
            }
            let mut bounds_failed = Vec::new();
            if bounds && !stamp.entries.is_empty() {
                let measured = crate::golden::check_bounds(&dir, &stamp.entries)?;
                bounds_failed.extend(
                    measured
                        .iter()
                        .filter(|b| !b.passed)
                        .map(|b| b.name.clone()),
                );
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
            if let Some(j) = &json {
                crate::golden::shard::write_json(
                    j,
                    &crate::golden::shard::CheckReport {
                        stamp,
                        outcomes,
                        bounds_failed,
                        passed: ok,
                    },
                )?;
                println!("wrote {}", j.display());
            }
            Ok(ok)
        }
        GoldenAction::List { dir, json } => {
            let entries = crate::golden::list(&dir)?;
            if json {
                // Serialised directly (not through serde_json::Value, which widens an f32 to
                // the f64 of its bits), so the bounds read as written: 0.004, not 0.00400000019.
                #[derive(serde::Serialize)]
                struct Doc<'a> {
                    dir: &'a std::path::Path,
                    entries: &'a [crate::golden::Listed],
                }
                let doc = Doc {
                    dir: &dir,
                    entries: &entries,
                };
                println!(
                    "{}",
                    serde_json::to_string_pretty(&doc).expect("serialisable")
                );
            } else {
                for e in &entries {
                    println!("{}", e.line());
                }
            }
            Ok(true)
        }
        GoldenAction::Bless {
            names,
            dir,
            kernel,
            shard,
            records,
            merge,
        } => {
            if !merge.is_empty() {
                let merged = crate::golden::shard::merge_bless_records(&dir, &merge)?;
                println!(
                    "merged {} records from {} shards into {}",
                    merged.len(),
                    merge.len(),
                    crate::golden::manifest_path(&dir).display()
                );
                return Ok(true);
            }
            if Dispatch::choose(kernel).is_none() {
                return Err(Error::field(
                    "--kernel",
                    format!("'{}' is not available on this CPU", kernel.name()),
                ));
            }
            let opts = CheckOptions { kernel };
            let written = match (&shard, &records) {
                (Some(s), Some(r)) => {
                    crate::image_io::check_output(r, &["toml"], "--records")?;
                    let w = crate::golden::shard::bless_shard(
                        &dir,
                        &names,
                        Shard::parse(s)?,
                        &opts,
                        r,
                    )?;
                    println!("wrote {}", r.display());
                    w
                }
                _ => crate::golden::bless(&dir, &names, &opts)?,
            };
            for p in written {
                println!("blessed {}", p.display());
            }
            Ok(true)
        }
    }
}

/// One line per entry's outcome, then the summary line of `golden check`.
fn print_outcomes(outcomes: &[crate::golden::Outcome]) {
    for o in outcomes {
        println!(
            "{:<34} {}  max abs error {:.3e}  {}",
            o.name,
            if o.passed { "pass" } else { "FAIL" },
            o.max_abs_error,
            o.message
        );
    }
    let failed = outcomes.iter().filter(|o| !o.passed).count();
    println!(
        "golden check: {} entries, {} passed, {} failed",
        outcomes.len(),
        outcomes.len() - failed,
        failed
    );
}

/// `golden check --device gpu`: one line per entry (pass, FAIL or skip with the reason) and
/// a summary; `Ok(false)` when an entry fails.
#[cfg(feature = "gpu")]
fn check_gpu(names: &[String], dir: &std::path::Path, fault: Option<&str>) -> Result<bool> {
    let faults = match fault {
        Some(f) => crate::gpu::Faults::parse(f)?,
        None => crate::gpu::Faults::NONE,
    };
    let gpu = crate::gpu::Gpu::new()?;
    let report = PathBuf::from("target/golden-failures/gpu");
    let outcomes = crate::golden::check_gpu(&gpu, dir, &report, names, faults)?;
    for o in &outcomes {
        match o.passed {
            None => println!("{:<40} skip  {}", o.name, o.message),
            Some(p) => println!(
                "{:<40} {}  max abs {:.3e}  {}",
                o.name,
                if p { "pass" } else { "FAIL" },
                o.max_abs,
                o.message
            ),
        }
    }
    let failed = outcomes.iter().filter(|o| o.passed == Some(false)).count();
    let passed = outcomes.iter().filter(|o| o.passed == Some(true)).count();
    println!(
        "golden check --device gpu ({}, {:?}{}): {} entries, {passed} passed, {failed} failed, {} skipped",
        gpu.info.name,
        gpu.info.backend,
        fault.map(|f| format!(", seeded fault {f}")).unwrap_or_default(),
        outcomes.len(),
        outcomes.len() - passed - failed
    );
    if failed > 0 {
        println!("expected | FLIP | actual images: {}", report.display());
    }
    Ok(failed == 0)
}

/// `golden check --device gpu` without the `gpu` feature: a one-line error.
#[cfg(not(feature = "gpu"))]
fn check_gpu(_: &[String], _: &std::path::Path, _: Option<&str>) -> Result<bool> {
    Err(Error::Message(
        "--device gpu: this brdfkit was built without the `gpu` feature (cargo build --features gpu)"
            .into(),
    ))
}
