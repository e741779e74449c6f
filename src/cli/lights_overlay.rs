//! Sample-point overlays on a tone-mapped probe (thesis Figures 3.6 and 3.8).
//!
//! Design rule: the overlay draws in the probe's own image space through the same
//! conventions as the samplers: a light direction goes through [`Probe::uv_of`] (rotation
//! undone) to image coordinates `(u, v)`, drawn at pixel `(u W s, v H s)` for scale `s`,
//! so a light at a texel centre lands in the middle of that texel's `s x s` block. Region
//! boundaries are drawn on texel edges. If a dot sits off a bright feature, a sampler or a
//! convention is wrong, not the drawing.

use crate::env::{LightSet, Probe, Region};
use crate::image_io::{encode_u8, Tonemap};
use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Stroke, Transform};

/// How to draw an overlay.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlayOptions {
    /// Exposure of the background in stops: radiance times `2^exposure` before the tone
    /// map, as for rendered PNGs ([`crate::image_io::display_u8`]).
    pub exposure: f32,
    /// Tone map of the background (the crate's one display encoding,
    /// [`crate::image_io::display`]).
    pub tone_map: Tonemap,
    /// Output pixels per probe texel (>= 1).
    pub scale: u32,
    /// Dot radius in output pixels.
    pub dot_radius: f32,
}

impl Default for OverlayOptions {
    fn default() -> Self {
        OverlayOptions {
            exposure: 0.0,
            tone_map: Tonemap::Reinhard,
            scale: 2,
            dot_radius: 2.5,
        }
    }
}

/// Why an overlay could not be made or written; messages name the file.
#[derive(Debug, thiserror::Error)]
pub enum OverlayError {
    #[error("overlay of {width}x{height} pixels cannot be allocated")]
    Size { width: u32, height: u32 },
    #[error("{path}: cannot encode PNG: {message}")]
    Encode {
        path: std::path::PathBuf,
        message: String,
    },
    #[error("{path}: cannot write overlay: {source}")]
    Io {
        path: std::path::PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// Draws the tone-mapped probe with one dot per light (red, black outline; area-free, so
/// zero-irradiance lights show too) and, when given, the median-cut region boundaries (green).
/// Fails only if the image size cannot be allocated.
pub fn render_overlay(
    probe: &Probe,
    lights: &LightSet,
    regions: Option<&[Region]>,
    opts: &OverlayOptions,
) -> Result<Pixmap, OverlayError> {
    let s = opts.scale.max(1);
    // `display_u8`'s product, with the scale computed once.
    let exposure = opts.exposure.exp2();
    let (w, h) = (probe.width() as u32 * s, probe.height() as u32 * s);
    let mut pm = Pixmap::new(w, h).ok_or(OverlayError::Size {
        width: w,
        height: h,
    })?;
    {
        let data = pm.data_mut();
        for y in 0..h {
            for x in 0..w {
                let t = probe.texel((y / s) as usize, (x / s) as usize);
                let i = ((y * w + x) * 4) as usize;
                for c in 0..3 {
                    data[i + c] = encode_u8(t[c] * exposure, opts.tone_map);
                }
                data[i + 3] = 255;
            }
        }
    }
    let sf = s as f32;
    if let Some(regions) = regions {
        let mut pb = PathBuilder::new();
        for r in regions {
            if let Some(rect) = tiny_skia::Rect::from_ltrb(
                r.col0 as f32 * sf,
                r.row0 as f32 * sf,
                r.col1 as f32 * sf,
                r.row1 as f32 * sf,
            ) {
                pb.push_rect(rect);
            }
        }
        if let Some(path) = pb.finish() {
            let mut paint = Paint::default();
            paint.set_color(Color::from_rgba8(40, 220, 60, 200));
            let stroke = Stroke {
                width: 1.0,
                ..Default::default()
            };
            pm.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
        }
    }
    let mut dots = PathBuilder::new();
    for i in 0..lights.len() {
        let (u, v) = probe.uv_of(lights.direction(i));
        dots.push_circle(u as f32 * w as f32, v as f32 * h as f32, opts.dot_radius);
    }
    if let Some(path) = dots.finish() {
        let mut paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        paint.set_color(Color::from_rgba8(255, 30, 30, 255));
        pm.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
        paint.set_color(Color::BLACK);
        let stroke = Stroke {
            width: 1.0,
            ..Default::default()
        };
        pm.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
    }
    Ok(pm)
}

/// [`render_overlay`] written as a PNG to `path` (temporary file, then rename).
pub fn write_overlay_png(
    path: &std::path::Path,
    probe: &Probe,
    lights: &LightSet,
    regions: Option<&[Region]>,
    opts: &OverlayOptions,
) -> Result<(), OverlayError> {
    let pm = render_overlay(probe, lights, regions, opts)?;
    let png = pm.encode_png().map_err(|e| OverlayError::Encode {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    crate::image_io::write_atomic(path, &png).map_err(|source| OverlayError::Io {
        path: path.to_path_buf(),
        source,
    })
}
