//! Run time against error (`brdfkit sweep`): render one scene over a grid of configurations
//! and measure, for each, the error against the converged reference and the time it took.
//!
//! # The grid
//! sampler x light count x SH order x lookup x precision, enumerated in that nesting order
//! (sampler outermost, precision innermost); a row's `index` is its position in the *whole*
//! grid, so shards ([`crate::shard`]) and merged CSVs agree on it. Defaults
//! ([`Grid::default`]): the five samplers of [`SamplerKind`] except `full`; counts
//! 1, 2, 4, ..., 1024; orders (SH bands) 1..=8; lookups nearest and bilinear; precision f32
//! only: 5 x 11 x 8 x 2 = 880 rows. SH orders above the data set's stored bands are
//! dropped; an order below them shades [`ShDataset::truncated`]. A scene whose material is
//! not an SH data set has one order (written 0) and one lookup (written `-`).
//!
//! # The reference
//! The scene with every texel of its probe as a light (sampler `full`), f64 shading, no
//! culling and no skips ([`crate::render::render_reference`]), the same reference as
//! `brdfkit render --reference`. It renders the material as the scene stores it (every
//! band, its own lookup), so a row with fewer orders or the other lookup measures that
//! difference too: for SH materials the truncation, not the light count, dominates the error
//! at low orders. It takes minutes for the default scene, so it is cached (`--cache DIR`,
//! default `target/brdfkit-cache`; `--no-cache`: not at all) as a linear EXR
//! `reference-<key>.exr` named by [`reference_key`]: a hash of the scene's configuration and
//! input files, the crate version, [`REFERENCE_ALGORITHM_VERSION`] and
//! [`crate::env::prepare::LIGHT_SET_ALGORITHM_VERSION`]. Beside it,
//! `reference-<key>.exr.fnv1a` holds [`image_checksum`] of its pixels; an entry is used only
//! when both files exist, its size is the scene's, every value is finite, and
//! the checksum matches ([`read_cached_reference`]); otherwise it is rendered again and
//! rewritten. This is the only cache a sweep reads: its light sets are computed.
//!
//! # The measurements of a row
//! Deterministic (the same bits on every machine and thread count, so shards merge exactly):
//! - `rel_rmse`: relative RMSE over the pixels the mesh covers,
//!   `sqrt(sum |x - r|^2 / sum |r|^2)` over those pixels' RGB channels (linear radiance);
//! - `max_err`: largest absolute channel difference (linear radiance, the probe's units);
//! - `flip_mean`: mean FLIP ([`crate::compare`]) between the display encodings (exposure 0,
//!   ACES, sRGB, 8 bits) of the two images;
//! - `default`: whether the row is the scene's own configuration ([`DefaultConfig`]).
//!
//! Measured (wall-clock, [`std::time::Instant`]; they vary run to run and machine to
//! machine): `prep_ms`, the sampler's time to collapse the decoded probe into the light set
//! (once per sampler and count, shared by that group's rows; no disk cache involved);
//! `frame_ms`, the median of `frames` full renders (raster + shading) of the row; and
//! `pareto`, whether no other row is at least as fast and at least as accurate
//! ([`pareto_front`] over (`frame_ms`, `rel_rmse`)).
//!
//! # CSV
//! One header line ([`CSV_HEADER`]), one line per row sorted by `index`, numbers in Rust's
//! shortest round-trip form (times with 3 decimals), so reading and writing a CSV gives the
//! same text. [`merge`] reads shard CSVs and writes what one run writes, the `pareto`
//! column recomputed over the union.

pub mod cache;
pub mod plot;

use cache::write_cached_reference;
pub use cache::{
    image_checksum, read_cached_reference, reference_key, REFERENCE_ALGORITHM_VERSION,
};

use crate::compare::{self, Loaded, Thresholds};
use crate::env::prepare::{EnvSpec, SamplerKind};
use crate::env::{LightSet, Probe};
use crate::error::{Error, Result};
use crate::image_io::{self, Image};
use crate::light::Light;
use crate::scene::{MaterialSpec, Precision, Scene, SceneFile};
use crate::sh::dataset::{Lookup, ShDataset};
use crate::shard::Shard;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// The CSV header: deterministic columns first, then measured ones.
pub const CSV_HEADER: &str =
    "index,sampler,lights,order,lookup,precision,rel_rmse,max_err,flip_mean,default,prep_ms,frame_ms,pareto";

