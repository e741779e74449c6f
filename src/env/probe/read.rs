//! Reading probe files: OpenEXR (any compression, RGB or RGBA) and Radiance .hdr, with the
//! declared size checked against [`LoadOptions::max_texels`] and the file length before
//! anything is decoded. Returns the raw texels; cleaning happens in [`super::Probe`].

use super::{LoadOptions, ProbeError};
use std::path::Path;

pub(super) fn check_size(
    path: &Path,
    width: usize,
    height: usize,
    opts: &LoadOptions,
) -> Result<(), ProbeError> {
    if width == 0 || height == 0 {
        return Err(ProbeError::Empty {
            path: path.to_path_buf(),
            width,
            height,
        });
    }
    if width
        .checked_mul(height)
        .is_none_or(|n| n > opts.max_texels)
    {
        return Err(ProbeError::TooLarge {
            path: path.to_path_buf(),
            width,
            height,
            max_texels: opts.max_texels,
        });
    }
    Ok(())
}

pub(super) type Raw = (usize, usize, Vec<[f32; 3]>);

pub(super) fn read_exr(path: &Path, opts: &LoadOptions) -> Result<Raw, ProbeError> {
    use crate::image_io::exr_guard::{self, ExrGuardError};
    use exr::prelude::*;
    let decode_err = |e: exr::error::Error| match e {
        exr::error::Error::Io(source) => ProbeError::Io {
            path: path.to_path_buf(),
            source,
        },
        other => ProbeError::Decode {
            path: path.to_path_buf(),
            message: other.to_string(),
        },
    };
    // Read only the headers first, so an absurd data window is rejected before any
    // pixel allocation (the crate's one guarded EXR reader, `image_io::exr_guard`).
    let guard_err = |e: ExrGuardError| match e {
        ExrGuardError::File(e) => ProbeError::File(e),
        ExrGuardError::Exr(e) => decode_err(e),
        ExrGuardError::DeclaredSize(message) => ProbeError::Decode {
            path: path.to_path_buf(),
            message,
        },
    };
    let headers =
        exr_guard::read_headers(path, crate::env::probe::MAX_PROBE_FILE_BYTES, "light probe")
            .map_err(guard_err)?;
    let header = headers
        .headers()
        .first()
        .ok_or_else(|| ProbeError::Decode {
            path: path.to_path_buf(),
            message: "no layer".into(),
        })?;
    let size = header.layer_size;
    check_size(path, size.width(), size.height(), opts)?;

    struct Px {
        w: usize,
        data: Vec<[f32; 3]>,
    }
    let image = headers
        .decode(|path| {
            read()
                .no_deep_data()
                .largest_resolution_level()
                .rgba_channels(
                    |res: Vec2<usize>, _| Px {
                        w: res.width(),
                        data: vec![[0.0; 3]; res.width() * res.height()],
                    },
                    |px: &mut Px, pos: Vec2<usize>, (r, g, b, _a): (f32, f32, f32, f32)| {
                        let w = px.w;
                        px.data[pos.y() * w + pos.x()] = [r, g, b];
                    },
                )
                .first_valid_layer()
                .all_attributes()
                .from_file(path)
        })
        .map_err(guard_err)?;
    let layer = image.layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    check_size(path, w, h, opts)?;
    Ok((w, h, layer.channel_data.pixels.data))
}

/// Texels a Radiance file may declare per byte of file: run-length encoded scan lines
/// spend at least 2 bytes per run of at most 127 values of one component, so a texel costs
/// at least 8/127 of a byte; 16 texels per byte is that bound rounded up.
pub const HDR_TEXELS_PER_BYTE: u64 = 16;
/// Texels any Radiance file may declare whatever its length (12 MiB of f32 RGB), which
/// admits the rare old-style run-length files that compress better than
/// [`HDR_TEXELS_PER_BYTE`].
pub const HDR_TEXEL_SLACK: u64 = 1 << 20;

pub(super) fn read_hdr(path: &Path, opts: &LoadOptions) -> Result<Raw, ProbeError> {
    let io_err = |source| ProbeError::Io {
        path: path.to_path_buf(),
        source,
    };
    let decode_err = |e: image::ImageError| ProbeError::Decode {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let file = std::fs::File::open(path).map_err(io_err)?;
    let mut reader =
        image::ImageReader::with_format(std::io::BufReader::new(file), image::ImageFormat::Hdr);
    let mut limits = image::Limits::default();
    // 16 bytes per texel covers the decoder's f32 RGB output plus its scratch line.
    limits.max_alloc = Some((opts.max_texels as u64).saturating_mul(16));
    reader.limits(limits);
    let (w, h) = reader.into_dimensions().map_err(decode_err)?;
    check_size(path, w as usize, h as usize, opts)?;
    // The header's resolution is checked against the file length before the decoder
    // allocates for it (a 100-byte file must not claim 2^26 texels).
    let file_len = std::fs::metadata(path).map_err(io_err)?.len();
    let justified = file_len
        .saturating_mul(HDR_TEXELS_PER_BYTE)
        .saturating_add(HDR_TEXEL_SLACK);
    if (w as u64) * (h as u64) > justified {
        return Err(ProbeError::Decode {
            path: path.to_path_buf(),
            message: format!(
                "header declares {w}x{h} texels, more than a {file_len}-byte Radiance file can hold"
            ),
        });
    }
    let file = std::fs::File::open(path).map_err(io_err)?;
    let mut reader =
        image::ImageReader::with_format(std::io::BufReader::new(file), image::ImageFormat::Hdr);
    let mut limits = image::Limits::default();
    limits.max_alloc = Some((opts.max_texels as u64).saturating_mul(16));
    limits.max_image_width = Some(w);
    limits.max_image_height = Some(h);
    reader.limits(limits);
    let img = reader.decode().map_err(decode_err)?.into_rgb32f();
    let (w, h) = (img.width() as usize, img.height() as usize);
    let data = img
        .into_raw()
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    Ok((w, h, data))
}
