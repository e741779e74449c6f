//! Work the renderer skips, each with what it may change in the image: dropped negligible
//! lights and SH bands within their bounds (`brdfkit::kernel::skip`), empty tiles and AOVs
//! nobody asked for by exact work counts. (Probe preprocessing already cached is guarded by
//! `light_sets_are_cached_by_contents_and_parameters` in tests/integration/env_scene.rs.)

use brdfkit::conventions::{hemi_texcoord, local_angles};
use brdfkit::env::lightset::{prepare::prepare, to_scene_lights};
use brdfkit::env::schema::{EnvSpec, SamplerKind};
use brdfkit::image_io::Image;
use brdfkit::kernel::skip::{band_tail_factor, summation_allowance};
use brdfkit::light::Light;
use brdfkit::raster::NO_TRIANGLE;
use brdfkit::render::{self, RenderOptions, RenderStats};
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use brdfkit::shade::{self, surface_at, FramePrep, ShadeOptions};
use glam::Vec3;
use std::path::Path;

/// Lights from the uniform sampler on the studio probe: a wide spread of powers.
fn studio_uniform(count: usize) -> Vec<Light> {
    let mut env =
        EnvSpec::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/studio.exr"));
    env.sampler = SamplerKind::Uniform;
    env.count = count;
    to_scene_lights(&prepare(&env, Path::new("/"), None).unwrap().lights)
}

fn scene(material: MaterialSpec, lights: Vec<Light>, w: u32, h: u32) -> Scene {
    let mut f = SceneFile::default();
    f.render.width = w;
    f.render.height = h;
    f.render.tile_size = 16;
    f.material = material;
    let mut s = Scene::resolve(&f, Path::new("/")).unwrap();
    s.lights = lights;
    s
}

/// Asserts `|a - b| <= bound + allowance` per pixel and channel; returns the largest
/// `|a - b| / bound` over pixels with a non-zero bound.
fn within(a: &Image, b: &Image, bound: impl Fn(usize) -> (Vec3, Vec3), what: &str) -> f32 {
    let mut worst = 0.0f32;
    for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        let (bd, allow) = bound(i);
        let d = (*p - *q).abs();
        assert!(
            d.cmple(bd + allow).all(),
            "{what}: pixel {i} changed by {d} > bound {bd} + rounding {allow}"
        );
        for c in 0..3 {
            if bd[c] > 0.0 {
                worst = worst.max(d[c] / bd[c]);
            }
        }
    }
    worst
}

/// `s` (or its AOV `aov`) rendered with the work done ([`RenderOptions::stats`]).
fn render_counted(s: &Scene, aov: Option<brdfkit::aov::Aov>) -> (Image, RenderStats) {
    let opts = RenderOptions {
        aov,
        stats: true,
        ..RenderOptions::default()
    };
    let r = render::render(s, &opts);
    (r.image, r.stats.expect("stats asked for"))
}

