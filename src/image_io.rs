//! Images out: linear float OpenEXR, and 8-bit sRGB PNG through exposure and a tone map.
//!
//! Design rule: the renderer's result is linear RGB radiance in f32; display encoding
//! happens only here, in one documented order: `x * 2^exposure`, then the tone map, then
//! the sRGB transfer curve (IEC 61966-2-1), then rounding to 8 bits. Every file is written
//! to a unique temporary name in the target directory, synced and renamed into place
//! ([`replace_via_temp`]), so a failed or interrupted write never leaves a half-written
//! file under the requested name.
//!
//! Reading: [`check_regular_file`] / [`read_regular_file`] guard every reader of the crate
//! against devices, FIFOs and oversized files; [`exr_guard`] is the one guarded OpenEXR
//! reader (declared pixels checked against the file's length before decoding), which
//! [`read_exr`] and the SH, D-BRDF and light-probe readers use.

mod atomic;
pub mod display;
pub mod exr_guard;
pub mod interrupt;
mod output_check;
pub mod shard_part;

pub use atomic::replace_via_temp;
pub use display::{display_u8, encode_u8, srgb_encode, to_u8, Tonemap};
pub use exr_guard::{
    check_exr_declared_size, exr_max_expansion, EXR_DECODE_SLACK, MAX_EXR_FILE_BYTES,
};
pub use interrupt::remove_temporary_files_on_signals;
pub use output_check::check_output;

use crate::error::{Error, FileError, Result};
use glam::Vec3;
use std::path::Path;

/// A row-major RGB f32 image (row 0 at the top).
#[derive(Clone, Debug, Default, PartialEq)]
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

/// [`replace_via_temp`] with the crate's [`Error`].
pub fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    replace_via_temp(path, write, |e| Error::io(path, "cannot write output", e))
}

/// Writes `bytes` to `path` atomically: a unique temporary sibling file, synced, then
/// renamed over `path` ([`replace_via_temp`]). Fails with the I/O error;
/// the temporary file is removed on failure.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    replace_via_temp(
        path,
        |tmp| std::io::Write::write_all(&mut std::fs::File::create(tmp)?, bytes),
        |e| e,
    )
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

/// Reads an OpenEXR file's RGB channels (first layer) into an [`Image`].
///
/// Read through the guarded reader [`exr_guard`]. Fails with an error naming the file if it
/// is not a regular file of at most [`MAX_EXR_FILE_BYTES`], cannot be read or decoded, or if
/// its header declares more pixels than its length can hold ([`check_exr_declared_size`]).
pub fn read_exr(path: &Path) -> Result<Image> {
    read_exr_rgba(path).map(|(img, _)| img)
}

/// [`read_exr`] with the alpha channel: the image's RGB and one alpha value per pixel
/// (row-major; 1 for every pixel of a file without an `A` channel, as the `exr` crate's
/// RGBA reader fills it).
pub fn read_exr_rgba(path: &Path) -> Result<(Image, Vec<f32>)> {
    let img = exr_guard::read_headers(path, MAX_EXR_FILE_BYTES, "EXR image")
        .and_then(|h| {
            h.decode(|path| {
                exr::prelude::read_first_rgba_layer_from_file(
                    path,
                    |res, _| {
                        let (w, h) = (res.width() as u32, res.height() as u32);
                        (Image::new(w, h), vec![1.0f32; res.width() * res.height()])
                    },
                    |(img, alpha): &mut (Image, Vec<f32>),
                     pos: exr::prelude::Vec2<usize>,
                     (r, g, b, a): (f32, f32, f32, f32)| {
                        let i = pos.y() * img.width as usize + pos.x();
                        img.pixels[i] = Vec3::new(r, g, b);
                        alpha[i] = a;
                    },
                )
            })
        })
        .map_err(|e| match e {
            exr_guard::ExrGuardError::File(e) => Error::from(e),
            exr_guard::ExrGuardError::Exr(e) => {
                Error::format(path, format!("cannot read EXR: {e}"))
            }
            exr_guard::ExrGuardError::DeclaredSize(m) => Error::format(path, m),
        })?;
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
