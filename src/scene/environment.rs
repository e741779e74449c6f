//! The scene's environment as one closed type, [`Environment`], and the one function that
//! builds it from an `[env]` table, [`build_environment`] ([`super::Scene::resolve`] and the
//! sweep's rows both call it).
//!
//! Design rule: a method is a variant. Everything that differs per method (what shading
//! adds, what the GPU build draws, what `export` writes, turning the environment, the
//! golden summary's words, the command line's report) is a method of [`Environment`] or an
//! exhaustive `match` on it (or, before anything is built, on
//! [`EnvMethod`](crate::env::schema::EnvMethod)), never a wildcard arm, so a new variant
//! does not compile until every consumer says what it does with it (the crate doc lists
//! the files). The environment's delta lights are held apart from the scene's own
//! `[[light]]`s ([`super::Scene::lights`]); shading takes both, the scene's own first
//! ([`super::Scene::delta_lights`]).
//!
//! The file stays whole past 400 lines on purpose: it is the variant and every answer
//! that depends on what a method prepared, so the compiler's list for a new method stays
//! in this file (and env_method.rs, for the answers before anything is built).

use super::env_method::{gpu_unsupported, REFLECTION_FILTERED_NOT_ON_GPU};
use crate::conventions::rotate_about_up;
use crate::env::lightcuts::{prepare_lightcuts, LightCuts, LightTree, TileFault};
use crate::env::lightset::prepare::{self, CacheDir};
use crate::env::lightset::to_scene_lights;
use crate::env::reflection::{self, prepare_reflection, ReflectionTerm};
use crate::env::schema::{EnvMethod, EnvSpec, SamplerKind, DEFAULT_REFLECTION_ORDER};
use crate::env::transfer::{self, prepare_transfer, PreparedTable, TransferBasis, TransferTable};
use crate::env::Probe;
use crate::error::{Error, Result};
use crate::light::Light;
use crate::material::cone_bound::{BoundFault, ConeBound};
use crate::material::Material;
use crate::progress::Progress;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A summary of the environment light preparation, for the command line to report.
#[derive(Clone, Debug)]
pub struct EnvSummary {
    pub file: PathBuf,
    /// Lights the method prepared: a light set's, a transfer table's exact lights, or the
    /// leaves (texels) of a light cuts tree.
    pub lights: usize,
    pub cache_hit: bool,
    /// Why an existing cache entry was ignored ([`crate::env::lightset::prepare::Prepared::cache_rejected`]).
    pub cache_rejected: Option<String>,
    pub negative_texels: usize,
    /// What the probe loader changed (negative power moved, [`crate::env::LoadReport::negative_warning`]);
    /// `None` on a cache hit (the probe was not decoded).
    pub probe_report: Option<crate::env::LoadReport>,
    /// The probe's size in texels when it was decoded (`None` on a cache hit).
    pub probe_size: Option<(usize, usize)>,
    /// The lights' RGB irradiances at normal incidence summed, after `[env] intensity`
    /// ([`crate::env::LightSet::total_irradiance`], W/m^2 for a probe in W/(m^2 sr)).
    pub total_irradiance: [f64; 3],
    /// The `[env]` table the environment was built from (its method concrete), and the
    /// directory its paths resolve against: what [`super::Scene::with_environment_turned`] builds
    /// again at another rotation.
    pub spec: crate::env::schema::EnvSpec,
    pub base: PathBuf,
}

/// How a scene's environment is shaded: one variant per method, holding what that method
/// prepared. Directions are world directions (the probe's rotation applied).
#[derive(Clone, Debug)]
pub enum Environment {
    /// No environment: the scene's own lights alone (no `[env]`, no `[transfer]`).
    None,
    /// `[env] method = "lights"`: the probe collapsed into directional lights by a sampler
    /// (or read from a light set file, `[env] lights`), irradiance in W/m^2.
    Lights(Vec<Light>),
    /// `[env] method = "transfer"` ([`crate::env::transfer`]): the table of every texel but
    /// the brightest, and those brightest texels as directional lights (`exact`). A
    /// `[transfer] table` file gives the table; `exact` is then the `[env]`'s light set, if
    /// any.
    Transfer {
        table: Arc<TransferTable>,
        exact: Vec<Light>,
    },
    /// `[env] method = "lightcuts"` ([`crate::env::lightcuts`]): every texel a light in a
    /// light tree, with the cut's parameters; shading cuts it per pixel.
    LightCuts(Arc<LightCuts>),
    /// `[env] method = "reflection"` ([`crate::env::reflection`]): the term of the
    /// material under every texel but the brightest (a reflection-space radiance table for
    /// an isotropic material, a filtered importance sampler for an anisotropic D-BRDF:
    /// [`ReflectionTerm`]), and those brightest texels as directional lights (`exact`).
    Reflection {
        table: Arc<ReflectionTerm>,
        exact: Vec<Light>,
    },
}