/// Dropping negligible lights changes no pixel by more than `render.drop_lights` of its own
/// value (`kernel::skip`: the frame sets the weakest lights aside, and every pixel whose
/// kept radiance is below `E_drop M / fraction` gets them back). Seeded fault: the old
/// skip, the dropped lights left out at every pixel (bounded only relative to the brightest
/// possible pixel), which must break the per-pixel bound (it does for every material here,
/// by 34x to 1400x: dim pixels on the studio probe's dark side).
#[test]
fn dropping_negligible_lights_stays_within_its_bound() {
    let lights = studio_uniform(256);
    let materials = [
        (
            "lambert",
            MaterialSpec::Lambert {
                albedo: [0.7, 0.5, 0.3],
            },
        ),
        ("blinn-phong", MaterialSpec::default()),
        (
            "lindt-paper (D-BRDF)",
            MaterialSpec::Library {
                name: "lindt-paper".into(),
                lookup: None,
            },
        ),
        (
            "magenta-plastic (SH)",
            MaterialSpec::Library {
                name: "magenta-plastic".into(),
                lookup: None,
            },
        ),
    ];
    for (what, m) in materials {
        for fraction in [brdfkit::kernel::skip::DEFAULT_DROP_LIGHTS, 0.02] {
            let mut s = scene(m.clone(), lights.clone(), 48, 36);
            s.render.drop_lights = 0.0;
            let (full, st_full) = render_counted(&s, None);
            assert_eq!(st_full.lights_dropped, 0);
            s.render.drop_lights = fraction;
            let (skipped, st) = render_counted(&s, None);
            assert!(
                st.lights_dropped > 0,
                "{what} at {fraction}: nothing dropped"
            );
            let prep = FramePrep::new(&s);
            // Rounding: two f32 sums over the full light set in different orders.
            let m = s.material.max_cosine_weighted().unwrap();
            let abs = prep.dropped.total_irradiance * m;
            let n = lights.len() * s.material.as_sh().map_or(1, |d| d.bands() * d.bands());
            let allow = Vec3::from_array(abs.to_array().map(|a| 2.0 * summation_allowance(n, a)));
            // The bound: |full - skipped| <= fraction x |skipped| per pixel and channel.
            let per_pixel = |img: &Image| {
                let img = img.clone();
                move |i: usize| (img.pixels[i].abs() * fraction, allow)
            };
            let ratio = within(&full, &skipped, per_pixel(&skipped), what);
            // The seeded fault: the old skip, every pixel without the dropped lights.
            let mut only_kept = s.clone();
            only_kept.lights = prep.dropped.kept.clone();
            only_kept.render.drop_lights = 0.0;
            let old = render::render(&only_kept, &Default::default()).image;
            let old_ratio = full
                .pixels
                .iter()
                .zip(&old.pixels)
                .flat_map(|(f, o)| {
                    (0..3).map(move |c| (f[c] - o[c]).abs() / (fraction * o[c].abs()))
                })
                .fold(0.0f32, f32::max);
            println!(
                "{what}: fraction {fraction}: dropped {} of {} lights ({:.2e} of irradiance), \
                 restored at {} of {} pixels; largest change / (fraction x pixel) = {ratio:.3}; \
                 old skip (seeded fault): {old_ratio:.3}",
                st.lights_dropped,
                st.lights,
                st.dropped_fraction,
                st.shade.pixels_restored,
                st.shade.pixels_shaded,
            );
            assert!(
                old_ratio > 1.0,
                "{what}: the old skip kept every pixel within {fraction} of itself ({old_ratio})"
            );
            // Where no pixel needed its dropped lights back, the skip saved work.
            if st.shade.pixels_restored < st.shade.pixels_shaded {
                assert!(st.shade.light_pairs < st_full.shade.light_pairs, "{what}");
            }
        }
    }
}

#[test]
fn dropping_sh_bands_stays_within_the_addition_theorem_bound() {
    let lights = studio_uniform(64);
    for (name, want) in [("teal-paint", 7), ("magenta-plastic", 4)] {
        let lib = brdfkit::library::build(name).unwrap();
        let full_ds = lib.as_sh().unwrap().clone();
        let b = full_ds.bands();
        let e = full_ds.band_energies();
        let total: f64 = e.iter().sum();
        let mut ds = full_ds.clone();
        // teal-paint (8 bands): a threshold between the top band's energy and the top two
        // bands'. magenta-plastic (5 bands, low frequency): 0.5 % of the energy, which its
        // top band (about 0.2 %) is below.
        let thr = if b == 8 {
            ((e[b - 1] + 0.5 * e[b - 2]) / total) as f32
        } else {
            5e-3
        };
        ds.set_band_threshold(thr).unwrap();
        let keep = ds.effective_bands();
        assert_eq!(keep, want, "{name} at threshold {thr}");
        let mut s = scene(MaterialSpec::default(), lights.clone(), 48, 36);
        s.render.drop_lights = 0.0;
        s.material = brdfkit::material::Material::from(ds.clone());
        let (skipped, st) = render_counted(&s, None);
        assert_eq!((st.sh_bands_stored, st.sh_bands_used), (b, keep), "{name}");
        s.render.band_skip = false;
        let (full, st_full) = render_counted(&s, None);
        assert_eq!(st_full.sh_bands_used, b);
        // Per pixel: sum_k E_k w_k over lights above the horizon, times the tail norm of
        // the pixel's view coefficients, times sqrt((B^2 - L^2)/(4 pi)).
        let vis = render::rasterize(&s, false);
        let tail = band_tail_factor(b, keep) as f32;
        let head = (b as f32) / (4.0 * std::f32::consts::PI).sqrt();
        let nt = b * b;
        let mut coeffs = vec![0.0f32; 3 * nt];
        let per_pixel: Vec<(Vec3, Vec3)> = (0..36u32)
            .flat_map(|y| (0..48u32).map(move |x| (x, y)))
            .map(|(x, y)| {
                let Some(sf) = surface_at(&s.mesh, &vis, x, y) else {
                    return (Vec3::ZERO, Vec3::ZERO);
                };
                let rule = s.material.frame_rule();
                let (frame, wo) = shade::frame_and_view(&sf, s.camera.position, &rule);
                let (p, a) = local_angles(wo);
                let (ts, tt) = hemi_texcoord(p, a);
                full_ds.lookup_coeffs(ts, tt, full_ds.coeff_lookup, &mut coeffs);
                let norm = |c: usize, from: usize| {
                    coeffs[c * nt + from..(c + 1) * nt]
                        .iter()
                        .map(|v| v * v)
                        .sum::<f32>()
                        .sqrt()
                };
                let mut ew = Vec3::ZERO;
                for l in &s.lights {
                    let (dir, e) = l.at(sf.position);
                    let z = frame.to_local(dir).z;
                    if z > 0.0 {
                        ew += e * if full_ds.cosine_included() { 1.0 } else { z };
                    }
                }
                let bound = ew * Vec3::from_array([0, 1, 2].map(|c| norm(c, keep * keep))) * tail;
                let abs = ew * Vec3::from_array([0, 1, 2].map(|c| norm(c, 0))) * head;
                let n = s.lights.len() * nt;
                let allow =
                    Vec3::from_array(abs.to_array().map(|a| 2.0 * summation_allowance(n, a)));
                (bound, allow)
            })
            .collect();
        let ratio = within(&full, &skipped, |i| per_pixel[i], name);
        println!(
            "{name}: {keep} of {b} bands at threshold {thr:.3e}; largest change / bound = {ratio:.3}"
        );
        assert!(
            ratio > 0.1,
            "{name}: bound more than 10x the change ({ratio})"
        );
    }
}

