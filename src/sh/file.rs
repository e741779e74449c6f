//! The brdfkit SH data-set file: one multichannel, multi-part OpenEXR file that a GPU build
//! can upload as 3D textures (thesis 3.1.4-3.1.5: one texture layer per SH term).
//!
//! Design rule: the file is self-describing. Every convention a reader needs (grid,
//! parameterization, SH normalisation, phase, ordering, cosine flag) is written as a header
//! attribute, and the reader refuses any file whose attributes are missing, unknown or
//! inconsistent rather than guessing.
//!
//! # Format, version 1
//! * OpenEXR, 32-bit float channels, lossless compression (ZIP), scan lines.
//! * Part (layer) `sh-coefficients`, required: image **width = nu** (azimuth texels),
//!   **height = nv** (polar texels). Pixel `(x, y) = (i, j)` holds view texel `(i, j)`;
//!   row `y = 0` (the top of the image in EXR viewers) is the polar texel next to the
//!   normal. One channel per `(l, m)` and colour, named `c.l{l}.m{m}.{R|G|B}`, e.g.
//!   `c.l3.m-2.R`; `3 bands^2` channels in all (EXR stores them sorted by name; readers
//!   find them by name). A GPU build packs channel `c.l{l}.m{m}.X` into depth layer
//!   `k = l*l + l + m` of the colour-X 3D texture and samples it at depth `(k + 1/2)/T`.
//! * Part `sh-basis`, optional: the basis table `Y_lm(light texel)` on its own
//!   `nu_b x nv_b` grid, channels `Y.l{l}.m{m}`.
//! * Attributes of every part (EXR attribute `name: type = value`):
//!   - `brdfkit.format: string = "brdfkit-sh"`, `brdfkit.version: int = 1`,
//!   - `brdfkit.content: string = "coefficients" | "basis"`,
//!   - `brdfkit.bands: int` (L, all l < L; 1..=[`MAX_BANDS`]),
//!   - `brdfkit.nu: int`, `brdfkit.nv: int` (must equal the image size),
//!   - `brdfkit.param: string` = [`PARAMETERIZATION`],
//!   - `brdfkit.sh: string` = [`SH_CONVENTION`],
//!   - `brdfkit.cosine: int` (1 if the values include `cos(polar_i)`, else 0; coefficient
//!     part only),
//!   - `brdfkit.provenance: string` (UTF-8 bytes, free text; coefficient part only),
//!   - `brdfkit.band_threshold: float` (optional, coefficient part only; default
//!     [`DEFAULT_BAND_THRESHOLD`] = 0 when absent): the largest fraction of the
//!     coefficient energy `sum c_lm^2` (over texels, colours, l, m) that a renderer may drop
//!     by shading only the first bands ([`ShDataset::effective_bands`]); must satisfy
//!     `0 <= value < 1`. Written only when non-zero, so files without it stay byte-identical.
//!
//! Reading fails with [`ShFileError`] naming the file and the problem; no partial data set
//! is ever returned. Writing goes to a temporary file in the same directory, then renames
//! it over the target, so a reader never sees a half-written file.

use super::basis::{num_terms, sh_lm};
use super::dataset::{ShBasisTable, ShDataError, ShDataset, DEFAULT_BAND_THRESHOLD, MAX_BANDS};
use exr::prelude::read;
use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image, ImageAttributes,
    IntegerBounds, Layer, LayerAttributes, ReadChannels, ReadLayers, Text, WritableImage,
};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Value of `brdfkit.format`.
pub const FORMAT_NAME: &str = "brdfkit-sh";
/// Value of `brdfkit.version` written by this code; the only version it reads.
pub const FORMAT_VERSION: i32 = 1;
/// Value of `brdfkit.param`: the hemispherical grid parameterization (see
/// [`crate::conventions`]).
pub const PARAMETERIZATION: &str = "hemisphere; s=azimuth/(2pi), t=polar/(pi/2); \
texel (i,j) centre ((i+0.5)/nu, (j+0.5)/nv); azimuth GL_REPEAT, polar GL_CLAMP_TO_EDGE; \
local frame: +z normal, azimuth 0 = world +y projected onto the tangent plane, \
azimuth = atan2(y, x) in [0, 2pi)";
/// Value of `brdfkit.sh`: the SH convention of [`crate::sh::basis`].
pub const SH_CONVENTION: &str = "real; orthonormal over the full sphere; \
no Condon-Shortley phase; m>0 sqrt2 K P cos(m az), m<0 sqrt2 K P sin(|m| az); \
index k = l*l + l + m; polar angle from local +z";

