//! `brdfkit lights --report`'s per-pixel error on a sphere: what a light set costs an
//! image, not only the irradiance it carries.
//!
//! The irradiance error over normals (0.13-0.47% for 128 lights on the shipped probes)
//! understates the per-pixel error of a rendered sphere (0.15-2.1% Lambert), and says
//! nothing about glossy materials, whose lobes narrower than the lights' spacing see a few
//! of them or none (14-35% relative RMSE at Blinn-Phong exponent 200). So the
//! report also renders a small unit sphere ([`SIZE`] pixels square, the scene's default
//! camera framing, the exact sphere per pixel: [`crate::mesh::Mesh::exact_sphere`]) under
//! the light set and under the full probe (every texel a light), both on the f64 path with
//! no skips ([`RenderOptions::converged_reference`]), so the difference is the light set's
//! alone, for a Lambert sphere and energy-normalised Blinn-Phong spheres of exponent 50
//! and 200 (`brdf::blinn_phong`, `kd = 0`, `ks = 1`: the bare lobe).

use crate::brdf::{BlinnPhong, Lambert};
use crate::env::lightset::to_scene_lights;
use crate::env::{LightSet, Probe, SamplerConfig};
use crate::material::Material;
use crate::render::{render, RenderOptions};
use crate::scene::{Scene, SceneFile};
use glam::{DVec3, Vec3};

/// Width and height of the report's sphere image, pixels.
pub const SIZE: u32 = 32;

/// A light set's error on one material's sphere against the full probe.
#[derive(Clone, Debug, PartialEq)]
pub struct SphereError {
    /// The material, e.g. `blinn-phong exponent 200`.
    pub material: String,
    /// Relative RMSE over the sphere's pixels: `sqrt(sum |d|^2 / sum |x|^2)`, `|.|` the
    /// Euclidean norm over RGB ([`crate::metrics::relative_l2`]).
    pub rel_rmse: f64,
    /// 99th percentile of the per-pixel relative error `|d| / |x|` over the pixels whose
    /// reference `|x|` is at least 1% of the image's largest (nearest rank).
    pub p99: f64,
    /// Pixels the sphere covers.
    pub pixels: usize,
}

/// The materials of the report: name and material.
fn materials() -> Vec<(String, Material)> {
    let bp = |a: f32| {
        (
            format!("blinn-phong exponent {a}"),
            Material::from(BlinnPhong {
                kd: Vec3::ZERO,
                ks: Vec3::ONE,
                exponent: a,
            }),
        )
    };
    vec![
        (
            "lambert".to_string(),
            Material::from(Lambert {
                albedo: Vec3::splat(0.8),
            }),
        ),
        bp(50.0),
        bp(200.0),
    ]
}

/// The unit sphere of the report, `size` pixels square, lit by `lights`.
fn sphere(size: u32, material: Material, lights: &LightSet) -> Scene {
    let toml = format!(
        "[mesh]\nsource = \"sphere\"\n[render]\nwidth = {size}\nheight = {size}\nprecision = \"f64\"\n"
    );
    let file = SceneFile::parse(&toml).expect("the report's sphere scene parses");
    let mut s = Scene::resolve(&file, std::path::Path::new("/"))
        .expect("the report's sphere scene resolves");
    s.material = material;
    s.lights = to_scene_lights(lights);
    s
}

/// The errors of `lights` against the full probe `probe` on the report's spheres,
/// `size` pixels square (module doc), in the order Lambert, Blinn-Phong 50, 200.
pub fn sphere_errors(probe: &Probe, lights: &LightSet, size: u32) -> Vec<SphereError> {
    let full = SamplerConfig::Full.run(probe);
    let opts = RenderOptions::converged_reference();
    materials()
        .into_iter()
        .map(|(name, m)| {
            let got = render(&sphere(size, m.clone(), lights), &opts).image;
            let want = render(&sphere(size, m, &full), &opts).image;
            let covered: Vec<(DVec3, DVec3)> = got
                .pixels
                .iter()
                .zip(&want.pixels)
                .filter(|(g, w)| **g != Vec3::ZERO || **w != Vec3::ZERO)
                .map(|(g, w)| (g.as_dvec3(), w.as_dvec3()))
                .collect();
            let (a, b): (Vec<DVec3>, Vec<DVec3>) = covered.iter().copied().unzip();
            let (num, den) = crate::metrics::squared_error_sums(&a, &b);
            let peak = b.iter().map(|x| x.length()).fold(0.0, f64::max);
            let mut rel: Vec<f64> = covered
                .iter()
                .filter(|(_, w)| w.length() >= 0.01 * peak && peak > 0.0)
                .map(|(g, w)| (*g - *w).length() / w.length())
                .collect();
            rel.sort_by(f64::total_cmp);
            let p99 = if rel.is_empty() {
                0.0
            } else {
                rel[((0.99 * rel.len() as f64).ceil() as usize).clamp(1, rel.len()) - 1]
            };
            SphereError {
                material: name,
                rel_rmse: crate::metrics::relative_l2(num, den),
                p99,
                pixels: covered.len(),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::env::LoadOptions;

    /// A small probe: dim sky, one bright 2x2 patch (a sun) and a dimmer one.
    fn probe() -> Probe {
        let (w, h) = (32, 16);
        let mut t = vec![[0.2f32, 0.25, 0.3]; w * h];
        for (r, c, v) in [
            (3, 5, 40.0),
            (3, 6, 40.0),
            (4, 5, 40.0),
            (4, 6, 40.0),
            (9, 20, 8.0),
        ] {
            t[r * w + c] = [v; 3];
        }
        Probe::from_texels("report", w, h, t, &LoadOptions::default())
            .unwrap()
            .0
    }

    #[test]
    fn the_full_probe_as_light_set_has_no_error_and_few_lights_have_glossy_error() {
        let p = probe();
        let full = SamplerConfig::Full.run(&p);
        for e in sphere_errors(&p, &full, 24) {
            assert!(e.pixels > 300, "{e:?}");
            assert_eq!((e.rel_rmse, e.p99), (0.0, 0.0), "{e:?}");
        }
        // 16 median-cut lights: the narrower the lobe, the larger the error, and the sphere's
        // error is well above the irradiance error the report already printed.
        let few = SamplerConfig::MedianCut { n: 16 }.run(&p);
        let e = sphere_errors(&p, &few, 24);
        let normals = crate::env::lightset::fibonacci_sphere(256);
        let irr = crate::env::lightset::irradiance_error(
            &few,
            &normals,
            &crate::env::lightset::reference_irradiance_many(&p, &normals),
        );
        eprintln!("irradiance error {irr:.4}; {e:?}");
        assert!(
            e[0].rel_rmse > 0.0 && e[0].p99 >= e[0].rel_rmse * 0.5,
            "{e:?}"
        );
        assert!(e[1].rel_rmse > 2.0 * e[0].rel_rmse, "{e:?}");
        assert!(e[2].rel_rmse > e[1].rel_rmse, "{e:?}");
        assert!(e[2].rel_rmse > 5.0 * irr, "{e:?} vs irradiance {irr}");
    }
}