impl Environment {
    /// The directional lights shading sums beside the scene's own: a light set, a
    /// transfer table's exact lights, none for light cuts (the tree is cut per pixel).
    pub fn delta_lights(&self) -> &[Light] {
        match self {
            Environment::None | Environment::LightCuts(_) => &[],
            Environment::Lights(l)
            | Environment::Transfer { exact: l, .. }
            | Environment::Reflection { exact: l, .. } => l,
        }
    }

    /// The transfer table whose term shading adds to every pixel, if the method has one.
    pub fn transfer_table(&self) -> Option<&Arc<TransferTable>> {
        match self {
            Environment::Transfer { table, .. } => Some(table),
            Environment::None
            | Environment::Lights(_)
            | Environment::LightCuts(_)
            | Environment::Reflection { .. } => None,
        }
    }

    /// The reflection term (a table or a filtered sampler, [`ReflectionTerm`]) shading adds
    /// to every pixel, if the method has one.
    pub fn reflection_term(&self) -> Option<&Arc<ReflectionTerm>> {
        match self {
            Environment::Reflection { table, .. } => Some(table),
            Environment::None
            | Environment::Lights(_)
            | Environment::LightCuts(_)
            | Environment::Transfer { .. } => None,
        }
    }

    /// The light cuts shading adds per pixel, if the method has them.
    pub fn light_cuts(&self) -> Option<&Arc<LightCuts>> {
        match self {
            Environment::LightCuts(c) => Some(c),
            Environment::None
            | Environment::Lights(_)
            | Environment::Transfer { .. }
            | Environment::Reflection { .. } => None,
        }
    }

    /// The `[env] method` this environment is shaded by (`None` without an environment).
    pub fn method(&self) -> Option<EnvMethod> {
        match self {
            Environment::None => None,
            Environment::Lights(_) => Some(EnvMethod::Lights),
            Environment::Transfer { .. } => Some(EnvMethod::Transfer),
            Environment::LightCuts(_) => Some(EnvMethod::Lightcuts),
            Environment::Reflection { .. } => Some(EnvMethod::Reflection),
        }
    }

