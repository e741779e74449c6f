//! Error of `[env] method = "reflection"` against the converged reference, for people: a
//! table, one row per material and probe, over all pixels and over the grazing band.
//!
//! ```sh
//! cargo run --release --example reflection_error -- [SIZE] [m=MATERIAL ...] [n=N,N...] \
//!     [bias=B] [png=DIR] [kd=K] [ks=K] [set=FIELD=VALUE ...] [diag] [PROBE...]
//! ```
//!
//! For Blinn-Phong exponents 50, 200 and 500 (the scene format's other defaults) and the
//! library's isotropic D-BRDF `gold-dust-paint` (a Lambert + D-BRDF fit), the SH data set
//! `magenta-plastic` for contrast (its `auto` method is the transfer table: an SH set
//! includes the cosine and states no Lambertian term, so its diffuse part stays in the
//! series), and the anisotropic `lindt-paper` (the library's one anisotropic D-BRDF:
//! filtered importance sampling, one row per `reflection_samples` of `n=`, default 64, the
//! lookups' level bias `bias=` instead of the default), or the ones named by `m=`, under
//! each shipped probe (or the ones named: `city`, `studio`, `sky`), renders a 256-segment sphere at SIZE x SIZE
//! (default 96) with the default reflection table (64 x 64 cells, 13 + 1 slices, 64 exact
//! lights, residual 256 wide) and with the converged reference
//! ([`RenderOptions::converged_reference`] on `sampler = "full"`: f64, every texel a light),
//! and prints:
//! - relative RMSE over the image ([`brdfkit::metrics::relative_rmse`]) and p99, the 99th
//!   percentile of the per-pixel relative error `|x - r| / |r|` (RGB norms, pixels with `|r|`
//!   below 1% of the mean left out: [`brdfkit::metrics::relative_error_quantile`]);
//! - the same over the pixels whose view polar angle is above 70 degrees (the grazing band,
//!   from the `view-polar` AOV) and their share of the covered pixels;
//! - the bake's own measured error (camera-weighted samples; [`ReflectionTable::error`]), the
//!   bake time and the table's size; for filtered importance sampling instead the relative
//!   RMSE of the N-sample image against the 2N-sample one (an estimate of the sampling
//!   error that needs no reference), the preparation time and the size held.
//!
//! With `png=DIR`, each row's image and its reference are written to
//! `DIR/NAME-PROBE[-N].png` and `DIR/NAME-PROBE-reference.png` (ACES, exposure 1), and the
//! per-pixel relative error to `DIR/NAME-PROBE[-N]-error.png` (red too bright, blue too
//! dark, full at 20%).
//!
//! Knobs for studies: `kd=K` and `ks=K` set the Blinn-Phong rows' albedos (grey; the sweep's
//! glossy class is `kd=0.05 ks=0.9`); each `set=FIELD=VALUE` adds `FIELD = VALUE` to the
//! method's `[env]` table (e.g. `set=exact_lights=256`, `set=reflection_grid=96`,
//! `set=reflection_residual=512`, `set=reflection_order=6`). `diag` prints, per row, where
//! the pixels above the 99th percentile lie: their share by view polar angle (0-60,
//! 60-70, 70-80, 80-90 degrees), their median reference norm over the image's mean and the
//! share that is too bright.
//!
//! [`ReflectionTable::error`]: brdfkit::env::reflection::ReflectionTable::error

use brdfkit::aov::{self, Aov};
use brdfkit::env::reflection::ReflectionTerm;
use brdfkit::render::{rasterize, render, RenderOptions};
use brdfkit::scene::{Environment, Scene, SceneFile};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

fn scene(material: &str, probe: &str, env: &str, size: u32) -> Scene {
    try_scene(material, probe, env, size).unwrap()
}

