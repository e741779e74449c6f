//! `[env] method = "lightcuts"` end to end: glossy spheres against the converged reference
//! (`RenderOptions::converged_reference()` on `sampler = "full"`: f64, every texel a
//! light) under the shipped probes, a seeded bound fault, the scene errors of the method,
//! and determinism across thread counts.

use brdfkit::env::lightcuts::LightCuts;
use brdfkit::image_io::Image;
use brdfkit::material::cone_bound::BoundFault;
use brdfkit::render::{rasterize, render, RenderOptions};
use brdfkit::scene::{Environment, Scene, SceneFile};
use brdfkit::shade::{shade, CutStats, ShadeOptions, ShadingPath};
use std::path::Path;
use std::sync::Arc;

const SIDE: u32 = 24;

fn scene(probe: &str, material: &str, env_extra: &str) -> brdfkit::error::Result<Scene> {
    let text = format!(
        "[mesh]\nsource = \"sphere\"\nsegments = 64\n[material]\n{material}\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\n{env_extra}\n\
         [render]\nwidth = {SIDE}\nheight = {SIDE}\n"
    );
    let file = SceneFile::parse(&text).unwrap();
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR")))
}

const BLINN_PHONG_200: &str = "kind = \"blinn-phong\"\nexponent = 200";
const LINDT: &str = "kind = \"library\"\nname = \"lindt-paper\"";

/// The light-cut render of `s` (default f32 path) and its cut sizes.
fn cut_render(s: &Scene) -> (Image, CutStats) {
    let vis = rasterize(s, false);
    let shaded = shade(s, &vis, &ShadeOptions::default());
    (shaded.image, shaded.report.cuts)
}

fn reference(probe: &str, material: &str) -> Image {
    render(
        &scene(probe, material, "sampler = \"full\"").unwrap(),
        &RenderOptions::converged_reference(),
    )
    .image
}

/// Blinn-Phong exponent 200 and the library D-BRDF (lindt-paper) under every shipped probe,
/// default `cut_error` (1%) and `cut_max`: relative RMSE against the converged reference
/// below the 1% target for glossy materials under an environment (measured, 24 x 24, on
/// this machine: see the report printed with `--nocapture`; the largest is well under the
/// bound). The mean cut is printed beside it.
#[test]
fn lightcuts_match_the_converged_reference() {
    let mut worst = 0.0f64;
    for probe in ["city", "sky", "studio"] {
        for (name, material) in [("blinn-phong-200", BLINN_PHONG_200), ("lindt-paper", LINDT)] {
            let r = reference(probe, material);
            let s = scene(probe, material, "method = \"lightcuts\"").unwrap();
            assert!(
                s.delta_lights().is_empty(),
                "the probe is in the tree, not in lights"
            );
            let (got, cuts) = cut_render(&s);
            let e = brdfkit::metrics::relative_rmse(&r, &got, None);
            let q = brdfkit::metrics::relative_error_quantile(&r, &got, 0.99, |_| true);
            eprintln!(
                "{probe} {name}: rel RMSE {e:.5} p99 {q:.5} mean cut {:.1} largest {} capped {}",
                cuts.mean(),
                cuts.largest,
                cuts.capped
            );
            assert!(cuts.pixels > 200, "{probe} {name}: {} pixels", cuts.pixels);
            assert!(e < 0.01, "{probe} {name}: rel RMSE {e}");
            worst = worst.max(e);
        }
    }
    eprintln!("worst rel RMSE {worst:.5}");
}