    /// The method's name as `[env] method` spells it (`none` without an environment).
    pub fn name(&self) -> &'static str {
        self.method().map_or("none", EnvMethod::name)
    }

    /// Why the GPU build does not draw this environment, or `None` when it does (light sets,
    /// transfer tables and reflection tables; [`gpu_unsupported`] says it of an `[env]
    /// method` before anything is built). A reflection term prepared on the filtered path
    /// (an anisotropic D-BRDF) is refused with [`REFLECTION_FILTERED_NOT_ON_GPU`].
    pub fn gpu_unsupported(&self) -> Option<&'static str> {
        match self {
            Environment::Reflection { table, .. } => match table.as_ref() {
                ReflectionTerm::Table(_) => None,
                ReflectionTerm::Filtered(_) => Some(REFLECTION_FILTERED_NOT_ON_GPU),
            },
            Environment::None
            | Environment::Lights(_)
            | Environment::Transfer { .. }
            | Environment::LightCuts(_) => self.method().and_then(gpu_unsupported),
        }
    }

    /// Why a scene with this environment and no light of its own has no list of lights to
    /// show (the `light-polar` and `light-azimuth` AOVs, [`crate::aov::check_available`]).
    pub fn why_no_light_list(&self) -> &'static str {
        match self {
            Environment::LightCuts(_) => {
                "the environment method \"lightcuts\" shades light cuts through a tree of the \
                 probe's texels, not a list of lights; give --env-method lights (delta lights) \
                 or a [[light]] table"
            }
            Environment::Transfer { .. } => {
                "the environment method \"transfer\" shades a transfer table and here no exact \
                 lights; give --env-method lights (delta lights), [env] exact_lights > 0 or a \
                 [[light]] table"
            }
            Environment::Reflection { .. } => {
                "the environment method \"reflection\" shades a reflection table and here no \
                 exact lights; give --env-method lights (delta lights), [env] exact_lights > 0 \
                 or a [[light]] table"
            }
            Environment::None | Environment::Lights(_) => "the scene has no lights",
        }
    }

    /// What the command line reports of this environment (`environment: WHAT from FILE`)
    /// and the cache its preparation uses (`light-set`, `transfer-table`); `lights` is
    /// [`EnvSummary::lights`].
    pub fn report(&self, lights: usize) -> (&'static str, String) {
        match self {
            Environment::Transfer { table, .. } => (
                "transfer-table",
                format!(
                    "a {} x {} transfer table and {lights} exact lights",
                    table.grid().0,
                    table.grid().1,
                ),
            ),
            Environment::Reflection { table, .. } => match &**table {
                ReflectionTerm::Table(table) => (
                    "reflection-table",
                    format!(
                        "a reflection table ({g} x {g} cells, {s} + 1 slices, psi order {o}, \
                         {mb:.1} MB) and {lights} exact lights",
                        g = table.grid(),
                        s = table.slices(),
                        o = table.order(),
                        mb = table.bytes() as f64 / 1e6,
                    ),
                ),
                ReflectionTerm::Filtered(f) => (
                    "reflection-table",
                    format!(
                        "filtered importance sampling of an anisotropic D-BRDF ({n} half \
                         vectors per pixel, a {w} x {h} pyramid of {k} levels, {mb:.1} MB; \
                         not cached) and {lights} exact lights",
                        n = f.sample_count(),
                        w = f.pyramid().size().0,
                        h = f.pyramid().size().1,
                        k = f.pyramid().levels(),
                        mb = f.bytes() as f64 / 1e6,
                    ),
                ),
            },
            Environment::LightCuts(_) => (
                "light-set",
                format!("light cuts through a tree of {lights} texels"),
            ),
            Environment::Lights(_) | Environment::None => ("light-set", format!("{lights} lights")),
        }
    }

    /// The golden manifest's words for this environment (after `env PROBE`): the table's
    /// grid and exact lights, the light set's sampler (`sampler`, named as scene files name
    /// it) and size, or the cut error; `lights` is [`EnvSummary::lights`].
    pub fn summary(&self, sampler: &str, kind: SamplerKind, lights: usize) -> String {
        match self {
            Environment::Transfer { table, .. } => {
                let (nu, nv) = table.grid();
                format!("transfer {nu}x{nv} + {lights} exact")
            }
            Environment::Lights(_) => match kind {
                SamplerKind::Full => format!("full ({lights} lights)"),
                SamplerKind::Uniform
                | SamplerKind::Importance
                | SamplerKind::Stratified
                | SamplerKind::MedianCut
                | SamplerKind::Lloyd => format!("{sampler} {lights}"),
            },
            Environment::LightCuts(c) => {
                format!("lightcuts cut_error {} ({lights} texels)", c.cut_error)
            }
            Environment::Reflection { table, .. } => match &**table {
                // The order only off the default: the manifest's words from before it was a
                // parameter stay.
                ReflectionTerm::Table(table) => format!(
                    "reflection {g}x{g}x{s}{o} + {lights} exact",
                    g = table.grid(),
                    s = table.slices(),
                    o = if table.order() == DEFAULT_REFLECTION_ORDER {
                        String::new()
                    } else {
                        format!(" order {}", table.order())
                    }
                ),
                ReflectionTerm::Filtered(f) => format!(
                    "reflection filtered-is {n} + {lights} exact",
                    n = f.sample_count()
                ),
            },
            Environment::None => "none".into(),
        }
    }

    /// The delta lights a scene's `[transfer] table` file shades beside (none, or the
    /// `[env]`'s light set), or why the file may not shade with this environment (for the
    /// `transfer.table` field): a method that shades a table or cuts of its own.
    pub fn lights_beside_transfer_table(self) -> std::result::Result<Vec<Light>, &'static str> {
        match self {
            Environment::None => Ok(Vec::new()),
            Environment::Lights(lights) => Ok(lights),
            Environment::Transfer { .. } => Err(
                "the [env] builds its own table (method = \"transfer\"): a scene shades with \
                 one table",
            ),
            Environment::Reflection { .. } => Err(
                "the [env] shades with a reflection table (method = \"reflection\"): a \
                 transfer table shades beside a light set only",
            ),
            Environment::LightCuts(_) => Err(
                "the [env] shades with light cuts (method = \"lightcuts\"): a table shades \
                 beside a light set only",
            ),
        }
    }

    /// Whether the viewer previews a turn of this environment rigidly
    /// ([`Environment::turned_rigidly`]) while the view changes, instead of building it
    /// again at the new rotation: a light set (preparing the rotated probe's set again costs
    /// up to seconds); a transfer table (read from the cache: the rotation is not in its
    /// key) and light cuts are built again.
    pub fn previews_rigidly(&self) -> bool {
        match self {
            Environment::None | Environment::Lights(_) => true,
            Environment::Transfer { .. }
            | Environment::LightCuts(_)
            | Environment::Reflection { .. } => false,
        }
    }

    /// The environment turned by `angle` radians about world up (+y, right-handed,
    /// [`rotate_about_up`]) without going back to the probe, where that is exact up to f32
    /// rounding: a light set's directions, a transfer table's lookup rotation and its exact
    /// lights. `None` for light cuts (a light tree is built from the turned probe again:
    /// [`super::Scene::with_environment_turned`]). The viewer previews a shift-drag so.
    pub fn turned_rigidly(&self, angle: f64) -> Option<Environment> {
        let turn = |lights: &[Light]| -> Vec<Light> {
            lights
                .iter()
                .map(|l| match *l {
                    Light::Directional {
                        to_light,
                        irradiance,
                    } => Light::Directional {
                        to_light: rotate_about_up(to_light.as_dvec3(), angle).as_vec3(),
                        irradiance,
                    },
                    p @ Light::Point { .. } => p,
                })
                .collect()
        };
        match self {
            Environment::None => Some(Environment::None),
            Environment::Lights(l) => Some(Environment::Lights(turn(l))),
            Environment::Transfer { table, exact } => Some(Environment::Transfer {
                table: Arc::new(table.turned(angle)),
                exact: turn(exact),
            }),
            Environment::Reflection { table, exact } => Some(Environment::Reflection {
                table: Arc::new(table.turned(angle)),
                exact: turn(exact),
            }),
            Environment::LightCuts(_) => None,
        }
    }
}

