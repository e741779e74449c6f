//! What projecting a transfer table from the downsampled residual costs in accuracy
//! ([`brdfkit::env::transfer::build`], "Residual"), for people: a table, one row per
//! material and residual width, against the table projected from the full-resolution
//! residual of the same probe.
//!
//! ```sh
//! cargo run --release --example upsample_probe -- assets/probes/city.exr /tmp 2048
//! cargo run --release --example transfer_residual_error -- /tmp/city-2048x1024.exr [SIZE] [w=WIDTH ...] [m=MATERIAL ...]
//! ```
//!
//! For every library SH material and Lambert (albedo 0.8), or the ones named with `m=`,
//! renders a 256-segment sphere at SIZE x SIZE (default 64) under PROBE with the transfer
//! method (default grid 128 x 65, 64 exact texels, the same exact texels for every table),
//! its table projected from the residual at most WIDTH texels wide (default 256 and 512,
//! [`brdfkit::env::transfer::build::RESIDUAL_WIDTH`] being the default of every render) and
//! from the full probe, and prints, per width, against the full probe's image:
//! - rel RMSE: relative RMSE over the image ([`brdfkit::metrics::relative_rmse`]);
//! - p99: the 99th percentile over covered pixels of the per-pixel relative error
//!   `|x - r| / |r|` (RGB norms), pixels with `|r|` below 1% of the mean `|r|` left out;
//! - build s: seconds to build the table (the full probe's in its own column).
//!
//! The transfer method's own error against the converged reference (`examples/transfer_error.rs`:
//! relative RMSE 0.1-1%, p99 a few percent) is the scale these numbers are read against.

use brdfkit::env::transfer::build::build_table_from_residual;
use brdfkit::env::transfer::BuildFault;
use brdfkit::env::transfer::{brightest_texels, TransferBasis};
use brdfkit::env::{LoadOptions, Probe};
use brdfkit::library::Representation;
use brdfkit::progress::Progress;
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{Environment, Scene, SceneFile};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(probe_path) = args.first() else {
        eprintln!("usage: transfer_residual_error PROBE [SIZE] [w=WIDTH ...] [m=MATERIAL ...]");
        std::process::exit(2);
    };
    let size: u32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(64);
    let mut widths: Vec<usize> = args
        .iter()
        .filter_map(|a| a.strip_prefix("w=")?.parse().ok())
        .collect();
    if widths.is_empty() {
        widths = vec![256, 512];
    }
    let only: Vec<&str> = args.iter().filter_map(|a| a.strip_prefix("m=")).collect();
    let mut materials: Vec<(String, String)> = brdfkit::library::LIBRARY
        .iter()
        .filter(|e| matches!(e.representation, Representation::Sh { .. }))
        .map(|e| {
            (
                e.name.to_string(),
                format!("kind = \"library\"\nname = \"{}\"", e.name),
            )
        })
        .collect();
    materials.push((
        "lambert".into(),
        "kind = \"lambert\"\nalbedo = [0.8, 0.8, 0.8]".into(),
    ));
    materials.retain(|(n, _)| only.is_empty() || only.contains(&n.as_str()));
    let path = std::fs::canonicalize(probe_path).unwrap_or_else(|e| {
        eprintln!("{probe_path}: {e}");
        std::process::exit(1)
    });
    let (probe, _) = Probe::load(&path, &LoadOptions::default()).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });
    let grid = (
        brdfkit::env::schema::DEFAULT_TRANSFER_AZIMUTH,
        brdfkit::env::schema::DEFAULT_TRANSFER_POLAR,
    );
    let exact = brightest_texels(&probe, brdfkit::env::schema::DEFAULT_EXACT_LIGHTS);
    println!(
        "{}: {} x {}, {size} x {size}",
        path.display(),
        probe.width(),
        probe.height()
    );
    let mut header = "| material |".to_string();
    for w in &widths {
        header += &format!(" rel RMSE {w} | p99 {w} | build s {w} |");
    }
    println!("{header} build s full |");
    println!("|---|{}---|", "---|---|---|".repeat(widths.len()));
    for (name, spec) in &materials {
        let text = format!(
            "[mesh]\nsource = \"sphere\"\nsegments = 256\n[material]\n{spec}\n\
             [env]\nfile = \"{}\"\nmethod = \"transfer\"\n\
             [render]\nwidth = {size}\nheight = {size}\n",
            path.display()
        );
        let file = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        let scene = Scene::resolve(&file, Path::new(".")).unwrap();
        let basis = TransferBasis::for_material(&scene.material).expect("a transfer material");
        let exact_lights = scene.environment.delta_lights().to_vec();
        let with_width = |max_width: usize| {
            let t0 = Instant::now();
            let table = build_table_from_residual(
                &probe,
                basis,
                grid,
                (&exact, max_width),
                1.0,
                &Progress::hidden(),
                BuildFault::None,
            )
            .unwrap();
            let secs = t0.elapsed().as_secs_f64();
            let mut s = scene.clone();
            s.environment = Environment::Transfer {
                table: Arc::new(table),
                exact: exact_lights.clone(),
            };
            (render(&s, &RenderOptions::default()).image, secs)
        };
        let (full, full_secs) = with_width(usize::MAX);
        let mut row = format!("| {name} |");
        for &w in &widths {
            let (img, secs) = with_width(w);
            let e = brdfkit::metrics::relative_rmse(&full, &img, None);
            let q = brdfkit::metrics::relative_error_quantile(&full, &img, 0.99, |_| true);
            row += &format!(" {:.4}% | {:.3}% | {secs:.2} |", e * 100.0, q * 100.0);
        }
        println!("{row} {full_secs:.2} |");
    }
}