fn try_scene(material: &str, probe: &str, env: &str, size: u32) -> brdfkit::error::Result<Scene> {
    let text = format!(
        "[mesh]\nsource = \"sphere\"\nsegments = 256\n[material]\n{material}\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\n{env}\n\
         [render]\nwidth = {size}\nheight = {size}\n"
    );
    let file = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR")))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(96);
    let mut probes: Vec<&str> = args
        .iter()
        .skip(1)
        .filter(|a| !a.contains('=') && *a != "diag")
        .map(|s| s.as_str())
        .collect();
    let only: Vec<&str> = args.iter().filter_map(|a| a.strip_prefix("m=")).collect();
    let counts: Vec<usize> = args
        .iter()
        .find_map(|a| a.strip_prefix("n="))
        .map_or(vec![64], |l| {
            l.split(',').map(|x| x.parse().unwrap()).collect()
        });
    let bias: Option<f32> = args
        .iter()
        .find_map(|a| a.strip_prefix("bias="))
        .map(|b| b.parse().unwrap());
    let png: Option<&str> = args.iter().find_map(|a| a.strip_prefix("png="));
    let kd: Option<&str> = args.iter().find_map(|a| a.strip_prefix("kd="));
    let ks: Option<&str> = args.iter().find_map(|a| a.strip_prefix("ks="));
    let extra: String = args
        .iter()
        .filter_map(|a| a.strip_prefix("set="))
        .map(|kv| {
            let (k, v) = kv.split_once('=').expect("set=FIELD=VALUE");
            format!("{k} = {v}\n")
        })
        .collect();
    let diag = args.iter().any(|a| a == "diag");
    if probes.is_empty() {
        probes = vec!["city", "studio", "sky"];
    }
    let albedo = |k: Option<&str>, key: &str| {
        k.map_or(String::new(), |k| format!("\n{key} = [{k}, {k}, {k}]"))
    };
    let bp = |e: u32| {
        format!(
            "kind = \"blinn-phong\"\nexponent = {e}{}{}",
            albedo(kd, "kd"),
            albedo(ks, "ks")
        )
    };
    let (bp50, bp200, bp500) = (bp(50), bp(200), bp(500));
    let materials = [
        ("blinn-phong-50", bp50.as_str()),
        ("blinn-phong-200", bp200.as_str()),
        ("blinn-phong-500", bp500.as_str()),
        (
            "gold-dust-paint",
            "kind = \"library\"\nname = \"gold-dust-paint\"",
        ),
        (
            "magenta-plastic",
            "kind = \"library\"\nname = \"magenta-plastic\"",
        ),
        // Anisotropic (exponents 30 and 90): filtered importance sampling.
        ("lindt-paper", "kind = \"library\"\nname = \"lindt-paper\""),
    ];
    println!(
        "| material | probe | rel RMSE | p99 | >70 deg rel RMSE | >70 deg p99 | >70 deg pixels | \
         bake: rel RMSE / p99 | bake s | MB |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for probe in &probes {
        for (name, material) in materials {
            if !only.is_empty() && !only.contains(&name) {
                continue;
            }
            let reference = render(
                &scene(material, probe, "sampler = \"full\"", size),
                &RenderOptions::converged_reference(),
            )
            .image;
            if let Some(dir) = png {
                let path = Path::new(dir).join(format!("{name}-{probe}-reference.png"));
                brdfkit::image_io::write_png(&path, &reference, 1.0, Default::default()).unwrap();
            }
            for &n in &counts {
                let t0 = Instant::now();
                let env = format!("method = \"reflection\"\nreflection_samples = {n}\n{extra}");
                let mut s = match try_scene(material, probe, &env, size) {
                    Ok(s) => s,
                    Err(e) => {
                        println!("| {name} | {probe} | refused: {e} |");
                        break;
                    }
                };
                let bake = t0.elapsed().as_secs_f64();
                with_bias(&mut s, bias);
                let term = s.environment.reflection_term().unwrap().clone();
                let got = render(&s, &RenderOptions::default()).image;
                let row = match &*term {
                    ReflectionTerm::Table(_) => name.to_string(),
                    ReflectionTerm::Filtered(_) => format!("{name} N={n}"),
                };
                if let Some(dir) = png {
                    let path = Path::new(dir).join(format!("{name}-{probe}-{n}.png"));
                    brdfkit::image_io::write_png(&path, &got, 1.0, Default::default()).unwrap();
                }
                let e = errors(&s, &reference, &got);
                if let Some(dir) = png {
                    let path = Path::new(dir).join(format!("{name}-{probe}-{n}-error.png"));
                    write_error_png(&path, &reference, &got);
                }
                if diag {
                    diagnose(&s, &reference, &got, &format!("{name} {probe}"));
                }
                let last = match &*term {
                    ReflectionTerm::Table(t) => {
                        let b = t.error();
                        format!("{:.3}% / {:.2}%", 100.0 * b.rel_rmse, 100.0 * b.p99)
                    }
                    ReflectionTerm::Filtered(_) => {
                        // The same scene at 2N: the sampling error's estimate.
                        let env2 =
                            format!("method = \"reflection\"\nreflection_samples = {}", 2 * n);
                        let mut s2 = scene(material, probe, &env2, size);
                        with_bias(&mut s2, bias);
                        let twice = render(&s2, &RenderOptions::default()).image;
                        let d = brdfkit::metrics::relative_rmse(&twice, &got, None);
                        format!("vs 2N: {:.3}%", 100.0 * d)
                    }
                };
                println!(
                    "| {row} | {probe} | {:.3}% | {:.2}% | {:.3}% | {:.2}% | {:.1}% | {last} | {bake:.1} | {:.1} |",
                    100.0 * e[0],
                    100.0 * e[1],
                    100.0 * e[2],
                    100.0 * e[3],
                    100.0 * e[4],
                    term.bytes() as f64 / 1e6
                );
                if matches!(&*term, ReflectionTerm::Table(_)) {
                    break;
                }
            }
        }
    }
}