fn occupied_and_covered(s: &Scene) -> (u64, u64) {
    let vis = render::rasterize(s, false);
    let tiles = vis.tile_occupied.iter().filter(|o| **o).count() as u64;
    let px = vis.visible.iter().filter(|v| **v != NO_TRIANGLE).count() as u64;
    (tiles, px)
}

#[test]
fn counters_show_empty_tiles_and_unasked_aovs_skipped() {
    let s = scene(MaterialSpec::default(), studio_uniform(24), 64, 48);
    let (tiles, px) = occupied_and_covered(&s);
    let (_, st) = render_counted(&s, None);
    assert_eq!(st.tiles, 12);
    assert!(tiles < st.tiles, "the teapot should leave some tile empty");
    assert_eq!(st.shade.tiles_shaded, tiles);
    assert_eq!(st.shade.tiles_skipped, st.tiles - tiles);
    assert_eq!(st.shade.pixels_shaded, px);
    assert!(st.shade.light_pairs <= px * 24);
    assert_eq!(
        (st.aov_pixels, st.coverage_counted),
        (0, false),
        "beauty computed an AOV"
    );
    // Without culling every shaded pixel meets every kept light, and the pixels that got
    // the dropped lights back ([`brdfkit::kernel::skip::needs_restore`]) meet those too.
    let prep = FramePrep::new(&s);
    let vis = render::rasterize(&s, false);
    let no_culling = ShadeOptions {
        cull_lights: false,
        ..ShadeOptions::default()
    };
    let c = shade::shade(&s, &vis, &no_culling).report.counts;
    let dropped = prep.dropped.dropped as u64;
    assert!(c.pixels_restored <= px);
    assert_eq!(
        c.light_pairs,
        px * (24 - dropped) + c.pixels_restored * dropped
    );
    // Counters do not depend on the thread count.
    let on = |threads| {
        let opts = RenderOptions {
            threads: Some(threads),
            stats: true,
            ..RenderOptions::default()
        };
        render::render(&s, &opts).stats.unwrap()
    };
    assert_eq!(on(1), on(2));

    // An AOV render shades nothing; only the coverage AOV counts coverage.
    let (_, a) = render_counted(&s, Some(brdfkit::aov::Aov::Normal));
    assert_eq!(a.shade, Default::default(), "an AOV render shaded");
    assert_eq!((a.aov_pixels, a.coverage_counted), (px, false));
    let (_, c) = render_counted(&s, Some(brdfkit::aov::Aov::Coverage));
    assert_eq!(c.shade, Default::default());
    assert_eq!((c.aov_pixels, c.coverage_counted), (64 * 48, true));

    // An empty scene (the camera looks away from the mesh) shades nothing.
    let mut empty = s.clone();
    empty.camera.target = empty.camera.position * 2.0;
    let (img, e) = render_counted(&empty, None);
    assert!(img.pixels.iter().all(|p| *p == Vec3::ZERO));
    let want = RenderStats {
        tiles: 12,
        lights: 24,
        lights_dropped: e.lights_dropped,
        dropped_fraction: e.dropped_fraction,
        ..Default::default()
    };
    assert_eq!(e.shade.tiles_skipped, 12);
    assert_eq!(
        RenderStats {
            shade: Default::default(),
            ..e.clone()
        },
        want
    );
    assert_eq!(
        e.shade.tiles_shaded + e.shade.pixels_shaded + e.shade.light_pairs,
        0
    );
}
