//! The sweep CSV: the in-memory row ([`Row`]), its text ([`CSV_HEADER`], [`csv_text`],
//! [`write_csv`]) and reading it back ([`read_csv`]); merging shards is `merge.rs`.
//!
//! (Past 400 lines because it is one schema: the record, its writer and its reader must
//! agree column for column, and the header check and error messages belong to the reader;
//! the per-column text is already `csv/columns.rs`.)
//!
//! Design rule: one schema, the private serde record `Record`, written and read with the
//! `csv` crate. Columns are matched by header name, so a CSV whose columns are reordered
//! reads the same; a missing, unknown or repeated column is an error at line 1 naming it,
//! and a bad value is an error naming the file, the line and the column. Writing is fixed:
//! the columns in [`CSV_HEADER`]'s order, integers in decimal, errors in Rust's shortest
//! round-trip form, times with 3 decimals, flags as `0`/`1`, so reading a CSV and writing
//! it again gives the same bytes (`assets/readme/sweep.csv` is checked that way). How each
//! column's text is written and read is `csv/columns.rs`.

mod columns;

use super::{Config, MethodAxis, MethodKind};
use crate::env::schema::SamplerKind;
use crate::error::{Error, Result};
use crate::image_io;
use crate::scene::Precision;
use crate::sh::dataset::Lookup;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The CSV header: deterministic columns first (the configuration: `method` and its
/// parameters, `-` where a parameter is not the row's method's; then the errors and the
/// default flag), then measured ones. `cut_error` and `cut_max` are the parameters of
/// `lightcuts`; `reflection_grid` and `exact_lights` those of `reflection`.
pub const CSV_HEADER: &str = "index,method,sampler,lights,transfer_azimuth,transfer_polar,exact_lights,cut_error,cut_max,reflection_grid,order,lookup,precision,rel_rmse,p99_rel,max_err,flip_mean,default,prep_ms,frame_ms,pareto";

/// The header of sweep CSVs written before the method axis (no `method` column), recognised
/// only to say so when one is read.
const HEADER_BEFORE_METHODS: &str =
    "index,sampler,lights,order,lookup,precision,rel_rmse,max_err,flip_mean,default,prep_ms,frame_ms,pareto";

/// The header of sweep CSVs written before the `p99_rel` column, recognised only to say so.
const HEADER_BEFORE_P99: &str = "index,method,sampler,lights,transfer_azimuth,transfer_polar,exact_lights,cut_error,cut_max,order,lookup,precision,rel_rmse,max_err,flip_mean,default,prep_ms,frame_ms,pareto";

/// The header of sweep CSVs written before the `reflection` method (no `reflection_grid`
/// column), recognised only to say so.
const HEADER_BEFORE_REFLECTION: &str = "index,method,sampler,lights,transfer_azimuth,transfer_polar,exact_lights,cut_error,cut_max,order,lookup,precision,rel_rmse,p99_rel,max_err,flip_mean,default,prep_ms,frame_ms,pareto";

/// Number of deterministic leading columns of [`CSV_HEADER`] (`index` .. `default`).
pub const DETERMINISTIC_COLUMNS: usize = 18;

/// The column names of [`CSV_HEADER`], in order (the field names of `Record`).
const COLUMNS: [&str; 21] = [
    "index",
    "method",
    "sampler",
    "lights",
    "transfer_azimuth",
    "transfer_polar",
    "exact_lights",
    "cut_error",
    "cut_max",
    "reflection_grid",
    "order",
    "lookup",
    "precision",
    "rel_rmse",
    "p99_rel",
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
    /// 99th percentile of the per-pixel relative error over covered pixels
    /// ([`crate::metrics::relative_error_quantile`]), dimensionless.
    pub p99_rel: f64,
    /// Largest absolute channel error, linear radiance.
    pub max_err: f64,
    /// Mean FLIP of the display encodings, in [0, 1].
    pub flip_mean: f64,
    /// Whether this is the scene's own configuration.
    pub default: bool,
    /// The method's preparation time, milliseconds (measured): the light set's sampling,
    /// or the transfer table's build and the choice of its exact lights.
    pub prep_ms: f64,
    /// Median frame time, milliseconds (measured).
    pub frame_ms: f64,
    /// On the Pareto front of (frame_ms, rel_rmse) over the rows of the CSV.
    pub pareto: bool,
}

/// A CSV line as serde sees it: one field per column, named as in [`CSV_HEADER`] and in its
/// order (serialization writes fields in declaration order). A method parameter is `None`
/// (written `-`) on the rows of other methods.
#[derive(Serialize, Deserialize)]
struct Record {
    index: usize,
    #[serde(with = "columns::method")]
    method: MethodKind,
    #[serde(with = "columns::sampler")]
    sampler: Option<SamplerKind>,
    #[serde(
        serialize_with = "columns::dash::serialize",
        deserialize_with = "columns::dash::lights"
    )]
    lights: Option<usize>,
    #[serde(
        serialize_with = "columns::dash::serialize",
        deserialize_with = "columns::dash::transfer_azimuth"
    )]
    transfer_azimuth: Option<usize>,
    #[serde(
        serialize_with = "columns::dash::serialize",
        deserialize_with = "columns::dash::transfer_polar"
    )]
    transfer_polar: Option<usize>,
    #[serde(
        serialize_with = "columns::dash::serialize",
        deserialize_with = "columns::dash::exact_lights"
    )]
    exact_lights: Option<usize>,
    #[serde(
        serialize_with = "columns::dash::serialize",
        deserialize_with = "columns::dash::cut_error"
    )]
    cut_error: Option<f32>,
    #[serde(
        serialize_with = "columns::dash::serialize",
        deserialize_with = "columns::dash::cut_max"
    )]
    cut_max: Option<usize>,
    #[serde(
        serialize_with = "columns::dash::serialize",
        deserialize_with = "columns::dash::reflection_grid"
    )]
    reflection_grid: Option<usize>,
    order: usize,
    #[serde(with = "columns::lookup")]
    lookup: Option<Lookup>,
    #[serde(with = "columns::precision")]
    precision: Precision,
    #[serde(serialize_with = "columns::shortest")]
    rel_rmse: f64,
    #[serde(serialize_with = "columns::shortest")]
    p99_rel: f64,
    #[serde(serialize_with = "columns::shortest")]
    max_err: f64,
    #[serde(serialize_with = "columns::shortest")]
    flip_mean: f64,
    #[serde(
        serialize_with = "columns::flag",
        deserialize_with = "columns::default_flag"
    )]
    default: bool,
    #[serde(serialize_with = "columns::millis")]
    prep_ms: f64,
    #[serde(serialize_with = "columns::millis")]
    frame_ms: f64,
    #[serde(
        serialize_with = "columns::flag",
        deserialize_with = "columns::pareto_flag"
    )]
    pareto: bool,
}

