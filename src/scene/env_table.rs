//! The `[env]` table as written: every field optional ([`EnvTable`]), read once into an
//! [`EnvSpec`] with its defaults, and written back from one.
//!
//! Design rule: what the table states decides two things the defaults cannot, both here,
//! on the one parse of the scene file: a table that states `sampler` or `count` and no
//! `method` asks for a delta light set (its method is `lights`; a stated `method = "auto"`
//! stays `auto`, [`super::env_method`]); and a field that belongs to another method than the
//! table's ([`method_fields`]: `cut_error` under `method = "transfer"`) is an error naming
//! the field and the method it belongs to. Under `auto` every method's fields may be
//! stated (the method is chosen per material). Written back, a table states its method and
//! that method's fields (all of them under `auto`), so it reads back as the same method.

use crate::env::schema::{EnvMethod, EnvSpec, SamplerKind};
use crate::error::MISPLACED_FIELD;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::path::PathBuf;

/// `[env]` as written ([`EnvSpec`] documents each field and its default).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct EnvTable {
    #[serde(skip_serializing_if = "Option::is_none")]
    file: Option<PathBuf>,
    #[serde(skip_serializing_if = "Option::is_none")]
    method: Option<EnvMethod>,
    #[serde(skip_serializing_if = "Option::is_none")]
    sampler: Option<SamplerKind>,
    #[serde(skip_serializing_if = "Option::is_none")]
    count: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    seed: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    rotation: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    intensity: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    zero_non_finite: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    transfer_azimuth: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    transfer_polar: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    exact_lights: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    reflection_grid: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    reflection_slices: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    reflection_residual: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    reflection_order: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    reflection_samples: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cut_error: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cut_max: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lights: Option<PathBuf>,
}

/// The fields of `[env]` that only `method` reads (the probe's `file`, `rotation`,
/// `intensity` and `zero_non_finite` are every method's). `auto` has none of its own.
pub fn method_fields(method: EnvMethod) -> &'static [&'static str] {
    match method {
        EnvMethod::Auto => &[],
        EnvMethod::Lights => &["sampler", "count", "seed", "lights"],
        EnvMethod::Transfer => &["transfer_azimuth", "transfer_polar", "exact_lights"],
        EnvMethod::Lightcuts => &["cut_error", "cut_max"],
        EnvMethod::Reflection => &[
            "reflection_grid",
            "reflection_slices",
            "reflection_residual",
            "reflection_order",
            "reflection_samples",
            "exact_lights",
        ],
    }
}

