//! Images out: linear float OpenEXR, and 8-bit sRGB PNG through exposure and a tone map.
//!
//! Design rule: the renderer's result is linear RGB radiance in f32; display encoding
//! happens only here, in one documented order: `x * 2^exposure`, then the tone map, then
//! the sRGB transfer curve (IEC 61966-2-1), then rounding to 8 bits. Every file is written
//! to a unique temporary name in the target directory, synced and renamed into place
//! ([`replace_via_temp`]), so a failed or interrupted write never leaves a half-written
//! file under the requested name.

mod atomic;

pub use atomic::replace_via_temp;

use crate::error::{Error, FileError, Result};
use glam::Vec3;
use serde::Deserialize;
use std::path::Path;

/// A row-major RGB f32 image (row 0 at the top).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

impl Image {
    pub fn new(width: u32, height: u32) -> Image {
        Image {
            width,
            height,
            pixels: vec![Vec3::ZERO; (width * height) as usize],
        }
    }
    #[inline]
    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }
}

/// Tone maps applied to exposed linear values before the sRGB curve.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize, serde::Serialize, clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Tonemap {
    /// `min(x, 1)` per channel: exact for values in [0, 1], clips highlights.
    Clamp,
    /// Reinhard 2002, per channel: `x / (1 + x)`.
    Reinhard,
    /// Narkowicz 2015 fit of the ACES filmic curve, per channel:
    /// `x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`, clamped to [0, 1].
    #[default]
    Aces,
}

impl Tonemap {
    #[inline]
    pub fn apply(self, x: f32) -> f32 {
        let x = x.max(0.0);
        match self {
            Tonemap::Clamp => x.min(1.0),
            Tonemap::Reinhard => x / (1.0 + x),
            Tonemap::Aces => {
                ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
            }
        }
    }
}

/// The sRGB transfer curve (linear [0, 1] to encoded [0, 1]).
#[inline]
pub fn srgb_encode(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Encoded [0, 1] to 8 bits by rounding; NaN maps to 0.
#[inline]
pub fn to_u8(x: f32) -> u8 {
    if x.is_nan() {
        0
    } else {
        (x.clamp(0.0, 1.0) * 255.0).round() as u8
    }
}

/// Display encoding of one linear value: exposure, tone map, sRGB, 8 bits.
#[inline]
pub fn display_u8(x: f32, exposure: f32, tonemap: Tonemap) -> u8 {
    to_u8(srgb_encode(tonemap.apply(x * exposure.exp2())))
}

/// [`replace_via_temp`] with the crate's [`Error`].
pub fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    replace_via_temp(path, write, |e| Error::io(path, "cannot write output", e))
}

/// Writes linear RGB as a 32-bit float OpenEXR file.
pub fn write_exr(path: &Path, img: &Image) -> Result<()> {
    write_atomically(path, |tmp| {
        let w = img.width as usize;
        exr::prelude::write_rgb_file(tmp, w, img.height as usize, |x, y| {
            let p = img.pixels[y * w + x];
            (p.x, p.y, p.z)
        })
        .map_err(|e| Error::format(path, format!("cannot write EXR: {e}")))
    })
}

/// Writes 8-bit RGB bytes (row-major) as PNG.
pub fn write_png_bytes(path: &Path, width: u32, height: u32, rgb: Vec<u8>) -> Result<()> {
    write_atomically(path, |tmp| {
        let buf =
            image::RgbImage::from_raw(width, height, rgb).expect("buffer matches the image size");
        buf.save_with_format(tmp, image::ImageFormat::Png)
            .map_err(|e| Error::format(path, format!("cannot write PNG: {e}")))
    })
}

/// Writes a linear image as an sRGB PNG through exposure (stops) and a tone map.
pub fn write_png(path: &Path, img: &Image, exposure: f32, tonemap: Tonemap) -> Result<()> {
    let bytes = img
        .pixels
        .iter()
        .flat_map(|p| p.to_array().map(|c| display_u8(c, exposure, tonemap)))
        .collect();
    write_png_bytes(path, img.width, img.height, bytes)
}

/// Checks that `path` is a regular file of at most `limit` bytes, without opening it, and
/// returns its length. `what` names the kind of file in the error ("scene file").
///
/// Every reader calls this (or [`read_regular_file`]) first: a device such as `/dev/zero`
/// reports length 0 and never ends, and opening a FIFO blocks until a writer appears, so a
/// length check alone does not bound either. Fails with [`FileError`] naming the file.
pub fn check_regular_file(
    path: &Path,
    limit: u64,
    what: &'static str,
) -> std::result::Result<u64, FileError> {
    let meta = std::fs::metadata(path).map_err(|source| FileError::Io {
        path: path.to_owned(),
        what,
        source,
    })?;
    if !meta.is_file() {
        return Err(FileError::NotRegular {
            path: path.to_owned(),
            what,
        });
    }
    if meta.len() > limit {
        return Err(FileError::TooLarge {
            path: path.to_owned(),
            what,
            len: meta.len(),
            limit,
        });
    }
    Ok(meta.len())
}

/// Reads a whole regular file of at most `limit` bytes ([`check_regular_file`]). The read
/// itself stops one byte past `limit`, so a file that grows after the check is still
/// refused rather than read without bound. Fails with [`FileError`] naming the file.
pub fn read_regular_file(
    path: &Path,
    limit: u64,
    what: &'static str,
) -> std::result::Result<Vec<u8>, FileError> {
    use std::io::Read;
    let len = check_regular_file(path, limit, what)?;
    let io = |source| FileError::Io {
        path: path.to_owned(),
        what,
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    // `len <= limit`, so the capacity is bounded by the caller's limit.
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(FileError::TooLarge {
            path: path.to_owned(),
            what,
            len: bytes.len() as u64,
            limit,
        });
    }
    Ok(bytes)
}

