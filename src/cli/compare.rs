//! `brdfkit compare A B`: exit 0 on pass, 1 on fail, 2 on unusable input. A failure stays
//! exit 1 whatever happens to the diff image: one that cannot be written is a warning line.

use crate::compare::{self, AlphaMode, Thresholds};
use crate::error::Result;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    /// The reference image (the oracle's render).
    pub expected: PathBuf,
    /// The image under test (e.g. a GPU build's render).
    pub actual: PathBuf,
    /// Golden manifest to take the FLIP thresholds from (with --entry).
    #[arg(long, requires = "entry")]
    pub manifest: Option<PathBuf>,
    /// Manifest entry whose thresholds apply (its `flip`, else its tolerance's); flags below still override.
    #[arg(long, requires = "manifest")]
    pub entry: Option<String>,
    /// Largest passing FLIP mean (default 0.01, or the entry's).
    #[arg(long)]
    pub max_flip_mean: Option<f32>,
    /// Percentile for the second FLIP bound, in (0, 1) (default 0.99, or the entry's).
    #[arg(long)]
    pub percentile: Option<f32>,
    /// Largest passing FLIP value at --percentile (default 0.1, or the entry's).
    #[arg(long)]
    pub max_flip_at_percentile: Option<f32>,
    /// Where to write expected | heatmap | actual on failure (default: ACTUAL's name with .diff.png). A diff that cannot be written is a warning; the exit status stays 1.
    #[arg(long)]
    pub diff: Option<PathBuf>,
    /// The alpha channel of RGBA images: ignored (RGBA compares with RGB on colour), or compared as a fourth channel (an image without alpha counts as opaque).
    #[arg(long, value_enum, default_value = "ignore")]
    pub alpha: AlphaMode,
    /// Print the error histogram even when the comparison passes.
    #[arg(long)]
    pub histogram: bool,
}

pub fn run(a: CompareArgs) -> Result<bool> {
    // Thresholds: the flags, else the manifest entry's (its `flip`, else its tolerance's),
    // else the defaults.
    let base = match (&a.manifest, &a.entry) {
        (Some(m), Some(name)) => {
            let manifest = crate::golden::load_manifest_file(m)?;
            let entry = crate::golden::Entry::find(&manifest, m, name)?;
            let th = entry
                .thresholds()
                .expect("tolerance checked by the manifest parser");
            println!(
                "thresholds of {} entry '{}': FLIP mean <= {}, p{} <= {}",
                m.display(),
                name,
                th.flip_mean,
                th.percentile * 100.0,
                th.flip_at_percentile
            );
            th
        }
        _ => Thresholds::DEFAULT,
    };
    let th = Thresholds {
        flip_mean: a.max_flip_mean.unwrap_or(base.flip_mean),
        percentile: a.percentile.unwrap_or(base.percentile),
        flip_at_percentile: a.max_flip_at_percentile.unwrap_or(base.flip_at_percentile),
    };
    if !(th.percentile > 0.0 && th.percentile < 1.0) {
        return Err(crate::error::Error::field(
            "--percentile",
            format!("{} must be in (0, 1)", th.percentile),
        ));
    }
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
    let (m, flip) = compare::compare_with_alpha(&expected, &actual, &th, a.alpha)?;
    let pass = m.passes(&th);
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
    println!("  max abs error   {:.6e}", m.max_abs);
    println!("  max rel error   {:.6e}", m.max_rel);
    println!("  RMSE            {:.6e}", m.rmse);
    println!("  PSNR            {:.2} dB", m.psnr);
    println!(
        "  FLIP mean       {:.6}  (max {})",
        m.flip_mean, th.flip_mean
    );
    println!(
        "  FLIP p{:<5}     {:.6}  (max {})",
        th.percentile * 100.0,
        m.flip_at_percentile,
        th.flip_at_percentile
    );
    println!(
        "  FLIP p95/p99/p99.9  {:.6} / {:.6} / {:.6}",
        m.flip_p95, m.flip_p99, m.flip_p999
    );
    println!(
        "  differing pixels {} of {}{}",
        m.differing_pixels,
        m.width * m.height,
        if m.non_finite > 0 {
            format!(", {} non-finite", m.non_finite)
        } else {
            String::new()
        }
    );
    if let Some(al) = &m.alpha {
        println!(
            "  alpha: max abs error {:.6e}, differing pixels {}, FLIP mean {:.6}, p{} {:.6}{}",
            al.max_abs,
            al.differing_pixels,
            al.flip_mean,
            th.percentile * 100.0,
            al.flip_at_percentile,
            if al.non_finite > 0 {
                format!(", {} non-finite", al.non_finite)
            } else {
                String::new()
            }
        );
    }
    if !pass || a.histogram {
        println!("  error histogram (largest channel difference per pixel):");
        let total = (m.width * m.height).max(1) as f64;
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
        println!("PASS");
    } else {
        let out = a.diff.clone().unwrap_or_else(|| {
            let stem = a
                .actual
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            a.actual.with_file_name(format!("{stem}.diff.png"))
        });
        match compare::write_report_image(&out, &expected, &actual, &flip) {
            Ok(()) => println!(
                "FAIL: expected | FLIP heatmap | actual written to {}",
                out.display()
            ),
            Err(e) => {
                println!("FAIL");
                eprintln!("warning: diff image not written: {e}");
            }
        }
    }
    Ok(pass)
}