impl EnvTable {
    /// The names of the method-specific fields this table states.
    fn stated(&self) -> Vec<&'static str> {
        let t = self;
        [
            ("sampler", t.sampler.is_some()),
            ("count", t.count.is_some()),
            ("seed", t.seed.is_some()),
            ("lights", t.lights.is_some()),
            ("transfer_azimuth", t.transfer_azimuth.is_some()),
            ("transfer_polar", t.transfer_polar.is_some()),
            ("exact_lights", t.exact_lights.is_some()),
            ("reflection_grid", t.reflection_grid.is_some()),
            ("reflection_slices", t.reflection_slices.is_some()),
            ("reflection_residual", t.reflection_residual.is_some()),
            ("reflection_order", t.reflection_order.is_some()),
            ("reflection_samples", t.reflection_samples.is_some()),
            ("cut_error", t.cut_error.is_some()),
            ("cut_max", t.cut_max.is_some()),
        ]
        .into_iter()
        .filter_map(|(name, stated)| stated.then_some(name))
        .collect()
    }

    /// The spec this table states (module doc), or the one-line error of a field stated
    /// under another method.
    fn into_spec(self) -> Result<EnvSpec, String> {
        let method = match self.method {
            Some(m) => m,
            None if self.sampler.is_some() || self.count.is_some() => EnvMethod::Lights,
            None => EnvMethod::Auto,
        };
        let own = method_fields(method);
        if method != EnvMethod::Auto {
            for field in self.stated() {
                if own.contains(&field) {
                    continue;
                }
                let owner = <EnvMethod as clap::ValueEnum>::value_variants()
                    .iter()
                    .find(|m| method_fields(**m).contains(&field))
                    .map_or("another method", |m| m.name());
                let why = match self.method {
                    Some(_) => String::new(),
                    None => " (it states sampler or count and no method)".into(),
                };
                return Err(format!(
                    "{MISPLACED_FIELD}{field}`: belongs to method = \"{owner}\", not to this \
                     [env]'s method \"{}\"{why}",
                    method.name()
                ));
            }
        }
        let d = EnvSpec::new(self.file.unwrap_or_default());
        Ok(EnvSpec {
            method,
            sampler: self.sampler.unwrap_or(d.sampler),
            count: self.count.unwrap_or(d.count),
            seed: self.seed.unwrap_or(d.seed),
            rotation: self.rotation.unwrap_or(d.rotation),
            intensity: self.intensity.unwrap_or(d.intensity),
            zero_non_finite: self.zero_non_finite.unwrap_or(d.zero_non_finite),
            transfer_azimuth: self.transfer_azimuth.unwrap_or(d.transfer_azimuth),
            transfer_polar: self.transfer_polar.unwrap_or(d.transfer_polar),
            exact_lights: self.exact_lights.unwrap_or(d.exact_lights),
            reflection_grid: self.reflection_grid.unwrap_or(d.reflection_grid),
            reflection_slices: self.reflection_slices.unwrap_or(d.reflection_slices),
            reflection_residual: self.reflection_residual.unwrap_or(d.reflection_residual),
            reflection_order: self.reflection_order.unwrap_or(d.reflection_order),
            reflection_samples: self.reflection_samples.unwrap_or(d.reflection_samples),
            cut_error: self.cut_error.unwrap_or(d.cut_error),
            cut_max: self.cut_max.unwrap_or(d.cut_max),
            lights: self.lights,
            ..d
        })
    }

    /// The table that states `spec`: its method, the probe's fields and that method's
    /// fields (every method's under `auto`; module doc).
    fn of_spec(spec: &EnvSpec) -> EnvTable {
        let (lights, transfer, cuts, reflection) = match spec.method {
            // Stated `auto` stays `auto` whatever else is stated.
            EnvMethod::Auto => (true, true, true, true),
            EnvMethod::Lights => (true, false, false, false),
            EnvMethod::Transfer => (false, true, false, false),
            EnvMethod::Lightcuts => (false, false, true, false),
            EnvMethod::Reflection => (false, false, false, true),
        };
        EnvTable {
            file: (!spec.file.as_os_str().is_empty()).then(|| spec.file.clone()),
            method: Some(spec.method),
            sampler: lights.then_some(spec.sampler),
            count: lights.then_some(spec.count),
            seed: lights.then_some(spec.seed),
            rotation: Some(spec.rotation),
            intensity: Some(spec.intensity),
            zero_non_finite: Some(spec.zero_non_finite),
            transfer_azimuth: transfer.then_some(spec.transfer_azimuth),
            transfer_polar: transfer.then_some(spec.transfer_polar),
            exact_lights: (transfer || reflection).then_some(spec.exact_lights),
            reflection_grid: reflection.then_some(spec.reflection_grid),
            reflection_slices: reflection.then_some(spec.reflection_slices),
            reflection_residual: reflection.then_some(spec.reflection_residual),
            reflection_order: reflection.then_some(spec.reflection_order),
            reflection_samples: reflection.then_some(spec.reflection_samples),
            cut_error: cuts.then_some(spec.cut_error),
            cut_max: cuts.then_some(spec.cut_max),
            lights: spec.lights.clone().filter(|_| lights),
        }
    }
}

/// Reads `[env]` (serde `deserialize_with` of [`super::SceneFile::env`]; module doc).
pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<EnvSpec>, D::Error> {
    match Option::<EnvTable>::deserialize(d)? {
        None => Ok(None),
        Some(t) => t.into_spec().map(Some).map_err(serde::de::Error::custom),
    }
}

/// Writes `[env]` (serde `serialize_with` of [`super::SceneFile::env`]; module doc).
pub(super) fn serialize<S: Serializer>(env: &Option<EnvSpec>, s: S) -> Result<S::Ok, S::Error> {
    match env {
        None => s.serialize_none(),
        Some(spec) => s.serialize_some(&EnvTable::of_spec(spec)),
    }
}
