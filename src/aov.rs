//! Debug outputs (arbitrary output variables), chosen with `--aov NAME`.
//!
//! Each AOV is an RGB image whose EXR values are documented below; the PNG encoding maps
//! them to [0, 1] linearly (no exposure, no tone map, no sRGB curve) so that grey levels
//! read as values, as in the thesis's Figures 3.1-3.3. Angles are shown as the texture
//! coordinates of `conventions::hemi_texcoord`: polar / (pi/2) and azimuth / (2 pi).
//! Azimuths are measured in the world-up frame ([`ShadingFrame::from_normal`], the frame of
//! the thesis's figures), whatever the material: an isotropic tabulated material is shaded
//! in a frame turned to its view (`conventions`, "Frame of isotropic tabulated
//! materials"), where the view azimuth would be one constant.
//! Pixels without a surface are 0.

use crate::conventions::{hemi_texcoord, local_angles, ShadingFrame};
use crate::image_io::Image;
use crate::raster::VisBuffer;
use crate::scene::Scene;
use crate::shade::{local_view, surface_at};
use glam::Vec3;
use rayon::prelude::*;

/// The available AOVs.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Deserialize, serde::Serialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Aov {
    /// World shading normal (flipped towards the viewer on back faces); PNG: n/2 + 1/2.
    Normal,
    /// View-axis distance of the visible surface (scene units); PNG: divided by the largest.
    Depth,
    /// Number of triangles covering each pixel centre (before the depth test); PNG: count/2.
    Coverage,
    /// Polar angle of the view vector over pi/2 (thesis Fig. 3.3 left).
    ViewPolar,
    /// Azimuth of the view vector over 2 pi (thesis Fig. 3.3 right).
    ViewAzimuth,
    /// Polar angle of the first light over pi/2; above 1 below the horizon (Fig. 3.1/3.2 left).
    LightPolar,
    /// Azimuth of the first light over 2 pi (thesis Fig. 3.1/3.2 right).
    LightAzimuth,
}

impl Aov {
    /// Whether the AOV needs the per-pixel coverage count from the rasterizer.
    pub fn needs_coverage(self) -> bool {
        self == Aov::Coverage
    }

    /// The name `--aov` takes (`light-polar`, ...).
    pub fn name(self) -> String {
        use clap::ValueEnum;
        self.to_possible_value()
            .map(|v| v.get_name().to_string())
            .unwrap_or_default()
    }
}

/// Refuses an AOV that `scene` does not produce, with a field error naming `--aov`, the
/// AOV and why. `light-polar` and `light-azimuth` show the first light of the scene's light
/// list (`[[light]]` tables, then an environment's delta lights): an environment shaded by
/// light cuts, or by a transfer table without exact lights, has no such list, and the
/// image would be black everywhere.
pub fn check_available(scene: &Scene, aov: Aov) -> crate::error::Result<()> {
    if !matches!(aov, Aov::LightPolar | Aov::LightAzimuth) || !scene.delta_lights().is_empty() {
        return Ok(());
    }
    let why = scene.environment.why_no_light_list();
    Err(crate::error::Error::field(
        "--aov",
        format!(
            "{} shows the scene's first light, and there is none: {why}",
            aov.name()
        ),
    ))
}

/// Computes an AOV image from a visibility buffer.
pub fn compute(scene: &Scene, vis: &VisBuffer, aov: Aov) -> Image {
    compute_counted(scene, vis, aov).0
}

/// [`compute`], also returning the number of pixels whose value was computed (every pixel
/// for `coverage`, the pixels with a visible surface otherwise; counted per row, summed
/// after).
pub fn compute_counted(scene: &Scene, vis: &VisBuffer, aov: Aov) -> (Image, u64) {
    let mut img = Image::new(vis.width, vis.height);
    if aov == Aov::Coverage {
        for (p, c) in img.pixels.iter_mut().zip(vis.coverage_row_major()) {
            *p = Vec3::splat(c as f32);
        }
        let n = img.pixels.len() as u64;
        return (img, n);
    }
    let eye = scene.camera.position;
    let lights = scene.delta_lights();
    let first_light = lights.first();
    let counted: u64 = img
        .pixels
        .par_chunks_mut(vis.width as usize)
        .enumerate()
        .map(|(y, row)| {
            let mut n = 0u64;
            for (x, out) in row.iter_mut().enumerate() {
                let Some(s) = surface_at(&scene.mesh, vis, x as u32, y as u32) else {
                    continue;
                };
                n += 1;
                let frame = ShadingFrame::from_normal(s.normal);
                *out = match aov {
                    Aov::Normal => s.normal,
                    Aov::Depth => Vec3::splat(s.view_depth),
                    Aov::Coverage => unreachable!(),
                    Aov::ViewPolar | Aov::ViewAzimuth => {
                        let (p, a) = local_angles(local_view(&frame, &s, eye));
                        let (ts, tt) = hemi_texcoord(p, a);
                        Vec3::splat(if aov == Aov::ViewPolar { tt } else { ts })
                    }
                    Aov::LightPolar | Aov::LightAzimuth => match first_light {
                        None => Vec3::ZERO,
                        Some(l) => {
                            let (dir, _) = l.at(s.position);
                            let (p, a) = local_angles(frame.to_local(dir));
                            let (ts, tt) = hemi_texcoord(p, a);
                            Vec3::splat(if aov == Aov::LightPolar { tt } else { ts })
                        }
                    },
                };
            }
            n
        })
        .sum();
    (img, counted)
}

/// Maps AOV values to [0, 1] for an 8-bit PNG (see the module doc).
pub fn png_bytes(img: &Image, aov: Aov) -> Vec<u8> {
    let max_depth = img
        .pixels
        .iter()
        .map(|p| p.x)
        .fold(0.0f32, f32::max)
        .max(f32::MIN_POSITIVE);
    img.pixels
        .iter()
        .flat_map(|p| {
            let v = match aov {
                Aov::Normal => {
                    if *p == Vec3::ZERO {
                        Vec3::ZERO
                    } else {
                        *p * 0.5 + 0.5
                    }
                }
                Aov::Depth => *p / max_depth,
                Aov::Coverage => *p * 0.5,
                _ => *p,
            };
            v.to_array().map(crate::image_io::to_u8)
        })
        .collect()
}
