//! `brdfkit compare A B`: exit 0 on pass, 1 on fail, 2 on unusable input. A failure stays
//! exit 1 whatever happens to the diff image: one that cannot be written is a warning line.
//! The report (text, or `--json`) is over the covered pixels ([`crate::compare::coverage`]);
//! a non-finite pixel is reported first and fails, and no measure is printed beside it.
//!
//! (Past 400 lines because it is one command: its arguments, the choice of bounds, and the
//! text and JSON forms of the same report, which must say the same things.)

use crate::compare::{
    self, coverage, AlphaMode, Loaded, Metrics, Pixels, RadiometricBounds, Thresholds,
};
use crate::error::Result;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    /// The reference image (the oracle's render).
    pub expected: PathBuf,
    /// The image under test (e.g. a GPU build's render).
    pub actual: PathBuf,
    /// File to take the bounds from (with --entry): golden/gpu-bounds.toml (the bounds `golden check --device gpu` applies: the file's own FLIP and radiometric bounds for the entries it lists, the manifest's FLIP bounds beside it for the rest) or a golden manifest such as golden/manifest.toml (the entry's `flip`, else its tolerance's; no radiometric bounds).
    #[arg(long, visible_aliases = ["manifest", "bounds-from"], requires = "entry")]
    pub bounds: Option<PathBuf>,
    /// Golden entry whose bounds apply (with --bounds); the flags below still override.
    #[arg(long, requires = "bounds")]
    pub entry: Option<String>,
    /// Largest passing FLIP mean over the covered pixels (default 0.01, or the entry's).
    #[arg(long)]
    pub max_flip_mean: Option<f32>,
    /// Percentile for the second FLIP bound, in (0, 1) (default 0.99, or the entry's).
    #[arg(long)]
    pub percentile: Option<f32>,
    /// Largest passing FLIP value at --percentile over the covered pixels (default 0.1, or the entry's).
    #[arg(long)]
    pub max_flip_at_percentile: Option<f32>,
    /// Largest passing error of a channel's mean, |sum actual / sum expected - 1| over the pixels lit in both images (default: not checked, or the entry's). 0.001 fails a build 0.1% too bright.
    #[arg(long)]
    pub max_mean_error: Option<f32>,
    /// Largest passing relative RMSE, sqrt(sum |a - e|^2 / sum |e|^2) over the pixels lit in both images (default: not checked, or the entry's).
    #[arg(long)]
    pub max_rel_rmse: Option<f32>,
    /// Largest passing per-pixel relative error |a - e| / max(|e|, 1% of the brightest |e|) at --percentile, over the pixels lit in both images (default: not checked, or the entry's).
    #[arg(long)]
    pub max_rel_error: Option<f32>,
    /// Largest passing share of the covered pixels that are black in one image only (a silhouette one rasterizer covers and the other does not; left out of the three measures above) (default: not checked, or the entry's).
    #[arg(long)]
    pub max_coverage_mismatch: Option<f32>,
    /// Where to write expected | heatmap | actual on failure (default: ACTUAL's name with .diff.png). A diff that cannot be written is a warning; the exit status stays 1.
    #[arg(long)]
    pub diff: Option<PathBuf>,
    /// The alpha channel of RGBA images: ignored (RGBA compares with RGB on colour), or compared as a fourth channel (an image without alpha counts as opaque). Alpha never decides which pixels are covered.
    #[arg(long, value_enum, default_value = "ignore")]
    pub alpha: AlphaMode,
    /// Print the error histogram even when the comparison passes.
    #[arg(long)]
    pub histogram: bool,
    /// Print one JSON object on stdout instead of the report: verdict, pixel counts, every measure (null where not measured), every bound with its value, limit and outcome, and the failed bounds' names. The exit status is the same.
    #[arg(long)]
    pub json: bool,
}

/// Where the bounds came from, for the report.
struct Source {
    /// "defaults", or the file and entry.
    text: String,
    file: Option<PathBuf>,
    entry: Option<String>,
}

