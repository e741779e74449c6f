//! What the measured formats cost where a user sees it: the converged render of a measured
//! table (and of the D-BRDF fitted to it) against the converged render of what it was
//! made from, under each shipped probe.
//!
//! ```sh
//! cargo run --release --example measured_error -- [SIZE] [PROBE...] [ROW...]
//! ```
//!
//! PROBE: `city`, `studio`, `sky` (default all three). `--keep DIR` leaves the files it
//! writes (`NAME.bsdf`, `NAME.binary`, and `NAME-fit.exr`, each D-BRDF fit) in DIR, to
//! look at with `brdfkit render --material`.
//!
//! No measured file can be downloaded in the project's environment, so every table here is
//! written from an analytic BRDF and read back through its own reader:
//!
//! - `rgl:NAME`: the RGL test materials (`brdfkit::brdf::rgl::samples`) read as files,
//!   against their analytic sources (for `blinn-spectral`, the Blinn-Phong whose diffuse
//!   colour is its spectrum in linear sRGB): the reader's interpolation error;
//! - `merl:NAME`: a MERL table written from an analytic source (`MerlBrdf::tabulate`, the
//!   `.binary` layout, read back from disk) against that source: the table's own error;
//! - `merl-fit:NAME`: the D-BRDF fitted to that MERL table (`fit_dbrdf` with the defaults of
//!   `brdfkit fit-dbrdf`: 64 x 32 half-vector table) against the table itself: what the
//!   thesis's treatment of specular measured data costs. The fit's projected-solid-angle
//!   weighted relative L2 (`rel L2` of `brdfkit fit-dbrdf`) is printed beside it.
//!
//! MERL sources: `gold` (Ashikhmin-Shirley, `nu = nv = 200`, `rs = 0.9/0.7/0.3`, no
//! diffuse: a metal), `glossy` (Blinn-Phong, `ks = 0.6`, exponent 80, `kd = 0.02`: a
//! glossy paint) and `diffuse` (Blinn-Phong `kd = 0.3/0.2/0.1`, `ks = 0.5`, exponent 20:
//! a mostly diffuse plastic, which a D-BRDF lobe alone cannot hold).
//!
//! Renders a 128-segment sphere at SIZE x SIZE (default 24) with
//! `RenderOptions::converged_reference()` on `sampler = "full"` (f64, every probe texel a
//! light, no culling) and prints, per row and probe, the relative RMSE over the image and
//! the 99th percentile of the per-pixel relative error (as `examples/library_error.rs`).

use brdfkit::acquire::fit::{fit_dbrdf, FitOptions};
use brdfkit::brdf::dbrdf::file::write_dbrdf;
use brdfkit::brdf::rgl::samples::{sample, SAMPLE_NAMES};
use brdfkit::brdf::{AshikhminShirley, BlinnPhong, MerlBrdf, RglBrdf};
use brdfkit::conventions::local_direction_f64;
use brdfkit::image_io::Image;
use brdfkit::material::Material;
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use glam::Vec3;
use std::path::Path;
use std::sync::Arc;