/// Number of deterministic leading columns of [`CSV_HEADER`] (`index` .. `default`).
pub const DETERMINISTIC_COLUMNS: usize = 10;

/// Default light counts: 1, 2, 4, ..., 1024.
pub fn default_counts() -> Vec<usize> {
    (0..=10).map(|k| 1usize << k).collect()
}

/// The samplers a sweep runs by default: every [`SamplerKind`] except `full` (the reference).
pub fn default_samplers() -> Vec<SamplerKind> {
    vec![
        SamplerKind::Uniform,
        SamplerKind::Importance,
        SamplerKind::Stratified,
        SamplerKind::MedianCut,
        SamplerKind::Lloyd,
    ]
}

/// The sampler's command-line name (`median-cut`, ...).
pub fn sampler_name(s: SamplerKind) -> String {
    use clap::ValueEnum;
    s.to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_default()
}

/// Parses a sampler name as [`sampler_name`] writes it.
pub fn parse_sampler(s: &str) -> Option<SamplerKind> {
    use clap::ValueEnum;
    SamplerKind::from_str(s, false).ok()
}

/// `nearest` / `bilinear`, `-` for none.
pub fn lookup_name(l: Option<Lookup>) -> &'static str {
    match l {
        Some(Lookup::Nearest) => "nearest",
        Some(Lookup::Bilinear) => "bilinear",
        None => "-",
    }
}

/// Parses [`lookup_name`]'s output (`-` is `Some(None)`).
pub fn parse_lookup(s: &str) -> Option<Option<Lookup>> {
    match s {
        "nearest" => Some(Some(Lookup::Nearest)),
        "bilinear" => Some(Some(Lookup::Bilinear)),
        "-" => Some(None),
        _ => None,
    }
}

/// `f32` / `f64`.
pub fn precision_name(p: Precision) -> &'static str {
    match p {
        Precision::F32 => "f32",
        Precision::F64 => "f64",
    }
}

/// The axes of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub samplers: Vec<SamplerKind>,
    /// Requested light counts (the sampler's `n`).
    pub counts: Vec<usize>,
    /// SH orders (bands kept, `l < order`); `[0]` for a material that is not SH.
    pub orders: Vec<usize>,
    /// Coefficient-table lookups; `[None]` for a material that is not SH.
    pub lookups: Vec<Option<Lookup>>,
    pub precisions: Vec<Precision>,
}

impl Default for Grid {
    fn default() -> Self {
        Grid {
            samplers: default_samplers(),
            counts: default_counts(),
            orders: (1..=8).collect(),
            lookups: vec![Some(Lookup::Nearest), Some(Lookup::Bilinear)],
            precisions: vec![Precision::F32],
        }
    }
}

/// One configuration of the grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// Position in the whole grid (see the module doc).
    pub index: usize,
    pub sampler: SamplerKind,
    pub lights: usize,
    pub order: usize,
    pub lookup: Option<Lookup>,
    pub precision: Precision,
}

