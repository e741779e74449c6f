//! The sweep CSV: the in-memory row ([`Row`]), its text ([`CSV_HEADER`], [`csv_text`],
//! [`write_csv`]) and reading it back ([`read_csv`]); merging shards is `merge.rs`.
//!
//! Design rule: one schema, the private serde record `Record`, written and read with the
//! `csv` crate. Columns are matched by header name, so a CSV whose columns are reordered
//! reads the same; a missing, unknown or repeated column is an error at line 1 naming it,
//! and a bad value is an error naming the file, the line and the column. Writing is fixed:
//! the columns in [`CSV_HEADER`]'s order, integers in decimal, errors in Rust's shortest
//! round-trip form, times with 3 decimals, flags as `0`/`1`, so reading a CSV and writing
//! it again gives the same bytes (`assets/readme/sweep.csv` is checked that way).

use super::Config;
use super::{lookup_name, parse_lookup, parse_sampler, precision_name, sampler_name};
use crate::env::prepare::SamplerKind;
use crate::error::{Error, Result};
use crate::image_io;
use crate::scene::Precision;
use crate::sh::dataset::Lookup;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::path::Path;

/// The CSV header: deterministic columns first, then measured ones.
pub const CSV_HEADER: &str =
    "index,sampler,lights,order,lookup,precision,rel_rmse,max_err,flip_mean,default,prep_ms,frame_ms,pareto";

/// Number of deterministic leading columns of [`CSV_HEADER`] (`index` .. `default`).
pub const DETERMINISTIC_COLUMNS: usize = 10;

/// The column names of [`CSV_HEADER`], in order (the field names of `Record`).
const COLUMNS: [&str; 13] = [
    "index",
    "sampler",
    "lights",
    "order",
    "lookup",
    "precision",
    "rel_rmse",
    "max_err",
    "flip_mean",
    "default",
    "prep_ms",
    "frame_ms",
    "pareto",
];

/// One measured configuration: a CSV line.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub config: Config,
    /// Relative RMSE over covered pixels (see the module doc), dimensionless.
    pub rel_rmse: f64,
    /// Largest absolute channel error, linear radiance.
    pub max_err: f64,
    /// Mean FLIP of the display encodings, in [0, 1].
    pub flip_mean: f64,
    /// Whether this is the scene's own configuration.
    pub default: bool,
    /// Light-set preparation time, milliseconds (measured).
    pub prep_ms: f64,
    /// Median frame time, milliseconds (measured).
    pub frame_ms: f64,
    /// On the Pareto front of (frame_ms, rel_rmse) over the rows of the CSV.
    pub pareto: bool,
}

/// A CSV line as serde sees it: one field per column, named as in [`CSV_HEADER`] and in its
/// order (serialization writes fields in declaration order).
#[derive(Serialize, Deserialize)]
struct Record {
    index: usize,
    #[serde(with = "sampler_column")]
    sampler: SamplerKind,
    lights: usize,
    order: usize,
    #[serde(with = "lookup_column")]
    lookup: Option<Lookup>,
    #[serde(with = "precision_column")]
    precision: Precision,
    #[serde(serialize_with = "shortest")]
    rel_rmse: f64,
    #[serde(serialize_with = "shortest")]
    max_err: f64,
    #[serde(serialize_with = "shortest")]
    flip_mean: f64,
    #[serde(serialize_with = "flag", deserialize_with = "default_flag")]
    default: bool,
    #[serde(serialize_with = "millis")]
    prep_ms: f64,
    #[serde(serialize_with = "millis")]
    frame_ms: f64,
    #[serde(serialize_with = "flag", deserialize_with = "pareto_flag")]
    pareto: bool,
}

impl From<&Row> for Record {
    fn from(r: &Row) -> Record {
        let c = &r.config;
        Record {
            index: c.index,
            sampler: c.sampler,
            lights: c.lights,
            order: c.order,
            lookup: c.lookup,
            precision: c.precision,
            rel_rmse: r.rel_rmse,
            max_err: r.max_err,
            flip_mean: r.flip_mean,
            default: r.default,
            prep_ms: r.prep_ms,
            frame_ms: r.frame_ms,
            pareto: r.pareto,
        }
    }
}

