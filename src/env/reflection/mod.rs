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
//! - `psi` as a Fourier series of order 2 ([`table::COEFFS`] coefficients), projected from
//!   [`table::PSI_SAMPLES`] samples. `psi` is measured from a reference tangent about `r`,
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
//! # Layout
//! - [`table`]: [`ReflectionTable`] and its lookup;
//! - [`build`]: the bake and its error measurement;
//! - [`cache`]: the disk cache.

pub mod build;
pub mod cache;
pub mod lobe;
pub mod table;

pub use build::{bake_table, BakeFault, BakeParams};
pub use table::{BakeError, ReflectionTable};

use crate::env::schema::EnvSpec;
use crate::env::transfer::{prepare_table, PreparedTable};
use crate::error::{Error, Result};
use crate::material::Material;
use crate::progress::Progress;
use std::path::Path;

/// Why `material` cannot be shaded by a reflection-space table, or `None` when it can (an
/// isotropic model: [`crate::brdf::Brdf::is_isotropic`]).
pub fn unsupported(material: &Material) -> Option<String> {
    (!material.as_brdf().is_isotropic()).then(|| {
        format!(
            "\"reflection\" tabulates isotropic materials only; this {} is anisotropic \
             (use \"lightcuts\" or \"lights\")",
            material.name()
        )
    })
}

/// The bake parameters an `[env]` table states.
pub fn params_of(spec: &EnvSpec) -> BakeParams {
    BakeParams {
        grid: spec.reflection_grid,
        slices: spec.reflection_slices,
        residual: spec.reflection_residual,
    }
}

/// What [`prepare_reflection`] made for a scene's `[env]` with `method = "reflection"`.
pub type PreparedReflection = PreparedTable<ReflectionTable>;

/// Loads the probe of `spec` (relative to `base`) and bakes the table of `material` on the
/// spec's parameters (or reads it from its valid cache entry in `cache_dir`), the brightest
/// `spec.exact_lights` texels split off as lights; `spec.intensity` scales both
/// ([`prepare_table`]). `progress` counts grid nodes when the table is baked. Errors name
/// the file or the field.
pub fn prepare_reflection(
    spec: &EnvSpec,
    base: &Path,
    material: &Material,
    cache_dir: Option<&Path>,
    progress: &Progress,
) -> Result<PreparedReflection> {
    spec.check()?;
    if let Some(why) = unsupported(material) {
        return Err(Error::field("env.method", why));
    }
    let params = params_of(spec);
    prepare_table(
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
    )
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_lobe;