/// Where [`build_environment`] finds the probe of an `[env]` table.
pub enum ProbeSource<'a> {
    /// The files the table names (relative to `base`), light sets and transfer tables read
    /// from and written to `cache`; `progress` counts a light set's sampling or a table's
    /// rows when they are computed. `brdfkit render` and every tool that resolves a scene.
    Files {
        base: &'a Path,
        cache: &'a CacheDir,
        progress: &'a Progress,
    },
    /// A probe decoded once by the caller (with the table's rotation and cleaning), nothing
    /// cached: the sweep, whose rows all sample one probe. The table's light set file
    /// (`[env] lights`) is not read: a light set is sampled from this probe.
    Decoded(&'a Probe),
}

/// Builds the environment of `spec` (its method concrete: `auto` is replaced first,
/// [`super::env_method::concrete_method`]) for `material`, and a summary of what was
/// prepared (`None` from a [`ProbeSource::Decoded`] probe). The one way an environment is
/// made: the same calls give the same bits wherever the probe comes from. Errors name the
/// field: a method the material cannot be shaded with (`env.method`), a field out of range
/// ([`EnvSpec::check`]), a probe or light set file that cannot be read.
pub fn build_environment(
    spec: &EnvSpec,
    material: &Material,
    source: ProbeSource<'_>,
) -> Result<(Environment, Option<EnvSummary>)> {
    match spec.method {
        EnvMethod::Auto => Err(Error::field(
            "env.method",
            "\"auto\" is replaced by its method before the environment is built",
        )),
        EnvMethod::Lights => match source {
            ProbeSource::Files {
                base,
                cache,
                progress,
            } => {
                let p = prepare::prepare_with_progress(spec, base, cache.path(), progress)?;
                cache.record_use(p.cache_file.as_deref(), p.cache_hit);
                let summary = EnvSummary {
                    // The light set file when `[env] lights` names one (the probe is not read).
                    file: base.join(spec.lights.as_ref().unwrap_or(&spec.file)),
                    lights: p.lights.len(),
                    cache_hit: p.cache_hit,
                    cache_rejected: p.cache_rejected,
                    negative_texels: p.report.as_ref().map_or(0, |r| r.negative_texels),
                    probe_report: p.report,
                    probe_size: p.report.as_ref().map(|r| r.size),
                    total_irradiance: p.lights.total_irradiance().to_array(),
                    spec: spec.clone(),
                    base: base.to_path_buf(),
                };
                let lights = to_scene_lights(&p.lights);
                Ok((Environment::Lights(lights), Some(summary)))
            }
            ProbeSource::Decoded(probe) => {
                spec.check()?;
                let mut ls = spec.sampler_config().run(probe);
                // The scene's `[env] intensity`, exactly as `prepare::prepare` applies it.
                spec.scale_intensity(&mut ls);
                Ok((Environment::Lights(to_scene_lights(&ls)), None))
            }
        },
        EnvMethod::Transfer => {
            let basis = TransferBasis::for_material(material).ok_or_else(|| {
                Error::field(
                    "env.method",
                    format!(
                        "\"transfer\" shades SH data sets and Lambert only, not {}",
                        material.name()
                    ),
                )
            })?;
            table_environment(
                spec,
                source,
                |base, cache, progress| prepare_transfer(spec, base, basis, cache, progress),
                |probe, exact| {
                    transfer::build_table(
                        probe,
                        basis,
                        (spec.transfer_azimuth, spec.transfer_polar),
                        exact,
                        spec.intensity,
                        &Progress::hidden(),
                        transfer::BuildFault::None,
                    )
                },
                |table, exact| Environment::Transfer { table, exact },
            )
        }
        EnvMethod::Reflection => {
            if let Some(why) = reflection::unsupported(material) {
                return Err(Error::field("env.method", why));
            }
            table_environment(
                spec,
                source,
                |base, cache, progress| prepare_reflection(spec, base, material, cache, progress),
                |probe, exact| {
                    reflection::build_term(spec, probe, material, exact, &Progress::hidden())
                },
                |table, exact| Environment::Reflection { table, exact },
            )
        }
        EnvMethod::Lightcuts => {
            ConeBound::new(material)
                .map_err(|why| Error::field("env.method", format!("\"lightcuts\": {why}")))?;
            match source {
                ProbeSource::Files { base, progress, .. } => {
                    let p = prepare_lightcuts(spec, base, progress)?;
                    // Every texel of positive weight is a light (a leaf of the tree).
                    let tree = &p.cuts.tree;
                    let summary = EnvSummary {
                        file: base.join(&spec.file),
                        lights: tree.len().div_ceil(2),
                        cache_hit: false,
                        cache_rejected: None,
                        negative_texels: p.report.negative_texels,
                        probe_report: Some(p.report),
                        probe_size: Some(p.report.size),
                        total_irradiance: tree.leaf_irradiance_sum().to_array(),
                        spec: spec.clone(),
                        base: base.to_path_buf(),
                    };
                    Ok((Environment::LightCuts(Arc::new(p.cuts)), Some(summary)))
                }
                ProbeSource::Decoded(probe) => {
                    spec.check()?;
                    // As `prepare_lightcuts` does.
                    let cuts = LightCuts {
                        tree: LightTree::build(probe, spec.intensity),
                        cut_error: spec.cut_error,
                        cut_max: spec.cut_max,
                        fault: BoundFault::None,
                        tile_fault: TileFault::None,
                    };
                    Ok((Environment::LightCuts(Arc::new(cuts)), None))
                }
            }
        }
    }
}