const COEFF_LAYER: &str = "sh-coefficients";
const BASIS_LAYER: &str = "sh-basis";
const COLOURS: [&str; 3] = ["R", "G", "B"];

/// What went wrong with an SH data-set file.
#[derive(Debug, thiserror::Error)]
pub enum ShFileError {
    /// Not a regular file (a device or FIFO is refused unopened), or over
    /// [`crate::image_io::MAX_EXR_FILE_BYTES`].
    #[error(transparent)]
    File(#[from] crate::error::FileError),
    #[error("{path}: I/O error: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: not a readable OpenEXR file: {message}")]
    Exr { path: PathBuf, message: String },
    #[error("{path}: no `{layer}` part")]
    MissingLayer { path: PathBuf, layer: &'static str },
    #[error("{path}: part `{layer}`: attribute `{name}` missing or of the wrong type")]
    MissingAttribute {
        path: PathBuf,
        layer: &'static str,
        name: &'static str,
    },
    #[error("{path}: part `{layer}`: attribute `{name}` has unsupported value `{value}`")]
    BadAttribute {
        path: PathBuf,
        layer: &'static str,
        name: &'static str,
        value: String,
    },
    #[error("{path}: unsupported format version {version} (this reader knows {FORMAT_VERSION})")]
    Version { path: PathBuf, version: i32 },
    #[error("{path}: part `{layer}`: band count {bands} out of range 1..={MAX_BANDS}")]
    Bands {
        path: PathBuf,
        layer: &'static str,
        bands: i32,
    },
    #[error("{path}: part `{layer}`: grid attributes {nu} x {nv} disagree with image size {width} x {height}")]
    GridMismatch {
        path: PathBuf,
        layer: &'static str,
        nu: i32,
        nv: i32,
        width: usize,
        height: usize,
    },
    #[error("{path}: part `{layer}`: missing channel `{channel}`")]
    MissingChannel {
        path: PathBuf,
        layer: &'static str,
        channel: String,
    },
    #[error("{path}: part `{layer}`: {count} channels, expected {expected}")]
    ChannelCount {
        path: PathBuf,
        layer: &'static str,
        count: usize,
        expected: usize,
    },
    #[error("{path}: part `{layer}`: channel `{channel}` is not 32-bit float")]
    ChannelType {
        path: PathBuf,
        layer: &'static str,
        channel: String,
    },
    #[error(
        "{path}: part `{layer}`: channel `{channel}` has a non-finite value at texel ({i}, {j})"
    )]
    NonFinite {
        path: PathBuf,
        layer: &'static str,
        channel: String,
        i: usize,
        j: usize,
    },
    /// A finite value over [`crate::brdf::MAX_BRDF_VALUE`] in magnitude (it would overflow
    /// to Inf in shading).
    #[error(
        "{path}: part `{layer}`: channel `{channel}` value {value:e} at texel ({i}, {j}) exceeds the limit +-{max:e}",
        max = crate::brdf::MAX_BRDF_VALUE
    )]
    TooLarge {
        path: PathBuf,
        layer: &'static str,
        channel: String,
        i: usize,
        j: usize,
        value: f32,
    },
    #[error("{path}: inconsistent data: {source}")]
    Data {
        path: PathBuf,
        #[source]
        source: ShDataError,
    },
}

/// Channel name of coefficient `k` (flat SH index) and colour `c` (0 R, 1 G, 2 B).
pub fn coeff_channel_name(k: usize, c: usize) -> String {
    let (l, m) = sh_lm(k);
    format!("c.l{l}.m{m}.{}", COLOURS[c])
}

/// Channel name of basis term `k`.
pub fn basis_channel_name(k: usize) -> String {
    let (l, m) = sh_lm(k);
    format!("Y.l{l}.m{m}")
}

fn text(s: &str) -> Text {
    Text::from_bytes_unchecked(s.as_bytes().into())
}

