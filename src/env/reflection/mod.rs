//! Reflection-space radiance tables: the outgoing radiance of one isotropic material under
//! one distant environment, tabulated over the reflected direction, for glossy lobes that
//! a table over normals (a transfer table) cannot hold.
//!
//! # Parameterisation
//! For an isotropic BRDF `f` and a fixed probe `L`, the outgoing radiance
//! `L_o(n, v) = integral_{l.n > 0} L(l) f(l, v) (l.n) dl` (4 degrees of freedom) is a
//! function of the reflected direction `r = 2 (n.v) n - v` (2D), the view's polar angle
//! `polar_o = acos(n.v)` and the angle `psi` of `n` about `r` (Ramamoorthi & Hanrahan 2002,
//! "Frequency space environment map rendering": the reflection-space reparameterisation of
//! isotropic BRDFs). A glossy lobe's high frequencies are all in `r`; `polar_o` and `psi`
//! vary slowly except near grazing. So the table holds:
//! - `r` on the vertices of an octahedral `G x G` grid of the sphere
//!   ([`crate::conventions`], "Octahedral sphere grids"; `reflection_grid`, default 64),
//!   bilinear between the four nodes around a pixel's `r`;
//! - `polar_o` on `reflection_slices` uniform slices over 0-85 degrees plus one at 89.9
//!   degrees ([`table::HORIZON_SLICE_DEG`]), linear between two;
//! - `psi` as a Fourier series of order `reflection_order` (default 2; [`table::coeffs`]:
//!   `2 order + 1` coefficients), projected from [`table::psi_samples`]: `max(3 order, 8)` samples
//!   (below, "Order of the series in psi"). `psi` is measured from a reference tangent about `r`,
//!   which no single field gives on the whole sphere (hairy ball): each node uses +y
//!   projected normal to `r`, or +z where `|r.y| > 0.8` ([`table::CHART_SWITCH`]); a pixel
//!   evaluates each corner node's series at its `psi` measured in that node's chart, so
//!   mixing charts needs no conversion.
//!
//! Values are in the probe's own frame; the probe rotation is applied at lookup (the
//! viewer turning the environment reads one cache entry for every angle).
//!
//! # Diffuse term
//! A model's Lambertian term `c` ([`crate::brdf::Brdf::lambertian_term`]: `k_d / pi` of
//! Blinn-Phong and Phong, `r_d / pi` of a Lambert + D-BRDF, zero for the others) is not in
//! the series: its radiance `c E(n)` depends on the normal alone, so the table holds it
//! over normals, `c` times the residual's irradiance `E(n) = sum_texels P max(0, l.n)` on
//! the same octahedral vertices, bilinear at lookup; the series hold `f - c` (the lobes).
//! In the series' variables the clamped cosine of a bright texel near the normal's horizon
//! is a kink in `psi` and `polar_o` that order 2 and linear slices cannot follow: under the
//! studio probe (extended lamps past the 64 exact texels) the default Blinn-Phong's table
//! with the term in the series was 1.2% relative RMSE and 30% at the 99th percentile
//! against the converged reference, broad regions too bright or too dark by 10-30%, and
//! pure Lambert through the series showed the same; over normals the term is what a
//! transfer table does for Lambert.
//!
//! # Bake
//! By brute force in f64 from the material's own BRDF ([`crate::material::Material::eval_f64`]:
//! the Blinn-Phong and Phong formulas, the D-BRDF's `p(h)` table, a MERL table; no fit),
//! over the residual probe: the `exact_lights` brightest texels (luminance x solid angle,
//! [`crate::env::transfer::brightest_texels`]) are summed exactly per pixel as directional
//! lights instead, as transfer tables do, and the rest is downsampled to at most
//! `reflection_residual` texels wide ([`build`]). The bake measures its own table against
//! exact f64 sums over every texel of the full-resolution residual at sample points and
//! stores the result ([`table::BakeError`]) in the table and its cache entry; `render
//! --stats` prints it.
//!
//! The design and its defaults come from an accuracy study of this parameterisation
//! (Blinn-Phong exponents 200 and 500 under the shipped probes against exact sums): order 2
//! in `psi` is the knee (order 0 left 188% at the 99th percentile, order 1 33%, order 2
//! 4.5%, order 3 4.0%); the horizon slice is required; 64 exact texels are needed under
//! studio; a 256-wide residual keeps its own floor at or below 1.1% p99.
//!
//! # Order of the series in psi
//! The order is the scene's knob (`[env] reflection_order`, 1 to [`table::MAX_ORDER`],
//! default [`crate::env::schema::DEFAULT_REFLECTION_ORDER`] = 2). At order `K` a node and
//! slice hold, per colour, `L(psi) ~ a0 + sum_{k = 1..K} (a_k cos k psi + b_k sin k psi)`
//! with `a_k = (2 / N) sum_m L(psi_m) cos k psi_m`, `b_k` likewise with `sin`,
//! `psi_m = 2 pi m / N`, `N = max(3 K, 8)` (and `a0` half of the `k = 0` sum): the
//! discrete Fourier projection, exact for a series of order below `N - K` in psi (`2 K`
//! from order 3 on, 6 at order 2), so the samples alias no harmonic below that onto one
//! the table holds. (`N` was `4 K`; at order 6 on 128 cells under studio, 18 samples
//! instead of 24 changed the rendered error by at most 0.07 points of p99 for Blinn-Phong
//! 50, 200, 500 and gold-dust-paint, [`table::psi_samples`], and cut the bake's sums by a
//! quarter; order 2 keeps its 8.) The lookup
//! evaluates the basis by `cos 2 psi = c^2 - s^2`, `sin 2 psi = 2 c s` and angle addition
//! above; at order 2 the bake and the lookup compute what they did before the order was a
//! parameter, bit for bit, so the default's tables, cache entries (their keys and bytes,
//! [`cache`]) and golden images were unchanged (the bake's sums in the node's frame later
//! changed the bits: [`cache::REFLECTION_ALGORITHM_VERSION`] 5).
//!
//! Why more than 2: under studio (lamps past the 64 exact texels) the sweep's glossy class
//! (`kd = 0.05`, `ks = 0.9`) missed 10% at the 99th percentile at order 2 (Blinn-Phong
//! 200: 0.87% relative RMSE, 23.5% p99 at 96 x 96 against the converged reference;
//! docs/rendering.md, "Why studio's glossy class misses: the series in psi"). At a view
//! 60-80 degrees from the normal the lobe about `r` is an ellipse that turns with psi, so
//! a bright texel a few lobe widths from `r` is a narrow peak in psi: the series' own
//! error there (exact sums at 32 values of psi, `examples/reflection_psi_error.rs`, p99
//! with 64 exact texels) was 33%, 11%, 3.1% and 0.5% at orders 2, 4, 6 and 8 for
//! Blinn-Phong 200 at 60-70 degrees (63%, 26%, 7.8%, 2.6% at 70-80). Order 6 with
//! `reflection_grid = 128` met the 10% p99 bound for Blinn-Phong 50, 200 and 500 and
//! gold-dust-paint under studio. Cost: memory and bake time grow as the coefficients and
//! samples do, `2 K + 1` and `4 K` (order 6: 2.6 times the bytes and 3 times the bake of
//! order 2; [`table::value_count`]); the lookup sums `2 K + 1` products per node, slice
//! and colour.
//!
//! # Anisotropic D-BRDFs
//! The parameterisation holds isotropic materials only. The rule, per material
//! ([`ReflectionPath::of`]): an isotropic material gets a table; an anisotropic D-BRDF or
//! Lambert + D-BRDF (the library's `lindt-paper`) is shaded by deterministic filtered
//! importance sampling ([`filtered`]: a fixed set of `reflection_samples` half vectors
//! drawn from the lobe's own `p(h)` table, each reflected direction read from a mip
//! pyramid of the same residual probe at the level of its share of solid angle,
//! [`pyramid`]), beside the same exact lights and the same diffuse term over normals; any
//! other anisotropic model is refused. [`ReflectionTerm`] holds what either path
//! prepared; `render --stats` names the path.
//!
//! # Layout
//! - [`table`]: [`ReflectionTable`] and its lookup;
//! - [`build`]: the bake and its error measurement;
//! - [`cache`]: the disk cache;
//! - [`filtered`]: [`FilteredSampler`], the anisotropic D-BRDFs' path, and [`pyramid`],
//!   the residual's radiance pyramid it reads.