impl Grid {
    /// Number of configurations.
    pub fn len(&self) -> usize {
        self.samplers.len()
            * self.counts.len()
            * self.orders.len()
            * self.lookups.len()
            * self.precisions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every configuration, in index order.
    pub fn configs(&self) -> Vec<Config> {
        let mut out = Vec::with_capacity(self.len());
        for &sampler in &self.samplers {
            for &lights in &self.counts {
                for &order in &self.orders {
                    for &lookup in &self.lookups {
                        for &precision in &self.precisions {
                            out.push(Config {
                                index: out.len(),
                                sampler,
                                lights,
                                order,
                                lookup,
                                precision,
                            });
                        }
                    }
                }
            }
        }
        out
    }

    /// Fits the SH axes to the scene's material: orders above `bands` are dropped (an error
    /// if none remain); a material that is not SH (`bands == None`) gets `[0]` and `[None]`.
    pub fn fit_material(&mut self, bands: Option<usize>) -> Result<()> {
        match bands {
            None => {
                self.orders = vec![0];
                self.lookups = vec![None];
            }
            Some(b) => {
                self.orders.retain(|&o| o >= 1 && o <= b);
                if self.orders.is_empty() {
                    return Err(Error::field(
                        "--orders",
                        format!("no order in 1..={b}: the material's data set stores {b} bands"),
                    ));
                }
                if self.lookups.iter().any(Option::is_none) {
                    return Err(Error::field("--lookups", "give nearest and/or bilinear"));
                }
            }
        }
        Ok(())
    }
}

/// The scene's own configuration, to mark the default row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DefaultConfig {
    pub sampler: SamplerKind,
    pub lights: usize,
    pub order: usize,
    pub lookup: Option<Lookup>,
    pub precision: Precision,
}

impl DefaultConfig {
    /// Whether `c` is this configuration.
    pub fn matches(&self, c: &Config) -> bool {
        c.sampler == self.sampler
            && c.lights == self.lights
            && c.order == self.order
            && c.lookup == self.lookup
            && c.precision == self.precision
    }
}

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

impl Row {
    /// The CSV line (no newline).
    pub fn csv_line(&self) -> String {
        let c = &self.config;
        format!(
            "{},{},{},{},{},{},{},{},{},{},{:.3},{:.3},{}",
            c.index,
            sampler_name(c.sampler),
            c.lights,
            c.order,
            lookup_name(c.lookup),
            precision_name(c.precision),
            self.rel_rmse,
            self.max_err,
            self.flip_mean,
            self.default as u8,
            self.prep_ms,
            self.frame_ms,
            self.pareto as u8
        )
    }

    /// The deterministic columns of [`Row::csv_line`] (`index` .. `default`).
    pub fn deterministic_part(&self) -> String {
        self.csv_line()
            .split(',')
            .take(DETERMINISTIC_COLUMNS)
            .collect::<Vec<_>>()
            .join(",")
    }

    fn parse(line: &str) -> std::result::Result<Row, String> {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != 13 {
            return Err(format!("{} fields, expected 13", f.len()));
        }
        let num = |i: usize, name: &str| -> std::result::Result<f64, String> {
            f[i].parse::<f64>()
                .map_err(|_| format!("{name} {:?} is not a number", f[i]))
        };
        let int = |i: usize, name: &str| -> std::result::Result<usize, String> {
            f[i].parse::<usize>()
                .map_err(|_| format!("{name} {:?} is not a whole number", f[i]))
        };
        let flag = |i: usize, name: &str| -> std::result::Result<bool, String> {
            match f[i] {
                "0" => Ok(false),
                "1" => Ok(true),
                other => Err(format!("{name} {other:?} is not 0 or 1")),
            }
        };
        Ok(Row {
            config: Config {
                index: int(0, "index")?,
                sampler: parse_sampler(f[1]).ok_or(format!("unknown sampler {:?}", f[1]))?,
                lights: int(2, "lights")?,
                order: int(3, "order")?,
                lookup: parse_lookup(f[4]).ok_or(format!("unknown lookup {:?}", f[4]))?,
                precision: match f[5] {
                    "f32" => Precision::F32,
                    "f64" => Precision::F64,
                    other => return Err(format!("unknown precision {other:?}")),
                },
            },
            rel_rmse: num(6, "rel_rmse")?,
            max_err: num(7, "max_err")?,
            flip_mean: num(8, "flip_mean")?,
            default: flag(9, "default")?,
            prep_ms: num(10, "prep_ms")?,
            frame_ms: num(11, "frame_ms")?,
            pareto: flag(12, "pareto")?,
        })
    }
}

