//! The timed runner of a sweep ([`Sweep`]): prepares the scene, the probe and the reference
//! once, then renders and measures each configuration of the grid.
//!
//! Design rule: everything a row's deterministic columns depend on is fixed in
//! [`Sweep::prepare`] (scene, probe, reference, coverage mask); [`Sweep::run`] only builds
//! each configuration's scene, times it and measures it ([`super::metrics`]). Times are
//! wall-clock ([`Instant`]) and kept at the CSV's precision.

use super::cache::write_cached_reference;
use super::{metrics, read_cached_reference, reference_key};
use super::{Config, DefaultConfig, Grid, Row};
use crate::compare::Loaded;
use crate::env::prepare::{EnvSpec, SamplerKind};
use crate::env::{LightSet, Probe};
use crate::error::{Error, Result};
use crate::image_io::Image;
use crate::light::Light;
use crate::progress::Progress;
use crate::scene::{Precision, Scene, SceneFile};
use crate::sh::dataset::ShDataset;
use crate::shard::Shard;
use std::path::{Path, PathBuf};
use std::time::Instant;

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
    /// it (`on_reference` is called with the cache file, `None` without a cache, and the
    /// reference scene's tile count before a render starts; the [`Progress`] it returns
    /// counts the render's tiles). The scene must have an `[env]`.
    pub fn prepare(
        mut file: SceneFile,
        base: &Path,
        mut grid: Grid,
        cache_dir: Option<&Path>,
        frames: usize,
        on_reference: impl FnOnce(Option<&Path>, u64) -> Progress,
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
            e.use_full_probe();
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
                let progress =
                    on_reference(reference_file.as_deref(), crate::render::tile_count(&full));
                let img = pool.install(|| {
                    let mut opts = crate::render::RenderOptions::converged_reference();
                    opts.shading.progress = progress.clone();
                    crate::render::render(&full, &opts).image
                });
                progress.finish();
                if let Some(f) = &reference_file {
                    write_cached_reference(f, &img)?;
                }
                (img, true)
            }
        };
        let covered = metrics::covered_pixels(&full);
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
        // The scene's `[env] intensity`, exactly as `env::prepare::prepare` applies it.
        self.env.scale_intensity(&mut ls);
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
            s.material = d.into();
        }
        Ok(s)
    }

    /// Renders and measures the configurations (in order), calling `progress` after each.
    /// The light set is prepared once per run of consecutive rows with the same sampler and
    /// count. Rows come back with `pareto` unset (see [`super::finish_rows`]).
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
                let img = self.pool.install(|| {
                    crate::render::render(&scene, &crate::render::RenderOptions::default()).image
                });
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
    /// the reference ([`super::metrics`]).
    pub fn errors(&self, img: &Image) -> Result<(f64, f64, f64)> {
        metrics::errors(&self.reference, &self.covered, img)
    }
}