/// [`read_regular_file`] for text: also fails (naming the file) on invalid UTF-8.
pub fn read_regular_text(
    path: &Path,
    limit: u64,
    what: &'static str,
) -> std::result::Result<String, FileError> {
    let bytes = read_regular_file(path, limit, what)?;
    String::from_utf8(bytes).map_err(|e| FileError::Io {
        path: path.to_owned(),
        what,
        source: std::io::Error::new(std::io::ErrorKind::InvalidData, e.utf8_error()),
    })
}

/// Largest EXR file (image, SH data set, D-BRDF table) any reader opens: 1 GiB, far above
/// the assets (a 10-band SH data set on a 64 x 64 grid is 5 MB) and small enough that the
/// decoders' allocations, bounded by [`check_exr_declared_size`], stay bounded too.
pub const MAX_EXR_FILE_BYTES: u64 = 1 << 30;

/// Bytes any EXR file may declare (decoded, all parts) whatever its length.
pub const EXR_DECODE_SLACK: u64 = 16 << 20;

/// The largest factor by which an EXR compression can expand data: exact for none (1),
/// RLE (a 2-byte run of at most 128 bytes: 64) and ZIP/ZIPS/PXR24 (deflate's 1032:1,
/// rounded up, with PXR24's 24-to-32-bit widening); PIZ, B44 and DWA have no small bound,
/// and 4096 is assumed (far above what photographic images reach).
pub fn exr_max_expansion(c: exr::compression::Compression) -> u64 {
    use exr::compression::Compression as C;
    match c {
        C::Uncompressed => 1,
        C::RLE => 64,
        C::ZIP1 | C::ZIP16 => 1100,
        C::PXR24 => 1500,
        _ => 4096,
    }
}

/// Checks the pixel bytes an EXR file's headers declare (every part, largest level, plus
/// one tile block per tiled part) against what a file of `file_len` bytes can hold: at most
/// [`exr_max_expansion`] x `file_len` + [`EXR_DECODE_SLACK`]. Call it on the headers
/// (`exr::meta::MetaData::read_from_file`) before decoding: the `exr` crate allocates
/// every declared pixel up front. Fails with a message (without the path) naming the
/// declared size.
pub fn check_exr_declared_size(
    headers: &[exr::meta::header::Header],
    file_len: u64,
) -> std::result::Result<(), String> {
    let mut declared: u64 = 0;
    let mut limit: u64 = 0;
    for h in headers {
        let (w, ht) = (h.layer_size.width() as u64, h.layer_size.height() as u64);
        let bpp = h.channels.bytes_per_pixel as u64;
        let bytes = w.saturating_mul(ht).saturating_mul(bpp);
        declared = declared.saturating_add(bytes);
        // The decoder allocates one whole block per tile, whatever the data window: a tile
        // description can declare far more pixels than the image (found by fuzzing: 4194304
        // x 64 pixel tiles in a 1109-byte file, a 704 MB allocation).
        if let exr::meta::BlockDescription::Tiles(t) = h.blocks {
            let tile = (t.tile_size.width() as u64)
                .saturating_mul(t.tile_size.height() as u64)
                .saturating_mul(bpp);
            declared = declared.saturating_add(tile);
        }
        limit = limit.max(file_len.saturating_mul(exr_max_expansion(h.compression)));
    }
    let limit = limit.saturating_add(EXR_DECODE_SLACK);
    if declared > limit {
        let sizes: Vec<String> = headers
            .iter()
            .map(|h| format!("{}x{}", h.layer_size.width(), h.layer_size.height()))
            .collect();
        return Err(format!(
            "EXR header declares {} pixels ({declared} bytes), more than a {file_len}-byte file can hold",
            sizes.join(" + ")
        ));
    }
    Ok(())
}

/// Reads an OpenEXR file's RGB channels (first layer) into an [`Image`].
///
/// Fails with an error naming the file if it is not a regular file of at most
/// [`MAX_EXR_FILE_BYTES`], cannot be read or decoded, or if its header
/// declares more pixels than its length can hold ([`check_exr_declared_size`]).
pub fn read_exr(path: &Path) -> Result<Image> {
    check_regular_file(path, MAX_EXR_FILE_BYTES, "EXR image")?;
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| Error::format(path, format!("cannot read EXR: {e}")))?;
    let file_len = std::fs::metadata(path)
        .map_err(|e| Error::io(path, "cannot read EXR", e))?
        .len();
    check_exr_declared_size(&meta.headers, file_len).map_err(|m| Error::format(path, m))?;
    let img = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |res, _| Image::new(res.width() as u32, res.height() as u32),
        |img: &mut Image, pos: exr::prelude::Vec2<usize>, (r, g, b, _a): (f32, f32, f32, f32)| {
            let w = img.width as usize;
            img.pixels[pos.y() * w + pos.x()] = Vec3::new(r, g, b);
        },
    )
    .map_err(|e| Error::format(path, format!("cannot read EXR: {e}")))?;
    Ok(img.layer_data.channel_data.pixels)
}

/// The output format implied by a path's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    Exr,
}

/// Format from the extension (case-insensitive): `.png` or `.exr`; anything else is an
/// error naming the path.
pub fn format_of(path: &Path) -> Result<Format> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .as_deref()
    {
        Some("png") => Ok(Format::Png),
        Some("exr") => Ok(Format::Exr),
        _ => Err(Error::format(
            path,
            "unknown output format: the file name must end in .png or .exr",
        )),
    }
}
