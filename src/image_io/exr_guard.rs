//! The one guarded OpenEXR reader: every EXR file brdfkit opens (SH data sets
//! [`crate::sh::file`], D-BRDF tables [`crate::brdf::dbrdf::file`], light probes
//! [`crate::env::Probe`], images [`super::read_exr`]) is read through [`read_headers`] and
//! [`ExrHeaders::decode`], and its part attributes through [`Attributes`].
//!
//! Design rule: no pixel is decoded before two checks pass, in this order:
//! 1. the path is a regular file of at most the caller's byte limit
//!    ([`super::check_regular_file`]; a device or FIFO is refused unopened), then only the
//!    headers are read;
//! 2. the pixels the headers declare fit what a file of that length can hold
//!    ([`check_exr_declared_size`]): the `exr` crate allocates every declared pixel (and one
//!    whole block per tile) before it reads any.
//!
//! [`ExrHeaders`] is the only way from a path to decoded pixels, so a reader cannot skip the
//! second check; between the two a caller may inspect the headers (the probe reader checks
//! its texel limit there). Errors come back as [`ExrGuardError`], which each format maps into
//! its own error type (naming the file), so messages stay those of the format.

use crate::error::FileError;
use exr::meta::attribute::{AttributeValue, Text};
use exr::meta::header::Header;
use exr::prelude::{AnyChannels, FlatSamples, Image, Layers, ReadChannels, ReadLayers};
use std::collections::HashMap;
use std::path::Path;

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
pub fn check_exr_declared_size(headers: &[Header], file_len: u64) -> Result<(), String> {
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

/// Why a guarded read stopped, before the caller maps it into its format's error.
#[derive(Debug, thiserror::Error)]
pub enum ExrGuardError {
    /// Not a regular file, over the caller's byte limit, or its metadata unreadable.
    #[error(transparent)]
    File(#[from] FileError),
    /// The `exr` crate failed on the headers or the pixels (also I/O errors and truncation).
    #[error("{0}")]
    Exr(exr::error::Error),
    /// The headers declare more pixels than the file's length can hold
    /// ([`check_exr_declared_size`]'s message, without the path).
    #[error("{0}")]
    DeclaredSize(String),
}

/// The headers of an EXR file that passed the first check (a regular file within the byte
/// limit); [`ExrHeaders::decode`] applies the second before any pixel is read.
pub struct ExrHeaders<'a> {
    path: &'a Path,
    file_len: u64,
    meta: exr::meta::MetaData,
}

/// Checks that `path` is a regular file of at most `limit` bytes (`what` names the kind of
/// file in the error, "SH data set"), then reads its headers only. Fails with
/// [`ExrGuardError::File`] or [`ExrGuardError::Exr`].
pub fn read_headers<'a>(
    path: &'a Path,
    limit: u64,
    what: &'static str,
) -> Result<ExrHeaders<'a>, ExrGuardError> {
    let file_len = super::check_regular_file(path, limit, what)?;
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(ExrGuardError::Exr)?;
    Ok(ExrHeaders {
        path,
        file_len,
        meta,
    })
}

impl ExrHeaders<'_> {
    /// The headers, one per part.
    pub fn headers(&self) -> &[Header] {
        &self.meta.headers
    }

    /// The file's length in bytes when it was checked.
    pub fn file_len(&self) -> u64 {
        self.file_len
    }

    /// Checks the declared pixels against the file's length ([`check_exr_declared_size`],
    /// [`ExrGuardError::DeclaredSize`]), then decodes with `read`, called on the file's path
    /// (an `exr` reader; its error becomes [`ExrGuardError::Exr`]).
    pub fn decode<T>(
        self,
        read: impl FnOnce(&Path) -> Result<T, exr::error::Error>,
    ) -> Result<T, ExrGuardError> {
        check_exr_declared_size(&self.meta.headers, self.file_len)
            .map_err(ExrGuardError::DeclaredSize)?;
        read(self.path).map_err(ExrGuardError::Exr)
    }
}

/// Every part of an EXR file with every channel as flat samples and every attribute.
pub type AllLayers = Image<Layers<AnyChannels<FlatSamples>>>;

/// Reads every part, channel and attribute (largest resolution level, no deep data) of a
/// regular EXR file of at most `limit` bytes, through both checks of the module doc.
pub fn read_all_layers(
    path: &Path,
    limit: u64,
    what: &'static str,
) -> Result<AllLayers, ExrGuardError> {
    read_headers(path, limit, what)?.decode(|path| {
        exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .all_layers()
            .all_attributes()
            .from_file(path)
    })
}

/// An attribute name or string value as EXR text: the bytes as they are (UTF-8 allowed, as
/// in provenance strings; `Text::from` would refuse non-ASCII).
pub fn text(s: &str) -> Text {
    Text::from_bytes_unchecked(s.as_bytes().into())
}

