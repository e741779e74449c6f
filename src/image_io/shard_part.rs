//! The partial image one shard of a sharded still writes (`brdfkit render --shard I/N`) and
//! `brdfkit render --merge` reads: an OpenEXR file whose one RGB f32 layer holds the rows the
//! shard owns, stacked top to bottom in image order (so it is `width` wide and as high as
//! the shard's rows), and whose attributes say where they go and what they are of:
//!
//! | attribute | type | meaning |
//! |---|---|---|
//! | `brdfkit.format` | string | `render-shard` |
//! | `brdfkit.version` | int | [`PART_VERSION`] |
//! | `brdfkit.shard` | string | `I/N`, 0-based |
//! | `brdfkit.shard.rows` | int | image rows per band (band `b` belongs to shard `b % N`) |
//! | `brdfkit.shard.width`, `brdfkit.shard.height` | int | the full image's size in pixels |
//! | `brdfkit.shard.scene` | string | the hash of the scene and render options (`xxh3-64:...`) |
//! | `brdfkit.shard.aov` | string | the AOV rendered, `none` for the shaded image |
//! | `brdfkit.shard.exposure` | float | the scene's exposure (stops), for a merged PNG |
//! | `brdfkit.shard.tonemap` | string | the scene's tone map, for a merged PNG |
//!
//! Design rule: this file only stores and checks the format (plain numbers and strings);
//! which rows a shard owns and whether the parts of a merge fit together is the command's
//! (`src/cli/render_shard.rs`). A file that lacks an attribute, or whose layer is not the
//! size its attributes declare, is an error naming the file and the attribute.

use super::exr_guard::{self, text, Attributes, ExrGuardError};
use super::{write_atomically, MAX_EXR_FILE_BYTES};
use crate::error::{Error, Result};
use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image as ExrImage, Layer,
    LayerAttributes, WritableImage,
};
use glam::Vec3;
use std::path::Path;

/// `brdfkit.format` of a shard's partial image.
pub const PART_FORMAT: &str = "render-shard";
/// `brdfkit.version` of the format this build writes and reads.
pub const PART_VERSION: i32 = 1;

/// What a partial image's attributes record (the module doc's table).
#[derive(Clone, Debug, PartialEq)]
pub struct PartHeader {
    /// The shard, `index` of `count` (0-based).
    pub index: usize,
    pub count: usize,
    /// Image rows per band.
    pub rows: u32,
    /// The full image's size.
    pub width: u32,
    pub height: u32,
    /// The scene hash, [`crate::hash::tagged`].
    pub scene: String,
    /// The AOV's name, or `none`.
    pub aov: String,
    pub exposure: f32,
    /// The tone map's name.
    pub tonemap: String,
}

/// A partial image read back: its header and its rows (`width` x `pixels.len() / width`,
/// row-major, the shard's rows in image order).
#[derive(Clone, Debug)]
pub struct Part {
    pub header: PartHeader,
    pub pixels: Vec<Vec3>,
}

/// Writes `pixels` (the shard's rows, row-major, `header.width` wide) with `header` to
/// `path`, atomically ([`write_atomically`]): nothing appears under `path` on failure.
pub fn write_part(path: &Path, header: &PartHeader, pixels: &[Vec3]) -> Result<()> {
    let w = header.width as usize;
    assert!(w > 0 && !pixels.is_empty() && pixels.len().is_multiple_of(w));
    let h = pixels.len() / w;
    let mut attrs = LayerAttributes::named(text("rgb"));
    let o = &mut attrs.other;
    let s = |v: &str| AttributeValue::Text(text(v));
    o.insert(text("brdfkit.format"), s(PART_FORMAT));
    o.insert(text("brdfkit.version"), AttributeValue::I32(PART_VERSION));
    o.insert(
        text("brdfkit.shard"),
        s(&format!("{}/{}", header.index, header.count)),
    );
    o.insert(
        text("brdfkit.shard.rows"),
        AttributeValue::I32(header.rows as i32),
    );
    o.insert(
        text("brdfkit.shard.width"),
        AttributeValue::I32(header.width as i32),
    );
    o.insert(
        text("brdfkit.shard.height"),
        AttributeValue::I32(header.height as i32),
    );
    o.insert(text("brdfkit.shard.scene"), s(&header.scene));
    o.insert(text("brdfkit.shard.aov"), s(&header.aov));
    o.insert(
        text("brdfkit.shard.exposure"),
        AttributeValue::F32(header.exposure),
    );
    o.insert(text("brdfkit.shard.tonemap"), s(&header.tonemap));
    let channel = |name: &str, c: usize| {
        AnyChannel::new(
            text(name),
            FlatSamples::F32(pixels.iter().map(|p| p[c]).collect()),
        )
    };
    let channels =
        AnyChannels::sort(vec![channel("R", 0), channel("G", 1), channel("B", 2)].into());
    let image = ExrImage::from_layer(Layer::new((w, h), attrs, Encoding::FAST_LOSSLESS, channels));
    write_atomically(path, |tmp| {
        image
            .write()
            .to_file(tmp)
            .map_err(|e| Error::format(path, format!("cannot write EXR: {e}")))
    })
}

