//! `brdfkit acquire`, `brdfkit fit-dbrdf` and `brdfkit materials`.

use super::source::parse_source;
use super::{AcquireArgs, FitDbrdfArgs, MethodArg};
use crate::acquire::fit::{fit_dbrdf_with_progress, FitOptions};
use crate::acquire::{
    acquire_with_progress, hemisphere_error_with_progress, ringing_flagged, AcquireOptions,
    ErrorGrid, ErrorReport, Method, RINGING_THRESHOLD,
};
use crate::brdf::dbrdf::file::write_dbrdf;
use crate::error::{Error, Result};
use crate::library::{Representation, LIBRARY};
use crate::progress::Progress;
use crate::sh::write_sh_dataset;

fn row(bands: usize, method: &str, r: &ErrorReport) -> String {
    format!(
        "{bands:>5}  {method:<8} {:>9.4} {:>10.4} {:>9.2}% {:>9.2}% {:>9.2}%{}",
        r.rel_l2,
        r.rel_l2_unweighted,
        100.0 * r.min_over_peak,
        100.0 * r.worst_min_over_peak,
        100.0 * r.share_below_zero,
        if ringing_flagged(r) { "  ringing" } else { "" }
    )
}

pub fn run_acquire(a: AcquireArgs) -> Result<()> {
    if a.bands == 0 || a.bands > 10 {
        return Err(Error::field(
            "--bands",
            format!("{} is out of range (1 to 10)", a.bands),
        ));
    }
    if let Some(t) = a.band_threshold {
        if !(0.0..1.0).contains(&t) {
            return Err(Error::field(
                "--band-threshold",
                format!("{t} is out of range (0 <= fraction < 1)"),
            ));
        }
    }
    let method = match a.method {
        MethodArg::Zero => Method::Zero,
        MethodArg::Lsq => Method::Lsq {
            lambda: crate::acquire::DEFAULT_LAMBDA,
        },
        MethodArg::Even => Method::Even,
        MethodArg::Positive => Method::Positive,
        MethodArg::Nonneg => Method::NonNegative {
            lambda: crate::acquire::DEFAULT_LAMBDA,
        },
    };
    let method = match (method, a.lambda) {
        (Method::Lsq { .. } | Method::NonNegative { .. }, Some(l)) => {
            if !(l.is_finite() && l > 0.0) {
                return Err(Error::field("--lambda", format!("{l} must be > 0")));
            }
            match method {
                Method::Lsq { .. } => Method::Lsq { lambda: l },
                _ => Method::NonNegative { lambda: l },
            }
        }
        (m, _) => m,
    };
    let (nu, nv) = a.grid;
    crate::image_io::check_output(&a.output, &["exr"], "--output")?;
    let src = parse_source(&a.source)?;
    let grid = ErrorGrid::default();
    let methods: Vec<Method> = if a.no_table {
        vec![]
    } else {
        vec![
            Method::Zero,
            method_lsq(method),
            Method::Even,
            Method::Positive,
            Method::NonNegative {
                lambda: method_lsq(method).lambda(),
            },
        ]
    };
    if !methods.is_empty() {
        println!(
            "source {} ({}), view grid {nu}x{nv}, f_r cos(polar_i) over {}x{} light directions per view texel",
            a.source, src.name(), grid.n_mu, grid.n_az
        );
        println!(
            "rel L2 and min/peak weighted by view texels' projected solid angle (screen area); \
             unweighted worst cases for comparison; flag: min/peak < {:.0}%",
            100.0 * RINGING_THRESHOLD
        );
        println!("bands  method      rel L2 unweighted  min/peak     worst below zero");
    }
    // Every acquisition and every error report counts its view texels: the table's
    // (bands x methods, each acquired and measured) and the written data set's (measured
    // too without the table). The error report is the larger part: grid light directions
    // per view texel against the quadrature's.
    let acquisitions = a.bands * methods.len() + 1;
    let reports = a.bands * methods.len() + usize::from(a.no_table);
    let pb = Progress::bar(
        ((acquisitions + reports) * nu * nv) as u64,
        "acquire",
        "view texels",
    );
    let mut flagged = None;
    for bands in 1..=a.bands {
        for m in &methods {
            let ds =
                acquire_with_progress(src.as_ref(), &AcquireOptions::new(bands, nu, nv, *m), &pb)
                    .map_err(|e| Error::field("acquire", e.to_string()))?;
            let r = hemisphere_error_with_progress(src.as_ref(), &ds, nu, nv, grid, &pb);
            pb.suspend(|| println!("{}", row(bands, m.name(), &r)));
            if bands == a.bands && m.name() == method.name() && ringing_flagged(&r) {
                flagged = Some(r);
            }
        }
    }
    let ds = acquire_with_progress(
        src.as_ref(),
        &AcquireOptions::new(a.bands, nu, nv, method),
        &pb,
    );
    let mut ds = ds.map_err(|e| Error::field("acquire", e.to_string()))?;
    if a.no_table {
        let r = hemisphere_error_with_progress(src.as_ref(), &ds, nu, nv, grid, &pb);
        pb.suspend(|| println!("{}", row(a.bands, method.name(), &r)));
        if ringing_flagged(&r) {
            flagged = Some(r);
        }
    }
    pb.finish();
    if let Some(r) = flagged {
        println!(
            "warning: ringing: min/peak {:.1}% is below the {:.0}% threshold at {} bands ({}); \
             render this material from its D-BRDF fit instead (`brdfkit fit-dbrdf {}`), thesis 2.3.4",
            100.0 * r.min_over_peak,
            100.0 * RINGING_THRESHOLD,
            a.bands,
            method.name(),
            a.source
        );
    }
    if let Some(t) = a.band_threshold {
        ds.set_band_threshold(t)
            .map_err(|e| Error::field("--band-threshold", e.to_string()))?;
        eprintln!(
            "band threshold {t}: a renderer shades {} of {} bands",
            ds.effective_bands(),
            ds.bands()
        );
    }
    write_sh_dataset(&a.output, &ds).map_err(|e| Error::format(&a.output, e.to_string()))?;
    eprintln!(
        "wrote {} ({} bands, {nu}x{nv} view texels, method {}, f_r cos(polar_i))",
        a.output.display(),
        a.bands,
        method.name()
    );
    Ok(())
}

