//! Tests of the SH file: exact round trips, the band threshold attribute, and named errors
//! for malformed, truncated and absent files (hostile inputs: tests/hostile.rs).

use super::read::AnyLayer;
use super::*;
use crate::image_io::exr_guard::text;
use crate::sh::basis::num_terms;
use crate::sh::dataset::{ShBasisTable, ShDataset, DEFAULT_BAND_THRESHOLD};
use exr::prelude::{read, AttributeValue, FlatSamples, ReadChannels, ReadLayers, WritableImage};
use rand::{Rng, SeedableRng};
use std::path::PathBuf;

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

#[test]
fn lookup_round_trips_is_absent_for_nearest_and_rejects_bad_values() {
    use crate::sh::dataset::Lookup;
    let tmp = tmpdir();
    let dir = tmp.path();
    let mut ds = sample(2, false);
    let attr = |p: &std::path::Path| {
        let img = read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .all_layers()
            .all_attributes()
            .from_file(p)
            .unwrap();
        img.layer_data[0]
            .attributes
            .other
            .get(&text(LOOKUP_ATTRIBUTE))
            .cloned()
    };
    // Nearest (the meaning of an absent attribute) is not written.
    let p = dir.join("nearest.exr");
    write_sh_dataset(&p, &ds).unwrap();
    assert_eq!(attr(&p), None);
    assert_eq!(read_sh_dataset(&p).unwrap().coeff_lookup, Lookup::Nearest);
    ds.coeff_lookup = Lookup::Bilinear;
    let p = dir.join("bilinear.exr");
    write_sh_dataset(&p, &ds).unwrap();
    assert_eq!(attr(&p), Some(AttributeValue::Text(text("bilinear"))));
    let back = read_sh_dataset(&p).unwrap();
    assert_eq!(back.coeff_lookup, Lookup::Bilinear);
    assert_eq!(back, ds);
    // An explicit "nearest" (another writer) reads as nearest.
    let (_d, p) =
        corrupted(|l| set_attr(l, LOOKUP_ATTRIBUTE, AttributeValue::Text(text("nearest"))));
    assert_eq!(read_sh_dataset(&p).unwrap().coeff_lookup, Lookup::Nearest);
    for bad in [
        AttributeValue::Text(text("linear")),
        AttributeValue::Text(text("Bilinear")),
        AttributeValue::I32(1),
    ] {
        let (_dir, p) = corrupted(|l| set_attr(l, LOOKUP_ATTRIBUTE, bad));
        let e = read_sh_dataset(&p).unwrap_err();
        assert!(
            matches!(
                e,
                ShFileError::BadAttribute {
                    name: "brdfkit.lookup",
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

    let (_dir, p) = corrupted(|l| set_attr(l, "brdfkit.sh", AttributeValue::Text(text("complex"))));
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

/// The format doc: a stored `sh-basis` table must be the analytic basis at its texel
/// centres. A table changed by 0.01 in one value (100 x [`BASIS_TABLE_TOLERANCE`]) is
/// refused with `Data`, naming the texel and term; the unchanged table reads back.
///
/// [`BASIS_TABLE_TOLERANCE`]: crate::sh::dataset::BASIS_TABLE_TOLERANCE
#[test]
fn a_stored_basis_table_that_is_not_the_analytic_basis_is_refused() {
    let dir = tmpdir();
    let p = dir.path().join("basis.exr");
    let ds = sample(2, true);
    write_sh_dataset(&p, &ds).unwrap();
    assert_eq!(read_sh_dataset(&p).unwrap().basis_table(), ds.basis_table());
    let mut img = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(&p)
        .unwrap();
    let basis = img
        .layer_data
        .iter_mut()
        .find(|l| {
            l.attributes
                .layer_name
                .as_ref()
                .is_some_and(|n| n.eq("sh-basis"))
        })
        .unwrap();
    for c in basis.channel_data.list.iter_mut() {
        if c.name.eq("Y.l1.m1") {
            if let FlatSamples::F32(v) = &mut c.sample_data {
                // texel (i, j) = (3, 2) of the 5 x 4 basis grid
                v[2 * 5 + 3] += 0.01;
            }
        }
    }
    img.write().to_file(&p).unwrap();
    let e = read_sh_dataset(&p).unwrap_err();
    let k = crate::sh::sh_index(1, 1);
    assert!(
        matches!(
            &e,
            ShFileError::Data {
                source: crate::sh::ShDataError::BasisTable { i: 3, j: 2, k: kk, .. },
                ..
            } if *kk == k
        ),
        "{e}"
    );
    assert!(e.to_string().contains("basis.exr"), "{e}");
}

/// Each format's reader refuses the other's file with a message naming the file and the
/// format found: the D-BRDF reader ([`crate::brdf::dbrdf::file`]) given an SH data set.
#[test]
fn the_dbrdf_reader_refuses_an_sh_file() {
    let tmp = tmpdir();
    let sh = tmp.path().join("sh.exr");
    let ds = ShDataset::zeros(2, 2, 1, true, "x").unwrap();
    write_sh_dataset(&sh, &ds).unwrap();
    let e = crate::brdf::dbrdf::file::read_dbrdf(&sh)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("not a brdfkit D-BRDF file") && e.contains("sh.exr"),
        "{e}"
    );
}