/// Relative RMSE, p99, the same two over the grazing band (view polar above 70 degrees),
/// and the band's share of the covered pixels, of `got` against `reference` (module doc).
fn errors(
    s: &Scene,
    reference: &brdfkit::image_io::Image,
    got: &brdfkit::image_io::Image,
) -> [f64; 5] {
    let vis = rasterize(s, false);
    let polar = aov::compute(s, &vis, Aov::ViewPolar);
    let covered: Vec<bool> = reference.pixels.iter().map(|p| p.length() > 0.0).collect();
    let grazing: Vec<bool> = polar
        .pixels
        .iter()
        .zip(&covered)
        .map(|(p, &c)| c && p.x > 70.0 / 90.0)
        .collect();
    let all = brdfkit::metrics::relative_rmse(reference, got, None);
    let p99 = brdfkit::metrics::relative_error_quantile(reference, got, 0.99, |_| true);
    let g = brdfkit::metrics::relative_rmse(reference, got, Some(&grazing));
    // The grazing band's p99: the same quantile over the band's pixels alone.
    let mask = |img: &brdfkit::image_io::Image| {
        let mut m = img.clone();
        for (p, &k) in m.pixels.iter_mut().zip(&grazing) {
            if !k {
                *p = glam::Vec3::ZERO;
            }
        }
        m
    };
    let gp99 =
        brdfkit::metrics::relative_error_quantile(&mask(reference), &mask(got), 0.99, |_| true);
    let share = grazing.iter().filter(|&&k| k).count() as f64
        / covered.iter().filter(|&&k| k).count().max(1) as f64;
    [all, p99, g, gp99, share]
}

/// The scene's filtered sampler with the lookups' level bias `bias`, when given.
fn with_bias(s: &mut Scene, bias: Option<f32>) {
    let Some(b) = bias else { return };
    if let Environment::Reflection { table, exact } = &s.environment {
        if let ReflectionTerm::Filtered(f) = &**table {
            s.environment = Environment::Reflection {
                table: Arc::new(ReflectionTerm::Filtered(f.clone().with_lod_bias(b))),
                exact: exact.clone(),
            };
        }
    }
}

/// The per-pixel relative error `|x - r| / |r|` as a PNG: red too bright, blue too
/// dark, full at 20%; black where the reference is below 1% of its mean (left out of p99).
fn write_error_png(
    path: &Path,
    reference: &brdfkit::image_io::Image,
    got: &brdfkit::image_io::Image,
) {
    let mean = mean_norm(reference);
    let bytes = reference
        .pixels
        .iter()
        .zip(&got.pixels)
        .flat_map(|(r, x)| {
            let n = r.length();
            if n <= 0.01 * mean as f32 {
                return [0, 0, 0];
            }
            let e = (*x - *r).length() / n;
            let v = (e / 0.2).min(1.0);
            let g = (255.0 * v) as u8;
            if x.length() >= n {
                [g, 0, 0]
            } else {
                [0, 0, g]
            }
        })
        .collect();
    brdfkit::image_io::write_png_bytes(path, reference.width, reference.height, bytes).unwrap();
}

/// Mean RGB norm of the covered (non-zero) pixels of `img`.
fn mean_norm(img: &brdfkit::image_io::Image) -> f64 {
    let covered: Vec<f64> = img
        .pixels
        .iter()
        .map(|p| p.as_dvec3().length())
        .filter(|&n| n > 0.0)
        .collect();
    covered.iter().sum::<f64>() / covered.len().max(1) as f64
}

/// Prints where the pixels above the 99th percentile of the relative error lie (module
/// doc, `diag`).
fn diagnose(
    s: &Scene,
    reference: &brdfkit::image_io::Image,
    got: &brdfkit::image_io::Image,
    row: &str,
) {
    let vis = rasterize(s, false);
    let polar = aov::compute(s, &vis, Aov::ViewPolar);
    let mean = mean_norm(reference);
    // (relative error, polar degrees, reference norm / mean, too bright)
    let mut px: Vec<(f64, f64, f64, bool)> = reference
        .pixels
        .iter()
        .zip(&got.pixels)
        .zip(&polar.pixels)
        .filter_map(|((r, x), p)| {
            let n = r.as_dvec3().length();
            (n > 0.01 * mean).then(|| {
                (
                    (x.as_dvec3() - r.as_dvec3()).length() / n,
                    90.0 * p.x as f64,
                    n / mean,
                    x.as_dvec3().length() > n,
                )
            })
        })
        .collect();
    px.sort_by(|a, b| a.0.total_cmp(&b.0));
    let i = ((px.len() as f64 * 0.99) as usize).min(px.len().saturating_sub(1));
    let top = &px[i..];
    let bins = [0.0, 60.0, 70.0, 80.0, 90.1];
    let shares: Vec<String> = bins
        .windows(2)
        .map(|w| {
            let k = top.iter().filter(|t| t.1 >= w[0] && t.1 < w[1]).count();
            let all = px.iter().filter(|t| t.1 >= w[0] && t.1 < w[1]).count();
            format!("{}-{}: {k}/{all}", w[0], w[1].floor())
        })
        .collect();
    let mut norms: Vec<f64> = top.iter().map(|t| t.2).collect();
    norms.sort_by(f64::total_cmp);
    let bright = top.iter().filter(|t| t.3).count();
    println!(
        "  diag {row}: p99 pixels {} (of {}), by view polar {}; median |ref|/mean {:.3}; too bright {bright}",
        top.len(),
        px.len(),
        shares.join(", "),
        norms.get(norms.len() / 2).copied().unwrap_or(0.0)
    );
}
