//! One basis for an SH data set, everywhere: a data set that carries a basis table renders
//! as the same data set without one (its definition is the analytic basis, `sh::dataset`
//! module doc), through every light kind, every shading path and with the band skip on and
//! off.
//!
//! Expected image, per lighting and band-skip setting: the scalar oracle
//! (`ShadingPath::ScalarOracle`) of the data set *without* a table under the *directional* form
//! of the lights. Each combination (light kind x path x skip) is one assertion at
//! `SH_KERNEL_TOLERANCE` with the metric of tests/integration/kernel.rs. A distant point light stands
//! for a directional one: at distance `R = 1e7` from the origin, over a teapot within about 3
//! units of it, its direction varies by 3e-7 rad (about the f32 rounding of
//! `position - p` there, 1 ulp of 1e7 over 1e7) and its irradiance by 6e-7 relative. At
//! `R = 1e5` (3e-5 rad) this 8-band data set already moved pixels by 1.3e-3 of the metric's
//! scale, a real difference in lighting, not in the basis. The table is coarse on purpose (the data set's own 16 x 8
//! grid, nearest lookup, as the thesis's hardware required): a path that read it would be
//! off by far more than the tolerance, and `table_basis_on_any_path_fails_the_check`
//! shows the check catches that.

use crate::shading_paths;

use brdfkit::env::lightset::{prepare::prepare, to_scene_lights};
use brdfkit::env::schema::{EnvSpec, SamplerKind};
use brdfkit::image_io::Image;
use brdfkit::kernel::SH_KERNEL_TOLERANCE;
use brdfkit::lanes::Dispatch;
use brdfkit::light::Light;
use brdfkit::render;
use brdfkit::scene::{Scene, SceneFile};
use brdfkit::sh::{ShBasisTable, ShDataset};
use brdfkit::shade::{self, FramePrep, KernelFault, ShadeOptions};
use glam::Vec3;
use shading_paths::{f64_no_skips, scalar_oracle};
use std::path::Path;
use std::sync::Arc;

/// Distance of the point lights standing for directional ones (scene units).
const FAR: f32 = 1e7;

/// Largest per-channel difference of `a` from `expected`, relative to the expected pixel's
/// largest channel or to 1% of the image's peak, whichever is larger (tests/integration/kernel.rs), and
/// whether every pixel is within `tol` of that scale plus 1e-6.
fn compare(a: &Image, expected: &Image, tol: f32) -> (f32, bool) {
    let peak = expected
        .pixels
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0f32, f32::max);
    let mut worst = 0.0f32;
    let mut ok = true;
    for (p, q) in a.pixels.iter().zip(&expected.pixels) {
        let d = (*p - *q).abs().max_element();
        let scale = q.abs().max_element().max(1e-2 * peak);
        worst = worst.max(d / scale);
        ok &= d <= tol * scale + 1e-6;
    }
    (worst, ok)
}

/// blue-silk (8 bands) with a declared band threshold, so the band skip does drop bands;
/// without and with a basis table on its own grid.
fn datasets() -> (Arc<ShDataset>, Arc<ShDataset>) {
    let lib = brdfkit::library::build("blue-silk").unwrap();
    let mut plain = lib.as_sh().unwrap().clone();
    plain.set_band_threshold(0.02).unwrap();
    let mut tabled = plain.clone();
    let (nu, nv) = plain.grid();
    tabled
        .set_basis_table(Some(ShBasisTable::tabulate(nu, nv, plain.bands()).unwrap()))
        .unwrap();
    (Arc::new(plain), Arc::new(tabled))
}

/// The teapot at 64 x 48 under `lights`, no light dropping, band skip as given.
fn scene(material: Arc<ShDataset>, lights: Vec<Light>, band_skip: bool) -> Scene {
    let mut f = SceneFile::default();
    f.render.width = 64;
    f.render.height = 48;
    f.render.drop_lights = 0.0;
    f.render.band_skip = band_skip;
    let mut s = Scene::resolve(&f, Path::new("/")).unwrap();
    s.material = material.into();
    s.lights = lights;
    s
}

/// Each directional light as a point light `FAR` away along its direction with the same
/// irradiance at the origin.
fn as_far_points(lights: &[Light]) -> Vec<Light> {
    lights
        .iter()
        .map(|l| match *l {
            Light::Directional {
                to_light,
                irradiance,
            } => Light::Point {
                position: to_light * FAR,
                intensity: irradiance * (FAR * FAR),
            },
            p => p,
        })
        .collect()
}

/// A directional light of zero power: it keeps point lights on the per-pixel path (the
/// pixel-packed one serves only scenes without directional lights) and adds exactly 0.
fn dark() -> Light {
    Light::Directional {
        to_light: Vec3::Y,
        irradiance: Vec3::ZERO,
    }
}

/// 64 median-cut lights of the city probe, prepared without any cache.
fn env_lights() -> Vec<Light> {
    let mut spec =
        EnvSpec::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/city.exr"));
    spec.sampler = SamplerKind::MedianCut;
    spec.count = 64;
    to_scene_lights(&prepare(&spec, Path::new("/"), None).unwrap().lights)
}

fn lightings() -> Vec<(&'static str, Vec<Light>)> {
    let sun = Light::Directional {
        to_light: Vec3::new(0.4, 0.8, 0.45).normalize(),
        irradiance: Vec3::new(2.0, 1.8, 1.5),
    };
    vec![("directional", vec![sun]), ("env set", env_lights())]
}