fn scene(probe: &str, size: u32) -> Scene {
    let text = format!(
        "[mesh]\nsource = \"sphere\"\nsegments = 128\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\nsampler = \"full\"\n\
         [render]\nwidth = {size}\nheight = {size}\n"
    );
    let file = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn merl_source(name: &str) -> Material {
    match name {
        "gold" => Material::AshikhminShirley(AshikhminShirley {
            nu: 200.0,
            nv: 200.0,
            rs: Vec3::new(0.9, 0.7, 0.3),
            rd: Vec3::ZERO,
        }),
        "glossy" => Material::BlinnPhong(BlinnPhong {
            kd: Vec3::splat(0.02),
            ks: Vec3::splat(0.6),
            exponent: 80.0,
        }),
        "diffuse" => Material::BlinnPhong(BlinnPhong {
            kd: Vec3::new(0.3, 0.2, 0.1),
            ks: Vec3::splat(0.5),
            exponent: 20.0,
        }),
        _ => panic!("unknown MERL source {name:?} (gold, glossy, diffuse)"),
    }
}

/// The material as its reader gives it back from a file written to a temporary directory.
fn merl_table(name: &str, dir: &Path) -> MerlBrdf {
    let src = merl_source(name);
    let path = dir.join(format!("{name}.binary"));
    MerlBrdf::tabulate(src.as_brdf()).write(&path).unwrap();
    MerlBrdf::read(&path).unwrap()
}

/// (reference material, tested material, note) of a row.
fn row(kind: &str, name: &str, dir: &Path) -> (Material, Material, String) {
    match kind {
        "rgl" => {
            let s = sample(name).unwrap_or_else(|| panic!("unknown RGL sample {name:?}"));
            let path = dir.join(format!("{name}.bsdf"));
            std::fs::write(&path, &s.bytes).unwrap();
            let file = RglBrdf::read(&path).unwrap();
            (
                analytic(name),
                Material::from(Arc::new(file)),
                format!("{} KB file", s.bytes.len() / 1024),
            )
        }
        "merl" => (
            merl_source(name),
            Material::from(Arc::new(merl_table(name, dir))),
            String::new(),
        ),
        "merl-fit" => {
            let table = merl_table(name, dir);
            let fit = fit_dbrdf(&table, &FitOptions::default()).unwrap();
            let note = format!("fit rel L2 {:.4}", fit.report.rel_l2);
            let out = dir.join(format!("{name}-fit.exr"));
            write_dbrdf(
                &out,
                &fit.brdf,
                &format!("measured_error: fit of {name}.binary"),
            )
            .unwrap();
            (
                Material::from(Arc::new(table)),
                Material::from(Arc::new(fit.brdf)),
                note,
            )
        }
        _ => panic!("unknown row kind {kind:?} (rgl, merl, merl-fit)"),
    }
}

/// The analytic source of an RGL sample as a material (the samples' sources are Blinn-Phong
/// or Ashikhmin-Shirley; the spectral one's diffuse colour is its spectrum in sRGB),
/// checked against `brdfkit::brdf::rgl::samples::source` at a few pairs of directions.
fn analytic(name: &str) -> Material {
    use brdfkit::brdf::rgl::samples::{source, spectral_reference};
    let m = match name {
        "blinn-rgb" => Material::BlinnPhong(BlinnPhong {
            kd: Vec3::new(0.3, 0.2, 0.1),
            ks: Vec3::splat(0.5),
            exponent: 20.0,
        }),
        "aniso-rgb" => Material::AshikhminShirley(AshikhminShirley {
            nu: 8.0,
            nv: 64.0,
            rs: Vec3::splat(0.25),
            rd: Vec3::new(0.35, 0.2, 0.1),
        }),
        "blinn-spectral" => Material::BlinnPhong(spectral_reference()),
        _ => unreachable!("SAMPLE_NAMES"),
    };
    let src = source(name).unwrap();
    for k in 0..16 {
        let a = 0.1 + 0.09 * k as f64;
        let wi = local_direction_f64(0.05 * k as f64, a);
        let wo = local_direction_f64(1.2 - 0.07 * k as f64, 2.0 * a + 1.0);
        assert_eq!(
            m.eval_f64(wi, wo),
            src.eval_f64(wi, wo),
            "{name}: not its source"
        );
    }
    m
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let keep = args
        .iter()
        .position(|a| a == "--keep")
        .map(|k| args.get(k + 1).expect("--keep DIR").clone());
    let size: u32 = args.iter().find_map(|s| s.parse().ok()).unwrap_or(24);
    const PROBES: [&str; 3] = ["city", "studio", "sky"];
    let mut probes: Vec<&str> = PROBES
        .into_iter()
        .filter(|p| args.iter().any(|a| a == p))
        .collect();
    if probes.is_empty() {
        probes = PROBES.to_vec();
    }
    let mut rows: Vec<String> = args
        .iter()
        .filter(|a| a.parse::<u32>().is_err() && !PROBES.contains(&a.as_str()))
        .filter(|a| *a != "--keep" && Some(*a) != keep.as_ref())
        .cloned()
        .collect();
    if rows.is_empty() {
        rows = SAMPLE_NAMES.iter().map(|n| format!("rgl:{n}")).collect();
        for m in ["gold", "glossy", "diffuse"] {
            rows.push(format!("merl:{m}"));
            rows.push(format!("merl-fit:{m}"));
        }
    }
    let tmp = tempfile::tempdir().unwrap();
    let dir = match &keep {
        Some(d) => {
            std::fs::create_dir_all(d).unwrap();
            Path::new(d).to_path_buf()
        }
        None => tmp.path().to_path_buf(),
    };
    let opts = RenderOptions::converged_reference();
    println!("| row | probe | rel RMSE | p99 | note |");
    println!("|---|---|---|---|---|");
    for r in &rows {
        let (kind, name) = r
            .split_once(':')
            .unwrap_or_else(|| panic!("row {r:?}: KIND:NAME"));
        let (reference, tested, note) = row(kind, name, &dir);
        for &probe in &probes {
            let mut s = scene(probe, size);
            s.material = reference.clone();
            let want: Image = render(&s, &opts).image;
            s.material = tested.clone();
            let got: Image = render(&s, &opts).image;
            println!(
                "| {r} | {probe} | {:.2}% | {:.2}% | {note} |",
                100.0 * brdfkit::metrics::relative_rmse(&want, &got, None),
                100.0 * brdfkit::metrics::relative_error_quantile(&want, &got, 0.99, |_| true),
            );
        }
    }
}