impl From<&Row> for Record {
    fn from(r: &Row) -> Record {
        let c = &r.config;
        let mut rec = Record {
            index: c.index,
            method: c.method.kind(),
            sampler: None,
            lights: None,
            transfer_azimuth: None,
            transfer_polar: None,
            exact_lights: None,
            cut_error: None,
            cut_max: None,
            reflection_grid: None,
            order: c.order,
            lookup: c.lookup,
            precision: c.precision,
            rel_rmse: r.rel_rmse,
            p99_rel: r.p99_rel,
            max_err: r.max_err,
            flip_mean: r.flip_mean,
            default: r.default,
            prep_ms: r.prep_ms,
            frame_ms: r.frame_ms,
            pareto: r.pareto,
        };
        match c.method {
            MethodAxis::Lights { sampler, count } => {
                rec.sampler = Some(sampler);
                rec.lights = Some(count);
            }
            MethodAxis::Transfer {
                azimuth,
                polar,
                exact_lights,
            } => {
                rec.transfer_azimuth = Some(azimuth);
                rec.transfer_polar = Some(polar);
                rec.exact_lights = Some(exact_lights);
            }
            MethodAxis::Lightcuts { cut_error, cut_max } => {
                rec.cut_error = Some(cut_error);
                rec.cut_max = Some(cut_max);
            }
            MethodAxis::Reflection { grid, exact_lights } => {
                rec.reflection_grid = Some(grid);
                rec.exact_lights = Some(exact_lights);
            }
        }
        rec
    }
}