/// The steps the tabulated methods (transfer and reflection tables) share: from files,
/// the method's preparation (`prepare`: probe, exact texels, cache, progress) and its
/// summary; from a decoded probe, the same without the cache: the brightest
/// `spec.exact_lights` texels split off, the table baked from the rest (`bake`) and those
/// texels made lights. `variant` wraps the table and its exact lights.
fn table_environment<T>(
    spec: &EnvSpec,
    source: ProbeSource<'_>,
    prepare: impl FnOnce(&Path, Option<&Path>, &Progress) -> Result<PreparedTable<T>>,
    bake: impl FnOnce(&Probe, &[usize]) -> Result<T>,
    variant: impl FnOnce(Arc<T>, Vec<Light>) -> Environment,
) -> Result<(Environment, Option<EnvSummary>)> {
    match source {
        ProbeSource::Files {
            base,
            cache,
            progress,
        } => {
            let p = prepare(base, cache.path(), progress)?;
            cache.record_use(p.cache_file.as_deref(), p.cache_hit);
            let summary = EnvSummary {
                file: base.join(&spec.file),
                lights: p.lights.len(),
                cache_hit: p.cache_hit,
                cache_rejected: p.cache_rejected.clone(),
                negative_texels: p.report.negative_texels,
                probe_report: Some(p.report),
                probe_size: Some(p.report.size),
                total_irradiance: p.lights.total_irradiance().to_array(),
                spec: spec.clone(),
                base: base.to_path_buf(),
            };
            let env = variant(Arc::new(p.table), to_scene_lights(&p.lights));
            Ok((env, Some(summary)))
        }
        ProbeSource::Decoded(probe) => {
            spec.check()?;
            // As the preparation from files does, without its cache.
            let exact = transfer::brightest_texels(probe, spec.exact_lights);
            let table = bake(probe, &exact)?;
            let lights = transfer::build::texel_lights(probe, &exact, spec.intensity);
            Ok((variant(Arc::new(table), to_scene_lights(&lights)), None))
        }
    }
}
