//! The text of the sweep CSV's columns (the `serde` `with` functions of the parent's
//! `Record`): errors in Rust's shortest round-trip form, times with 3 decimals, flags `0`/`1`,
//! names as the CLI spells them, `-` for a parameter a row's method does not have.
//! Deserializers name their column in errors where the `csv` crate cannot.

use crate::env::schema::SamplerKind;
use crate::scene::Precision;
use crate::sh::dataset::Lookup;
use crate::sweep::MethodKind;
use crate::sweep::{lookup_name, parse_lookup, parse_sampler, precision_name, sampler_name};
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serializer};

/// An error column as `{}` writes it: Rust's shortest round-trip decimal, no exponent.
pub fn shortest<S: Serializer>(x: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(x)
}

/// A time in milliseconds with 3 decimals (1 us).
pub fn millis<S: Serializer>(x: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{x:.3}"))
}

pub fn flag<S: Serializer>(b: &bool, s: S) -> std::result::Result<S::Ok, S::Error> {
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

pub fn default_flag<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<bool, D::Error> {
    parse_flag("default", d)
}

pub fn pareto_flag<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<bool, D::Error> {
    parse_flag("pareto", d)
}

/// The `sampler` column: [`sampler_name`] / [`parse_sampler`], `-` for none.
pub mod sampler {
    use super::*;

    pub fn serialize<S: Serializer>(
        v: &Option<SamplerKind>,
        s: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        match v {
            Some(v) => s.serialize_str(&sampler_name(*v)),
            None => s.serialize_str("-"),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<Option<SamplerKind>, D::Error> {
        let name = String::deserialize(d)?;
        if name == "-" {
            return Ok(None);
        }
        parse_sampler(&name)
            .map(Some)
            .ok_or_else(|| D::Error::custom(format!("column sampler: unknown sampler {name:?}")))
    }
}

/// The `method` column: [`MethodKind::name`] / [`MethodKind::parse`].
pub mod method {
    use super::*;

    pub fn serialize<S: Serializer>(v: &MethodKind, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(&v.name())
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<MethodKind, D::Error> {
        let name = String::deserialize(d)?;
        MethodKind::parse(&name).ok_or_else(|| {
            let known: Vec<String> = MethodKind::ALL.iter().map(|m| m.name()).collect();
            D::Error::custom(format!(
                "column method: {name:?} is not a method this build sweeps ({})",
                known.join(", ")
            ))
        })
    }
}

/// An optional number column: the value as `{}` writes it, `-` for none. Its
/// deserializers, one per column, name the column in errors (the `csv` crate does not
/// know it for a custom error).
pub mod dash {
    use super::*;
    use std::fmt::Display;
    use std::str::FromStr;

    pub fn serialize<T: Display, S: Serializer>(
        v: &Option<T>,
        s: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        match v {
            Some(v) => s.collect_str(v),
            None => s.serialize_str("-"),
        }
    }

    fn parse<'de, T: FromStr, D: Deserializer<'de>>(
        column: &str,
        d: D,
    ) -> std::result::Result<Option<T>, D::Error> {
        let text = String::deserialize(d)?;
        if text == "-" {
            return Ok(None);
        }
        text.parse().map(Some).map_err(|_| {
            D::Error::custom(format!("column {column}: {text:?} is not a number or -"))
        })
    }

    pub fn lights<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Option<usize>, D::Error> {
        parse("lights", d)
    }
    pub fn transfer_azimuth<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<Option<usize>, D::Error> {
        parse("transfer_azimuth", d)
    }
    pub fn transfer_polar<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<Option<usize>, D::Error> {
        parse("transfer_polar", d)
    }
    pub fn exact_lights<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<Option<usize>, D::Error> {
        parse("exact_lights", d)
    }
    pub fn cut_error<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<Option<f32>, D::Error> {
        parse("cut_error", d)
    }
    pub fn cut_max<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<Option<usize>, D::Error> {
        parse("cut_max", d)
    }
    pub fn reflection_grid<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<Option<usize>, D::Error> {
        parse("reflection_grid", d)
    }
}

/// The `lookup` column: [`lookup_name`] / [`parse_lookup`].
pub mod lookup {
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
pub mod precision {
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