impl Record {
    /// The row, or the message of the first method parameter that is missing (`-` on a
    /// row of its method) or present on a row of another method.
    fn into_row(self) -> std::result::Result<Row, String> {
        let method = self.method;
        let name = method.name();
        use MethodKind::{Lightcuts, Lights, Reflection, Transfer};
        let params: [(&str, bool, &[MethodKind]); 8] = [
            ("sampler", self.sampler.is_some(), &[Lights]),
            ("lights", self.lights.is_some(), &[Lights]),
            (
                "transfer_azimuth",
                self.transfer_azimuth.is_some(),
                &[Transfer],
            ),
            ("transfer_polar", self.transfer_polar.is_some(), &[Transfer]),
            (
                "exact_lights",
                self.exact_lights.is_some(),
                &[Transfer, Reflection],
            ),
            ("cut_error", self.cut_error.is_some(), &[Lightcuts]),
            ("cut_max", self.cut_max.is_some(), &[Lightcuts]),
            (
                "reflection_grid",
                self.reflection_grid.is_some(),
                &[Reflection],
            ),
        ];
        for (column, given, of) in params {
            let belongs = of.contains(&method);
            if given && !belongs {
                return Err(format!(
                    "column {column}: a {name} row has no {column} (write -)"
                ));
            }
            if !given && belongs {
                return Err(format!(
                    "column {column}: a {name} row needs a {column}, not -"
                ));
            }
        }
        let axis = match method {
            MethodKind::Lights => MethodAxis::Lights {
                sampler: self.sampler.expect("checked above"),
                count: self.lights.expect("checked above"),
            },
            MethodKind::Transfer => MethodAxis::Transfer {
                azimuth: self.transfer_azimuth.expect("checked above"),
                polar: self.transfer_polar.expect("checked above"),
                exact_lights: self.exact_lights.expect("checked above"),
            },
            MethodKind::Lightcuts => MethodAxis::Lightcuts {
                cut_error: self.cut_error.expect("checked above"),
                cut_max: self.cut_max.expect("checked above"),
            },
            MethodKind::Reflection => MethodAxis::Reflection {
                grid: self.reflection_grid.expect("checked above"),
                exact_lights: self.exact_lights.expect("checked above"),
            },
        };
        Ok(Row {
            config: Config {
                index: self.index,
                method: axis,
                order: self.order,
                lookup: self.lookup,
                precision: self.precision,
            },
            rel_rmse: self.rel_rmse,
            p99_rel: self.p99_rel,
            max_err: self.max_err,
            flip_mean: self.flip_mean,
            default: self.default,
            prep_ms: self.prep_ms,
            frame_ms: self.frame_ms,
            pareto: self.pareto,
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
    if headers.iter().collect::<Vec<_>>().join(",") == HEADER_BEFORE_METHODS {
        return Err(
            "a sweep CSV from before the method axis (no method column): its rows are \
             lights rows of an older grid and its index numbering may not be this build's; \
             regenerate it with this build (`brdfkit sweep`, see `brdfkit sweep --help`)"
                .into(),
        );
    }
    if headers.iter().collect::<Vec<_>>().join(",") == HEADER_BEFORE_P99 {
        return Err(
            "a sweep CSV from before the p99_rel column: regenerate it with this build \
             (`brdfkit sweep`, see `brdfkit sweep --help`)"
                .into(),
        );
    }
    if headers.iter().collect::<Vec<_>>().join(",") == HEADER_BEFORE_REFLECTION {
        return Err(
            "a sweep CSV from before the reflection method (no reflection_grid column): \
             regenerate it with this build (`brdfkit sweep`, see `brdfkit sweep --help`), or \
             add the column after cut_max with - on every row"
                .into(),
        );
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
        let line = record.position().map_or(0, ::csv::Position::line);
        rows.push(
            r.into_row()
                .map_err(|m| Error::format(path, format!("line {line}: {m}")))?,
        );
    }
    Ok(rows)
}

#[cfg(test)]
mod tests;