fn common_attrs(layer: &str, content: &str, bands: usize, nu: usize, nv: usize) -> LayerAttributes {
    let mut a = LayerAttributes::named(text(layer));
    let o = &mut a.other;
    o.insert(
        text("brdfkit.format"),
        AttributeValue::Text(text(FORMAT_NAME)),
    );
    o.insert(text("brdfkit.version"), AttributeValue::I32(FORMAT_VERSION));
    o.insert(text("brdfkit.content"), AttributeValue::Text(text(content)));
    o.insert(text("brdfkit.bands"), AttributeValue::I32(bands as i32));
    o.insert(text("brdfkit.nu"), AttributeValue::I32(nu as i32));
    o.insert(text("brdfkit.nv"), AttributeValue::I32(nv as i32));
    o.insert(
        text("brdfkit.param"),
        AttributeValue::Text(text(PARAMETERIZATION)),
    );
    o.insert(
        text("brdfkit.sh"),
        AttributeValue::Text(text(SH_CONVENTION)),
    );
    a
}

/// Writes `ds` (and its basis table, if set) to `path` in the format of the module doc.
/// Writes to a unique temporary file beside `path` first, syncs it and renames it over
/// `path` ([`crate::image_io::replace_via_temp`]).
/// Fails with [`ShFileError::Io`] / [`ShFileError::Exr`] (the temporary file is removed).
pub fn write_sh_dataset(path: &Path, ds: &ShDataset) -> Result<(), ShFileError> {
    let (nu, nv) = ds.grid();
    let nt = num_terms(ds.bands());
    let mut chans = Vec::with_capacity(3 * nt);
    for c in 0..3 {
        for k in 0..nt {
            let mut v = Vec::with_capacity(nu * nv);
            for j in 0..nv {
                for i in 0..nu {
                    v.push(ds.texel(i, j, c)[k]);
                }
            }
            chans.push(AnyChannel::new(
                text(&coeff_channel_name(k, c)),
                FlatSamples::F32(v),
            ));
        }
    }
    let mut attrs = common_attrs(COEFF_LAYER, "coefficients", ds.bands(), nu, nv);
    attrs.other.insert(
        text("brdfkit.cosine"),
        AttributeValue::I32(ds.cosine_included() as i32),
    );
    attrs.other.insert(
        text("brdfkit.provenance"),
        AttributeValue::Text(text(ds.provenance())),
    );
    if ds.band_threshold() != DEFAULT_BAND_THRESHOLD {
        attrs.other.insert(
            text("brdfkit.band_threshold"),
            AttributeValue::F32(ds.band_threshold()),
        );
    }
    let mut layers = vec![Layer::new(
        (nu, nv),
        attrs,
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(chans.into()),
    )];
    if let Some(tb) = ds.basis_table() {
        let (bu, bv) = tb.grid();
        let chans: Vec<_> = (0..nt)
            .map(|k| {
                let v: Vec<f32> = (0..bv)
                    .flat_map(|j| (0..bu).map(move |i| (i, j)))
                    .map(|(i, j)| tb.texel(i, j)[k])
                    .collect();
                AnyChannel::new(text(&basis_channel_name(k)), FlatSamples::F32(v))
            })
            .collect();
        layers.push(Layer::new(
            (bu, bv),
            common_attrs(BASIS_LAYER, "basis", tb.bands(), bu, bv),
            Encoding::FAST_LOSSLESS,
            AnyChannels::sort(chans.into()),
        ));
    }
    let image = Image::from_layers(
        ImageAttributes::new(IntegerBounds::from_dimensions((nu, nv))),
        layers,
    );
    crate::image_io::replace_via_temp(
        path,
        |tmp| image.write().to_file(tmp).map_err(|e| exr_err(path, e)),
        |source| ShFileError::Io {
            path: path.to_owned(),
            source,
        },
    )
}

fn exr_err(path: &Path, e: exr::error::Error) -> ShFileError {
    match e {
        exr::error::Error::Io(source) if source.kind() != std::io::ErrorKind::UnexpectedEof => {
            ShFileError::Io {
                path: path.to_owned(),
                source,
            }
        }
        other => ShFileError::Exr {
            path: path.to_owned(),
            message: other.to_string(),
        },
    }
}

