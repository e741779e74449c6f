//! Closed-form images under environment light: the white furnace through the `full`
//! sampler (every texel a light) and the default sampler, and the orientation of a probe
//! (a bright texel block must light the sphere where `brdfkit::conventions` says).
//!
//! Probes are written as small EXR files into a temporary directory; light sets are made
//! with `env::lightset::prepare::prepare` without a cache directory (never the user's cache).

use crate::closed_form_common;

use brdfkit::brdf::Lambert;
use brdfkit::env::lightset::{prepare::prepare, to_scene_lights};
use brdfkit::env::schema::{EnvSpec, SamplerKind};
use brdfkit::light::Light;
use closed_form_common::*;
use glam::{DVec3, Vec3};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// Writes an equirectangular EXR probe whose texel (row, col) has radiance `f(row, col)`
/// (row 0 is the top line of the image).
fn write_probe(
    dir: &Path,
    name: &str,
    w: usize,
    h: usize,
    f: impl Fn(usize, usize) -> f32 + Sync,
) -> PathBuf {
    let p = dir.join(name);
    exr::prelude::write_rgb_file(&p, w, h, |x, y| {
        let v = f(y, x);
        (v, v, v)
    })
    .unwrap();
    p
}

/// The light set of `probe` through `sampler` (no cache).
fn env_lights(probe: &Path, sampler: SamplerKind, count: usize) -> Vec<Light> {
    let mut spec = EnvSpec::new(probe.to_path_buf());
    spec.sampler = sampler;
    spec.count = count;
    to_scene_lights(&prepare(&spec, Path::new("/"), None).unwrap().lights)
}

/// White furnace: a probe of constant radiance `L` and a Lambert sphere of albedo `a`
/// reflect `a L` at every point, whatever the normal (the cosine-weighted hemisphere
/// integral is `pi`). With every texel a light of power `L x (exact solid angle)`, the
/// render is the midpoint rule of `integral max(0, n.d) dω` over the probe's texels: its
/// error comes only from the texels the horizon cuts (the integrand has a kink there) and
/// the curvature inside texels, O(texel^2). Bound 2e-3 per pixel, at 64 x 32, 128 x 64 and
/// 256 x 128 texels (measured 9.1e-4, 2.5e-4, 4.6e-5: the error falls as texel^2).
#[test]
fn white_furnace_full_sampler() {
    let tmp = tempfile::tempdir().unwrap();
    let (radiance, albedo) = (2.0f64, 0.7f64);
    let expected = radiance * albedo;
    for (w, h) in [(64, 32), (128, 64), (256, 128)] {
        let probe = write_probe(tmp.path(), &format!("c{w}.exr"), w, h, |_, _| {
            radiance as f32
        });
        let lights = env_lights(&probe, SamplerKind::Full, 1);
        assert_eq!(lights.len(), w * h, "full sampler: one light per texel");
        let mut scene = sphere_scene(
            24,
            48,
            48,
            Material::from(Lambert {
                albedo: Vec3::splat(albedo as f32),
            }),
            lights,
        );
        let paths = if w == 128 {
            render_paths(&scene)
        } else {
            vec![(
                "f32 fast",
                brdfkit::render::render(&scene, &Default::default()).image,
            )]
        };
        for (path, img) in paths {
            let (max, rms) = furnace_errors(&img, expected);
            eprintln!(
                "white furnace full {w}x{h} [{path}]: max rel {max:.3e}, rms rel {rms:.3e} (bound 2e-3)"
            );
            assert!(max <= 2e-3, "{w}x{h} [{path}]: max rel error {max:.3e}");
        }
        // The default light dropping (render.drop_lights = 1e-3) on top of the full set:
        // it drops the weakest lights (the pole rows' small texels) up to 1e-3 of the total
        // irradiance `4 pi L`; a pixel facing a pole loses up to all of it times
        // `albedo/pi`, i.e. `4e-3` of `albedo L` (the bound of `kernel::skip`).
        if w == 128 {
            scene.render.drop_lights = brdfkit::kernel::skip::DEFAULT_DROP_LIGHTS;
            let (max, rms) = furnace_errors(
                &brdfkit::render::render(&scene, &Default::default()).image,
                expected,
            );
            eprintln!(
                "white furnace full {w}x{h} with the default drop_lights 1e-3: max rel {max:.3e}, rms rel {rms:.3e} (bound 2e-3 + 4e-3)"
            );
            assert!(max <= 2e-3 + 4.0 * 1e-3, "{max:.3e}");
        }
    }
}

/// Largest and RMS relative error of the covered pixels against the constant `expected`.
fn furnace_errors(img: &brdfkit::image_io::Image, expected: f64) -> (f64, f64) {
    let (mut max, mut sum, mut n) = (0.0f64, 0.0, 0usize);
    for p in img.pixels.iter().filter(|p| p.max_element() > 0.0) {
        for c in 0..3 {
            let e = (p[c] as f64 - expected).abs() / expected;
            max = max.max(e);
            sum += e * e;
            n += 1;
        }
    }
    assert!(n > 3 * 1000, "sphere not in view");
    (max, (sum / n as f64).sqrt())
}

