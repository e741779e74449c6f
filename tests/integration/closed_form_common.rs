//! Shared by the closed-form image tests (`tests/integration/closed_form_*.rs`): a unit
//! sphere in front of a fixed camera, the renderer's three shading paths, an f64 ray caster
//! of the *exact* sphere, and the error measures.
//!
//! Independence: nothing here calls the renderer's shading code (no `Brdf::eval`, no light
//! code, no shading frame) to get an expected value. The renderer's own per-pixel surface
//! (position and interpolated normal) is read through `render::rasterize` +
//! `shade::surface_at`, which are geometry, not shading; expected radiances are closed forms
//! written in f64 by each test.
#![allow(dead_code)]

use brdfkit::image_io::Image;
use brdfkit::light::Light;
pub use brdfkit::material::Material;
use brdfkit::render::{rasterize, render};
use brdfkit::scene::{Precision, Scene, SceneFile};
use brdfkit::shade::{shade, surface_at, ShadeOptions, ShadingPath};
use glam::{DVec3, Vec3};
use std::path::Path;

/// Camera of every closed-form scene: looking at the unit sphere at the origin from
/// front-right-above (not along an axis, so no symmetry hides a mirrored convention).
pub const EYE: [f32; 3] = [1.2, 1.6, 3.2];
/// Vertical field of view (degrees): the sphere (15.4 degrees half-angle from `EYE`) fills
/// most of the frame.
pub const FOV_Y_DEG: f32 = 35.0;

/// The smallest `MIN_VIEW_COS` of the renderer's view lifting, restated (documented in
/// `brdfkit::shade`: the view direction is lifted to at least 1e-3 above the horizon).
pub const MIN_VIEW_COS: f64 = 1e-3;

/// A unit sphere tessellated with `segments` stacks, seen from [`EYE`], `w x h` pixels, with
/// `material` and `lights`; nothing dropped (`render.drop_lights = 0`) unless a test asks.
pub fn sphere_scene(
    segments: u32,
    w: u32,
    h: u32,
    material: Material,
    lights: Vec<Light>,
) -> Scene {
    let toml = format!(
        "[camera]\nposition = [{}, {}, {}]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = {FOV_Y_DEG}\n\
         [mesh]\nsource = \"sphere\"\nsegments = {segments}\n\
         [render]\nwidth = {w}\nheight = {h}\ndrop_lights = 0.0\n",
        EYE[0], EYE[1], EYE[2]
    );
    let file = SceneFile::parse(&toml).expect("closed-form scene parses");
    let mut s = Scene::resolve(&file, Path::new("/")).expect("closed-form scene resolves");
    s.material = material;
    s.lights = lights;
    s
}

/// The three shading paths of the renderer on one scene: the f32 fast path (kernels), the
/// f32 scalar oracle (`ShadingPath::ScalarOracle`) and the f64 path (`render.precision = f64`).
pub fn render_paths(scene: &Scene) -> Vec<(&'static str, Image)> {
    let mut fast = scene.clone();
    fast.render.precision = Precision::F32;
    let mut f64s = scene.clone();
    f64s.render.precision = Precision::F64;
    let vis = rasterize(scene, false);
    let oracle = ShadeOptions::default().with_path(ShadingPath::ScalarOracle);
    vec![
        ("f32 fast", render(&fast, &Default::default()).image),
        ("f32 oracle", shade(scene, &vis, &oracle).image),
        ("f64", render(&f64s, &Default::default()).image),
    ]
}

/// A visible surface point in f64: world position and unit normal.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub position: DVec3,
    pub normal: DVec3,
}

/// The renderer's own surface at each pixel (row-major), promoted to f64: the rasterizer's
/// perspective-correct barycentrics of the tessellated sphere, the interpolated normal.
pub fn renderer_surfaces(scene: &Scene) -> Vec<Option<Hit>> {
    let vis = rasterize(scene, false);
    let (w, h) = (scene.render.width, scene.render.height);
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            out.push(surface_at(&scene.mesh, &vis, x, y).map(|s| Hit {
                position: s.position.as_dvec3(),
                normal: s.normal.as_dvec3().normalize(),
            }));
        }
    }
    out
}