/// The Pareto front of points `(time, error)`, both smaller-is-better: `front[i]` is true
/// when no other point is at least as good in both and strictly better in one. Equal
/// points are all on the front. NaN points are never on it and dominate nothing.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(t, e)| {
            !t.is_nan()
                && !e.is_nan()
                && !points
                    .iter()
                    .any(|&(t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .collect()
}

/// Sorts rows by index and sets their `pareto` flags over (frame_ms, rel_rmse).
pub fn finish_rows(rows: &mut [Row]) {
    rows.sort_by_key(|r| r.config.index);
    let pts: Vec<(f64, f64)> = rows.iter().map(|r| (r.frame_ms, r.rel_rmse)).collect();
    for (r, p) in rows.iter_mut().zip(pareto_front(&pts)) {
        r.pareto = p;
    }
}

/// The CSV text of rows (header, then one line per row, each ending in a newline).
pub fn csv_text(rows: &[Row]) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for r in rows {
        s.push_str(&r.csv_line());
        s.push('\n');
    }
    s
}

/// Writes rows as CSV through a temporary file ([`image_io::write_atomically`]).
pub fn write_csv(path: &Path, rows: &[Row]) -> Result<()> {
    let text = csv_text(rows);
    image_io::write_atomically(path, |tmp| {
        std::fs::write(tmp, text.as_bytes()).map_err(|e| Error::io(path, "cannot write CSV", e))
    })
}

/// Reads a sweep CSV. Errors name the file and, for content, the line.
pub fn read_csv(path: &Path) -> Result<Vec<Row>> {
    let text =
        std::fs::read_to_string(path).map_err(|e| Error::io(path, "cannot read sweep CSV", e))?;
    let mut lines = text.lines();
    match lines.next() {
        Some(h) if h.trim_end() == CSV_HEADER => {}
        Some(_) => {
            return Err(Error::format(
                path,
                "line 1: not a sweep CSV (the header differs from `brdfkit sweep`'s)",
            ))
        }
        None => return Err(Error::format(path, "line 1: empty file, no CSV header")),
    }
    let mut rows = Vec::new();
    for (k, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let row = Row::parse(line.trim_end())
            .map_err(|m| Error::format(path, format!("line {}: {m}", k + 2)))?;
        rows.push(row);
    }
    Ok(rows)
}

/// Merges shard CSVs into what one run writes: rows sorted by index, the Pareto column
/// recomputed over the union. A row index in two files is an error naming both files.
pub fn merge(inputs: &[PathBuf]) -> Result<Vec<Row>> {
    let mut rows: Vec<(Row, usize)> = Vec::new();
    for (k, p) in inputs.iter().enumerate() {
        rows.extend(read_csv(p)?.into_iter().map(|r| (r, k)));
    }
    rows.sort_by_key(|(r, _)| r.config.index);
    for w in rows.windows(2) {
        if w[0].0.config.index == w[1].0.config.index {
            return Err(Error::format(
                &inputs[w[1].1],
                format!(
                    "row index {} is also in {} (the same row in two shards)",
                    w[1].0.config.index,
                    inputs[w[0].1].display()
                ),
            ));
        }
    }
    let mut rows: Vec<Row> = rows.into_iter().map(|(r, _)| r).collect();
    finish_rows(&mut rows);
    Ok(rows)
}

/// The scene a sweep renders: the default is the teapot in `blue-silk` (library SH
/// material, 8 bands, its own bilinear lookup) under `assets/probes/city.exr`, 160x120,
/// environment sampler and count at their defaults (the render defaults).
pub fn default_scene_file() -> Result<SceneFile> {
    let rel = PathBuf::from("assets/probes/city.exr");
    let probe = if rel.is_file() {
        std::env::current_dir().map(|d| d.join(&rel)).unwrap_or(rel)
    } else {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(&rel)
    };
    if !probe.is_file() {
        return Err(Error::format(
            &probe,
            "the default sweep scene's probe is missing: run from the repository or give --scene",
        ));
    }
    let mut f = SceneFile {
        material: MaterialSpec::Library {
            name: "blue-silk".into(),
            lookup: None,
        },
        env: Some(EnvSpec::new(probe)),
        ..SceneFile::default()
    };
    f.render.width = 160;
    f.render.height = 120;
    Ok(f)
}