/// The default sampler (`lloyd`, 128 lights) under the same furnace: stated, with the
/// loose bound the sampler tests use (5% RMS); the measured numbers are in the output.
#[test]
fn white_furnace_default_sampler() {
    let tmp = tempfile::tempdir().unwrap();
    let probe = write_probe(tmp.path(), "c.exr", 128, 64, |_, _| 2.0);
    let spec = EnvSpec::new(probe.clone());
    assert_eq!(spec.sampler, SamplerKind::Lloyd);
    let lights = env_lights(&probe, spec.sampler, spec.count);
    let mut scene = sphere_scene(
        24,
        48,
        48,
        Material::from(Lambert {
            albedo: Vec3::splat(0.7),
        }),
        lights,
    );
    scene.render.drop_lights = brdfkit::kernel::skip::DEFAULT_DROP_LIGHTS;
    let (max, rms) = furnace_errors(
        &brdfkit::render::render(&scene, &Default::default()).image,
        1.4,
    );
    eprintln!(
        "white furnace default sampler (lloyd, {} lights, drop_lights 1e-3): max rel {max:.3e}, rms rel {rms:.3e}",
        spec.count
    );
    assert!(rms < 0.05, "rms {rms:.3e}");
}

/// Direction of probe image coordinates `(u, v)`, written from the convention documented
/// in `brdfkit::conventions` (not by calling it): polar angle `pi v` from +y, azimuth
/// `2 pi u`, column 0 facing +z, u = 1/4 facing -x:
/// `(-sin(pi v) sin(2 pi u), cos(pi v), sin(pi v) cos(2 pi u))`.
fn documented_probe_direction(u: f64, v: f64) -> DVec3 {
    let (polar, az) = (PI * v, 2.0 * PI * u);
    DVec3::new(-polar.sin() * az.sin(), polar.cos(), polar.sin() * az.cos())
}

/// Normal of the brightest pixel of a render of the sphere (the renderer's own normal there).
fn brightest_normal(scene: &brdfkit::scene::Scene) -> DVec3 {
    let img = brdfkit::render::render(scene, &Default::default()).image;
    let surfaces = renderer_surfaces(scene);
    let (i, _) = img
        .pixels
        .iter()
        .enumerate()
        .filter(|(i, _)| surfaces[*i].is_some())
        .map(|(i, p)| (i, p.element_sum()))
        .fold((0, f32::MIN), |a, b| if b.1 > a.1 { b } else { a });
    surfaces[i].unwrap().normal
}

/// A black probe with one bright 2 x 2 texel block lights a Lambert sphere; a Lambert
/// surface is brightest where its normal points at the light, so the brightest pixel's
/// normal must be the block's direction by the documented convention, within the block's
/// half-width plus the pixel spacing of normals (bound 4 degrees; the block is 5.6 degrees
/// wide, neighbouring pixel normals ~2 degrees apart). The same probe mirrored in u (the
/// seeded fault: columns reversed, as a reader that flipped the azimuth would see it) must
/// fail the same check: its spot lands ~37 degrees away.
#[test]
fn probe_orientation_matches_conventions() {
    let tmp = tempfile::tempdir().unwrap();
    let (w, h) = (64usize, 32usize);
    // The block's corner texel: chosen so that its direction faces the camera but off the
    // symmetry plane x = 0 (a mirror in u moves it across that plane).
    let (u0, v0) = (0.93, 0.36);
    let (col, row) = ((u0 * w as f64) as usize, (v0 * h as f64) as usize);
    let bright = |r: usize, c: usize| (r == row || r == row + 1) && (c == col || c == col + 1);
    // Centre of the 2 x 2 block = the shared corner of its four texels.
    let (uc, vc) = ((col + 1) as f64 / w as f64, (row + 1) as f64 / h as f64);
    let expected = documented_probe_direction(uc, vc);
    let eye = Vec3::from(EYE).as_dvec3().normalize();
    assert!(expected.dot(eye) > 0.8, "the spot must face the camera");

    let lambert = Material::from(Lambert { albedo: Vec3::ONE });
    let angle_deg = |a: DVec3, b: DVec3| a.dot(b).clamp(-1.0, 1.0).acos().to_degrees();
    const BOUND_DEG: f64 = 4.0;

    let probe = write_probe(tmp.path(), "spot.exr", w, h, |r, c| {
        if bright(r, c) {
            50.0
        } else {
            0.0
        }
    });
    let scene = sphere_scene(
        64,
        64,
        64,
        lambert.clone(),
        env_lights(&probe, SamplerKind::Full, 1),
    );
    let n = brightest_normal(&scene);
    let err = angle_deg(n, expected);
    eprintln!("probe orientation: lit spot {err:.2} deg from the documented direction (bound {BOUND_DEG})");
    assert!(
        err <= BOUND_DEG,
        "lit spot at {n}, expected {expected}: {err:.2} deg off"
    );

    // Seeded fault: the same probe mirrored in u.
    let mirrored = write_probe(tmp.path(), "mirrored.exr", w, h, |r, c| {
        if bright(r, w - 1 - c) {
            50.0
        } else {
            0.0
        }
    });
    let scene_m = sphere_scene(
        64,
        64,
        64,
        lambert,
        env_lights(&mirrored, SamplerKind::Full, 1),
    );
    let nm = brightest_normal(&scene_m);
    let err_m = angle_deg(nm, expected);
    eprintln!(
        "probe mirrored in u (seeded fault): lit spot {err_m:.2} deg from the documented direction"
    );
    assert!(
        err_m > BOUND_DEG,
        "a probe mirrored in u passed the orientation check"
    );
}