impl From<Record> for Row {
    fn from(r: Record) -> Row {
        Row {
            config: Config {
                index: r.index,
                sampler: r.sampler,
                lights: r.lights,
                order: r.order,
                lookup: r.lookup,
                precision: r.precision,
            },
            rel_rmse: r.rel_rmse,
            max_err: r.max_err,
            flip_mean: r.flip_mean,
            default: r.default,
            prep_ms: r.prep_ms,
            frame_ms: r.frame_ms,
            pareto: r.pareto,
        }
    }
}

/// An error column as `{}` writes it: Rust's shortest round-trip decimal, no exponent.
fn shortest<S: Serializer>(x: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(x)
}

/// A time in milliseconds with 3 decimals (1 us).
fn millis<S: Serializer>(x: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{x:.3}"))
}

fn flag<S: Serializer>(b: &bool, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_u8(*b as u8)
}

fn parse_flag<'de, D: Deserializer<'de>>(
    column: &str,
    d: D,
) -> std::result::Result<bool, D::Error> {
    match String::deserialize(d)?.as_str() {
        "0" => Ok(false),
        "1" => Ok(true),
        other => Err(D::Error::custom(format!(
            "column {column}: {other:?} is not 0 or 1"
        ))),
    }
}

fn default_flag<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<bool, D::Error> {
    parse_flag("default", d)
}

fn pareto_flag<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<bool, D::Error> {
    parse_flag("pareto", d)
}

/// The `sampler` column: [`sampler_name`] / [`parse_sampler`].
mod sampler_column {
    use super::*;

    pub fn serialize<S: Serializer>(v: &SamplerKind, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(&sampler_name(*v))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<SamplerKind, D::Error> {
        let name = String::deserialize(d)?;
        parse_sampler(&name)
            .ok_or_else(|| D::Error::custom(format!("column sampler: unknown sampler {name:?}")))
    }
}

/// The `lookup` column: [`lookup_name`] / [`parse_lookup`].
mod lookup_column {
    use super::*;

    pub fn serialize<S: Serializer>(
        v: &Option<Lookup>,
        s: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(lookup_name(*v))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<Option<Lookup>, D::Error> {
        let name = String::deserialize(d)?;
        parse_lookup(&name)
            .ok_or_else(|| D::Error::custom(format!("column lookup: unknown lookup {name:?}")))
    }
}

/// The `precision` column: [`precision_name`].
mod precision_column {
    use super::*;

    pub fn serialize<S: Serializer>(v: &Precision, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(precision_name(*v))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<Precision, D::Error> {
        let name = String::deserialize(d)?;
        [Precision::F32, Precision::F64]
            .into_iter()
            .find(|&p| precision_name(p) == name)
            .ok_or_else(|| {
                D::Error::custom(format!("column precision: unknown precision {name:?}"))
            })
    }
}

/// CSV text of `rows`, with the header line when `header`; every line ends in `\n`.
fn write_text(rows: &[Row], header: bool) -> String {
    let mut w = ::csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    if header {
        w.write_record(COLUMNS).expect("writing to memory");
    }
    for r in rows {
        w.serialize(Record::from(r)).expect("writing to memory");
    }
    let bytes = w.into_inner().expect("writing to memory");
    String::from_utf8(bytes).expect("the CSV writer writes the UTF-8 it is given")
}

impl Row {
    /// The CSV line (no newline).
    pub fn csv_line(&self) -> String {
        let mut line = write_text(std::slice::from_ref(self), false);
        line.pop();
        line
    }

