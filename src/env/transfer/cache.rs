//! The disk cache of transfer tables, beside the light-set cache
//! ([`crate::env::lightset::prepare::cache`]): same directory ([`crate::env::lightset::prepare::CacheDir`]),
//! same rules (only `brdfkit render` and `brdfkit view` pass one; tests, `golden` and
//! `sweep` never do).
//!
//! # Key
//! [`StableHasher`](crate::hash::StableHasher) (XXH3-64) of a key tag, the crate version,
//! [`TRANSFER_ALGORITHM_VERSION`], the probe file's bytes, the loader options that change
//! texels (`zero_non_finite`, `max_texels`) and every table parameter: the basis (kind,
//! bands, cosine), the grid `(nu, nv)`, the number of brightest texels left out, the
//! intensity's bits and the residual's largest width ([`super::build::RESIDUAL_WIDTH`])
//! ([`table_cache_key`]). The probe rotation is not in the key: the table
//! lives in the probe's own frame and the rotation is applied at lookup, so the viewer
//! turning the environment (shift-drag) reads one entry for every angle. Entries are
//! `<dir>/transfer-<key>.bin`, `<key>` 16 hex digits ([`table_file_name`]).
//!
//! # Format
//! One line of JSON ([`TableHeader`]: format tag, versions, key, grid, basis, value count,
//! checksum), a newline, then the table's values as little-endian f32. Every read checks the
//! tag, both versions, the key (the check every environment cache shares,
//! [`crate::env::cache_entry`]), the grid and basis against what the caller wants, the byte
//! count and the XXH3-64 checksum of the values ([`values_checksum`]); an entry that fails
//! any of it is ignored (and rewritten), never trusted. Writes are atomic
//! ([`crate::image_io::write_atomic`]: a unique temporary sibling, then a rename).

use super::table::TransferTable;
use super::{TableCache, TransferBasis};
use crate::env::cache_entry::{
    encode_values_entry, impl_values_header, key_hasher, read_values_entry, values_checksum,
    EntryKind, CRATE_VERSION,
};
use crate::env::LoadOptions;
use crate::hash;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Version of the algorithm that turns probe texels and table parameters into a transfer
/// table ([`super::build::build_table`], [`super::build::brightest_texels`]). Part of every
/// key and stored in every entry: bump it when a table's values change for the same inputs.
/// 2: a probe wider than [`super::build::RESIDUAL_WIDTH`] is projected from its
/// downsampled residual.
pub const TRANSFER_ALGORITHM_VERSION: u32 = 2;

/// Format tag of a transfer-table cache entry.
pub const TABLE_CACHE_FORMAT: &str = "brdfkit-transfer-cache-v1";

/// A transfer-table cache entry as this build writes it ([`crate::env::cache_entry`]).
const ENTRY: EntryKind = EntryKind {
    format: TABLE_CACHE_FORMAT,
    algorithm: "transfer algorithm version",
    algorithm_version: TRANSFER_ALGORITHM_VERSION,
    file: ("transfer", "bin"),
};

/// Largest entry read: 2^24 values ([`super::build::build_table`]'s limit) plus a header.
const MAX_ENTRY_BYTES: u64 = (4 << 24) + (1 << 16);

/// The table parameters a cache key covers (module doc, "Key").
#[derive(Clone, Copy, Debug)]
pub struct TableParams {
    pub basis: TransferBasis,
    pub grid: (usize, usize),
    /// Brightest texels left out of the table.
    pub exact_lights: usize,
    pub intensity: f32,
}

/// The cache key of the table of the probe file `bytes` (module doc, "Key").
pub fn table_cache_key(bytes: &[u8], opts: &LoadOptions, p: &TableParams) -> u64 {
    versioned_key(TRANSFER_ALGORITHM_VERSION, bytes, opts, p)
}

