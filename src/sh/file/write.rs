//! Writing an SH data set in the format of [`super`] ([`write_sh_dataset`]).
//!
//! Design rule: every convention a reader needs is written as an attribute of every part
//! (`common_attrs`); the file appears under its name only complete
//! ([`crate::image_io::replace_via_temp`]).

use super::{
    basis_channel_name, coeff_channel_name, exr_err, lookup_value, ShFileError, BASIS_LAYER,
    COEFF_LAYER, FORMAT_NAME, FORMAT_VERSION, ISOTROPIC_ATTRIBUTE, LOOKUP_ATTRIBUTE,
    PARAMETERIZATION, SH_CONVENTION,
};
use crate::image_io::exr_guard::text;
use crate::sh::basis::num_terms;
use crate::sh::dataset::{Lookup, ShDataset, DEFAULT_BAND_THRESHOLD};
use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image, ImageAttributes,
    IntegerBounds, Layer, LayerAttributes, WritableImage,
};
use std::path::Path;

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
    // Written only when not nearest (the meaning of an absent attribute), so files of
    // nearest data sets stay byte-identical to those written before the attribute existed.
    if ds.coeff_lookup != Lookup::Nearest {
        attrs.other.insert(
            text(LOOKUP_ATTRIBUTE),
            AttributeValue::Text(text(lookup_value(ds.coeff_lookup))),
        );
    }
    // Written only when set, so files of other data sets stay byte-identical.
    if ds.isotropic {
        attrs
            .other
            .insert(text(ISOTROPIC_ATTRIBUTE), AttributeValue::I32(1));
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