/// The thresholds: the flags, else the bounds file's entry, else the defaults.
fn thresholds(a: &CompareArgs) -> Result<(Thresholds, Source)> {
    let (base, source) = match (&a.bounds, &a.entry) {
        (Some(file), Some(name)) => {
            let r = crate::golden::bounds_from_file(file, name)?;
            let text = if r.from == *file {
                format!("{} entry '{name}'", file.display())
            } else {
                format!(
                    "{} entry '{name}' (not in {})",
                    r.from.display(),
                    file.display()
                )
            };
            (
                r.thresholds,
                Source {
                    text,
                    file: Some(r.from),
                    entry: Some(name.clone()),
                },
            )
        }
        _ => (
            Thresholds::DEFAULT,
            Source {
                text: "defaults".into(),
                file: None,
                entry: None,
            },
        ),
    };
    let th = Thresholds {
        flip_mean: a.max_flip_mean.unwrap_or(base.flip_mean),
        percentile: a.percentile.unwrap_or(base.percentile),
        flip_at_percentile: a.max_flip_at_percentile.unwrap_or(base.flip_at_percentile),
        radiometric: RadiometricBounds {
            mean_error: a.max_mean_error.or(base.radiometric.mean_error),
            rel_rmse: a.max_rel_rmse.or(base.radiometric.rel_rmse),
            rel_error_at_percentile: a.max_rel_error.or(base.radiometric.rel_error_at_percentile),
            coverage_mismatch: a
                .max_coverage_mismatch
                .or(base.radiometric.coverage_mismatch),
        },
    };
    for (flag, v) in [
        ("--max-mean-error", th.radiometric.mean_error),
        ("--max-rel-rmse", th.radiometric.rel_rmse),
        ("--max-rel-error", th.radiometric.rel_error_at_percentile),
        ("--max-coverage-mismatch", th.radiometric.coverage_mismatch),
    ] {
        if v.is_some_and(|v| !(v >= 0.0 && v.is_finite())) {
            return Err(crate::error::Error::field(
                flag,
                format!("{} must be finite and >= 0", v.unwrap_or_default()),
            ));
        }
    }
    if !(th.percentile > 0.0 && th.percentile < 1.0) {
        return Err(crate::error::Error::field(
            "--percentile",
            format!("{} must be in (0, 1)", th.percentile),
        ));
    }
    Ok((th, source))
}

pub fn run(a: CompareArgs) -> Result<bool> {
    let (th, source) = thresholds(&a)?;
    // An explicit --diff with a wrong extension is a usage error, refused before the
    // comparison. Where it cannot be written is found only when a failure writes it, and
    // is a warning then: the comparison's verdict does not depend on the diff image.
    if let Some(p) = &a.diff {
        if !p.extension().is_some_and(|x| x.eq_ignore_ascii_case("png")) {
            return Err(crate::error::Error::format(
                p,
                "--diff: wrong output format: the file name must end in .png",
            ));
        }
    }
    let expected = compare::load(&a.expected)?;
    let actual = compare::load(&a.actual)?;
    let (m, flip) = compare::compare_with(&expected, &actual, &th, a.alpha, Pixels::Covered)?;
    let pass = m.passes(&th);
    if !a.json && source.file.is_some() {
        println!(
            "thresholds of {}: FLIP mean <= {}, {} <= {}{}",
            source.text,
            th.flip_mean,
            compare::percentile_label(th.percentile),
            th.flip_at_percentile,
            radiometric_text(&th)
        );
    }
    if !a.json {
        print_report(&a, &expected, &actual, &m, &th, pass);
    }
    let mut diff_written = None;
    if !pass {
        let out = a.diff.clone().unwrap_or_else(|| {
            let stem = a
                .actual
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            a.actual.with_file_name(format!("{stem}.diff.png"))
        });
        match compare::write_report_image(&out, &expected, &actual, &flip) {
            Ok(()) => {
                if !a.json {
                    println!(
                        "  expected | FLIP heatmap | actual written to {}",
                        out.display()
                    );
                }
                diff_written = Some(out);
            }
            Err(e) => eprintln!("warning: diff image not written: {e}"),
        }
    }
    if a.json {
        let doc = json_report(&a, &m, &th, &source, pass, diff_written.as_deref());
        println!(
            "{}",
            serde_json::to_string_pretty(&doc).expect("serialisable")
        );
    }
    Ok(pass)
}

/// The radiometric bounds `th` sets, for the thresholds line (empty when none).
fn radiometric_text(th: &Thresholds) -> String {
    let r = &th.radiometric;
    [
        ("mean error", r.mean_error),
        ("relative RMSE", r.rel_rmse),
        (
            &*format!(
                "relative error {}",
                compare::percentile_label(th.percentile)
            ),
            r.rel_error_at_percentile,
        ),
        ("coverage mismatch", r.coverage_mismatch),
    ]
    .iter()
    .filter_map(|(name, v)| v.map(|v| format!(", {name} <= {v}")))
    .collect()
}

