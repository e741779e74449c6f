//! `brdfkit lights`: collapse a light probe into a light set, write it, draw it.

use crate::cli::lights_overlay::{write_overlay_png, OverlayOptions};
use crate::env::lightset::file::{write_csv, write_json, LightSetHeader};
use crate::env::lightset::samplers::median_cut_with_progress;
use crate::env::lightset::{fibonacci_sphere, irradiance_error, reference_irradiance_many};
use crate::env::LoadOptions;
use crate::env::{probe::load_probe, schema::SamplerKind};
use crate::error::{Error, Result};
use crate::progress::Progress;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct LightsArgs {
    /// Equirectangular light probe: OpenEXR (any compression) or Radiance .hdr.
    pub probe: PathBuf,
    /// Sampler.
    #[arg(long, value_enum, default_value = "median-cut")]
    pub sampler: crate::env::schema::SamplerKind,
    /// Number of lights (median cut: any N; powers of two split every region evenly).
    #[arg(short = 'n', long = "count", default_value_t = 128)]
    pub count: usize,
    /// Write the light set: .json (with a header) or .csv
    /// (dir_x,dir_y,dir_z,irradiance_r,irradiance_g,irradiance_b).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Draw the tone-mapped probe with the lights (and median-cut regions) into a PNG.
    #[arg(long)]
    pub overlay: Option<PathBuf>,
    /// Seed of the random samplers.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Rotate the environment about +y (degrees).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub rotation: f64,
    /// Exposure of the overlay's background (stops).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub exposure: f32,
    /// Load probes with NaN/Inf texels, setting those texels to black (default: error).
    #[arg(long)]
    pub zero_non_finite: bool,
    /// Print the irradiance error against the full probe, and the per-pixel error of a
    /// small Lambert sphere and Blinn-Phong spheres (exponents 50 and 200) rendered with
    /// the light set against the full probe.
    #[arg(long)]
    pub report: bool,
}

/// Normals the `--report` error is measured over.
pub const REPORT_NORMALS: usize = 256;

pub fn run(a: LightsArgs) -> Result<()> {
    let opts = LoadOptions {
        rotation: a.rotation.to_radians(),
        zero_non_finite: a.zero_non_finite,
        ..LoadOptions::default()
    };
    if a.count == 0 || a.count > crate::env::schema::MAX_LIGHTS {
        return Err(Error::field(
            "-n",
            format!(
                "{} is out of range (1 to {})",
                a.count,
                crate::env::schema::MAX_LIGHTS
            ),
        ));
    }
    let out_kind = match &a.output {
        None => None,
        Some(p) => {
            crate::image_io::check_output(p, &["json", "csv"], "--output")?;
            Some(
                p.extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("json")),
            )
        }
    };
    if let Some(p) = &a.overlay {
        crate::image_io::check_output(p, &["png"], "--overlay")?;
    }
    let (probe, report) = load_probe(&a.probe, &opts)?;
    if let Some(w) = report.negative_warning(&a.probe.display().to_string()) {
        eprintln!("warning: {w}");
    }
    let config = a.sampler.config(a.count, a.seed);
    let pb = Progress::bar(
        0,
        &format!("{} lights by {}", a.count, config.name()),
        config.progress_unit(),
    );
    let (lights, regions) = if a.sampler == SamplerKind::MedianCut {
        let mc = median_cut_with_progress(&probe, a.count, &pb);
        (mc.lights, Some(mc.regions))
    } else {
        (config.run_with_progress(&probe, &pb), None)
    };
    pb.finish();
    let total = lights.total_irradiance();
    println!(
        "{} lights by {} from {} ({}x{}), summed light irradiance RGB [{:.6e}, {:.6e}, {:.6e}]",
        lights.len(),
        config.name(),
        a.probe.display(),
        probe.width(),
        probe.height(),
        total.x,
        total.y,
        total.z
    );
    if a.report {
        let normals = fibonacci_sphere(REPORT_NORMALS);
        let reference = reference_irradiance_many(&probe, &normals);
        println!("irradiance error vs the full probe (relative RMS over {REPORT_NORMALS} normals): {:.6}", irradiance_error(&lights, &normals, &reference));
        let size = super::lights_report::SIZE;
        for e in super::lights_report::sphere_errors(&probe, &lights, size) {
            println!(
                "per-pixel error vs the full probe, {} sphere ({size}x{size}, {} px, f64): relative RMSE {:.6}, p99 {:.6}",
                e.material, e.pixels, e.rel_rmse, e.p99
            );
        }
    }
    if let (Some(p), Some(json)) = (&a.output, out_kind) {
        if json {
            write_json(
                p,
                &LightSetHeader::new(&config, a.probe.to_str(), &lights),
                &lights,
            )
        } else {
            write_csv(p, &lights)
        }
        .map_err(|e| Error::Message(e.to_string()))?;
        println!("wrote {}", p.display());
    }
    if let Some(p) = &a.overlay {
        let o = OverlayOptions {
            exposure: a.exposure,
            ..OverlayOptions::default()
        };
        write_overlay_png(p, &probe, &lights, regions.as_deref(), &o)
            .map_err(|e| Error::Message(e.to_string()))?;
        println!("wrote {}", p.display());
    }
    Ok(())
}