type AnyLayer = Layer<AnyChannels<FlatSamples>>;

struct Part<'a> {
    path: &'a Path,
    layer: &'static str,
    attrs: &'a HashMap<Text, AttributeValue>,
    width: usize,
    height: usize,
    channels: HashMap<String, &'a FlatSamples>,
}

impl<'a> Part<'a> {
    fn new(path: &'a Path, layer: &'static str, l: &'a AnyLayer) -> Self {
        Part {
            path,
            layer,
            attrs: &l.attributes.other,
            width: l.size.0,
            height: l.size.1,
            channels: l
                .channel_data
                .list
                .iter()
                .map(|c| {
                    (
                        String::from_utf8_lossy(c.name.bytes()).into_owned(),
                        &c.sample_data,
                    )
                })
                .collect(),
        }
    }

    fn missing(&self, name: &'static str) -> ShFileError {
        ShFileError::MissingAttribute {
            path: self.path.to_owned(),
            layer: self.layer,
            name,
        }
    }

    fn int(&self, name: &'static str) -> Result<i32, ShFileError> {
        match self.attrs.get(&text(name)) {
            Some(AttributeValue::I32(v)) => Ok(*v),
            _ => Err(self.missing(name)),
        }
    }

    fn string(&self, name: &'static str) -> Result<String, ShFileError> {
        match self.attrs.get(&text(name)) {
            Some(AttributeValue::Text(t)) => Ok(String::from_utf8_lossy(t.bytes()).into_owned()),
            _ => Err(self.missing(name)),
        }
    }

    fn expect_string(&self, name: &'static str, want: &str) -> Result<(), ShFileError> {
        let v = self.string(name)?;
        if v != want {
            return Err(ShFileError::BadAttribute {
                path: self.path.to_owned(),
                layer: self.layer,
                name,
                value: v,
            });
        }
        Ok(())
    }

    /// Checks the common attributes; returns `(bands, nu, nv)`.
    fn header(&self, content: &str) -> Result<(usize, usize, usize), ShFileError> {
        self.expect_string("brdfkit.format", FORMAT_NAME)?;
        let version = self.int("brdfkit.version")?;
        if version != FORMAT_VERSION {
            return Err(ShFileError::Version {
                path: self.path.to_owned(),
                version,
            });
        }
        self.expect_string("brdfkit.content", content)?;
        self.expect_string("brdfkit.param", PARAMETERIZATION)?;
        self.expect_string("brdfkit.sh", SH_CONVENTION)?;
        let bands = self.int("brdfkit.bands")?;
        if bands < 1 || bands as usize > MAX_BANDS {
            return Err(ShFileError::Bands {
                path: self.path.to_owned(),
                layer: self.layer,
                bands,
            });
        }
        let (nu, nv) = (self.int("brdfkit.nu")?, self.int("brdfkit.nv")?);
        if nu as i64 != self.width as i64 || nv as i64 != self.height as i64 {
            return Err(ShFileError::GridMismatch {
                path: self.path.to_owned(),
                layer: self.layer,
                nu,
                nv,
                width: self.width,
                height: self.height,
            });
        }
        Ok((bands as usize, self.width, self.height))
    }

    fn check_count(&self, expected: usize) -> Result<(), ShFileError> {
        if self.channels.len() != expected {
            return Err(ShFileError::ChannelCount {
                path: self.path.to_owned(),
                layer: self.layer,
                count: self.channels.len(),
                expected,
            });
        }
        Ok(())
    }

    fn channel(&self, name: String) -> Result<&'a [f32], ShFileError> {
        match self.channels.get(&name) {
            None => Err(ShFileError::MissingChannel {
                path: self.path.to_owned(),
                layer: self.layer,
                channel: name,
            }),
            Some(FlatSamples::F32(v)) => {
                if let Some(p) = v.iter().position(|x| !x.is_finite()) {
                    return Err(ShFileError::NonFinite {
                        path: self.path.to_owned(),
                        layer: self.layer,
                        channel: name,
                        i: p % self.width,
                        j: p / self.width,
                    });
                }
                if let Some(p) = v.iter().position(|x| x.abs() > crate::brdf::MAX_BRDF_VALUE) {
                    return Err(ShFileError::TooLarge {
                        path: self.path.to_owned(),
                        layer: self.layer,
                        channel: name,
                        i: p % self.width,
                        j: p / self.width,
                        value: v[p],
                    });
                }
                Ok(v)
            }
            Some(_) => Err(ShFileError::ChannelType {
                path: self.path.to_owned(),
                layer: self.layer,
                channel: name,
            }),
        }
    }
}