fn versioned_key(algorithm: u32, bytes: &[u8], opts: &LoadOptions, p: &TableParams) -> u64 {
    let mut h = key_hasher(
        b"brdfkit-transfer-table-v1",
        CRATE_VERSION,
        algorithm,
        bytes,
    );
    h.write_u64(opts.zero_non_finite as u64);
    h.write_u64(opts.max_texels as u64);
    match p.basis {
        TransferBasis::Irradiance => h.write_u64(0),
        TransferBasis::Sh { bands, cosine } => {
            h.write_u64(1);
            h.write_u64(bands as u64);
            h.write_u64(cosine as u64);
        }
    }
    h.write_u64(p.grid.0 as u64);
    h.write_u64(p.grid.1 as u64);
    h.write_u64(p.exact_lights as u64);
    h.write_u64(p.intensity.to_bits() as u64);
    h.write_u64(super::build::RESIDUAL_WIDTH as u64);
    h.finish()
}

/// This cache's entries as [`crate::env::transfer::prepare_table`] names and writes them.
pub const TABLE_CACHE: TableCache<TransferTable> = TableCache {
    file_name: table_file_name,
    encode: encode_entry,
};

/// The cache file of `key` in `dir`.
pub fn table_file_name(dir: &Path, key: u64) -> PathBuf {
    ENTRY.file_name(dir, key)
}

/// The first line of an entry (module doc, "Format").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableHeader {
    pub format: String,
    pub crate_version: String,
    pub algorithm_version: u32,
    /// The key, 16 hex digits (also the file name's).
    pub key: String,
    pub nu: usize,
    pub nv: usize,
    /// Terms per colour ([`TransferBasis::terms`]).
    pub terms: usize,
    /// Number of f32 values after the header line: `nu nv 3 terms`.
    pub values: usize,
    /// [`values_checksum`] in [`hash::tagged`] form.
    pub checksum: String,
}

impl_values_header!(TableHeader);

/// The bytes of the entry of `table` under `key`.
pub fn encode_entry(table: &TransferTable, key: u64) -> Vec<u8> {
    let (nu, nv) = table.grid();
    let values = table.values();
    let header = TableHeader {
        format: TABLE_CACHE_FORMAT.into(),
        crate_version: CRATE_VERSION.into(),
        algorithm_version: TRANSFER_ALGORITHM_VERSION,
        key: EntryKind::key_text(key),
        nu,
        nv,
        terms: table.terms(),
        values: values.len(),
        checksum: hash::tagged(values_checksum(values)),
    };
    encode_values_entry(&header, values)
}

