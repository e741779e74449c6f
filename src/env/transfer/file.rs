//! The exported transfer table: a JSON header and a file of raw values, as `brdfkit export`
//! writes a scene's table for a GPU build to upload ([`write_table`]) and a scene's
//! `[transfer] table` reads it back ([`read_table`]).
//!
//! Design rule: the values file is the table's memory exactly (one buffer upload, no
//! parsing) and the header says everything needed to read it; unlike the cache
//! ([`super::cache`]) the format carries no crate version or key, so it stays readable by
//! any later build, and a header that disagrees with its values is refused, never guessed
//! at.
//!
//! # Format (docs/file-formats.md, "Transfer tables")
//! - The values file: `nu * nv * 3 * terms` little-endian f32, no header, laid out
//!   `values[((j * nu + i) * 3 + c) * terms + k]` (node `(i, j)` with `j` the polar index,
//!   slowest; colour `c` in R, G, B; term `k` the SH index `l^2 + l + m`, or the one
//!   irradiance term). Units: W/m^2 per unit of `Y_k` (SH) or W/m^2 (irradiance) for a
//!   probe in W/(m^2 sr), after the probe's intensity.
//! - The header ([`TableFile`]): format tag [`FORMAT`], [`VERSION`], the values file's name
//!   (relative to the header), the grid, the basis, the probe rotation (f32 radians, in its
//!   shortest round-trip decimal form), the value count and the XXH3-64 checksum of the
//!   values ([`crate::env::cache_entry::values_checksum`]).

use super::table::TransferTable;
use super::TransferBasis;
use crate::env::cache_entry::values_checksum;
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Format tag of an exported transfer table's header.
pub const FORMAT: &str = "brdfkit-transfer-table";

/// Version of the exported table format.
pub const VERSION: u32 = 1;

/// Largest values file read: 2^24 values ([`super::build::build_table`]'s limit).
const MAX_VALUES: usize = 1 << 24;

/// Largest header read (bytes).
const MAX_HEADER_BYTES: u64 = 1 << 16;

/// How a GPU build reads the values file, as the header states it.
pub const LAYOUT: &str = "little-endian f32, values[((j * nu + i) * 3 + c) * terms + k]: \
                          polar node j slowest, then azimuth node i, colour c (R, G, B), \
                          term k (SH index l*l + l + m, or the one irradiance term)";

/// How a GPU build looks the table up, as the header states it.
pub const LOOKUP: &str = "world unit normal n turned by -rotation_rad about +y; node (i, j) \
                          is probe polar angle pi j / (nv - 1) from +y and probe azimuth \
                          2 pi i / nu (atan2(-x, z), conventions of src/conventions); \
                          bilinear in both angles, azimuth wrapping, poles are rows; values \
                          in the shading frame of the node's normal; radiance = sum_k c_k(wo) \
                          T_k(n) per colour (Lambert: c = albedo / pi)";

/// The header of an exported transfer table (module doc, "Format").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableFile {
    pub format: String,
    pub version: u32,
    /// The values file, relative to the header's directory.
    pub values_file: String,
    /// Azimuth nodes (wrapping).
    pub nu: usize,
    /// Polar nodes, both poles included.
    pub nv: usize,
    /// `"sh"` or `"irradiance"`.
    pub basis: String,
    /// SH bands (`terms = bands^2`); 1 for `"irradiance"`.
    pub bands: usize,
    /// Whether the SH terms include `cos(polar_i)` (for data sets that exclude it); false
    /// for `"irradiance"`, whose one term is the irradiance itself.
    pub cosine: bool,
    /// Terms per colour.
    pub terms: usize,
    /// Probe rotation about +y, radians (f32), that the lookup undoes.
    pub rotation_rad: f64,
    /// Number of f32 values in the values file: `nu * nv * 3 * terms`.
    pub values: usize,
    /// XXH3-64 of the value count and the values' bits, `"xxh3-64:<16 hex>"`.
    pub checksum: String,
    /// [`LAYOUT`] (informative).
    pub layout: String,
    /// [`LOOKUP`] (informative).
    pub lookup: String,
}

/// A basis in words, for messages: `SH, 8 bands, times the cosine` or `irradiance`.
pub fn basis_text(basis: TransferBasis) -> String {
    match basis {
        TransferBasis::Sh { bands, cosine } => format!(
            "SH, {bands} bands, {} the cosine",
            if cosine { "times" } else { "without" }
        ),
        TransferBasis::Irradiance => "irradiance".into(),
    }
}