/// What a prepared sweep holds: the scene template, the probe, the reference.
pub struct Sweep {
    /// The scene without its environment lights (explicit lights kept), f32.
    template: Scene,
    /// The explicit (non-environment) lights of the scene.
    explicit: Vec<Light>,
    env: EnvSpec,
    probe: Probe,
    /// The SH data set of the material, if SH.
    sh: Option<ShDataset>,
    reference: Loaded,
    /// Pixels the mesh covers (row-major).
    covered: Vec<bool>,
    pub grid: Grid,
    pub default: DefaultConfig,
    /// The reference's cache file (`None` without a cache) and whether it was rendered now.
    pub reference_file: Option<PathBuf>,
    /// Why a cached reference was present but not used (damaged, edited, another size).
    pub reference_rejected: Option<String>,
    pub reference_rendered: bool,
    /// Renders per row whose median is `frame_ms` (>= 1).
    pub frames: usize,
    pool: rayon::ThreadPool,
}

impl Sweep {
    /// Loads the scene (`base`: directory its relative paths resolve against), fits the
    /// grid to its material, and loads the reference from `cache_dir` or renders and caches
    /// it (`on_reference` is called with the cache file before a render starts; no cache
    /// with `None`). The scene must have an `[env]`.
    pub fn prepare(
        mut file: SceneFile,
        base: &Path,
        mut grid: Grid,
        cache_dir: Option<&Path>,
        frames: usize,
        on_reference: impl FnOnce(Option<&Path>),
    ) -> Result<Sweep> {
        let Some(env) = file.env.clone() else {
            return Err(Error::field(
                "--scene",
                "the scene has no [env]: a sweep varies the environment's sampler and light count",
            ));
        };
        let threads = file.render.threads;
        file.output = Default::default();
        file.render.threads = 0;
        file.render.precision = Precision::F32;
        if let Some(e) = file.env.as_mut() {
            e.sampler = SamplerKind::Full;
        }
        let key = reference_key(&file, base)?;
        // Resolve with the full probe: the reference's light set (computed: no light-set
        // cache; collapsing a probe into one light per texel is cheaper than reading one).
        let full = Scene::resolve(&file, base)?;
        let env_lights = full.env.as_ref().map_or(0, |e| e.lights);
        let explicit = full.lights[..full.lights.len() - env_lights].to_vec();
        let sh = full.material.as_sh().cloned();
        grid.fit_material(sh.as_ref().map(ShDataset::bands))?;
        if grid.is_empty() {
            return Err(Error::field("--samplers/--counts", "the grid is empty"));
        }
        for &n in &grid.counts {
            if n == 0 || n > crate::env::prepare::MAX_LIGHTS {
                return Err(Error::field(
                    "--counts",
                    format!(
                        "{n} is out of range (1 to {})",
                        crate::env::prepare::MAX_LIGHTS
                    ),
                ));
            }
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        let reference_file = cache_dir.map(|d| d.join(format!("reference-{key:016x}.exr")));
        let (w, h) = (full.render.width, full.render.height);
        let (cached, reference_rejected) = match reference_file.as_deref() {
            None => (None, None),
            Some(f) => match read_cached_reference(f, w, h) {
                Ok(img) => (img, None),
                Err(why) => (None, Some(why)),
            },
        };
        let (reference, rendered) = match cached {
            Some(img) => (img, false),
            None => {
                on_reference(reference_file.as_deref());
                let img = pool.install(|| crate::render::render_reference(&full));
                if let Some(f) = &reference_file {
                    write_cached_reference(f, &img)?;
                }
                (img, true)
            }
        };
        let vis = crate::render::rasterize(&full, false);
        let covered = (0..full.render.height)
            .flat_map(|y| (0..full.render.width).map(move |x| (x, y)))
            .map(|(x, y)| vis.visible[vis.index(x, y)] != crate::raster::NO_TRIANGLE)
            .collect();
        let (probe, _) =
            crate::env::prepare::load_probe(&base.join(&env.file), &env.load_options())?;
        let default = DefaultConfig {
            sampler: env.sampler,
            lights: env.count,
            order: sh.as_ref().map_or(0, ShDataset::bands),
            lookup: sh.as_ref().map(|d| d.coeff_lookup),
            precision: Precision::F32,
        };
        let mut template = full;
        template.lights = Vec::new();
        Ok(Sweep {
            template,
            explicit,
            env,
            probe,
            sh,
            reference: Loaded::from_linear(reference),
            covered,
            grid,
            default,
            reference_file,
            reference_rejected,
            reference_rendered: rendered,
            frames: frames.max(1),
            pool,
        })
    }

    /// The configurations of `shard`, in index order.
    pub fn configs(&self, shard: Shard) -> Vec<Config> {
        self.grid
            .configs()
            .into_iter()
            .filter(|c| shard.contains(c.index))
            .collect()
    }

    /// The light set of a sampler and count, and its preparation time in milliseconds.
    pub fn light_set(&self, sampler: SamplerKind, n: usize) -> (LightSet, f64) {
        let config = sampler.config(n, self.env.seed);
        let start = Instant::now();
        let mut ls = config.run(&self.probe);
        if self.env.intensity != 1.0 {
            for p in ls
                .power_r
                .iter_mut()
                .chain(ls.power_g.iter_mut())
                .chain(ls.power_b.iter_mut())
            {
                *p *= self.env.intensity;
            }
        }
        (ls, start.elapsed().as_secs_f64() * 1e3)
    }

    /// The scene of a configuration with a given light set.
    pub fn scene(&self, c: &Config, lights: &LightSet) -> Result<Scene> {
        let mut s = self.template.clone();
        s.lights = self.explicit.clone();
        s.lights
            .extend(crate::env::prepare::to_scene_lights(lights));
        s.render.precision = c.precision;
        if let Some(ds) = &self.sh {
            let mut d = if c.order < ds.bands() {
                ds.truncated(c.order)
                    .map_err(|e| Error::field("--orders", e.to_string()))?
            } else {
                ds.clone()
            };
            if let Some(l) = c.lookup {
                d.coeff_lookup = l;
            }
            s.material = Arc::new(d);
        }
        Ok(s)
    }

    /// Renders and measures the configurations (in order), calling `progress` after each.
    /// The light set is prepared once per run of consecutive rows with the same sampler and
    /// count. Rows come back with `pareto` unset (see [`finish_rows`]).
    pub fn run(&self, configs: &[Config], mut progress: impl FnMut(&Row)) -> Result<Vec<Row>> {
        let mut rows = Vec::with_capacity(configs.len());
        let mut cached: Option<((SamplerKind, usize), LightSet, f64)> = None;
        for c in configs {
            let key = (c.sampler, c.lights);
            if cached.as_ref().map(|x| x.0) != Some(key) {
                let (ls, ms) = self.light_set(c.sampler, c.lights);
                cached = Some((key, ls, ms));
            }
            let (_, ls, prep_ms) = cached.as_ref().expect("prepared above");
            let scene = self.scene(c, ls)?;
            let mut times = Vec::with_capacity(self.frames);
            let mut image = None;
            for _ in 0..self.frames {
                let start = Instant::now();
                let img = self.pool.install(|| crate::render::render(&scene, None));
                times.push(start.elapsed().as_secs_f64() * 1e3);
                image.get_or_insert(img);
            }
            times.sort_by(f64::total_cmp);
            // Kept at the CSV's precision (1 us), so the Pareto front computed here is the
            // one `--merge` recomputes from the written rows (ties included).
            let frame_ms = (times[times.len() / 2] * 1e3).round() / 1e3;
            let img = image.expect("frames >= 1");
            let (rel_rmse, max_err, flip_mean) = self.errors(&img)?;
            let row = Row {
                config: *c,
                rel_rmse,
                max_err,
                flip_mean,
                default: self.default.matches(c),
                prep_ms: *prep_ms,
                frame_ms,
                pareto: false,
            };
            progress(&row);
            rows.push(row);
        }
        Ok(rows)
    }

    /// (relative RMSE over covered pixels, max abs error, FLIP mean) of an image against
    /// the reference.
    pub fn errors(&self, img: &Image) -> Result<(f64, f64, f64)> {
        let (m, _) = compare::compare(
            &self.reference,
            &Loaded::from_linear(img.clone()),
            &Thresholds::DEFAULT,
        )?;
        Ok((
            relative_rmse(&self.reference.image, img, &self.covered),
            m.max_abs as f64,
            m.flip_mean as f64,
        ))
    }
}

/// `sqrt(sum |x - r|^2 / sum |r|^2)` over the RGB channels of the pixels where `mask` is
/// true (0 when both are zero there; infinite when only the reference is zero).
pub fn relative_rmse(reference: &Image, img: &Image, mask: &[bool]) -> f64 {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for ((r, x), &m) in reference.pixels.iter().zip(&img.pixels).zip(mask) {
        if m {
            let (r, x) = (r.as_dvec3(), x.as_dvec3());
            num += (x - r).length_squared();
            den += r.length_squared();
        }
    }
    if num == 0.0 {
        0.0
    } else {
        (num / den).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_basic() {
        // (time, error)
        let pts = [
            (1.0, 10.0), // front: fastest
            (2.0, 5.0),  // front
            (3.0, 5.0),  // dominated by (2, 5)
            (4.0, 1.0),  // front: most accurate
            (5.0, 2.0),  // dominated by (4, 1)
            (2.0, 5.0),  // equal to a front point: also on it
            (f64::NAN, 0.1),
        ];
        assert_eq!(
            pareto_front(&pts),
            vec![true, true, false, true, false, true, false]
        );
        assert!(pareto_front(&[]).is_empty());
        assert_eq!(pareto_front(&[(1.0, 1.0)]), vec![true]);
    }

    #[test]
    fn pareto_front_is_not_dominated_and_dominates_the_rest() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64::seed_from_u64(5);
        let pts: Vec<(f64, f64)> = (0..300)
            .map(|_| (rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0)))
            .collect();
        let front = pareto_front(&pts);
        for (i, &(t, e)) in pts.iter().enumerate() {
            let dominated = pts
                .iter()
                .any(|&(t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e));
            assert_eq!(front[i], !dominated);
        }
        assert!(front.iter().any(|&f| f));
    }