/// The custom attributes of one EXR part, looked up by name and type. Every accessor
/// returns `None` for an attribute that is missing *or* of another type: a format reader
/// names the attribute in its own error and never guesses a conversion.
#[derive(Clone, Copy)]
pub struct Attributes<'a>(pub &'a HashMap<Text, AttributeValue>);

impl<'a> Attributes<'a> {
    /// The attribute `name`, any type.
    pub fn get(&self, name: &str) -> Option<&'a AttributeValue> {
        self.0.get(&text(name))
    }

    /// An `int` attribute.
    pub fn i32(&self, name: &str) -> Option<i32> {
        match self.get(name)? {
            AttributeValue::I32(v) => Some(*v),
            _ => None,
        }
    }

    /// A `float` attribute.
    pub fn f32(&self, name: &str) -> Option<f32> {
        match self.get(name)? {
            AttributeValue::F32(v) => Some(*v),
            _ => None,
        }
    }

    /// A `v3f` attribute.
    pub fn v3f(&self, name: &str) -> Option<(f32, f32, f32)> {
        match self.get(name)? {
            AttributeValue::FloatVec3(v) => Some(*v),
            _ => None,
        }
    }

    /// A `string` attribute, its bytes read as UTF-8 (invalid sequences replaced).
    pub fn string(&self, name: &str) -> Option<String> {
        match self.get(name)? {
            AttributeValue::Text(t) => Some(String::from_utf8_lossy(t.bytes()).into_owned()),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A valid 16 x 8 RGB f32 EXR (uncompressed scan lines) whose data window is then
    /// widened to `width` texels: the chunk table still matches, so only the declared-size
    /// check stands between the header and the decoder's allocation.
    fn widened_exr(dir: &Path, width: i32) -> std::path::PathBuf {
        use exr::prelude::*;
        let p = dir.join("wide.exr");
        let layer = Layer::new(
            (16, 8),
            LayerAttributes::named("rgb"),
            Encoding::UNCOMPRESSED,
            SpecificChannels::rgb(|_: Vec2<usize>| (0.5f32, 0.5f32, 0.5f32)),
        );
        Image::from_layer(layer).write().to_file(&p).unwrap();
        let mut b = std::fs::read(&p).unwrap();
        let key = b"dataWindow\0box2i\0";
        let at = b.windows(key.len()).position(|w| w == key).unwrap() + key.len() + 4;
        b[at + 8..at + 12].copy_from_slice(&(width - 1).to_le_bytes());
        std::fs::write(&p, b).unwrap();
        p
    }

    #[test]
    fn decode_is_never_reached_when_the_headers_declare_too_much() {
        let dir = tempfile::tempdir().unwrap();
        // The unpatched width decodes (the check admits a real file) ...
        let p = widened_exr(dir.path(), 16);
        let n = read_headers(&p, MAX_EXR_FILE_BYTES, "test image")
            .unwrap()
            .decode(|_| Ok(1))
            .unwrap();
        assert_eq!(n, 1);
        // ... 2^22 x 8 x 12 bytes (384 MiB) from a file of a few hundred bytes does not.
        let p = widened_exr(dir.path(), 1 << 22);
        let h = read_headers(&p, MAX_EXR_FILE_BYTES, "test image").unwrap();
        assert_eq!(h.headers()[0].layer_size.width(), 1 << 22);
        let r = h.decode(|_| -> Result<(), exr::error::Error> {
            panic!("decoder reached past the declared-size check")
        });
        match r {
            Err(ExrGuardError::DeclaredSize(m)) => assert!(m.contains("4194304x8"), "{m}"),
            other => panic!("{other:?}"),
        }
        // The byte limit is the caller's: a file over it is refused before its headers.
        let r = read_headers(&p, 10, "test image");
        assert!(matches!(
            r,
            Err(ExrGuardError::File(FileError::TooLarge { .. }))
        ));
    }

    #[test]
    fn attributes_are_found_by_name_and_type_only() {
        let mut m = HashMap::new();
        m.insert(text("a.int"), AttributeValue::I32(7));
        m.insert(text("a.float"), AttributeValue::F32(0.25));
        m.insert(text("a.v3f"), AttributeValue::FloatVec3((1.0, 2.0, 3.0)));
        m.insert(text("a.text"), AttributeValue::Text(text("üñí")));
        let a = Attributes(&m);
        assert_eq!(a.i32("a.int"), Some(7));
        assert_eq!(a.f32("a.float"), Some(0.25));
        assert_eq!(a.v3f("a.v3f"), Some((1.0, 2.0, 3.0)));
        assert_eq!(a.string("a.text").as_deref(), Some("üñí"));
        // Wrong type or absent: None, never a conversion.
        assert_eq!(a.i32("a.float"), None);
        assert_eq!(a.f32("a.int"), None);
        assert_eq!(a.string("a.int"), None);
        assert_eq!(a.v3f("a.text"), None);
        assert_eq!(a.i32("absent"), None);
    }
}