/// Reads and checks the entry `path` for `key`, a table of `basis` on `grid` (module doc,
/// "Format"), with the probe rotation `rotation` (radians) set for lookup. `Ok(None)`: no
/// entry; `Err`: an entry that is not used, and why.
pub fn read_entry(
    path: &Path,
    key: u64,
    basis: TransferBasis,
    grid: (usize, usize),
    rotation: f64,
) -> std::result::Result<Option<TransferTable>, String> {
    let n = grid.0 * grid.1 * 3 * basis.terms();
    let expected = |h: &TableHeader| {
        if (h.nu, h.nv, h.terms, h.values) != (grid.0, grid.1, basis.terms(), n) {
            return Err(format!(
                "grid {} x {}, {} terms, {} values; expected {} x {}, {} terms, {n} values",
                h.nu,
                h.nv,
                h.terms,
                h.values,
                grid.0,
                grid.1,
                basis.terms()
            ));
        }
        Ok(n)
    };
    let entry = read_values_entry(
        path,
        MAX_ENTRY_BYTES,
        "transfer cache",
        &ENTRY,
        key,
        expected,
    )?;
    Ok(entry.map(|(_, values)| TransferTable::from_parts(grid, basis, rotation, values)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::Progress;

    fn params() -> TableParams {
        TableParams {
            basis: TransferBasis::Sh {
                bands: 2,
                cosine: true,
            },
            grid: (8, 5),
            exact_lights: 2,
            intensity: 1.0,
        }
    }

    fn table() -> TransferTable {
        let texels: Vec<[f32; 3]> = (0..32 * 16)
            .map(|i| [1.0 + (i % 7) as f32, 0.5, 0.25 * (i % 3) as f32])
            .collect();
        let (probe, _) =
            crate::env::Probe::from_texels("t", 32, 16, texels, &LoadOptions::default()).unwrap();
        let p = params();
        super::super::build_table(
            &probe,
            p.basis,
            p.grid,
            &[3, 4],
            1.0,
            &Progress::hidden(),
            super::super::BuildFault::None,
        )
        .unwrap()
    }

    #[test]
    fn key_covers_every_parameter_and_version() {
        let o = LoadOptions::default();
        let p = params();
        let k = table_cache_key(b"probe", &o, &p);
        let mut changed = vec![
            table_cache_key(b"probf", &o, &p),
            versioned_key(TRANSFER_ALGORITHM_VERSION + 1, b"probe", &o, &p),
        ];
        let o2 = LoadOptions {
            zero_non_finite: !o.zero_non_finite,
            ..o
        };
        changed.push(table_cache_key(b"probe", &o2, &p));
        for q in [
            TableParams {
                basis: TransferBasis::Sh {
                    bands: 3,
                    cosine: true,
                },
                ..p
            },
            TableParams {
                basis: TransferBasis::Sh {
                    bands: 2,
                    cosine: false,
                },
                ..p
            },
            TableParams {
                basis: TransferBasis::Irradiance,
                ..p
            },
            TableParams { grid: (16, 5), ..p },
            TableParams { grid: (8, 9), ..p },
            TableParams {
                exact_lights: 3,
                ..p
            },
            TableParams {
                intensity: 2.0,
                ..p
            },
        ] {
            changed.push(table_cache_key(b"probe", &o, &q));
        }
        for (i, c) in changed.iter().enumerate() {
            assert_ne!(*c, k, "change {i} kept the key");
        }
        // The rotation is not in the key (module doc).
        let o3 = LoadOptions { rotation: 1.0, ..o };
        assert_eq!(table_cache_key(b"probe", &o3, &p), k);
    }

    #[test]
    fn entry_round_trips_and_damage_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let t = table();
        let p = params();
        let path = table_file_name(tmp.path(), 42);
        let read = |path: &Path| read_entry(path, 42, p.basis, p.grid, 0.0);
        assert_eq!(read(&path), Ok(None));
        let bytes = encode_entry(&t, 42);
        std::fs::write(&path, &bytes).unwrap();
        assert_eq!(read(&path), Ok(Some(t.clone())));
        // Read with a rotation: the same values, the rotation set for lookup.
        let r = read_entry(&path, 42, p.basis, p.grid, 0.5)
            .unwrap()
            .unwrap();
        assert_eq!(r.values(), t.values());
        assert_eq!(r.rotation(), 0.5);
        // A flipped bit in the last value: the checksum refuses it.
        let mut bad = bytes.clone();
        *bad.last_mut().unwrap() ^= 1;
        std::fs::write(&path, &bad).unwrap();
        assert!(read(&path).unwrap_err().contains("checksum"));
        // Truncated.
        std::fs::write(&path, &bytes[..bytes.len() - 4]).unwrap();
        assert!(read(&path).unwrap_err().contains("truncated"));
        // Another key, grid or version.
        std::fs::write(&path, &bytes).unwrap();
        assert!(read_entry(&path, 43, p.basis, p.grid, 0.0)
            .unwrap_err()
            .contains("key"));
        assert!(read_entry(&path, 42, p.basis, (8, 9), 0.0)
            .unwrap_err()
            .contains("grid"));
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let other = format!("\"algorithm_version\":{}", TRANSFER_ALGORITHM_VERSION + 1);
        let old = text.replacen(
            &format!("\"algorithm_version\":{TRANSFER_ALGORITHM_VERSION}"),
            &other,
            1,
        );
        // Lossy text of binary values would not round-trip: patch the header bytes only.
        let nl = bytes.iter().position(|&b| b == b'\n').unwrap();
        let mut patched = old.as_bytes()[..old.find('\n').unwrap()].to_vec();
        patched.extend_from_slice(&bytes[nl..]);
        std::fs::write(&path, &patched).unwrap();
        assert!(read(&path)
            .unwrap_err()
            .contains("transfer algorithm version"));
    }
}
