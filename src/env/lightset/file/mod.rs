//! Reading and writing [`LightSet`]s as JSON (with a header) and CSV.
//!
//! Design rule: a file on disk is either complete or absent. Every write goes to a
//! temporary file in the destination directory and is renamed over the target, so a
//! crash never leaves half a light set for a later run (or cache) to read. Every read
//! validates what it got (equal lengths, finite values, unit directions, non-negative
//! irradiances) and every error names the file and the line or field.
//!
//! JSON: `{"format": "brdfkit-lightset", "version": 1, "header": {...}, "lights":
//! {"dir_x": [...], ..., "irradiance_b": [...]}}`. CSV: a first line
//! `dir_x,dir_y,dir_z,irradiance_r,irradiance_g,irradiance_b` ([`CSV_HEADER`]), then one
//! light per line. Numbers are written with Rust's shortest round-trip formatting, so f32
//! values read back bit-exact. Each light's `irradiance_*` is its RGB irradiance at normal
//! incidence (W/m^2 for a probe in W/(m^2 sr); [`LightSet`]).
//!
//! Files written before the rename name these `power_*` (JSON keys `power_r`, ...,
//! header `total_power`; CSV header [`CSV_HEADER_V0`]): both are still read, and only the
//! new names are written.

use super::LightSet;
use crate::image_io::write_atomic;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The CSV header line.
pub const CSV_HEADER: &str = "dir_x,dir_y,dir_z,irradiance_r,irradiance_g,irradiance_b";
/// The CSV header line of files written before the irradiance columns were named so
/// (same columns, same meaning); still read.
pub const CSV_HEADER_V0: &str = "dir_x,dir_y,dir_z,power_r,power_g,power_b";
const FORMAT: &str = "brdfkit-lightset";
const VERSION: u32 = 1;

/// Metadata written with a JSON light set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LightSetHeader {
    /// Sampler name ([`crate::env::SamplerConfig::name`]).
    pub sampler: String,
    /// Number of lights in the file.
    pub n: usize,
    /// Seed of a random sampler.
    pub seed: Option<u64>,
    /// The probe file the set was made from.
    pub probe_file: Option<String>,
    /// Sum of the lights' RGB irradiances at normal incidence
    /// ([`LightSet::total_irradiance`], W/m^2 for a probe in W/(m^2 sr)); read from
    /// `total_power` in files written before the rename.
    #[serde(alias = "total_power")]
    pub total_irradiance: [f64; 3],
}

impl LightSetHeader {
    /// A header describing `lights`, made by `config` from `probe_file`.
    pub fn new(
        config: &super::samplers::SamplerConfig,
        probe_file: Option<&str>,
        lights: &LightSet,
    ) -> Self {
        let t = lights.total_irradiance();
        LightSetHeader {
            sampler: config.name().to_string(),
            n: lights.len(),
            seed: config.seed(),
            probe_file: probe_file.map(str::to_string),
            total_irradiance: [t.x, t.y, t.z],
        }
    }
}

/// Largest light-set file read (JSON or CSV), in bytes: 64 MiB. The largest sets brdfkit
/// writes are full-probe cache entries: a 512x256 probe's 131072 lights are 15 MB of
/// pretty-printed JSON (~115 bytes per light), so this admits a 1024x512 probe's (60 MB)
/// while bounding what a hostile file can make the reader allocate. A cache entry over it
/// is ignored and the set recomputed.
pub const MAX_LIGHTSET_BYTES: u64 = 64 << 20;

/// Why reading or writing a light set failed; every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum LightSetIoError {
    /// Not a regular file, too large, or unreadable ([`crate::image_io::read_regular_file`]).
    #[error(transparent)]
    File(#[from] crate::error::FileError),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: invalid light set JSON: {message}")]
    Json { path: PathBuf, message: String },
    /// A name [`read_by_extension`] cannot read (not `.json` or `.csv`).
    #[error("{path}: a light set file name ends in .json or .csv")]
    Extension { path: PathBuf },
    #[error("{path}:{line}: field {field}: {message}")]
    Csv {
        path: PathBuf,
        line: usize,
        field: String,
        message: String,
    },
    #[error("{path}: light {index}: field {field}: {message}")]
    Invalid {
        path: PathBuf,
        index: usize,
        field: &'static str,
        message: String,
    },
}