pub mod build;
pub mod cache;
pub mod filtered;
pub mod lobe;
pub mod pyramid;
mod sums;
pub mod table;

pub use build::{bake_table, BakeFault, BakeParams};
pub use filtered::{FilteredSampler, PdfFault};
pub use table::{BakeError, ReflectionTable};

use crate::env::schema::EnvSpec;
use crate::env::transfer::{prepare_table, PreparedTable, TableCache};
use crate::env::Probe;
use crate::error::{Error, Result};
use crate::material::Material;
use crate::progress::Progress;
use std::path::Path;

/// How `method = "reflection"` shades a material (module doc, "Anisotropic D-BRDFs"): the
/// rule, per material, is an isotropic material by a reflection-space table and an
/// anisotropic D-BRDF (or Lambert + D-BRDF) by filtered importance sampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReflectionPath {
    /// A baked [`ReflectionTable`].
    Table,
    /// A [`FilteredSampler`].
    FilteredSampling,
}

impl ReflectionPath {
    /// The path of `material`, or why the method cannot shade it.
    pub fn of(material: &Material) -> std::result::Result<ReflectionPath, String> {
        if material.as_brdf().is_isotropic() {
            Ok(ReflectionPath::Table)
        } else if filtered::dbrdf_lobe(material).is_some() {
            Ok(ReflectionPath::FilteredSampling)
        } else {
            Err(format!(
                "\"reflection\" tabulates isotropic materials and samples anisotropic D-BRDFs; \
                 this {} is neither (use \"lightcuts\" or \"lights\")",
                material.name()
            ))
        }
    }