/// The text report: header, non-finite pixels first, pixel counts, measures, verdict.
fn print_report(
    a: &CompareArgs,
    expected: &Loaded,
    actual: &Loaded,
    m: &Metrics,
    th: &Thresholds,
    pass: bool,
) {
    println!(
        "{} vs {} ({}x{} {} {} vs {}, alpha {})",
        a.expected.display(),
        a.actual.display(),
        m.width,
        m.height,
        expected.layout.kind,
        expected.layout.channels,
        actual.layout.channels,
        match a.alpha {
            AlphaMode::Ignore => "ignored",
            AlphaMode::Compare => "compared",
        }
    );
    if m.non_finite > 0 {
        println!(
            "  non-finite      {} pixel{} with a NaN or infinite value, at {}{}",
            m.non_finite,
            if m.non_finite == 1 { "" } else { "s" },
            m.non_finite_at
                .iter()
                .map(|[x, y]| format!("({x}, {y})"))
                .collect::<Vec<_>>()
                .join(", "),
            if m.non_finite > m.non_finite_at.len() {
                ", ..."
            } else {
                ""
            }
        );
    }
    println!(
        "  covered pixels  {} of {} ({}), {} measured",
        m.covered,
        m.width as u64 * m.height as u64,
        coverage::COVERAGE_RULE,
        m.measured
    );
    if m.non_finite > 0 {
        println!("  measures        not computed: a non-finite pixel has no error to measure");
    } else {
        let p = compare::percentile_label(th.percentile);
        println!("  max abs error   {:.6e}", m.max_abs);
        println!("  max rel error   {:.6e}", m.max_rel);
        println!("  RMSE            {:.6e}", m.rmse);
        if m.psnr.is_finite() {
            println!("  PSNR            {:.2} dB", m.psnr);
        } else {
            println!("  PSNR            inf (identical)");
        }
        println!(
            "  FLIP mean       {:.6}  (max {})",
            m.flip_mean, th.flip_mean
        );
        println!(
            "  FLIP {:<10} {:.6}  (max {})",
            p, m.flip_at_percentile, th.flip_at_percentile
        );
        println!(
            "  FLIP p95/p99/p99.9  {:.6} / {:.6} / {:.6}",
            m.flip_p95, m.flip_p99, m.flip_p999
        );
        println!(
            "  differing pixels {} of {} measured",
            m.differing_pixels, m.measured
        );
        let r = &m.radiometric;
        let limit = |v: Option<f32>| v.map_or(String::new(), |v| format!("  (max {v})"));
        println!(
            "  mean ratio      R {:.6} G {:.6} B {:.6}, mean error {:.3e}{}",
            r.mean_ratio[0],
            r.mean_ratio[1],
            r.mean_ratio[2],
            r.mean_error,
            limit(th.radiometric.mean_error)
        );
        println!(
            "  relative RMSE   {:.3e}{}",
            r.rel_rmse,
            limit(th.radiometric.rel_rmse)
        );
        println!(
            "  relative error  {} {:.3e}{}{} (over {} pixels lit in both; dark ones against 1% of the peak)",
            p,
            r.rel_error_at_percentile,
            limit(th.radiometric.rel_error_at_percentile),
            if p == "p99" {
                String::new()
            } else {
                format!(", p99 {:.3e}", r.rel_error_p99)
            },
            r.pixels
        );
        println!(
            "  coverage mismatch {} pixels ({:.3e} of measured){}",
            m.coverage_mismatch,
            m.coverage_mismatch_share(),
            limit(th.radiometric.coverage_mismatch)
        );
    }
    if let Some(al) = &m.alpha {
        println!(
            "  alpha: max abs error {:.6e}, differing pixels {}, FLIP mean {:.6}, {} {:.6}{}",
            al.max_abs,
            al.differing_pixels,
            al.flip_mean,
            compare::percentile_label(th.percentile),
            al.flip_at_percentile,
            if al.non_finite > 0 {
                format!(", {} non-finite", al.non_finite)
            } else {
                String::new()
            }
        );
    }
    if m.non_finite == 0 && (!pass || a.histogram) {
        println!("  error histogram (largest channel difference per measured pixel):");
        let total = m.measured.max(1) as f64;
        let mut lower = 0.0f32;
        for &(ub, count) in &m.histogram {
            let label = if ub == 0.0 {
                "= 0".to_string()
            } else if ub.is_infinite() {
                format!("> {lower:.0e}")
            } else {
                format!("<= {ub:.0e}")
            };
            let bar = "#".repeat((50.0 * count as f64 / total).ceil() as usize);
            println!("    {label:>9} {count:>9} {bar}");
            lower = ub;
        }
    }
    if pass {
        println!("PASS ({})", m.pixels.label());
    } else {
        let failed = m.failures(th);
        let flip_failed = failed.iter().any(|b| !b.measure.ends_with("non_finite"));
        println!(
            "FAIL: {}{}",
            failed
                .iter()
                .map(|b| b.failure_text())
                .collect::<Vec<_>>()
                .join(", "),
            if flip_failed {
                format!(" ({})", m.pixels.label())
            } else {
                String::new()
            }
        );
    }
}