/// A 32 x 32 view of the sphere's limb region at about the pixel density of the 640 x 480
/// bench frame (pixels 0.0046 radii apart, 2.4 degrees of view): here squares of pixels
/// share cuts (on the full 24 x 24 sphere above, normals turn too fast and the shared-cut
/// path splits its squares down to single pixels).
fn patch(probe: &str, material: &str, env_extra: &str) -> Scene {
    let text = format!(
        "[camera]\nposition = [0.0, 0.0, 3.5]\ntarget = [0.64, 0.64, 0.0]\nfov_y_deg = 2.4\n\
         [mesh]\nsource = \"sphere\"\nsegments = 64\n[material]\n{material}\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\n{env_extra}\n\
         [render]\nwidth = 32\nheight = 32\n"
    );
    let file = SceneFile::parse(&text).unwrap();
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// Largest relative RMSE between the shared cuts (default path) and the per-pixel cuts
/// (scalar-oracle path) on the patch: both meet the same per-pixel criterion (each
/// cluster's error bound at most `cut_error` = 1% of the pixel), so they may differ by
/// their two errors against the converged reference, each held under 1% above.
const SHARED_VS_PER_PIXEL: f64 = 0.01;

/// The shared cuts where they are shared: on the limb patch, every shipped probe,
/// Blinn-Phong 200 and lindt-paper, relative RMSE against the converged reference under
/// the 1% target for glossy materials under an environment and against the per-pixel cuts
/// under [`SHARED_VS_PER_PIXEL`]; prints p99, mean cut and pixels per cut.
#[test]
fn shared_cuts_match_the_reference_and_the_per_pixel_cuts() {
    for probe in ["city", "sky", "studio"] {
        for (name, material) in [("blinn-phong-200", BLINN_PHONG_200), ("lindt-paper", LINDT)] {
            let r = render(
                &patch(probe, material, "sampler = \"full\""),
                &RenderOptions::converged_reference(),
            )
            .image;
            let s = patch(probe, material, "method = \"lightcuts\"");
            let vis = rasterize(&s, false);
            let shared = shade(&s, &vis, &ShadeOptions::default());
            let per_pixel = shade(
                &s,
                &vis,
                &ShadeOptions::default().with_path(ShadingPath::ScalarOracle),
            );
            let e = brdfkit::metrics::relative_rmse(&r, &shared.image, None);
            let e_pp = brdfkit::metrics::relative_rmse(&r, &per_pixel.image, None);
            let d = brdfkit::metrics::relative_rmse(&per_pixel.image, &shared.image, None);
            let c = shared.report.cuts;
            eprintln!(
                "patch {probe} {name}: shared rel RMSE {e:.5} p99 {:.5}, per-pixel rel RMSE \
                 {e_pp:.5} p99 {:.5}, shared vs per-pixel {d:.5}; shared: {} pixels, {} cuts \
                 ({:.1} pixels per cut), mean cut {:.1}, largest {}, capped {}; per-pixel \
                 mean cut {:.1}",
                brdfkit::metrics::relative_error_quantile(&r, &shared.image, 0.99, |_| true),
                brdfkit::metrics::relative_error_quantile(&r, &per_pixel.image, 0.99, |_| true),
                c.pixels,
                c.tiles,
                c.pixels as f64 / c.tiles.max(1) as f64,
                c.mean(),
                c.largest,
                c.capped,
                per_pixel.report.cuts.mean()
            );
            assert!(c.pixels > 300, "{probe} {name}: {} pixels", c.pixels);
            assert!(
                c.tiles * 4 < c.pixels,
                "{probe} {name}: {} cuts for {} pixels: little sharing",
                c.tiles,
                c.pixels
            );
            assert!(e < 0.01, "{probe} {name}: rel RMSE {e}");
            assert!(d < SHARED_VS_PER_PIXEL, "{probe} {name}: vs per-pixel {d}");
        }
    }
}

/// Seeded faults: a bound that ignores the cone (the value at its axis) or one of a cone
/// half as wide stops refining clusters whose lobe lies off their axis, and the render
/// misses highlights: the accuracy check above fails (rel RMSE over 1%).
#[test]
fn seeded_bound_faults_fail_the_accuracy_check() {
    let r = reference("city", BLINN_PHONG_200);
    let s = scene("city", BLINN_PHONG_200, "method = \"lightcuts\"").unwrap();
    for fault in [BoundFault::IgnoreCone, BoundFault::HalfCone] {
        let mut faulty = s.clone();
        let mut cuts: LightCuts = (**s.environment.light_cuts().unwrap()).clone();
        cuts.fault = fault;
        faulty.environment = Environment::LightCuts(Arc::new(cuts));
        let (got, _) = cut_render(&faulty);
        let e = brdfkit::metrics::relative_rmse(&r, &got, None);
        eprintln!("{fault:?}: rel RMSE {e:.5}");
        assert!(e > 0.01, "{fault:?} passed: rel RMSE {e}");
    }
}

/// Same bits on 1 and 2 threads; a finer `cut_error` makes larger cuts.
#[test]
fn lightcuts_are_deterministic_and_refine_with_cut_error() {
    let s = scene("studio", LINDT, "method = \"lightcuts\"").unwrap();
    let one = render(
        &s,
        &RenderOptions {
            threads: Some(1),
            ..RenderOptions::default()
        },
    )
    .image;
    let two = render(
        &s,
        &RenderOptions {
            threads: Some(2),
            ..RenderOptions::default()
        },
    )
    .image;
    assert!(one.pixels == two.pixels, "thread count changed the image");
    let coarse = scene("studio", LINDT, "method = \"lightcuts\"\ncut_error = 0.1").unwrap();
    let (_, a) = cut_render(&coarse);
    let (_, b) = cut_render(&s);
    assert!(a.mean() < b.mean(), "{} vs {}", a.mean(), b.mean());
    let capped = scene("studio", LINDT, "method = \"lightcuts\"\ncut_max = 4").unwrap();
    let (_, c) = cut_render(&capped);
    assert!(c.largest <= 4 && c.capped > 0, "{c:?}");
}

#[test]
fn lightcuts_errors_name_the_field() {
    for (extra, field) in [
        ("cut_error = 0.0", "env.cut_error"),
        ("cut_error = 1.5", "env.cut_error"),
        ("cut_error = nan", "env.cut_error"),
        ("cut_max = 0", "env.cut_max"),
        ("cut_max = 100000", "env.cut_max"),
    ] {
        let e = scene(
            "city",
            BLINN_PHONG_200,
            &format!("method = \"lightcuts\"\n{extra}"),
        )
        .err()
        .unwrap_or_else(|| panic!("{extra} accepted"));
        assert!(e.to_string().contains(field), "{extra}: {e}");
    }
    // An SH data set has no cone bound: refused, naming env.method and the model.
    let sh = format!(
        "kind = \"sh-file\"\npath = {:?}",
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("golden/magenta-plastic-5b-8x4.exr")
            .to_str()
            .unwrap()
    );
    let e = scene("city", &sh, "method = \"lightcuts\"").err().unwrap();
    let msg = e.to_string();
    assert!(
        msg.contains("env.method") && msg.contains("sh-dataset"),
        "{msg}"
    );
}

/// The converged reference of a light-cut scene is the full probe:
/// `EnvSpec::use_full_probe` resets the method to `lights`.
#[test]
fn reference_of_a_lightcuts_scene_is_the_full_probe() {
    let text = "[env]\nfile = \"x.exr\"\nmethod = \"lightcuts\"\n";
    let mut file = SceneFile::parse(text).unwrap();
    let env = file.env.as_mut().unwrap();
    assert_eq!(env.method, brdfkit::env::schema::EnvMethod::Lightcuts);
    env.use_full_probe();
    assert_eq!(env.method, brdfkit::env::schema::EnvMethod::Lights);
    assert_eq!(env.sampler, brdfkit::env::schema::SamplerKind::Full);
}
