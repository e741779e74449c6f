//! Why each library material has the representation it has: for every entry of
//! `brdfkit::library::LIBRARY`, the error of each candidate representation against the
//! entry's source model, as `brdfkit acquire` and `brdfkit fit-dbrdf` measure it.
//!
//! ```sh
//! cargo run --release --example library_fit
//! ```
//!
//! Rows per material: SH least squares (`lsq`), the same held to `f_r cos >= 0` (`nonneg`,
//! the library's projection) and SH with the non-negative window (`positive`) at the
//! material's band count (8 for a D-BRDF entry), and the D-BRDF fit. Columns as in `brdfkit acquire`'s table: relative L2 of `f_r cos`
//! and the ringing min/peak, both weighted by the view texels' projected solid angle
//! (the share of a rendered sphere's screen area), and the ringing flag
//! (`brdfkit::acquire::RINGING_THRESHOLD`). The rule the library follows: SH where the
//! least-squares fit is not flagged and its relative L2 is below 0.1 (the SH is then
//! rendered from the `nonneg` fit), else the D-BRDF fit.
//! The entry marked `(thesis)` keeps the thesis's own choice on purpose.

use brdfkit::acquire::fit::{fit_dbrdf, fit_lambert_dbrdf, FitOptions};
use brdfkit::acquire::{
    acquire, hemisphere_error, ringing_flagged, AcquireOptions, ErrorGrid, ErrorReport, Method,
};
use brdfkit::brdf::stand_ins::source_model;
use brdfkit::library::{Representation, LIBRARY, LIBRARY_METHOD, VIEW_GRID};

fn row(name: &str, repr: &str, r: &ErrorReport, chosen: bool) {
    println!(
        "| {name} | {repr} | {:.4} | {:.2}% | {} | {} |",
        r.rel_l2,
        100.0 * r.min_over_peak,
        if ringing_flagged(r) { "ringing" } else { "" },
        if chosen { "**library**" } else { "" }
    );
}

fn main() {
    let (nu, nv) = VIEW_GRID;
    let grid = ErrorGrid::default();
    println!("| material | representation | rel L2 | min/peak | flag | |");
    println!("|---|---|---|---|---|---|");
    for m in LIBRARY {
        let src = source_model(m.name).expect("every library entry has a source model");
        let bands = match m.representation {
            Representation::Sh { bands } => bands,
            Representation::Dbrdf => 8,
        };
        let lsq = Method::Lsq {
            lambda: brdfkit::acquire::DEFAULT_LAMBDA,
        };
        for (label, method) in [
            ("lsq", lsq),
            ("nonneg", LIBRARY_METHOD),
            ("positive", Method::Positive),
        ] {
            let ds = acquire(src.as_ref(), &AcquireOptions::new(bands, nu, nv, method))
                .expect("library acquisitions succeed");
            let r = hemisphere_error(src.as_ref(), &ds, nu, nv, grid);
            let chosen =
                m.representation == (Representation::Sh { bands }) && method == LIBRARY_METHOD;
            row(m.name, &format!("SH {bands} bands, {label}"), &r, chosen);
        }
        let fit = fit_dbrdf(src.as_ref(), &FitOptions::default()).expect("library fits succeed");
        row(m.name, "D-BRDF fit", &fit.report, false);
        let fit =
            fit_lambert_dbrdf(src.as_ref(), &FitOptions::default()).expect("library fits succeed");
        row(
            m.name,
            &format!(
                "Lambert (rd {:.3} {:.3} {:.3}) + D-BRDF fit",
                fit.brdf.rd.x, fit.brdf.rd.y, fit.brdf.rd.z
            ),
            &fit.report,
            m.representation == Representation::Dbrdf,
        );
    }
}
