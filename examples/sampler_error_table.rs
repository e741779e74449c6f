//! The samplers' irradiance error table and light-set overlays, for people (was an ignored
//! test that asserted nothing and wrote to /tmp).
//!
//! ```sh
//! cargo run --release --example sampler_error_table -- OUT_DIR
//! ```
//!
//! Prints, for the shipped city and studio probes, the relative RMS irradiance error
//! (`env::lightset::irradiance_error` over 256 Fibonacci normals against the exact per-texel integral)
//! of each sampler at 16, 128 and 1024 lights, and writes `OUT_DIR/overlay_<probe>_<sampler>64.png`
//! (64 lights drawn over the probe; median cut with its regions).

use brdfkit::cli::lights_overlay::{write_overlay_png, OverlayOptions};
use brdfkit::env::lightset::samplers::{full_probe, importance, lloyd, median_cut};
use brdfkit::env::lightset::{fibonacci_sphere, irradiance_error, reference_irradiance_many};
use brdfkit::env::{LoadOptions, Probe, SamplerConfig};
use std::path::{Path, PathBuf};

fn main() {
    let Some(out) = std::env::args().nth(1).map(PathBuf::from) else {
        eprintln!("usage: sampler_error_table OUT_DIR");
        std::process::exit(2);
    };
    if let Err(e) = std::fs::create_dir_all(&out) {
        eprintln!("{}: cannot create directory: {e}", out.display());
        std::process::exit(2);
    }
    let normals = fibonacci_sphere(256);
    println!("| probe | sampler | N=16 | N=128 | N=1024 |");
    println!("|---|---|---|---|---|");
    for name in ["city.exr", "studio.exr"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("assets/probes")
            .join(name);
        let p = Probe::load(&path, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .0;
        let reference = reference_irradiance_many(&p, &normals);
        let makers: [fn(usize) -> SamplerConfig; 5] = [
            |n| SamplerConfig::Uniform { n, seed: 1 },
            |n| SamplerConfig::Importance { n, seed: 1 },
            |n| SamplerConfig::Stratified { n, seed: 1 },
            |n| SamplerConfig::MedianCut { n },
            |n| SamplerConfig::Lloyd { n, iterations: 16 },
        ];
        for make in makers {
            let errs: Vec<String> = [16, 128, 1024]
                .iter()
                .map(|&n| {
                    let e = irradiance_error(&make(n).run(&p), &normals, &reference);
                    format!("{e:.4}")
                })
                .collect();
            println!("| {name} | {} | {} |", make(1).name(), errs.join(" | "));
        }
        let full = irradiance_error(&full_probe(&p), &normals, &reference);
        println!("| {name} | full | {full:.2e} | | |");
        let stem = name.trim_end_matches(".exr");
        let opts = OverlayOptions {
            exposure: if stem == "studio" { -1.0 } else { 0.0 },
            ..Default::default()
        };
        let mc = median_cut(&p, 64);
        let sets = [
            ("importance", importance(&p, 64, 1), None),
            ("mediancut", mc.lights.clone(), Some(mc.regions.as_slice())),
            ("lloyd", lloyd(&p, 64, 16), None),
        ];
        for (sampler, lights, regions) in &sets {
            let png = out.join(format!("overlay_{stem}_{sampler}64.png"));
            write_overlay_png(&png, &p, lights, *regions, &opts)
                .unwrap_or_else(|e| panic!("{}: {e}", png.display()));
        }
    }
}
