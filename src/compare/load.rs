//! Reading the two images of a comparison: EXR as linear floats, PNG as 8-bit values
//! scaled to [0, 1], each with its display bytes for FLIP, its channel layout and its
//! alpha channel if it has one.
//!
//! Design rule: every read is bounded before it allocates (file length, side, decoded
//! bytes), and every error names the file.

use crate::error::{Error, Result};
use crate::image_io::{self, Image, Tonemap};
use glam::Vec3;
use std::path::Path;

/// What kind of file an image came from, with its channel layout.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// "EXR" or "PNG".
    pub kind: &'static str,
    /// Channel names, e.g. "RGB", "RGBA", "L".
    pub channels: String,
}

impl Layout {
    /// The colour channels without a trailing alpha: "RGB" for "RGB" and "RGBA", "L" for
    /// "L" and "LA".
    pub fn colour(&self) -> &str {
        self.channels
            .strip_suffix('A')
            .filter(|c| !c.is_empty())
            .unwrap_or(&self.channels)
    }
}

/// A loaded image for comparison: RGB values (linear for EXR, encoded/255 for PNG) and,
/// for FLIP, 8-bit display bytes.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub image: Image,
    pub display: Vec<u8>,
    pub layout: Layout,
    /// Alpha per pixel (row-major; linear for EXR, value/255 for PNG), when the file has
    /// an alpha channel.
    pub alpha: Option<Vec<f32>>,
}

impl Loaded {
    /// A linear image as if loaded from an EXR (display bytes through the same encoding).
    pub fn from_linear(image: Image) -> Loaded {
        let display = image
            .pixels
            .iter()
            .flat_map(|p| {
                p.to_array()
                    .map(|c| image_io::display_u8(c, 0.0, Tonemap::Aces))
            })
            .collect();
        Loaded {
            image,
            display,
            layout: Layout {
                kind: "EXR",
                channels: "RGB".into(),
            },
            alpha: None,
        }
    }
}

/// Largest image side accepted for comparison.
pub const MAX_SIDE: u32 = 1 << 15;

/// Bytes a PNG's decoder may allocate per byte of file (deflate's worst ratio, 1032:1,
/// rounded up).
pub const PNG_MAX_EXPANSION: u64 = 1100;
/// Bytes a PNG's decoder may allocate whatever the file's length.
pub const PNG_ALLOC_SLACK: u64 = 16 << 20;

/// Loads an EXR (R, G, B, optional A) or PNG (any 8/16-bit colour type, alpha kept in
/// [`Loaded::alpha`]). Errors name the
/// file: not a regular file or over [`crate::image_io::MAX_EXR_FILE_BYTES`], unreadable, unknown extension, undecodable or truncated, over [`MAX_SIDE`] per
/// side, missing R/G/B (EXR), or a PNG whose declared size needs more memory than
/// [`PNG_MAX_EXPANSION`] x its length + [`PNG_ALLOC_SLACK`].
pub fn load(path: &Path) -> Result<Loaded> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if matches!(ext.as_deref(), Some("exr" | "png")) {
        crate::image_io::check_regular_file(path, crate::image_io::MAX_EXR_FILE_BYTES, "image")?;
    }
    match ext.as_deref() {
        Some("exr") => {
            let meta = exr::meta::MetaData::read_from_file(path, false)
                .map_err(|e| Error::format(path, format!("cannot read EXR: {e}")))?;
            let header = meta
                .headers
                .first()
                .ok_or_else(|| Error::format(path, "EXR has no layers"))?;
            let names: Vec<String> = header
                .channels
                .list
                .iter()
                .map(|c| c.name.to_string())
                .collect();
            let size = header.layer_size;
            if size.0 as u64 > MAX_SIDE as u64 || size.1 as u64 > MAX_SIDE as u64 {
                return Err(Error::format(
                    path,
                    format!(
                        "EXR is {}x{}, larger than {MAX_SIDE} per side",
                        size.0, size.1
                    ),
                ));
            }
            for c in ["R", "G", "B"] {
                if !names.iter().any(|n| n == c) {
                    return Err(Error::format(
                        path,
                        format!("EXR has channels {names:?}: an R, G and B channel are needed"),
                    ));
                }
            }
            let has_alpha = names.iter().any(|n| n == "A");
            let (image, alpha) = image_io::read_exr_rgba(path)?;
            let mut loaded = Loaded::from_linear(image);
            if has_alpha {
                loaded.layout.channels = "RGBA".into();
                loaded.alpha = Some(alpha);
            }
            Ok(loaded)
        }
        Some("png") => {
            let reader = image::ImageReader::open(path)
                .map_err(|e| Error::io(path, "cannot read PNG", e))?;
            let mut reader = reader
                .with_guessed_format()
                .map_err(|e| Error::io(path, "cannot read PNG", e))?;
            let mut limits = image::Limits::default();
            // Decoded bytes are bounded by what the file's length can hold (deflate expands
            // at most 1032:1) plus a fixed slack, before the decoder allocates.
            let file_len = std::fs::metadata(path)
                .map_err(|e| Error::io(path, "cannot read PNG", e))?
                .len();
            limits.max_alloc = Some(
                file_len
                    .saturating_mul(PNG_MAX_EXPANSION)
                    .saturating_add(PNG_ALLOC_SLACK),
            );
            limits.max_image_width = Some(MAX_SIDE);
            limits.max_image_height = Some(MAX_SIDE);
            reader.limits(limits);
            let img = reader
                .decode()
                .map_err(|e| Error::format(path, format!("cannot decode PNG: {e}")))?;
            let channels = match img.color() {
                image::ColorType::L8 | image::ColorType::L16 => "L",
                image::ColorType::La8 | image::ColorType::La16 => "LA",
                image::ColorType::Rgb8 | image::ColorType::Rgb16 => "RGB",
                image::ColorType::Rgba8 | image::ColorType::Rgba16 => "RGBA",
                _ => "other",
            }
            .to_string();
            let alpha = img.color().has_alpha().then(|| {
                img.to_rgba8()
                    .pixels()
                    .map(|p| p[3] as f32 / 255.0)
                    .collect()
            });
            let rgb = img.to_rgb8();
            let (w, h) = rgb.dimensions();
            let display = rgb.into_raw();
            let pixels = display
                .chunks_exact(3)
                .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) / 255.0)
                .collect();
            Ok(Loaded {
                image: Image {
                    width: w,
                    height: h,
                    pixels,
                },
                display,
                layout: Layout {
                    kind: "PNG",
                    channels,
                },
                alpha,
            })
        }
        _ => Err(Error::format(
            path,
            "unknown image format: compare reads .exr and .png",
        )),
    }
}