    /// The deterministic columns of [`Row::csv_line`] (`index` .. `default`).
    pub fn deterministic_part(&self) -> String {
        self.csv_line()
            .split(',')
            .take(DETERMINISTIC_COLUMNS)
            .collect::<Vec<_>>()
            .join(",")
    }
}

/// The CSV text of rows (header, then one line per row, each ending in a newline).
pub fn csv_text(rows: &[Row]) -> String {
    write_text(rows, true)
}

/// Writes rows as CSV through a temporary file ([`image_io::write_atomically`]).
pub fn write_csv(path: &Path, rows: &[Row]) -> Result<()> {
    let text = csv_text(rows);
    image_io::write_atomically(path, |tmp| {
        std::fs::write(tmp, text.as_bytes()).map_err(|e| Error::io(path, "cannot write CSV", e))
    })
}

/// Reads a sweep CSV. Errors name the file and, for content, the line and the column.
pub fn read_csv(path: &Path) -> Result<Vec<Row>> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, "cannot read sweep CSV", e))?;
    parse_csv(path, &bytes)
}

/// Checks a header line: every column of [`CSV_HEADER`] once, in any order, and no other.
fn check_header(headers: &::csv::StringRecord) -> std::result::Result<(), String> {
    if headers.is_empty() {
        return Err("empty file, no CSV header".into());
    }
    for (i, h) in headers.iter().enumerate() {
        if !COLUMNS.contains(&h) {
            return Err(format!(
                "not a sweep CSV: unknown column {h:?} (`brdfkit sweep` writes {CSV_HEADER})"
            ));
        }
        if headers.iter().take(i).any(|x| x == h) {
            return Err(format!("not a sweep CSV: column {h:?} appears twice"));
        }
    }
    match COLUMNS.iter().find(|c| !headers.iter().any(|h| h == **c)) {
        Some(c) => Err(format!("not a sweep CSV: no column {c:?}")),
        None => Ok(()),
    }
}

/// The message of a CSV content error, prefixed with its line (and column when the `csv`
/// crate knows it; the column deserializers name theirs).
fn content_error(
    e: &::csv::Error,
    headers: &::csv::StringRecord,
    record: Option<&::csv::StringRecord>,
) -> String {
    use ::csv::{DeserializeErrorKind as K, ErrorKind};
    let line = e.position().map_or(0, ::csv::Position::line);
    match e.kind() {
        ErrorKind::UnequalLengths {
            len, expected_len, ..
        } => {
            format!("line {line}: {len} fields, expected {expected_len}")
        }
        ErrorKind::Utf8 { .. } => format!("line {line}: not UTF-8 text"),
        ErrorKind::Deserialize { err, .. } => match err.field() {
            Some(i) => {
                let column = headers.get(i as usize).unwrap_or("?");
                let value = record.and_then(|r| r.get(i as usize)).unwrap_or("");
                let what = match err.kind() {
                    K::ParseInt(_) => "is not a whole number".to_string(),
                    K::ParseFloat(_) => "is not a number".to_string(),
                    other => other.to_string(),
                };
                format!("line {line}: column {column}: {value:?} {what}")
            }
            None => format!("line {line}: {}", err.kind()),
        },
        _ => format!("line {line}: {e}"),
    }
}

/// Parses the text of a sweep CSV; `path` names it in errors.
fn parse_csv(path: &Path, bytes: &[u8]) -> Result<Vec<Row>> {
    let mut reader = ::csv::ReaderBuilder::new()
        .trim(::csv::Trim::All)
        .from_reader(bytes);
    let headers = reader
        .headers()
        .map_err(|e| Error::format(path, content_error(&e, &Default::default(), None)))?
        .clone();
    check_header(&headers).map_err(|m| Error::format(path, format!("line 1: {m}")))?;
    let mut rows = Vec::new();
    let mut record = ::csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(false) => break,
            Ok(true) => {}
            Err(e) => return Err(Error::format(path, content_error(&e, &headers, None))),
        }
        let r: Record = record
            .deserialize(Some(&headers))
            .map_err(|e| Error::format(path, content_error(&e, &headers, Some(&record))))?;
        rows.push(Row::from(r));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests;