/// Reads a partial image: every attribute of the module doc's table present and of its
/// type, the version this build's, the layer `width` wide with R, G and B f32 channels.
/// Errors name `path` (and the attribute).
pub fn read_part(path: &Path) -> Result<Part> {
    let image = exr_guard::read_all_layers(path, MAX_EXR_FILE_BYTES, "render shard").map_err(
        |e| match e {
            ExrGuardError::File(e) => Error::from(e),
            ExrGuardError::Exr(e) => Error::format(path, format!("cannot read EXR: {e}")),
            ExrGuardError::DeclaredSize(m) => Error::format(path, m),
        },
    )?;
    let not_part = || {
        Error::format(
            path,
            format!(
                "not a shard of a still image (no brdfkit.format = \"{PART_FORMAT}\"; `brdfkit render --shard I/N -o PART.exr` writes one)"
            ),
        )
    };
    let layer = image.layer_data.first().ok_or_else(not_part)?;
    let a = Attributes(&layer.attributes.other);
    if a.string("brdfkit.format").as_deref() != Some(PART_FORMAT) {
        return Err(not_part());
    }
    let missing = |name: &str| Error::format(path, format!("{name}: missing or not of its type"));
    let int = |name: &str| {
        a.i32(name)
            .filter(|&v| v > 0)
            .map(|v| v as u32)
            .ok_or_else(|| missing(name))
    };
    let string = |name: &str| a.string(name).ok_or_else(|| missing(name));
    let version = a
        .i32("brdfkit.version")
        .ok_or_else(|| missing("brdfkit.version"))?;
    if version != PART_VERSION {
        return Err(Error::format(
            path,
            format!("brdfkit.version: {version}, this build reads version {PART_VERSION}"),
        ));
    }
    let shard = string("brdfkit.shard")?;
    let (index, count) = shard
        .split_once('/')
        .and_then(|(i, n)| Some((i.parse::<usize>().ok()?, n.parse::<usize>().ok()?)))
        .filter(|&(i, n)| i < n)
        .ok_or_else(|| Error::format(path, format!("brdfkit.shard: {shard:?} is not I/N")))?;
    let header = PartHeader {
        index,
        count,
        rows: int("brdfkit.shard.rows")?,
        width: int("brdfkit.shard.width")?,
        height: int("brdfkit.shard.height")?,
        scene: string("brdfkit.shard.scene")?,
        aov: string("brdfkit.shard.aov")?,
        exposure: a
            .f32("brdfkit.shard.exposure")
            .ok_or_else(|| missing("brdfkit.shard.exposure"))?,
        tonemap: string("brdfkit.shard.tonemap")?,
    };
    if layer.size.0 != header.width as usize {
        return Err(Error::format(
            path,
            format!(
                "the layer is {} pixels wide, brdfkit.shard.width says {}",
                layer.size.0, header.width
            ),
        ));
    }
    let channel = |name: &str| {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.bytes() == name.as_bytes())
            .and_then(|c| match &c.sample_data {
                FlatSamples::F32(v) => Some(v),
                _ => None,
            })
            .ok_or_else(|| Error::format(path, format!("no f32 channel {name}")))
    };
    let (r, g, b) = (channel("R")?, channel("G")?, channel("B")?);
    let pixels = r
        .iter()
        .zip(g)
        .zip(b)
        .map(|((&r, &g), &b)| Vec3::new(r, g, b))
        .collect();
    Ok(Part { header, pixels })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> PartHeader {
        PartHeader {
            index: 1,
            count: 3,
            rows: 8,
            width: 4,
            height: 20,
            scene: "xxh3-64:0123456789abcdef".into(),
            aov: "none".into(),
            exposure: -0.5,
            tonemap: "aces".into(),
        }
    }

    #[test]
    fn round_trips_bits_and_header() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("part.exr");
        let pixels: Vec<Vec3> = (0..4 * 8)
            .map(|i| Vec3::new(i as f32 * 0.1, -1e-30, f32::MIN_POSITIVE))
            .collect();
        write_part(&p, &header(), &pixels).unwrap();
        let back = read_part(&p).unwrap();
        assert_eq!(back.header, header());
        assert_eq!(
            back.pixels
                .iter()
                .flat_map(|v| v.to_array().map(f32::to_bits))
                .collect::<Vec<_>>(),
            pixels
                .iter()
                .flat_map(|v| v.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        );
    }

    #[test]
    fn a_plain_exr_is_not_a_part() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("plain.exr");
        crate::image_io::write_exr(&p, &crate::image_io::Image::new(4, 4)).unwrap();
        let e = read_part(&p).unwrap_err().to_string();
        assert!(e.starts_with(&p.display().to_string()), "{e}");
        assert!(e.contains("not a shard"), "{e}");
    }
}