    /// The words `render --stats` and the reports use for the path.
    pub fn describe(self) -> &'static str {
        match self {
            ReflectionPath::Table => "isotropic material: a reflection-space table",
            ReflectionPath::FilteredSampling => {
                "anisotropic D-BRDF: filtered importance sampling of the residual probe"
            }
        }
    }
}

/// What `method = "reflection"` prepared for one material: one variant per
/// [`ReflectionPath`].
#[derive(Clone, Debug)]
pub enum ReflectionTerm {
    /// An isotropic material's table.
    Table(ReflectionTable),
    /// An anisotropic D-BRDF's sampler.
    Filtered(FilteredSampler),
}

impl ReflectionTerm {
    /// The path this term was prepared on.
    pub fn path(&self) -> ReflectionPath {
        match self {
            ReflectionTerm::Table(_) => ReflectionPath::Table,
            ReflectionTerm::Filtered(_) => ReflectionPath::FilteredSampling,
        }
    }

    /// The table, on the table path.
    pub fn table(&self) -> Option<&ReflectionTable> {
        match self {
            ReflectionTerm::Table(t) => Some(t),
            ReflectionTerm::Filtered(_) => None,
        }
    }

    /// Bytes the term holds.
    pub fn bytes(&self) -> usize {
        match self {
            ReflectionTerm::Table(t) => t.bytes(),
            ReflectionTerm::Filtered(f) => f.bytes(),
        }
    }

    /// The same term read with the probe turned by `angle` radians more about +y.
    pub fn turned(&self, angle: f64) -> ReflectionTerm {
        match self {
            ReflectionTerm::Table(t) => ReflectionTerm::Table(t.turned(angle)),
            ReflectionTerm::Filtered(f) => ReflectionTerm::Filtered(f.turned(angle)),
        }
    }
}

/// Why `material` cannot be shaded by `method = "reflection"`, or `None` when it can (an
/// isotropic model by a table, an anisotropic D-BRDF by filtered importance sampling:
/// [`ReflectionPath::of`]).
pub fn unsupported(material: &Material) -> Option<String> {
    ReflectionPath::of(material).err()
}

