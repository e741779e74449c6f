//! The disk cache of reflection-space radiance tables, beside the light-set and transfer
//! caches (same directory, same rules: [`crate::env::lightset::prepare::CacheDir`], only
//! `brdfkit render` and `brdfkit view` pass one).
//!
//! # Key
//! [`StableHasher`] (XXH3-64) of a key tag, the crate version,
//! [`REFLECTION_ALGORITHM_VERSION`], the probe file's bytes (in that order, the start every
//! environment cache's key shares: [`key_hasher`]), the loader options that change
//! texels (`zero_non_finite`, `max_texels`), the material (its complete `Debug` form, every
//! parameter and table value, streamed into the hasher: [`material_fingerprint`]), every
//! table parameter (grid, slices, residual width), the number of brightest texels left out,
//! the intensity's bits and, last and only when it is not the default 2, the order of the
//! series in psi ([`table_cache_key`]: a table of the default order keeps the key it had
//! before the order was a parameter, so its existing entries are still read). The probe
//! rotation is not in the key: the
//! table lives in the probe's own frame and the rotation is applied at lookup. Entries are
//! `<dir>/reflection-<key>.bin`.
//!
//! # Format
//! One line of JSON ([`TableHeader`]: format tag, versions, key, grid, slices, the order of
//! the series in psi (written only when it is not 2, read as 2 when absent: an entry of the
//! default order is byte for byte the entry from before the order was a parameter), value
//! count, the bake's measured error, checksum), a newline, then the values as
//! little-endian f32.
//! Every read checks what the transfer cache checks ([`crate::env::cache_entry`]); an entry
//! that fails any of it is ignored (and rewritten), never trusted.

use super::build::{BakeParams, MAX_VALUES};
use super::table::{value_count, BakeError, ReflectionTable};
use crate::env::cache_entry::{
    encode_values_entry, impl_values_header, key_hasher, read_values_entry, values_checksum,
    EntryKind, CRATE_VERSION,
};
use crate::env::schema::DEFAULT_REFLECTION_ORDER;
use crate::env::transfer::TableCache;
use crate::env::LoadOptions;
use crate::hash::{self, StableHasher};
use crate::material::Material;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Version of the algorithm that turns a probe, a material and the parameters into a table
/// ([`super::build::bake_table`]). Part of every key: bump it when a table's values change
/// for the same inputs. (Making the order of the series in psi a parameter did not: at the
/// default order 2 the bake writes the same bits. Version 5: the radial table in
/// `1 - cos(polar_h)` over the lobe's range and the sums in the node's frame over four
/// partial sums, `sums.rs`: the same tables to about 1e-6 of the lobe's peak, other bits.
/// Version 6: `max(3 order, 8)` samples in psi instead of `4 order`, other tables from order
/// 3 on; order 1 and 2 tables keep their bits.)
pub const REFLECTION_ALGORITHM_VERSION: u32 = 6;

/// Format tag of an entry.
pub const REFLECTION_CACHE_FORMAT: &str = "brdfkit-reflection-cache-v2";

const ENTRY: EntryKind = EntryKind {
    format: REFLECTION_CACHE_FORMAT,
    algorithm: "reflection algorithm version",
    algorithm_version: REFLECTION_ALGORITHM_VERSION,
    file: ("reflection", "bin"),
};

const MAX_ENTRY_BYTES: u64 = 4 * MAX_VALUES as u64 + (1 << 16);

/// A `fmt::Write` that feeds what is written into a hasher.
struct HashWriter<'a>(&'a mut StableHasher);

impl std::fmt::Write for HashWriter<'_> {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.0.write(s.as_bytes());
        Ok(())
    }
}

/// The material's complete `Debug` form (every parameter, every table value; f32 and f64
/// printed so they round-trip) fed into `h`: two materials hash alike only when they are
/// the same model with the same numbers.
pub fn material_fingerprint(material: &Material, h: &mut StableHasher) {
    use std::fmt::Write;
    let _ = write!(HashWriter(h), "{material:?}");
}

/// The cache key (module doc, "Key").
pub fn table_cache_key(
    bytes: &[u8],
    opts: &LoadOptions,
    material: &Material,
    p: &BakeParams,
    exact_lights: usize,
    intensity: f32,
) -> u64 {
    let mut h = key_hasher(
        b"brdfkit-reflection-table-v1",
        CRATE_VERSION,
        REFLECTION_ALGORITHM_VERSION,
        bytes,
    );
    h.write_u64(opts.zero_non_finite as u64);
    h.write_u64(opts.max_texels as u64);
    material_fingerprint(material, &mut h);
    h.write_u64(p.grid as u64);
    h.write_u64(p.slices as u64);
    h.write_u64(p.residual as u64);
    h.write_u64(exact_lights as u64);
    h.write_u64(intensity.to_bits() as u64);
    // Last and only off the default: the default's key is the one from before the order
    // was a parameter (module doc, "Key").
    if p.order != DEFAULT_REFLECTION_ORDER {
        h.write_u64(p.order as u64);
    }
    h.finish()
}

/// This cache's entries as [`crate::env::transfer::prepare_table`] names and writes them.
pub const TABLE_CACHE: TableCache<ReflectionTable> = TableCache {
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
    pub key: String,
    pub grid: usize,
    pub slices: usize,
    /// The order of the series in psi; absent (read as 2) at the default order (module
    /// doc, "Format").
    #[serde(default = "default_order", skip_serializing_if = "is_default_order")]
    pub order: usize,
    pub values: usize,
    pub error: BakeError,
    pub checksum: String,
}

fn default_order() -> usize {
    DEFAULT_REFLECTION_ORDER
}

fn is_default_order(order: &usize) -> bool {
    *order == DEFAULT_REFLECTION_ORDER
}

impl_values_header!(TableHeader);

/// The bytes of the entry of `table` under `key`.
pub fn encode_entry(table: &ReflectionTable, key: u64) -> Vec<u8> {
    let values = table.values();
    let header = TableHeader {
        format: REFLECTION_CACHE_FORMAT.into(),
        crate_version: CRATE_VERSION.into(),
        algorithm_version: REFLECTION_ALGORITHM_VERSION,
        key: EntryKind::key_text(key),
        grid: table.grid(),
        slices: table.slices(),
        order: table.order(),
        values: values.len(),
        error: table.error(),
        checksum: hash::tagged(values_checksum(values)),
    };
    encode_values_entry(&header, values)
}

/// Reads and checks the entry `path` for `key` and `params`, the probe rotation `rotation`
/// (radians) set for lookup. `Ok(None)`: no entry; `Err`: an entry not used, and why.
pub fn read_entry(
    path: &Path,
    key: u64,
    params: &BakeParams,
    rotation: f64,
) -> std::result::Result<Option<ReflectionTable>, String> {
    let n = value_count(params.grid, params.slices, params.order);
    let expected = |h: &TableHeader| {
        if (h.grid, h.slices, h.order, h.values) != (params.grid, params.slices, params.order, n) {
            return Err(format!(
                "grid {}, {} slices, psi order {}, {} values; expected grid {}, {} slices, \
                 psi order {}, {n} values",
                h.grid, h.slices, h.order, h.values, params.grid, params.slices, params.order
            ));
        }
        Ok(n)
    };
    let entry = read_values_entry(
        path,
        MAX_ENTRY_BYTES,
        "reflection cache",
        &ENTRY,
        key,
        expected,
    )?;
    Ok(entry.map(|(h, values)| {
        ReflectionTable::from_parts(
            params.grid,
            params.slices,
            params.order,
            rotation,
            values,
            h.error,
        )
    }))
}
