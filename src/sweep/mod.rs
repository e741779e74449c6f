//! Run time against error (`brdfkit sweep`): render one scene over a grid of configurations
//! and measure, for each, the error against the converged reference and the time it took.
//!
//! # The grid
//! The environment method with its parameters ([`MethodAxis`]) x SH order x lookup x
//! precision, enumerated in that nesting order (method outermost, precision innermost); a
//! row's `index` is its position in the *whole* grid, so shards ([`crate::shard`]) and
//! merged CSVs agree on it. Methods ([`MethodKind`], `[env] method`): `lights`, sampler x
//! light count, first (so a lights-only grid keeps the indices of the CSVs from before the
//! method axis); then `transfer`, table grid (azimuth x polar nodes) x exact lights
//! ([`crate::env::transfer`]), for SH data sets and Lambert only (left out with a note for
//! other materials); then `lightcuts`, cut error x largest cut ([`crate::env::lightcuts`]),
//! for every material with a cone bound (left out with a note for SH data sets and MERL
//! tables). Defaults ([`Grid::default`]): the five samplers of
//! [`SamplerKind`](crate::env::schema::SamplerKind) except `full`; counts 1, 2, 4, ...,
//! 1024; tables 32x17, 64x33, 128x65 x exact lights 0, 16, 64; cut errors 0.005, 0.01,
//! 0.02, 0.05 x largest cut 1000; orders (SH bands) 1..=8; lookups nearest and bilinear;
//! precision f32 only: (55 + 9) x 8 x 2 = 1024 rows for an 8-band SH data set (lightcuts
//! left out), 55 + 9 + 4 = 68 for Lambert, 55 + 4 = 59 for an analytic lobe. SH
//! orders above the data set's stored bands are dropped; an order below them shades
//! [`ShDataset::truncated`](crate::sh::dataset::ShDataset::truncated) (and a transfer
//! table of that many bands). A scene whose material is not an SH data set has one order
//! (written 0) and one lookup (written `-`). [`grid`]'s module doc says what adding a
//! method takes.
//!
//! # Material classes
//! `--class` ([`MaterialClass`]) sweeps a built-in scene of one of the three material
//! classes `[env] method = "auto"` chooses for ([`crate::scene::env_method`]: diffuse, SH
//! glossy, analytic glossy) on a narrower grid
//! ([`MaterialClass::grid`]); the sweep prints the fastest row within 1% relative RMSE
//! ([`fastest_within`], always on the Pareto front), where a class's default method is
//! picked.
//!
//! # The reference
//! The scene with every texel of its probe as a light (sampler `full`), f64 shading, no
//! culling and no skips ([`crate::render::RenderOptions::converged_reference`]), the same
//! reference as `brdfkit render --reference`, whatever the scene's `[env] method`
//! ([`crate::env::schema::EnvSpec::use_full_probe`]). It renders the material as the scene stores it (every
//! band, its own lookup), so a row with fewer orders or the other lookup measures that
//! difference too: for SH materials the truncation, not the light count, dominates the error
//! at low orders. It takes minutes for the default scene, so it is cached (`--cache DIR`,
//! default `target/brdfkit-cache`; `--no-cache`: not at all) as a linear EXR
//! `reference-<key>.exr` named by [`reference_key`]: a hash of the scene's configuration and
//! input files, the crate version, [`REFERENCE_ALGORITHM_VERSION`] and
//! [`crate::env::lightset::prepare::LIGHT_SET_ALGORITHM_VERSION`]. Beside it,
//! `reference-<key>.exr.xxh3` holds [`image_checksum`] of its pixels; an entry is used only
//! when both files exist, its size is the scene's, every value is finite, and
//! the checksum matches ([`read_cached_reference`]); otherwise it is rendered again and
//! rewritten. This is the only cache a sweep reads: its light sets are computed.
//!
//! # The measurements of a row
//! Deterministic (the same bits on every machine and thread count, so shards merge exactly):
//! - `rel_rmse`: relative RMSE over the pixels the mesh covers,
//!   `sqrt(sum |x - r|^2 / sum |r|^2)` over those pixels' RGB channels (linear radiance);
//! - `p99_rel`: the 99th percentile over the covered pixels of the per-pixel relative error
//!   `|x - r| / |r|` (RGB norms; pixels whose reference is below 1% of the mean left out,
//!   [`crate::metrics::relative_error_quantile`]): the tail `rel_rmse` averages away;
//! - `max_err`: largest absolute channel difference (linear radiance, the probe's units);
//! - `flip_mean`: mean FLIP ([`crate::compare`]) between the display encodings (exposure 0,
//!   ACES, sRGB, 8 bits) of the two images;
//! - `default`: whether the row is the scene's own configuration ([`DefaultConfig`]).
//!
//! Measured (wall-clock, [`std::time::Instant`]; they vary run to run and machine to
//! machine): `prep_ms`, the method's preparation from the decoded probe: the sampler's
//! light set (once per sampler and count, shared by that group's rows), or the transfer
//! table and its exact lights (once per table, exact-light count and order); no disk cache
//! involved;
//! `frame_ms`, the median of `frames` full renders (raster + shading) of the row; and
//! `pareto`, whether no other row is at least as fast and at least as accurate
//! ([`pareto_front`] over (`frame_ms`, `rel_rmse`)).
//!
//! # CSV
//! One header line ([`CSV_HEADER`]), one line per row sorted by `index`, numbers in Rust's
//! shortest round-trip form (times with 3 decimals), so reading and writing a CSV gives the
//! same text. Reading matches columns by header name ([`read_csv`]): reordered columns read
//! the same; a missing or unknown column, or a bad value, is an error naming the file, the
//! line and the column. A method's parameter columns hold `-` on other methods' rows.
//! A CSV from before the method axis (no `method` column) is refused with a message
//! saying so, not read as lights rows: its `index` numbered a grid without methods,
//! which merging or checking against this build's grid would silently misnumber whenever
//! that grid differs; regenerating it costs one sweep. [`merge()`] reads shard CSVs and writes what one run writes, the `pareto`
//! column recomputed over the union.
//!
//! # Layout
//! One concept per file, every public name re-exported here (`sweep::Row`, `sweep::merge`,
//! ...), as the data flows:
//! - [`grid`]: the axes ([`Grid`]), the method axis ([`MethodKind`], [`MethodAxis`]), one configuration ([`Config`]), the scene's own
//!   ([`DefaultConfig`]) and the names of axis values ([`sampler_name`], ...);
//! - [`default_scene`]: the scenes rendered without `--scene` ([`default_scene_file`],
//!   [`MaterialClass::scene_file`]);
//! - [`cache`]: the reference cache ([`reference_key`], [`read_cached_reference`]);
//! - [`run`]: the timed runner ([`Sweep`]: prepare once, then render and time each row);
//! - [`metrics`]: a row's errors against the reference ([`crate::metrics::relative_rmse`]);
//! - [`pareto`]: the Pareto front ([`pareto_front`], [`finish_rows`]) and the fastest row
//!   within a bound ([`fastest_within`]);
//! - [`csv`]: the row ([`Row`]) and its CSV, header-keyed on read ([`read_csv`],
//!   [`write_csv`]);
//! - [`merge`](mod@merge): shard CSVs merged into what one run writes ([`merge()`]);
//! - [`plot`]: the frame-time-against-error plot of a CSV;
//! - [`check`]: a stored CSV's deterministic columns against this build's
//!   ([`deterministic_mismatches`], `brdfkit sweep --check`).

pub mod cache;
pub mod check;
pub mod csv;
pub mod default_scene;
pub mod grid;
pub mod merge;
pub mod metrics;
pub mod pareto;
pub mod plot;
pub mod run;

pub use self::csv::{csv_text, read_csv, write_csv, Row, CSV_HEADER, DETERMINISTIC_COLUMNS};
pub use cache::{
    image_checksum, read_cached_reference, reference_key, REFERENCE_ALGORITHM_VERSION,
};
pub use check::{deterministic_mismatches, Mismatch};
pub use default_scene::{default_scene_file, probe_path, MaterialClass};
pub use grid::{
    default_counts, default_exact_lights, default_samplers, default_transfer_grids, describe,
    lookup_name, parse_lookup, parse_sampler, precision_name, sampler_name, Config, DefaultConfig,
    Grid, MethodAxis, MethodKind,
};
pub use merge::merge;
pub use pareto::{fastest_within, finish_rows, pareto_front, ERROR_BOUND};
pub use run::Sweep;