/// Reads a data set written by [`write_sh_dataset`] (with its basis table if the file has
/// one). Fails with a [`ShFileError`] naming the file and the problem (see the module doc),
/// among them [`ShFileError::File`] for a directory, device, FIFO or oversized file,
/// among them [`ShFileError::Exr`] for a header declaring more pixels than the file's
/// length can hold ([`crate::image_io::check_exr_declared_size`]); never returns partial
/// data.
pub fn read_sh_dataset(path: &Path) -> Result<ShDataset, ShFileError> {
    // Headers first: the declared pixels are checked against the file length before the
    // decoder allocates them.
    let file_len = crate::image_io::check_regular_file(
        path,
        crate::image_io::MAX_EXR_FILE_BYTES,
        "SH data set",
    )?;
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| exr_err(path, e))?;
    crate::image_io::check_exr_declared_size(&meta.headers, file_len).map_err(|message| {
        ShFileError::Exr {
            path: path.to_owned(),
            message,
        }
    })?;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(path)
        .map_err(|e| exr_err(path, e))?;
    let find = |name: &'static str| {
        image
            .layer_data
            .iter()
            .find(|l| l.attributes.layer_name.as_ref().is_some_and(|n| n.eq(name)))
    };
    let cl = find(COEFF_LAYER).ok_or_else(|| ShFileError::MissingLayer {
        path: path.to_owned(),
        layer: COEFF_LAYER,
    })?;
    let part = Part::new(path, COEFF_LAYER, cl);
    let (bands, nu, nv) = part.header("coefficients")?;
    let cosine = match part.int("brdfkit.cosine")? {
        0 => false,
        1 => true,
        v => {
            return Err(ShFileError::BadAttribute {
                path: path.to_owned(),
                layer: COEFF_LAYER,
                name: "brdfkit.cosine",
                value: v.to_string(),
            })
        }
    };
    let provenance = part.string("brdfkit.provenance")?;
    let band_threshold = match part.attrs.get(&text("brdfkit.band_threshold")) {
        None => DEFAULT_BAND_THRESHOLD,
        Some(AttributeValue::F32(v)) if (0.0..1.0).contains(v) => *v,
        Some(other) => {
            return Err(ShFileError::BadAttribute {
                path: path.to_owned(),
                layer: COEFF_LAYER,
                name: "brdfkit.band_threshold",
                value: format!("{other:?} (need a float in [0, 1))"),
            })
        }
    };
    let nt = num_terms(bands);
    part.check_count(3 * nt)?;
    let mut coeffs = vec![0.0f32; nu * nv * 3 * nt];
    for c in 0..3 {
        for k in 0..nt {
            let ch = part.channel(coeff_channel_name(k, c))?;
            for (p, v) in ch.iter().enumerate() {
                coeffs[(p * 3 + c) * nt + k] = *v;
            }
        }
    }
    let data_err = |source| ShFileError::Data {
        path: path.to_owned(),
        source,
    };
    let mut ds = ShDataset::new(nu, nv, bands, cosine, provenance, coeffs).map_err(data_err)?;
    ds.set_band_threshold(band_threshold).map_err(data_err)?;
    if let Some(bl) = find(BASIS_LAYER) {
        let part = Part::new(path, BASIS_LAYER, bl);
        let (bb, bu, bv) = part.header("basis")?;
        let bt = num_terms(bb);
        part.check_count(bt)?;
        let mut values = vec![0.0f32; bu * bv * bt];
        for k in 0..bt {
            let ch = part.channel(basis_channel_name(k))?;
            for (p, v) in ch.iter().enumerate() {
                values[p * bt + k] = *v;
            }
        }
        let tb = ShBasisTable::from_raw(bu, bv, bb, values).map_err(data_err)?;
        ds.set_basis_table(Some(tb)).map_err(data_err)?;
    }
    Ok(ds)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// A fresh directory, removed when dropped (unique per test thread and process).
    fn tmpdir() -> tempfile::TempDir {
        tempfile::tempdir().unwrap()
    }

    fn sample(bands: usize, with_basis: bool) -> ShDataset {
        let (nu, nv) = (6, 3);
        let mut rng = rand_pcg::Pcg64::seed_from_u64(11);
        let n = nu * nv * 3 * num_terms(bands);
        let c: Vec<f32> = (0..n).map(|_| rng.gen_range(-2.0..2.0)).collect();
        let mut ds = ShDataset::new(nu, nv, bands, true, "test: random, üñí", c).unwrap();
        if with_basis {
            ds.set_basis_table(Some(ShBasisTable::tabulate(5, 4, bands).unwrap()))
                .unwrap();
        }
        ds
    }

    #[test]
    fn round_trip_is_exact_with_and_without_basis() {
        let tmp = tmpdir();
        let dir = tmp.path();
        for with_basis in [false, true] {
            let ds = sample(3, with_basis);
            let p = dir.join(format!("a{with_basis}.exr"));
            write_sh_dataset(&p, &ds).unwrap();
            let back = read_sh_dataset(&p).unwrap();
            assert_eq!(back, ds);
            // channel naming and texel placement, read back with plain exr
            let img = read()
                .no_deep_data()
                .largest_resolution_level()
                .all_channels()
                .all_layers()
                .all_attributes()
                .from_file(&p)
                .unwrap();
            let l = &img.layer_data[0];
            assert_eq!((l.size.0, l.size.1), (6, 3));
            let ch = l
                .channel_data
                .list
                .iter()
                .find(|c| c.name.eq("c.l2.m-1.G"))
                .unwrap();
            let k = crate::sh::sh_index(2, -1);
            match &ch.sample_data {
                FlatSamples::F32(v) => assert_eq!(v[2 * 6 + 4], ds.texel(4, 2, 1)[k]),
                _ => panic!("not f32"),
            }
        }
    }

    #[test]
    fn band_threshold_round_trips_defaults_when_absent_and_rejects_bad_values() {
        let tmp = tmpdir();
        let dir = tmp.path();
        let mut ds = sample(3, false);
        let p = dir.join("none.exr");
        write_sh_dataset(&p, &ds).unwrap();
        assert_eq!(
            read_sh_dataset(&p).unwrap().band_threshold(),
            DEFAULT_BAND_THRESHOLD
        );
        ds.set_band_threshold(0.02).unwrap();
        let p = dir.join("set.exr");
        write_sh_dataset(&p, &ds).unwrap();
        let back = read_sh_dataset(&p).unwrap();
        assert_eq!(back.band_threshold(), 0.02);
        assert_eq!(back, ds);
        for bad in [
            AttributeValue::F32(1.0),
            AttributeValue::F32(-0.1),
            AttributeValue::I32(0),
        ] {
            let (_dir, p) = corrupted(|l| set_attr(l, "brdfkit.band_threshold", bad));
            let e = read_sh_dataset(&p).unwrap_err();
            assert!(
                matches!(
                    e,
                    ShFileError::BadAttribute {
                        name: "brdfkit.band_threshold",
                        ..
                    }
                ),
                "{e}"
            );
        }
    }

    /// Writes a valid file, lets `edit` corrupt the decoded image, writes it back raw;
    /// returns the directory (the caller keeps it alive) and the file.
    fn corrupted(edit: impl FnOnce(&mut AnyLayer)) -> (tempfile::TempDir, PathBuf) {
        let dir = tmpdir();
        let p = dir.path().join("bad.exr");
        write_sh_dataset(&p, &sample(2, false)).unwrap();
        let mut img = read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .all_layers()
            .all_attributes()
            .from_file(&p)
            .unwrap();
        edit(&mut img.layer_data[0]);
        img.write().to_file(&p).unwrap();
        (dir, p)
    }

    fn set_attr(l: &mut AnyLayer, name: &str, v: AttributeValue) {
        l.attributes.other.insert(text(name), v);
    }

    #[test]
    fn malformed_files_give_named_errors() {
        let (_dir, p) = corrupted(|l| set_attr(l, "brdfkit.version", AttributeValue::I32(2)));
        let e = read_sh_dataset(&p).unwrap_err();
        assert!(matches!(e, ShFileError::Version { version: 2, .. }), "{e}");
        assert!(e.to_string().contains("bad.exr"), "{e}");

        let (_dir, p) = corrupted(|l| set_attr(l, "brdfkit.bands", AttributeValue::I32(100000)));
        let e = read_sh_dataset(&p).unwrap_err();
        assert!(matches!(e, ShFileError::Bands { bands: 100000, .. }), "{e}");

        let (_dir, p) =
            corrupted(|l| set_attr(l, "brdfkit.sh", AttributeValue::Text(text("complex"))));
        let e = read_sh_dataset(&p).unwrap_err();
        assert!(
            matches!(
                e,
                ShFileError::BadAttribute {
                    name: "brdfkit.sh",
                    ..
                }
            ),
            "{e}"
        );

        let (_dir, p) = corrupted(|l| set_attr(l, "brdfkit.bands", AttributeValue::F32(2.0)));
        let e = read_sh_dataset(&p).unwrap_err();
        assert!(
            matches!(
                e,
                ShFileError::MissingAttribute {
                    name: "brdfkit.bands",
                    ..
                }
            ),
            "{e}"
        );

        let (_dir, p) = corrupted(|l| {
            l.attributes.other.remove(&text("brdfkit.cosine"));
        });
        let e = read_sh_dataset(&p).unwrap_err();
        assert!(
            matches!(
                e,
                ShFileError::MissingAttribute {
                    name: "brdfkit.cosine",
                    ..
                }
            ),
            "{e}"
        );

        let (_dir, p) = corrupted(|l| set_attr(l, "brdfkit.nu", AttributeValue::I32(7)));
        let e = read_sh_dataset(&p).unwrap_err();
        assert!(matches!(e, ShFileError::GridMismatch { nu: 7, .. }), "{e}");

        let (_dir, p) = corrupted(|l| {
            l.channel_data.list.retain(|c| !c.name.eq("c.l1.m0.B"));
        });
        let e = read_sh_dataset(&p).unwrap_err();
        assert!(
            matches!(
                e,
                ShFileError::ChannelCount {
                    count: 11,
                    expected: 12,
                    ..
                }
            ),
            "{e}"
        );

        let (_dir, p) = corrupted(|l| {
            for c in l.channel_data.list.iter_mut() {
                if c.name.eq("c.l1.m0.B") {
                    c.name = text("c.l1.m0.A");
                }
            }
        });
        let e = read_sh_dataset(&p).unwrap_err();
        match &e {
            ShFileError::MissingChannel { channel, .. } => assert_eq!(channel, "c.l1.m0.B"),
            _ => panic!("{e}"),
        }

        let (_dir, p) = corrupted(|l| {
            for c in l.channel_data.list.iter_mut() {
                if c.name.eq("c.l1.m1.R") {
                    if let FlatSamples::F32(v) = &mut c.sample_data {
                        v[2 * 6 + 5] = f32::NAN;
                    }
                }
            }
        });
        let e = read_sh_dataset(&p).unwrap_err();
        assert!(
            matches!(e, ShFileError::NonFinite { i: 5, j: 2, .. }),
            "{e}"
        );
    }

    #[test]
    fn truncated_empty_and_absent_files_fail_cleanly() {
        let tmp = tmpdir();
        let dir = tmp.path();
        let p = dir.join("t.exr");
        write_sh_dataset(&p, &sample(2, true)).unwrap();
        let bytes = std::fs::read(&p).unwrap();
        for cut in [0, 4, 100, bytes.len() / 2, bytes.len() - 1] {
            std::fs::write(&p, &bytes[..cut]).unwrap();
            let e = read_sh_dataset(&p).unwrap_err();
            assert!(e.to_string().contains("t.exr"), "cut {cut}: {e}");
        }
        let e = read_sh_dataset(&dir.join("absent.exr")).unwrap_err();
        assert!(
            matches!(
                e,
                ShFileError::Io { .. } | ShFileError::Exr { .. } | ShFileError::File(_)
            ),
            "{e}"
        );
        // no temporary file is left behind after a successful write
        let left: Vec<_> = std::fs::read_dir(dir).unwrap().collect();
        assert_eq!(left.len(), 1);
    }
}
