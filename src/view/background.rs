//! The probe behind the object (key `g`, display only): every pixel no triangle covers
//! shows the probe's radiance in that pixel's camera-ray direction, through the same
//! display encoding as the shaded pixels. Screenshots never include it (`brdfkit render`
//! draws no background).

use crate::env::schema::EnvSpec;
use crate::env::{LoadOptions, Probe};
use crate::image_io::display::display_u8;
use crate::raster::{VisBuffer, NO_TRIANGLE};
use crate::scene::OutputSpec;
use std::path::PathBuf;

/// A loaded probe, kept while its file and rotation stay.
pub struct Background {
    file: PathBuf,
    rotation: f64,
    probe: Probe,
}

impl Background {
    /// The probe of `env` (loaded again only when its file or rotation changed).
    pub fn of<'a>(
        kept: &'a mut Option<Background>,
        env: &EnvSpec,
    ) -> Result<&'a Background, String> {
        let fresh = kept
            .as_ref()
            .is_some_and(|b| b.file == env.file && b.rotation == env.rotation);
        if !fresh {
            let opts = LoadOptions {
                rotation: env.rotation.to_radians(),
                zero_non_finite: env.zero_non_finite,
                ..LoadOptions::default()
            };
            let (probe, _) = Probe::load(&env.file, &opts)
                .map_err(|e| format!("{}: {e}", env.file.display()))?;
            *kept = Some(Background {
                file: env.file.clone(),
                rotation: env.rotation,
                probe,
            });
        }
        Ok(kept.as_ref().expect("set above"))
    }

    /// Paints the uncovered pixels of `pixels` (0x00RRGGBB, `vis`'s frame size) with the
    /// probe's radiance times `intensity`, encoded as `output` says. `vis` is the frame's
    /// visibility buffer as [`crate::render::render_into`] leaves it (its camera rays set).
    pub fn paint(&self, vis: &VisBuffer, intensity: f32, output: &OutputSpec, pixels: &mut [u32]) {
        let Some(rays) = vis.rays else {
            return;
        };
        let ts = vis.tile_size;
        let (e, t) = (output.exposure, output.tonemap);
        for y in 0..vis.height {
            for x in 0..vis.width {
                let tile = (y / ts) * vis.tiles_x + x / ts;
                let i = (tile * ts * ts + (y % ts) * ts + x % ts) as usize;
                if vis.visible[i] != NO_TRIANGLE {
                    continue;
                }
                let (row, col) = self.probe.texel_of(rays.dir(x, y).normalize());
                let c = self
                    .probe
                    .texel(row, col)
                    .map(|v| display_u8(v * intensity, e, t));
                pixels[(y * vis.width + x) as usize] =
                    (c[0] as u32) << 16 | (c[1] as u32) << 8 | c[2] as u32;
            }
        }
    }
}