/// The exact unit sphere at the origin ray-cast in f64 through every pixel centre
/// `(x + 1/2, y + 1/2)` (screen x right, y down) of the scene's pinhole camera (look-at
/// with its `up`, vertical field of view, square pixels), row-major; `None` where the ray
/// misses.
pub fn analytic_sphere(scene: &Scene) -> Vec<Option<Hit>> {
    let cam = &scene.camera;
    let (w, h) = (scene.render.width, scene.render.height);
    let eye = cam.position.as_dvec3();
    let fwd = (cam.target.as_dvec3() - eye).normalize();
    let right = fwd.cross(cam.up.as_dvec3()).normalize();
    let up = right.cross(fwd);
    let ty = (0.5 * (cam.fov_y_deg as f64).to_radians()).tan();
    let tx = ty * w as f64 / h as f64;
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let ndc_x = 2.0 * (x as f64 + 0.5) / w as f64 - 1.0;
            let ndc_y = 1.0 - 2.0 * (y as f64 + 0.5) / h as f64;
            let d = (fwd + right * (ndc_x * tx) + up * (ndc_y * ty)).normalize();
            // |eye + t d|^2 = 1: t^2 + 2 (eye.d) t + |eye|^2 - 1 = 0, nearer root.
            let b = eye.dot(d);
            let c = eye.length_squared() - 1.0;
            let disc = b * b - c;
            out.push(if disc > 0.0 {
                let t = -b - disc.sqrt();
                let p = eye + d * t;
                Some(Hit {
                    position: p,
                    normal: p.normalize(),
                })
            } else {
                None
            });
        }
    }
    out
}

/// The documented view lifting of `brdfkit::shade` restated in world space: the unit view
/// vector `v` at a point with unit normal `n`, raised to at least [`MIN_VIEW_COS`] above the
/// tangent plane keeping its azimuth (straight up if it has none).
pub fn lifted_view(n: DVec3, v: DVec3) -> DVec3 {
    let c = v.dot(n);
    if c >= MIN_VIEW_COS {
        return v;
    }
    let tangential = v - n * c;
    let len = tangential.length();
    if len == 0.0 {
        return n;
    }
    tangential / len * (1.0 - MIN_VIEW_COS * MIN_VIEW_COS).sqrt() + n * MIN_VIEW_COS
}

/// Errors of an image against a closed form, over the pixels where both have a surface.
#[derive(Clone, Copy, Debug, Default)]
pub struct Errors {
    /// Pixels compared.
    pub pixels: usize,
    /// Largest `|got - expected|` over all channels divided by the expected image's peak.
    pub max_abs_over_peak: f64,
    /// Largest relative error `|got - expected| / expected` over channels whose expected
    /// value is at least 1% of the peak (relative error is meaningless at the terminator).
    pub max_rel: f64,
    /// Mean of `|got - expected| / peak` over compared pixels and channels.
    pub mean_abs_over_peak: f64,
}

impl std::fmt::Display for Errors {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} px: max rel {:.3e}, max |d|/peak {:.3e}, mean |d|/peak {:.3e}",
            self.pixels, self.max_rel, self.max_abs_over_peak, self.mean_abs_over_peak
        )
    }
}

/// Compares `img` with `expected(hit)` on the pixels (row-major) where `hits` has a hit and
/// `keep(hit)` holds; other pixels are not looked at (the caller picks hits that match the
/// image's coverage, see [`common_hits`]). Panics if the expected image is black.
pub fn compare(
    img: &Image,
    hits: &[Option<Hit>],
    keep: impl Fn(&Hit) -> bool,
    expected: impl Fn(&Hit) -> DVec3,
) -> Errors {
    let exp: Vec<Option<DVec3>> = hits
        .iter()
        .map(|h| h.filter(|h| keep(h)).map(|h| expected(&h)))
        .collect();
    let peak = exp
        .iter()
        .flatten()
        .map(|e| e.max_element())
        .fold(0.0f64, f64::max);
    assert!(peak > 0.0, "expected image is black");
    let mut e = Errors::default();
    let mut sum = 0.0;
    for (p, x) in img.pixels.iter().zip(&exp) {
        let Some(x) = x else { continue };
        let g = p.as_dvec3();
        e.pixels += 1;
        for c in 0..3 {
            let d = (g[c] - x[c]).abs();
            e.max_abs_over_peak = e.max_abs_over_peak.max(d / peak);
            sum += d / peak;
            if x[c] >= 0.01 * peak {
                e.max_rel = e.max_rel.max(d / x[c]);
            }
        }
    }
    e.mean_abs_over_peak = sum / (3 * e.pixels.max(1)) as f64;
    e
}

/// Hits of `analytic` kept only where the renderer also has a surface (`renderer`): the
/// inscribed polygon covers slightly fewer pixels than the exact sphere.
pub fn common_hits(analytic: &[Option<Hit>], renderer: &[Option<Hit>]) -> Vec<Option<Hit>> {
    analytic
        .iter()
        .zip(renderer)
        .map(|(a, r)| if r.is_some() { *a } else { None })
        .collect()
}

/// `n.v` of the exact sphere at a hit seen from [`EYE`] (1 facing the camera, 0 at the
/// silhouette).
pub fn view_cos(h: &Hit) -> f64 {
    let eye = Vec3::from(EYE).as_dvec3();
    (eye - h.position).normalize().dot(h.normal)
}

/// The unit vector of `v`, in f64.
pub fn unit(v: [f64; 3]) -> DVec3 {
    DVec3::from(v).normalize()
}