/// The `--json` document.
fn json_report(
    a: &CompareArgs,
    m: &Metrics,
    th: &Thresholds,
    source: &Source,
    pass: bool,
    diff: Option<&Path>,
) -> serde_json::Value {
    // f32 values go through their shortest decimal form (serde_json widens an f32 to the
    // f64 of its bits: 0.01 would read 0.009999999776482582).
    let d = compare::decimal;
    let finite = m.non_finite == 0;
    let measures = finite.then(|| {
        serde_json::json!({
            "max_abs": d(m.max_abs),
            "max_rel": d(m.max_rel),
            "rmse": m.rmse,
            "psnr_db": m.psnr.is_finite().then_some(m.psnr),
            "flip_mean": d(m.flip_mean),
            "flip_p95": d(m.flip_p95),
            "flip_p99": d(m.flip_p99),
            "flip_p999": d(m.flip_p999),
            "flip_at_percentile": d(m.flip_at_percentile),
            "differing_pixels": m.differing_pixels,
            "mean_ratio": m.radiometric.mean_ratio,
            "mean_error": m.radiometric.mean_error,
            "rel_rmse": m.radiometric.rel_rmse,
            "rel_error_at_percentile": m.radiometric.rel_error_at_percentile,
            "rel_error_p99": m.radiometric.rel_error_p99,
            "radiometric_pixels": m.radiometric.pixels,
            "coverage_mismatch": m.coverage_mismatch,
            "histogram": m.histogram.iter().map(|&(ub, n)| serde_json::json!({
                "upper": d(ub),
                "count": n,
            })).collect::<Vec<_>>(),
        })
    });
    let alpha = m.alpha.as_ref().map(|al| {
        serde_json::json!({
            "max_abs": d(al.max_abs),
            "differing_pixels": al.differing_pixels,
            "flip_mean": d(al.flip_mean),
            "flip_at_percentile": d(al.flip_at_percentile),
            "non_finite": al.non_finite,
        })
    });
    let bounds = m.bounds(th);
    let failed: Vec<&str> = bounds
        .iter()
        .filter(|b| b.passed == Some(false))
        .map(|b| b.measure)
        .collect();
    serde_json::json!({
        "expected": a.expected,
        "actual": a.actual,
        "verdict": if pass { "pass" } else { "fail" },
        "width": m.width,
        "height": m.height,
        "pixels": {
            "over": m.pixels,
            "rule": coverage::COVERAGE_RULE,
            "total": m.width as u64 * m.height as u64,
            "covered": m.covered,
            "measured": m.measured,
            "non_finite": m.non_finite,
            "non_finite_at": m.non_finite_at,
        },
        "measures": measures,
        "alpha": alpha,
        "thresholds": {
            "flip_mean": d(th.flip_mean),
            "percentile": d(th.percentile),
            "flip_at_percentile": d(th.flip_at_percentile),
            "mean_error": th.radiometric.mean_error.map(d),
            "rel_rmse": th.radiometric.rel_rmse.map(d),
            "rel_error_at_percentile": th.radiometric.rel_error_at_percentile.map(d),
            "coverage_mismatch": th.radiometric.coverage_mismatch.map(d),
            "from": source.file,
            "entry": source.entry,
        },
        "bounds": bounds,
        "failed": failed,
        "diff": diff,
    })
}