#[derive(Serialize, Deserialize)]
struct JsonFile {
    format: String,
    version: u32,
    header: LightSetHeader,
    lights: LightSet,
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> LightSetIoError + '_ {
    move |source| LightSetIoError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Writes a light set and its header as JSON (atomically).
pub fn write_json(
    path: &Path,
    header: &LightSetHeader,
    lights: &LightSet,
) -> Result<(), LightSetIoError> {
    let file = JsonFile {
        format: FORMAT.into(),
        version: VERSION,
        header: header.clone(),
        lights: lights.clone(),
    };
    let bytes = serde_json::to_vec_pretty(&file).map_err(|e| LightSetIoError::Json {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    write_atomic(path, &bytes).map_err(io_err(path))
}

/// Reads a JSON light set. Fails on I/O, a file that is not regular or is over
/// [`MAX_LIGHTSET_BYTES`], malformed JSON (message has line and column),
/// a wrong format tag or version, or invalid lights ([`validate`]).
pub fn read_json(path: &Path) -> Result<(LightSetHeader, LightSet), LightSetIoError> {
    let bytes = crate::image_io::read_regular_file(path, MAX_LIGHTSET_BYTES, "light set")?;
    let file: JsonFile = serde_json::from_slice(&bytes).map_err(|e| LightSetIoError::Json {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    if file.format != FORMAT || file.version != VERSION {
        return Err(LightSetIoError::Json {
            path: path.to_path_buf(),
            message: format!(
                "format {:?} version {} (expected {FORMAT:?} version {VERSION})",
                file.format, file.version
            ),
        });
    }
    validate(path, &file.lights)?;
    if file.header.n != file.lights.len() {
        return Err(LightSetIoError::Json {
            path: path.to_path_buf(),
            message: format!(
                "header says n = {} but there are {} lights",
                file.header.n,
                file.lights.len()
            ),
        });
    }
    Ok((file.header, file.lights))
}

/// Reads a light set by its extension: `.json` ([`read_json`], header dropped) or `.csv`
/// ([`read_csv`]); any other name is [`LightSetIoError::Extension`].
pub fn read_by_extension(path: &Path) -> Result<LightSet, LightSetIoError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("json") => read_json(path).map(|(_, ls)| ls),
        Some("csv") => read_csv(path),
        _ => Err(LightSetIoError::Extension {
            path: path.to_path_buf(),
        }),
    }
}

/// Writes a light set as CSV (atomically).
pub fn write_csv(path: &Path, lights: &LightSet) -> Result<(), LightSetIoError> {
    let mut s = String::with_capacity(64 * (lights.len() + 1));
    s.push_str(CSV_HEADER);
    s.push('\n');
    for i in 0..lights.len() {
        s.push_str(&format!(
            "{},{},{},{},{},{}\n",
            lights.dir_x[i],
            lights.dir_y[i],
            lights.dir_z[i],
            lights.irradiance_r[i],
            lights.irradiance_g[i],
            lights.irradiance_b[i]
        ));
    }
    write_atomic(path, s.as_bytes()).map_err(io_err(path))
}

/// Reads a CSV light set. Fails on I/O, a file that is not regular or is over
/// [`MAX_LIGHTSET_BYTES`], a header line other than [`CSV_HEADER`] or [`CSV_HEADER_V0`],
/// a line without exactly six fields, an unparsable number (naming line and field), or
/// invalid lights ([`validate`]). Blank lines are skipped.
pub fn read_csv(path: &Path) -> Result<LightSet, LightSetIoError> {
    let text = crate::image_io::read_regular_text(path, MAX_LIGHTSET_BYTES, "light set")?;
    let mut names: Vec<&str> = CSV_HEADER.split(',').collect();
    let mut lines = text.lines().enumerate();
    let csv_err = |line: usize, field: &str, message: String| LightSetIoError::Csv {
        path: path.to_path_buf(),
        line,
        field: field.to_string(),
        message,
    };
    match lines.next() {
        Some((_, h)) if h.trim() == CSV_HEADER => {}
        Some((_, h)) if h.trim() == CSV_HEADER_V0 => names = CSV_HEADER_V0.split(',').collect(),
        Some((_, h)) => {
            return Err(csv_err(
                1,
                "header",
                format!("expected {CSV_HEADER:?}, found {h:?}"),
            ))
        }
        None => return Err(csv_err(1, "header", "file is empty".into())),
    }
    let mut ls = LightSet::default();
    for (i, line) in lines {
        let lineno = i + 1;
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != 6 {
            return Err(csv_err(
                lineno,
                "*",
                format!("expected 6 fields, found {}", fields.len()),
            ));
        }
        let mut v = [0f32; 6];
        for (k, f) in fields.iter().enumerate() {
            v[k] = f
                .trim()
                .parse::<f32>()
                .map_err(|e| csv_err(lineno, names[k], format!("{f:?}: {e}")))?;
        }
        ls.dir_x.push(v[0]);
        ls.dir_y.push(v[1]);
        ls.dir_z.push(v[2]);
        ls.irradiance_r.push(v[3]);
        ls.irradiance_g.push(v[4]);
        ls.irradiance_b.push(v[5]);
    }
    validate(path, &ls)?;
    Ok(ls)
}

/// Checks a light set read from `path`: all six arrays the same length, every value
/// finite, directions unit length within 1e-4, irradiances `>= 0`.
pub fn validate(path: &Path, ls: &LightSet) -> Result<(), LightSetIoError> {
    let n = ls.dir_x.len();
    let arrays: [(&'static str, &Vec<f32>); 6] = [
        ("dir_x", &ls.dir_x),
        ("dir_y", &ls.dir_y),
        ("dir_z", &ls.dir_z),
        ("irradiance_r", &ls.irradiance_r),
        ("irradiance_g", &ls.irradiance_g),
        ("irradiance_b", &ls.irradiance_b),
    ];
    let invalid = |index, field, message| LightSetIoError::Invalid {
        path: path.to_path_buf(),
        index,
        field,
        message,
    };
    for (name, a) in arrays {
        if a.len() != n {
            return Err(invalid(
                a.len().min(n),
                name,
                format!("has {} entries, dir_x has {n}", a.len()),
            ));
        }
        for (i, v) in a.iter().enumerate() {
            if !v.is_finite() {
                return Err(invalid(i, name, format!("{v} is not finite")));
            }
            if name.starts_with("irradiance") && *v < 0.0 {
                return Err(invalid(i, name, format!("negative irradiance {v}")));
            }
        }
    }
    for i in 0..n {
        let l = ls.direction(i).length();
        if (l - 1.0).abs() > 1e-4 {
            return Err(invalid(i, "dir", format!("direction length {l} is not 1")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