/// The bake parameters an `[env]` table states.
pub fn params_of(spec: &EnvSpec) -> BakeParams {
    BakeParams {
        grid: spec.reflection_grid,
        slices: spec.reflection_slices,
        residual: spec.reflection_residual,
        order: spec.reflection_order,
    }
}

/// What [`prepare_reflection`] made for a scene's `[env]` with `method = "reflection"`.
pub type PreparedReflection = PreparedTable<ReflectionTerm>;

/// The term of `material` on its path from `probe` (times `spec.intensity`) without the
/// texels `exact`: a table baked on the spec's parameters, or a filtered sampler of
/// `spec.reflection_samples` half vectors (no cache: it is built in well under a second).
pub fn build_term(
    spec: &EnvSpec,
    probe: &Probe,
    material: &Material,
    exact: &[usize],
    progress: &Progress,
) -> Result<ReflectionTerm> {
    match ReflectionPath::of(material).map_err(|why| Error::field("env.method", why))? {
        ReflectionPath::Table => bake_table(
            probe,
            material,
            params_of(spec),
            exact,
            spec.intensity,
            progress,
            BakeFault::None,
        )
        .map(ReflectionTerm::Table),
        ReflectionPath::FilteredSampling => FilteredSampler::new(
            probe,
            material,
            exact,
            spec.intensity,
            spec.reflection_samples,
            spec.reflection_grid,
            PdfFault::None,
        )
        .map(ReflectionTerm::Filtered)
        .ok_or_else(|| Error::field("env.method", "not a D-BRDF")),
    }
}

/// The filtered sampler is not cached: [`prepare_table`] gets no cache directory for it,
/// so neither function is called.
const UNCACHED: TableCache<ReflectionTerm> = TableCache {
    file_name: |dir, _| dir.to_path_buf(),
    encode: |_, _| Vec::new(),
};

/// Loads the probe of `spec` (relative to `base`) and prepares the term of `material`
/// ([`ReflectionPath`]): the table baked on the spec's parameters (or read from its valid
/// cache entry in `cache_dir`), or the filtered sampler (never cached); the brightest
/// `spec.exact_lights` texels split off as lights; `spec.intensity` scales both
/// ([`prepare_table`]). `progress` counts grid nodes when a table is baked. Errors name
/// the file or the field.
pub fn prepare_reflection(
    spec: &EnvSpec,
    base: &Path,
    material: &Material,
    cache_dir: Option<&Path>,
    progress: &Progress,
) -> Result<PreparedReflection> {
    spec.check()?;
    let path = ReflectionPath::of(material).map_err(|why| Error::field("env.method", why))?;
    match path {
        ReflectionPath::Table => {
            let params = params_of(spec);
            let p = prepare_table(
                spec,
                base,
                cache_dir,
                cache::TABLE_CACHE,
                |bytes, opts, probe| {
                    params.check(probe.width(), probe.height())?;
                    Ok(cache::table_cache_key(
                        bytes,
                        opts,
                        material,
                        &params,
                        spec.exact_lights,
                        spec.intensity,
                    ))
                },
                |f, key, rotation| cache::read_entry(f, key, &params, rotation),
                |probe, exact| {
                    bake_table(
                        probe,
                        material,
                        params,
                        exact,
                        spec.intensity,
                        progress,
                        BakeFault::None,
                    )
                },
            )?;
            Ok(PreparedTable {
                table: ReflectionTerm::Table(p.table),
                lights: p.lights,
                report: p.report,
                cache_hit: p.cache_hit,
                cache_rejected: p.cache_rejected,
                cache_file: p.cache_file,
            })
        }
        ReflectionPath::FilteredSampling => prepare_table(
            spec,
            base,
            None::<&Path>,
            UNCACHED,
            |_, _, _| Ok(0),
            |_: &Path, _, _| Ok(None),
            |probe, exact| build_term(spec, probe, material, exact, progress),
        ),
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_filtered;
#[cfg(test)]
mod tests_lobe;
#[cfg(test)]
mod tests_order;