/// Fast-path render of `s` on `dispatch`, with an optional seeded fault.
fn fast(s: &Scene, dispatch: Dispatch, fault: Option<KernelFault>) -> Image {
    let vis = render::rasterize(s, false);
    let opts = ShadeOptions {
        kernel: Some(dispatch.path()),
        fault,
        ..ShadeOptions::default()
    };
    shade::shade(s, &vis, &opts).image
}

/// Every (path, image) of the tabled data set under `lights` in one light kind.
fn renders(
    tabled: &Arc<ShDataset>,
    lights: &[Light],
    points: bool,
    band_skip: bool,
) -> Vec<(String, Image)> {
    let mut out = Vec::new();
    let lights: Vec<Light> = if points {
        as_far_points(lights)
    } else {
        lights.to_vec()
    };
    let s = scene(tabled.clone(), lights.clone(), band_skip);
    let vis = render::rasterize(&s, false);
    for d in every_dispatch() {
        if points {
            // Points only: the pixel-packed path; plus a dark directional light: per pixel.
            out.push((format!("packed {}", d.name()), fast(&s, d, None)));
            let mut with_dark = lights.clone();
            with_dark.push(dark());
            let sd = scene(tabled.clone(), with_dark, band_skip);
            out.push((format!("fast {}", d.name()), fast(&sd, d, None)));
        } else {
            out.push((format!("fast {}", d.name()), fast(&s, d, None)));
        }
    }
    out.push(("scalar oracle".into(), scalar_oracle(&s, &vis)));
    // The f64 path shades every stored band; with the band skip, it shades the truncated
    // data set the frame preparation made (its table truncated with it).
    let f64_scene = if band_skip {
        let prep = FramePrep::new(&s);
        let (ds, _) = prep.sh.as_ref().unwrap();
        assert!(ds.basis_table().is_some(), "truncation dropped the table");
        scene(Arc::new(ds.as_ref().clone()), lights, band_skip)
    } else {
        s
    };
    out.push(("f64".into(), f64_no_skips(&f64_scene, &vis)));
    out
}

#[test]
fn a_basis_table_renders_the_same_through_every_light_kind_path_and_band_skip() {
    let (plain, tabled) = datasets();
    let kept = plain.effective_bands();
    assert!(
        kept < plain.bands(),
        "the band skip must drop bands here (keeps {kept} of {})",
        plain.bands()
    );
    let mut results = Vec::new();
    for (lighting, lights) in lightings() {
        for band_skip in [false, true] {
            let anchor_scene = scene(plain.clone(), lights.clone(), band_skip);
            let vis = render::rasterize(&anchor_scene, false);
            let expected = scalar_oracle(&anchor_scene, &vis);
            let lit = expected.pixels.iter().filter(|p| **p != Vec3::ZERO).count();
            assert!(lit > 300, "{lighting}: only {lit} lit pixels");
            for points in [false, true] {
                let kind = if points {
                    format!("{lighting} as points at {FAR:e}")
                } else {
                    lighting.to_string()
                };
                for (path, img) in renders(&tabled, &lights, points, band_skip) {
                    let (worst, ok) = compare(&img, &expected, SH_KERNEL_TOLERANCE);
                    let what = format!("{kind}, {path}, band skip {band_skip}");
                    eprintln!(
                        "{what}: worst {worst:.2e} = {:.3} x tolerance {SH_KERNEL_TOLERANCE:e}",
                        worst / SH_KERNEL_TOLERANCE
                    );
                    results.push((what, ok));
                }
            }
        }
    }
    // Per band skip and lighting: directional (one per path, oracle, f64) and as points
    // (packed and per pixel per path, oracle, f64).
    let paths = every_dispatch().len();
    assert_eq!(results.len(), 2 * 2 * ((paths + 2) + (2 * paths + 2)));
    for (what, ok) in results {
        assert!(ok, "{what}: differs from the analytic-basis oracle");
    }
}

/// The check above is not vacuous: reading the table (the bug it replaces: earlier versions
/// did for point lights) on the per-pixel or the packed path fails it.
#[test]
fn table_basis_on_any_path_fails_the_check() {
    let (plain, tabled) = datasets();
    let (_, lights) = lightings().remove(0);
    let expected = {
        let s = scene(plain.clone(), lights.clone(), false);
        scalar_oracle(&s, &render::rasterize(&s, false))
    };
    let points = as_far_points(&lights);
    let mut with_dark = points.clone();
    with_dark.push(dark());
    for (path, lights) in [
        ("fast, directional", lights.clone()),
        ("fast, point", with_dark),
        ("packed, point", points),
    ] {
        let s = scene(tabled.clone(), lights, false);
        let img = fast(&s, Dispatch::detect(), Some(KernelFault::TableBasis));
        let (worst, ok) = compare(&img, &expected, SH_KERNEL_TOLERANCE);
        eprintln!(
            "table basis on the {path} path: worst {worst:.2e} = {:.1} x tolerance",
            worst / SH_KERNEL_TOLERANCE
        );
        assert!(!ok, "{path}: reading the table went unnoticed");
    }
}

/// Every instruction set this CPU runs (portable, AVX2, AVX-512).
fn every_dispatch() -> Vec<Dispatch> {
    crate::common::kernel_paths("sh_basis")
        .into_iter()
        .map(|p| Dispatch::choose(p).unwrap())
        .collect()
}
