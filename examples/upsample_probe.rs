//! Writes a shipped light probe upsampled to the sizes users download, to measure how an
//! environment's preparation grows with the probe (the shipped probes are 512 x 256; 1K-8K
//! probes, 4096 x 2048 the common size, are what people use).
//!
//! ```text
//! cargo run --release --example upsample_probe -- [PROBE [OUT_DIR [WIDTH...]]]
//! ```
//!
//! PROBE defaults to `assets/probes/city.exr`, OUT_DIR to the system's temporary directory
//! (the files are large: keep them out of the repository), the widths to 1024, 2048 and 4096.
//! Each output is `<stem>-<width>x<height>.exr` (2:1), bilinear in the probe's texel centres
//! ([`upsample_bilinear`]: azimuth wraps, polar clamps at the pole rows), written as f32
//! RGB OpenEXR. Bilinear interpolation keeps the probe smooth, so a bright source spreads over
//! more texels at a larger size but its total power changes by at most a few percent; the
//! power of each output is printed beside the original's.

use brdfkit::env::probe::resample::upsample_bilinear;
use brdfkit::env::{LoadOptions, Probe};
use brdfkit::image_io::{write_exr, Image};
use glam::Vec3;
use std::path::{Path, PathBuf};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let src = PathBuf::from(
        args.first()
            .map(String::as_str)
            .unwrap_or("assets/probes/city.exr"),
    );
    let out = args
        .get(1)
        .map(PathBuf::from)
        .unwrap_or_else(std::env::temp_dir);
    let mut widths: Vec<usize> = args.iter().skip(2).filter_map(|a| a.parse().ok()).collect();
    if widths.is_empty() {
        widths = vec![1024, 2048, 4096];
    }
    let (probe, _) = Probe::load(&src, &LoadOptions::default()).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });
    let stem = src.file_stem().and_then(|s| s.to_str()).unwrap_or("probe");
    println!(
        "{}: {} x {}, power {:.6?}",
        src.display(),
        probe.width(),
        probe.height(),
        probe.total_power()
    );
    for w in widths {
        let h = w / 2;
        let texels = upsample_bilinear(&probe, w, h);
        let img = Image {
            width: w as u32,
            height: h as u32,
            pixels: texels.iter().map(|&t| Vec3::from(t)).collect(),
        };
        let path: PathBuf = Path::new(&out).join(format!("{stem}-{w}x{h}.exr"));
        write_exr(&path, &img).unwrap_or_else(|e| {
            eprintln!("{e}");
            std::process::exit(1)
        });
        let (big, _) = Probe::from_texels("upsampled", w, h, texels, &LoadOptions::default())
            .expect("finite, non-negative texels");
        println!("{}: power {:.6?}", path.display(), big.total_power());
    }
}