/// `lsq` with the chosen method's lambda (the default for methods without one).
fn method_lsq(chosen: Method) -> Method {
    Method::Lsq {
        lambda: chosen.lambda(),
    }
}

/// Relative L2 above which `brdfkit fit-dbrdf` says the fit does not hold its source (the
/// library's rule: a representation is used where its relative L2 is below 0.1,
/// `examples/library_fit.rs`). The file is still written: a bad fit is reported, not hidden.
const FIT_WARN_REL_L2: f64 = 0.1;

pub fn run_fit(a: FitDbrdfArgs) -> Result<()> {
    let (nu, nv) = a.grid;
    crate::image_io::check_output(&a.output, &["exr"], "--output")?;
    let src = parse_source(&a.source)?;
    let opts = FitOptions {
        nu,
        nv,
        ..FitOptions::default()
    };
    let pb = Progress::bar(0, "fit-dbrdf", "steps");
    let fit = fit_dbrdf_with_progress(src.as_ref(), &opts, &pb);
    pb.finish();
    let fit = fit.map_err(|e| Error::field("fit-dbrdf", format!("{}: {e}", a.source)))?;
    let d = &fit.brdf;
    println!(
        "source {} ({}): D-BRDF p(h) {nu}x{nv}, c = {:.4}, R_s = ({:.3}, {:.3}, {:.3}), p(h) refined by least squares: {}",
        a.source,
        src.name(),
        d.c,
        d.rs.x,
        d.rs.y,
        d.rs.z,
        if fit.refined { "yes" } else { "no (back-scatter kept)" }
    );
    let (vu, vv) = opts.view;
    println!(
        "error over {vu}x{vv} view texels (weighted by projected solid angle) x {}x{} light directions: \
         rel L2 {:.4} (unweighted {:.4}), min/peak {:.2}% (worst {:.2}%), below zero {:.2}%",
        opts.grid.n_mu,
        opts.grid.n_az,
        fit.report.rel_l2,
        fit.report.rel_l2_unweighted,
        100.0 * fit.report.min_over_peak,
        100.0 * fit.report.worst_min_over_peak,
        100.0 * fit.report.share_below_zero
    );
    if fit.report.rel_l2 > FIT_WARN_REL_L2 {
        println!(
            "warning: the D-BRDF does not hold this source: rel L2 {:.4} is above {FIT_WARN_REL_L2} \
             (its view dependence at a fixed half vector, c F(k.h) / D, is not the source's; \
             a Lambert base under the lobe, or SH (`brdfkit acquire {}`), may hold it)",
            fit.report.rel_l2, a.source
        );
    }
    let prov = format!(
        "brdfkit fit-dbrdf: source {}, p(h) {nu}x{nv}, rel L2 {:.4}",
        a.source, fit.report.rel_l2
    );
    write_dbrdf(&a.output, d, &prov).map_err(|e| Error::format(&a.output, e.to_string()))?;
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

pub fn run_materials() -> Result<()> {
    for m in LIBRARY {
        let kind = match m.representation {
            Representation::Sh { .. } => "sh",
            Representation::Dbrdf => "dbrdf",
        };
        println!("{:<22} {:<6} {}", m.name, kind, m.description);
    }
    Ok(())
}
