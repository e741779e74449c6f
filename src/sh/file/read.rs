//! Reading an SH data set ([`read_sh_dataset`]): the guarded EXR read, then every attribute
//! and channel checked before a data set is built.
//!
//! Design rule: the bytes go through the crate's one guarded EXR reader
//! ([`crate::image_io::exr_guard`]); this file only checks the format. Anything missing,
//! unknown or inconsistent is an error naming the file and the problem; nothing is guessed,
//! no partial data set is returned.

use super::{
    basis_channel_name, coeff_channel_name, exr_err, lookup_value, ShFileError, BASIS_LAYER,
    COEFF_LAYER, FORMAT_NAME, FORMAT_VERSION, ISOTROPIC_ATTRIBUTE, LOOKUP_ATTRIBUTE,
    PARAMETERIZATION, SH_CONVENTION,
};
use crate::image_io::exr_guard::{self, Attributes, ExrGuardError};
use crate::sh::basis::num_terms;
use crate::sh::dataset::{Lookup, ShBasisTable, ShDataset, DEFAULT_BAND_THRESHOLD, MAX_BANDS};
use exr::prelude::{AnyChannels, AttributeValue, FlatSamples, Layer};
use std::collections::HashMap;
use std::path::Path;

/// One decoded EXR part.
pub(super) type AnyLayer = Layer<AnyChannels<FlatSamples>>;

struct Part<'a> {
    path: &'a Path,
    layer: &'static str,
    attrs: Attributes<'a>,
    width: usize,
    height: usize,
    channels: HashMap<String, &'a FlatSamples>,
}

impl<'a> Part<'a> {
    fn new(path: &'a Path, layer: &'static str, l: &'a AnyLayer) -> Self {
        Part {
            path,
            layer,
            attrs: Attributes(&l.attributes.other),
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
        self.attrs.i32(name).ok_or_else(|| self.missing(name))
    }

    fn string(&self, name: &'static str) -> Result<String, ShFileError> {
        self.attrs.string(name).ok_or_else(|| self.missing(name))
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

/// Reads a data set written by [`write_sh_dataset`](super::write_sh_dataset) (with its basis
/// table if the file has one). Fails with a [`ShFileError`] naming the file and the problem
/// (see the module doc), among them [`ShFileError::File`] for a directory, device, FIFO or
/// oversized file, among them [`ShFileError::Exr`] for a header declaring more pixels than
/// the file's length can hold ([`crate::image_io::check_exr_declared_size`]), and
/// [`ShFileError::Data`] for a basis table that is not the analytic basis at its texel
/// centres; never returns partial data.
pub fn read_sh_dataset(path: &Path) -> Result<ShDataset, ShFileError> {
    // Headers first: the declared pixels are checked against the file length before the
    // decoder allocates them.
    let image =
        exr_guard::read_all_layers(path, crate::image_io::MAX_EXR_FILE_BYTES, "SH data set")
            .map_err(|e| match e {
                ExrGuardError::File(e) => ShFileError::File(e),
                ExrGuardError::Exr(e) => exr_err(path, e),
                ExrGuardError::DeclaredSize(message) => ShFileError::Exr {
                    path: path.to_owned(),
                    message,
                },
            })?;
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
    let band_threshold = match part.attrs.get("brdfkit.band_threshold") {
        None => DEFAULT_BAND_THRESHOLD,
        Some(AttributeValue::F32(v)) if (0.0..1.0).contains(v) => *v,
        Some(other) => {
            return Err(ShFileError::BadAttribute {
                path: path.to_owned(),
                layer: COEFF_LAYER,
                name: "brdfkit.band_threshold",
                value: format!("{} (need a float in [0, 1))", shown(other)),
            })
        }
    };
    // Absent: nearest, the meaning of every file written before the attribute existed.
    let coeff_lookup = match part.attrs.get(LOOKUP_ATTRIBUTE) {
        None => Lookup::Nearest,
        Some(v) => [Lookup::Nearest, Lookup::Bilinear]
            .into_iter()
            .find(|&l| matches!(v, AttributeValue::Text(t) if t.eq(lookup_value(l))))
            .ok_or_else(|| ShFileError::BadAttribute {
                path: path.to_owned(),
                layer: COEFF_LAYER,
                name: LOOKUP_ATTRIBUTE,
                value: format!("{} (need the string \"nearest\" or \"bilinear\")", shown(v)),
            })?,
    };
    let isotropic = match part.attrs.get(ISOTROPIC_ATTRIBUTE) {
        None | Some(AttributeValue::I32(0)) => false,
        Some(AttributeValue::I32(1)) => true,
        Some(other) => {
            return Err(ShFileError::BadAttribute {
                path: path.to_owned(),
                layer: COEFF_LAYER,
                name: ISOTROPIC_ATTRIBUTE,
                value: format!("{} (need the int 0 or 1)", shown(other)),
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
    ds.coeff_lookup = coeff_lookup;
    ds.isotropic = isotropic;
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

/// An attribute's value as an error message shows it: the number, the text in quotes, or
/// the attribute's type for anything else (never Rust's debug form of the value).
fn shown(v: &AttributeValue) -> String {
    match v {
        AttributeValue::F32(x) => x.to_string(),
        AttributeValue::F64(x) => x.to_string(),
        AttributeValue::I32(x) => x.to_string(),
        AttributeValue::Text(t) => format!("\"{t}\""),
        other => format!(
            "an attribute of type {}",
            String::from_utf8_lossy(other.kind_name())
        ),
    }
}