    #[test]
    fn grid_order_and_size() {
        let g = Grid::default();
        assert_eq!(g.len(), 880);
        let c = g.configs();
        assert_eq!(c.len(), 880);
        assert!(c.iter().enumerate().all(|(i, c)| c.index == i));
        // precision innermost, then lookup, order, count; sampler outermost
        assert_eq!(c[1].lookup, Some(Lookup::Bilinear));
        assert_eq!(c[2].order, 2);
        assert_eq!(c[16].lights, 2);
        assert_eq!(c[176].sampler, SamplerKind::Importance);
    }

    #[test]
    fn csv_round_trip() {
        let row = Row {
            config: Config {
                index: 7,
                sampler: SamplerKind::MedianCut,
                lights: 64,
                order: 5,
                lookup: Some(Lookup::Bilinear),
                precision: Precision::F64,
            },
            rel_rmse: 0.012345678901234,
            max_err: 1.5e-3,
            flip_mean: 0.0291,
            default: true,
            prep_ms: 1.2345,
            frame_ms: 83.0,
            pareto: true,
        };
        let text = csv_text(std::slice::from_ref(&row));
        let line = text.lines().nth(1).unwrap();
        assert_eq!(
            line,
            "7,median-cut,64,5,bilinear,f64,0.012345678901234,0.0015,0.0291,1,1.234,83.000,1"
        );
        let back = Row::parse(line).unwrap();
        assert_eq!(back.csv_line(), line);
        assert_eq!(
            back.deterministic_part(),
            "7,median-cut,64,5,bilinear,f64,0.012345678901234,0.0015,0.0291,1"
        );
    }

    #[test]
    fn fit_material_drops_orders() {
        let mut g = Grid::default();
        g.fit_material(Some(5)).unwrap();
        assert_eq!(g.orders, vec![1, 2, 3, 4, 5]);
        let mut g = Grid::default();
        g.fit_material(None).unwrap();
        assert_eq!((g.orders.clone(), g.lookups.clone()), (vec![0], vec![None]));
        let mut g = Grid {
            orders: vec![9],
            ..Grid::default()
        };
        assert!(g.fit_material(Some(8)).is_err());
    }
}
