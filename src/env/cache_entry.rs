//! What every disk cache entry of the environment says about the build that wrote it, and
//! the one check of it: the light sets' JSON entries ([`super::lightset::prepare::cache`]) and the
//! transfer tables' binary ones ([`super::transfer::cache`]) each store a format tag, the
//! crate version, their algorithm's version, their key (16 hex digits, also in the file
//! name) and an XXH3-64 checksum of their payload ([`crate::hash::tagged`] form). An entry is
//! used only when its format, both versions and key are this build's and the caller's, and
//! its payload hashes to its checksum; otherwise it is ignored (and rewritten), and the
//! reason is one line ([`EntryKind::check_stamp`], [`check_checksum`]).
//!
//! The tables' binary entries (transfer and reflection) share one body: a line of JSON (the
//! cache's own header, [`ValuesHeader`]), a newline, then the values as little-endian f32
//! ([`encode_values_entry`], [`read_values_entry`]).

use crate::hash::StableHasher;
use serde::{de::DeserializeOwned, Serialize};

/// The crate version, in every cache key and entry (a cache never outlives a release).
pub const CRATE_VERSION: &str = env!("CARGO_PKG_VERSION");

/// The header fields of an entry as read (borrowed from it).
#[derive(Clone, Copy, Debug)]
pub struct Stamp<'a> {
    pub format: &'a str,
    pub crate_version: &'a str,
    pub algorithm_version: u32,
    pub key: &'a str,
}

/// One kind of cache entry as this build writes it.
#[derive(Clone, Copy, Debug)]
pub struct EntryKind {
    /// The format tag.
    pub format: &'static str,
    /// What the algorithm version is of, in messages ("light-set algorithm version").
    pub algorithm: &'static str,
    pub algorithm_version: u32,
    /// The entry's file name before the key and its extension: `("lights", "json")` names
    /// `lights-KEY.json` ([`EntryKind::file_name`]).
    pub file: (&'static str, &'static str),
}

impl EntryKind {
    /// `key` as entries store it and file names carry it: 16 hex digits.
    pub fn key_text(key: u64) -> String {
        format!("{key:016x}")
    }

    /// The entry file of `key` in `dir`: `STEM-KEY.EXT` (`file`, [`EntryKind::key_text`]).
    pub fn file_name(&self, dir: &std::path::Path, key: u64) -> std::path::PathBuf {
        let (stem, ext) = self.file;
        dir.join(format!("{stem}-{}.{ext}", EntryKind::key_text(key)))
    }

    /// Checks that `stamp` is this build's (format, crate version, algorithm version) and
    /// names `key`; else why not, in one line.
    pub fn check_stamp(&self, stamp: Stamp, key: u64) -> std::result::Result<(), String> {
        let differs =
            |what: &str, found: &dyn std::fmt::Display, wanted: &dyn std::fmt::Display| {
                Err(format!("{what} {found}, this build writes {wanted}"))
            };
        if stamp.format != self.format {
            return differs("format", &stamp.format, &self.format);
        }
        if stamp.crate_version != CRATE_VERSION {
            return differs("crate version", &stamp.crate_version, &CRATE_VERSION);
        }
        if stamp.algorithm_version != self.algorithm_version {
            return differs(
                self.algorithm,
                &stamp.algorithm_version,
                &self.algorithm_version,
            );
        }
        let key = EntryKind::key_text(key);
        if stamp.key != key {
            return differs("key", &stamp.key, &key);
        }
        Ok(())
    }
}

/// The start of every cache key: a [`StableHasher`] (XXH3-64) fed the key's tag (`tag`:
/// the cache and its key layout), the crate version, the algorithm version and the probe
/// file's length and bytes, in that order; each cache hashes its own settings after them.
pub fn key_hasher(
    tag: &[u8],
    crate_version: &str,
    algorithm_version: u32,
    probe_bytes: &[u8],
) -> StableHasher {
    let mut h = StableHasher::new();
    h.write(tag);
    h.write_str(crate_version);
    h.write_u64(algorithm_version as u64);
    h.write_u64(probe_bytes.len() as u64);
    h.write(probe_bytes);
    h
}

/// Checks that an entry's stored checksum (`stored`, [`crate::hash::tagged`] form) is the one
/// of its payload (`computed`); `payload` names it in the message ("lights", "values").
pub fn check_checksum(
    stored: &str,
    computed: u64,
    payload: &str,
) -> std::result::Result<(), String> {
    let sum = crate::hash::tagged(computed);
    if stored != sum {
        return Err(format!(
            "checksum {stored} does not match its {payload} ({sum}): edited or damaged"
        ));
    }
    Ok(())
}

/// The bytes of the cache entry `path` (a regular file of at most `max_bytes`; `what` names
/// the cache in an error): `Ok(None)` when there is none.
pub fn read_entry_bytes(
    path: &std::path::Path,
    max_bytes: u64,
    what: &'static str,
) -> std::result::Result<Option<Vec<u8>>, String> {
    if !path.exists() {
        return Ok(None);
    }
    crate::image_io::read_regular_file(path, max_bytes, what)
        .map(Some)
        .map_err(|e| e.to_string())
}