/// The header of `table` with its values in the file `values_file`.
pub fn header_of(table: &TransferTable, values_file: &str) -> TableFile {
    let (nu, nv) = table.grid();
    let (basis, bands, cosine) = match table.basis() {
        TransferBasis::Sh { bands, cosine } => ("sh", bands, cosine),
        TransferBasis::Irradiance => ("irradiance", 1, false),
    };
    TableFile {
        format: FORMAT.into(),
        version: VERSION,
        values_file: values_file.into(),
        nu,
        nv,
        basis: basis.into(),
        bands,
        cosine,
        terms: table.terms(),
        rotation_rad: table
            .rotation()
            .to_string()
            .parse()
            .expect("an f32's decimal form"),
        values: table.values().len(),
        checksum: crate::hash::tagged(values_checksum(table.values())),
        layout: LAYOUT.into(),
        lookup: LOOKUP.into(),
    }
}

/// The values file's bytes (module doc, "Format").
pub fn values_bytes(table: &TransferTable) -> Vec<u8> {
    table
        .values()
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

/// Writes `table` as the header `json` and the values file `bin` beside it (each
/// atomically). The header names `bin` by its file name.
pub fn write_table(json: &Path, bin: &Path, table: &TransferTable) -> Result<()> {
    let name = bin
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let header = header_of(table, &name);
    let text = serde_json::to_string_pretty(&header).expect("a header serialises") + "\n";
    let write = |p: &Path, bytes: &[u8]| {
        crate::image_io::write_atomic(p, bytes).map_err(|e| Error::io(p, "cannot write", e))
    };
    write(bin, &values_bytes(table))?;
    write(json, text.as_bytes())
}

/// Reads the table whose header is `json` (module doc, "Format"). Errors are one line
/// naming the file and the field: a wrong format tag or version, an unknown basis, a grid
/// (`nu >= 3`, `nv >= 2`), term count or value count that disagree with each other or with
/// the values file's size, a checksum that does not match, a rotation or value that is not
/// finite.
pub fn read_table(json: &Path) -> Result<TransferTable> {
    let text = crate::image_io::read_regular_text(json, MAX_HEADER_BYTES, "transfer table")?;
    let h: TableFile = serde_json::from_str(&text)
        .map_err(|e| Error::format(json, format!("not a transfer table header: {e}")))?;
    let bad = |field: &str, why: String| Error::format(json, format!("{field}: {why}"));
    if h.format != FORMAT {
        return Err(bad(
            "format",
            format!("'{}', expected '{FORMAT}'", h.format),
        ));
    }
    if h.version != VERSION {
        return Err(bad("version", format!("{}, expected {VERSION}", h.version)));
    }
    let basis = match h.basis.as_str() {
        "sh" => {
            if !(1..=crate::sh::MAX_BANDS).contains(&h.bands) {
                return Err(bad(
                    "bands",
                    format!(
                        "{} is out of range (1 to {})",
                        h.bands,
                        crate::sh::MAX_BANDS
                    ),
                ));
            }
            TransferBasis::Sh {
                bands: h.bands,
                cosine: h.cosine,
            }
        }
        "irradiance" => {
            if h.bands != 1 || h.cosine {
                return Err(bad(
                    "bands",
                    "an irradiance table has bands = 1 and cosine = false".into(),
                ));
            }
            TransferBasis::Irradiance
        }
        other => {
            return Err(bad(
                "basis",
                format!("'{other}' is not 'sh' or 'irradiance'"),
            ))
        }
    };
    if h.terms != basis.terms() {
        return Err(bad(
            "terms",
            format!("{}, but the basis has {} terms", h.terms, basis.terms()),
        ));
    }
    if h.nu < 3 {
        return Err(bad("nu", format!("{} must be at least 3", h.nu)));
    }
    if h.nv < 2 {
        return Err(bad(
            "nv",
            format!("{} must be at least 2 (both poles are rows)", h.nv),
        ));
    }
    let n =
        h.nu.checked_mul(h.nv)
            .and_then(|x| x.checked_mul(3 * h.terms))
            .filter(|&x| x <= MAX_VALUES)
            .ok_or_else(|| {
                bad(
                    "nv",
                    format!(
                        "{} x {} nodes x {} terms is over 2^24 values",
                        h.nu, h.nv, h.terms
                    ),
                )
            })?;
    if h.values != n {
        return Err(bad(
            "values",
            format!("{}, expected nu * nv * 3 * terms = {n}", h.values),
        ));
    }
    let rotation = h.rotation_rad as f32;
    if !rotation.is_finite() {
        return Err(bad(
            "rotation_rad",
            format!("{} is not a finite f32", h.rotation_rad),
        ));
    }
    let name = Path::new(&h.values_file);
    let plain = name.components().count() == 1
        && matches!(
            name.components().next(),
            Some(std::path::Component::Normal(_))
        );
    if !plain {
        return Err(bad(
            "values_file",
            format!("'{}' must be a file name beside the header", h.values_file),
        ));
    }
    let bin: PathBuf = json.parent().unwrap_or(Path::new(".")).join(name);
    let bytes =
        crate::image_io::read_regular_file(&bin, 4 * MAX_VALUES as u64, "transfer table values")?;
    if bytes.len() != 4 * n {
        return Err(Error::format(
            &bin,
            format!(
                "{} bytes, expected {} (values = {n} f32 in {})",
                bytes.len(),
                4 * n,
                json.display()
            ),
        ));
    }
    let values: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let sum = crate::hash::tagged(values_checksum(&values));
    if h.checksum != sum {
        return Err(bad(
            "checksum",
            format!(
                "'{}' does not match the values of {} ({sum}): edited or damaged",
                h.checksum,
                bin.display()
            ),
        ));
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(Error::format(
            &bin,
            format!("value {i} is {}: not finite", values[i]),
        ));
    }
    Ok(TransferTable::from_parts(
        (h.nu, h.nv),
        basis,
        rotation as f64,
        values,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::env::LoadOptions;
    use crate::progress::Progress;

    fn table(rotation: f64) -> TransferTable {
        let texels: Vec<[f32; 3]> = (0..32 * 16)
            .map(|i| [1.0 + (i % 7) as f32, 0.5, 0.25 * (i % 3) as f32])
            .collect();
        let opts = LoadOptions {
            rotation,
            ..LoadOptions::default()
        };
        let (probe, _) = crate::env::Probe::from_texels("t", 32, 16, texels, &opts).unwrap();
        super::super::build_table(
            &probe,
            TransferBasis::Sh {
                bands: 2,
                cosine: true,
            },
            (8, 5),
            &[3],
            1.0,
            &Progress::hidden(),
            super::super::BuildFault::None,
        )
        .unwrap()
    }

    #[test]
    fn table_round_trips_bit_exact_and_damage_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let (json, bin) = (tmp.path().join("t.json"), tmp.path().join("t.bin"));
        // A rotation whose f32 is not a short decimal.
        let t = table(1.0f64.to_radians());
        write_table(&json, &bin, &t).unwrap();
        let back = read_table(&json).unwrap();
        assert_eq!(back, t, "values, grid, basis, rotation and its sin/cos");
        assert_eq!(std::fs::metadata(&bin).unwrap().len(), 4 * 8 * 5 * 3 * 4);

        let err = |j: &Path| read_table(j).unwrap_err().to_string();
        // A flipped bit in the last value.
        let good = std::fs::read(&bin).unwrap();
        let mut flipped = good.clone();
        *flipped.last_mut().unwrap() ^= 1;
        std::fs::write(&bin, &flipped).unwrap();
        let e = err(&json);
        assert!(e.contains("t.json") && e.contains("checksum"), "{e}");
        // Truncated.
        std::fs::write(&bin, &good[..good.len() - 4]).unwrap();
        let e = err(&json);
        assert!(e.contains("t.bin") && e.contains("bytes, expected"), "{e}");
        std::fs::write(&bin, &good).unwrap();
        // Header fields that disagree.
        let text = std::fs::read_to_string(&json).unwrap();
        for (from, to, field) in [
            ("\"nu\": 8", "\"nu\": 16", "values"),
            ("\"terms\": 4", "\"terms\": 9", "terms"),
            ("\"basis\": \"sh\"", "\"basis\": \"lambert\"", "basis"),
            ("\"version\": 1", "\"version\": 2", "version"),
            (
                "\"values_file\": \"t.bin\"",
                "\"values_file\": \"../t.bin\"",
                "values_file",
            ),
        ] {
            assert!(text.contains(from), "{from}");
            std::fs::write(&json, text.replacen(from, to, 1)).unwrap();
            let e = err(&json);
            assert!(
                e.contains("t.json") && e.contains(&format!("{field}:")),
                "{from}: {e}"
            );
            assert_eq!(e.lines().count(), 1, "{e}");
        }
    }
}