/// XXH3-64 of the value count and the values' bits: the checksum a table's entry stores
/// ([`ValuesHeader::checksum`], in [`crate::hash::tagged`] form) and every read recomputes.
pub fn values_checksum(values: &[f32]) -> u64 {
    let mut h = StableHasher::new();
    h.write_u64(values.len() as u64);
    h.write_f32s(values.iter().copied());
    h.finish()
}

/// The JSON header line of a table's entry (module doc): its stamp, checked by
/// [`EntryKind::check_stamp`], and the checksum of its values ([`values_checksum`]).
pub trait ValuesHeader: Serialize + DeserializeOwned {
    fn stamp(&self) -> Stamp<'_>;
    fn checksum(&self) -> &str;
}

/// Implements [`ValuesHeader`] for a header struct with the stamp's fields (`format`,
/// `crate_version`, `algorithm_version`, `key`) and `checksum`, as every table cache's has.
macro_rules! impl_values_header {
    ($header:ty) => {
        impl $crate::env::cache_entry::ValuesHeader for $header {
            fn stamp(&self) -> $crate::env::cache_entry::Stamp<'_> {
                $crate::env::cache_entry::Stamp {
                    format: &self.format,
                    crate_version: &self.crate_version,
                    algorithm_version: self.algorithm_version,
                    key: &self.key,
                }
            }

            fn checksum(&self) -> &str {
                &self.checksum
            }
        }
    };
}
pub(crate) use impl_values_header;

/// The bytes of a table's entry: `header` as one line of JSON, a newline, then `values` as
/// little-endian f32.
pub fn encode_values_entry<H: ValuesHeader>(header: &H, values: &[f32]) -> Vec<u8> {
    let mut out = serde_json::to_vec(header).expect("a header serialises");
    out.push(b'\n');
    out.reserve(4 * values.len());
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// Reads and checks the table entry `path` of `kind` under `key` (at most `max_bytes`;
/// `what` names the cache in messages, "transfer cache"): its header's stamp, then
/// `expected`, which checks the header against what the caller wants and returns the
/// number of values it must hold, then the byte count and the checksum of the values.
/// `Ok(None)`: no entry; `Err`: an entry that is not used, and why, in one line.
pub fn read_values_entry<H: ValuesHeader>(
    path: &std::path::Path,
    max_bytes: u64,
    what: &'static str,
    kind: &EntryKind,
    key: u64,
    expected: impl FnOnce(&H) -> std::result::Result<usize, String>,
) -> std::result::Result<Option<(H, Vec<f32>)>, String> {
    let Some(bytes) = read_entry_bytes(path, max_bytes, what)? else {
        return Ok(None);
    };
    let nl = bytes
        .iter()
        .position(|&b| b == b'\n')
        .ok_or("no header line")?;
    let h: H =
        serde_json::from_slice(&bytes[..nl]).map_err(|e| format!("not a {what} entry: {e}"))?;
    kind.check_stamp(h.stamp(), key)?;
    let n = expected(&h)?;
    let body = &bytes[nl + 1..];
    if body.len() != 4 * n {
        return Err(format!(
            "{} bytes of values, expected {}: truncated or padded",
            body.len(),
            4 * n
        ));
    }
    let values: Vec<f32> = body
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    check_checksum(h.checksum(), values_checksum(&values), "values")?;
    Ok(Some((h, values)))
}

#[cfg(test)]
mod tests {
    use super::*;

    const KIND: EntryKind = EntryKind {
        format: "test-cache-v1",
        algorithm: "test algorithm version",
        algorithm_version: 3,
        file: ("test", "bin"),
    };

    #[test]
    fn every_field_of_the_stamp_is_checked() {
        let key = EntryKind::key_text(42);
        let good = Stamp {
            format: KIND.format,
            crate_version: CRATE_VERSION,
            algorithm_version: 3,
            key: &key,
        };
        assert_eq!(KIND.check_stamp(good, 42), Ok(()));
        let cases = [
            (
                Stamp {
                    format: "x",
                    ..good
                },
                42,
                "format x,",
            ),
            (
                Stamp {
                    crate_version: "0.0.0",
                    ..good
                },
                42,
                "crate version 0.0.0,",
            ),
            (
                Stamp {
                    algorithm_version: 2,
                    ..good
                },
                42,
                "test algorithm version 2, this build writes 3",
            ),
            (
                good,
                43,
                "key 000000000000002a, this build writes 000000000000002b",
            ),
        ];
        for (stamp, k, why) in cases {
            let e = KIND.check_stamp(stamp, k).unwrap_err();
            assert!(e.contains(why), "{e}");
        }
        assert!(check_checksum(&crate::hash::tagged(7), 7, "lights").is_ok());
        let e = check_checksum(&crate::hash::tagged(7), 8, "lights").unwrap_err();
        assert!(e.contains("does not match its lights"), "{e}");
    }
}
