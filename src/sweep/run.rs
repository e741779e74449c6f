//! The timed runner of a sweep ([`Sweep`]): prepares the scene, the probe and the reference
//! once, then renders and measures each configuration of the grid.
//!
//! Design rule: everything a row's deterministic columns depend on is fixed in
//! [`Sweep::prepare`] (scene, probe, reference, coverage mask); [`Sweep::run`] only builds
//! each configuration's scene, times it and measures it ([`super::metrics`]). Times are
//! wall-clock ([`Instant`]) and kept at the CSV's precision.
//!
//! A row's environment ([`Sweep::environment`]) is the scene's `[env]` with the row's method
//! and parameters, built by the one function `brdfkit render` builds it with
//! ([`crate::scene::build_environment`]) from the probe decoded once
//! ([`ProbeSource::Decoded`]), so the same bits; a `transfer` row's table is built for the
//! row's SH order (the truncated data set's bands).

use super::cache::write_cached_reference;
use super::MethodAxis;
use super::{metrics, read_cached_reference, reference_key};
use super::{Config, DefaultConfig, Grid, Row};
use crate::compare::Loaded;
use crate::env::schema::{EnvMethod, EnvSpec};
use crate::env::transfer::TransferBasis;
use crate::env::Probe;
use crate::error::{Error, Result};
use crate::image_io::Image;
use crate::material::Material;
use crate::progress::Progress;
use crate::scene::{build_environment, Environment, Precision, ProbeSource, Scene, SceneFile};
use crate::sh::dataset::ShDataset;
use crate::shard::Shard;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Why the sweep leaves `method` out for `material` (`None` when it sweeps it): a transfer
/// table shades SH data sets and Lambert only, light cuts every material with a cone bound,
/// a reflection table isotropic materials, and not SH data sets (their bake evaluates the set
/// per sample: minutes; their method is the transfer table).
pub fn not_swept(method: super::MethodKind, material: &Material) -> Option<String> {
    match method {
        super::MethodKind::Lights => None,
        super::MethodKind::Transfer => TransferBasis::for_material(material)
            .is_none()
            .then(|| "it shades SH data sets and Lambert only".to_string()),
        super::MethodKind::Lightcuts => crate::material::cone_bound::ConeBound::new(material).err(),
        super::MethodKind::Reflection => match material {
            Material::Sh(_) => Some(
                "an SH data set's table is the transfer table (a reflection bake evaluates \
                 the set per sample: minutes)"
                    .to_string(),
            ),
            m => crate::env::reflection::unsupported(m),
        },
    }
}

/// What a prepared sweep holds: the scene template, the probe, the reference.
pub struct Sweep {
    /// The scene without its environment (its own lights kept), f32.
    template: Scene,
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
    /// What [`Grid::fit_material`] left out, one note per method.
    pub notes: Vec<String>,
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
        // The scene's own method (`auto` made concrete for its material): its default row.
        file.resolve_env_method();
        let Some(env) = file.env.clone() else {
            return Err(Error::field(
                "--scene",
                "the scene has no [env]: a sweep varies the environment's method and its parameters",
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
        let sh = full.material.as_sh().cloned();
        let mut notes = grid.fit_material(sh.as_ref().map(ShDataset::bands), |m| {
            not_swept(m, &full.material)
        })?;
        if grid.is_empty() {
            return Err(Error::field(
                "--samplers/--counts/--transfer-grids/--exact-lights",
                "the grid is empty",
            ));
        }
        for &n in &grid.counts {
            if n == 0 || n > crate::env::schema::MAX_LIGHTS {
                return Err(Error::field(
                    "--counts",
                    format!(
                        "{n} is out of range (1 to {})",
                        crate::env::schema::MAX_LIGHTS
                    ),
                ));
            }
        }
        for &(nu, nv) in &grid.transfer_grids {
            if nu < 3 || nv < 2 {
                return Err(Error::field(
                    "--transfer-grids",
                    format!("{nu}x{nv}: at least 3 azimuth and 2 polar nodes"),
                ));
            }
        }
        for &k in &grid.exact_lights {
            if k > crate::env::schema::MAX_LIGHTS {
                return Err(Error::field(
                    "--exact-lights",
                    format!(
                        "{k} is out of range (0 to {})",
                        crate::env::schema::MAX_LIGHTS
                    ),
                ));
            }
        }
        for &g in &grid.reflection_grids {
            if !(2..=1024).contains(&g) {
                return Err(Error::field(
                    "--reflection-grids",
                    format!("{g} is out of range (2 to 1024 cells per side)"),
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
        let (probe, report) =
            crate::env::probe::load_probe(&base.join(&env.file), &env.load_options())?;
        // The probe is loaded once per sweep (every row samples this one): its loader
        // warning is one note, the file as the scene names it.
        notes.extend(report.negative_warning(&env.file.display().to_string()));
        if grid.methods.contains(&super::MethodKind::Transfer) {
            if let Some(&(nu, _)) = grid
                .transfer_grids
                .iter()
                .find(|(nu, _)| probe.width() % nu != 0)
            {
                return Err(Error::field(
                    "--transfer-grids",
                    format!(
                        "{nu} azimuth nodes do not divide the probe's width {}",
                        probe.width()
                    ),
                ));
            }
        }
        let default = DefaultConfig {
            method: MethodAxis::of_spec(&env),
            order: sh.as_ref().map_or(0, ShDataset::bands),
            lookup: sh.as_ref().map(|d| d.coeff_lookup),
            precision: Precision::F32,
        };
        let mut template = full;
        template.environment = Environment::None;
        Ok(Sweep {
            template,
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
            notes,
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

    /// The SH data set of order `order` (the material's, truncated when `order` is below
    /// its bands), or `None` for a material that is not SH.
    fn dataset(&self, order: usize) -> Result<Option<ShDataset>> {
        let Some(ds) = &self.sh else {
            return Ok(None);
        };
        Ok(Some(if order < ds.bands() {
            ds.truncated(order)
                .map_err(|e| Error::field("--orders", e.to_string()))?
        } else {
            ds.clone()
        }))
    }

    /// The environment of a method at SH order `order` (used by `transfer` only: the
    /// table's bands), and its preparation time in milliseconds: the light set's sampling,
    /// or the choice of the exact texels and the table's build. The probe is decoded once,
    /// in [`Sweep::prepare`], for every row.
    pub fn environment(&self, method: &MethodAxis, order: usize) -> Result<(Environment, f64)> {
        let start = Instant::now();
        let mut spec = self.env.clone();
        // The probe is sampled (a light set file, if the scene names one, is not read).
        spec.lights = None;
        let material = match *method {
            MethodAxis::Lights { sampler, count } => {
                spec.method = EnvMethod::Lights;
                (spec.sampler, spec.count) = (sampler, count);
                self.template.material.clone()
            }
            MethodAxis::Transfer {
                azimuth,
                polar,
                exact_lights,
            } => {
                spec.method = EnvMethod::Transfer;
                (spec.transfer_azimuth, spec.transfer_polar) = (azimuth, polar);
                spec.exact_lights = exact_lights;
                match self.dataset(order)? {
                    Some(ds) => ds.into(),
                    None => self.template.material.clone(),
                }
            }
            MethodAxis::Lightcuts { cut_error, cut_max } => {
                spec.method = EnvMethod::Lightcuts;
                (spec.cut_error, spec.cut_max) = (cut_error, cut_max);
                self.template.material.clone()
            }
            MethodAxis::Reflection { grid, exact_lights } => {
                spec.method = EnvMethod::Reflection;
                (spec.reflection_grid, spec.exact_lights) = (grid, exact_lights);
                self.template.material.clone()
            }
        };
        let (env, _) = build_environment(&spec, &material, ProbeSource::Decoded(&self.probe))?;
        Ok((env, start.elapsed().as_secs_f64() * 1e3))
    }

    /// The scene of a configuration with its environment.
    pub fn scene(&self, c: &Config, env: &Environment) -> Result<Scene> {
        let mut s = self.template.clone();
        s.environment = env.clone();
        s.render.precision = c.precision;
        if let Some(mut d) = self.dataset(c.order)? {
            if let Some(l) = c.lookup {
                d.coeff_lookup = l;
            }
            s.material = d.into();
        }
        Ok(s)
    }

    /// Renders and measures the configurations (in order), calling `progress` after each.
    /// The environment is prepared once per run of consecutive rows that share it (the
    /// same method point; for `transfer`, also the same order). Rows come back with
    /// `pareto` unset (see [`super::finish_rows`]).
    pub fn run(&self, configs: &[Config], mut progress: impl FnMut(&Row)) -> Result<Vec<Row>> {
        let mut rows = Vec::with_capacity(configs.len());
        let mut cached: Option<((MethodAxis, usize), Environment, f64)> = None;
        // Every row's frames have one size: their buffers are reused from row to row,
        // so a frame's time has no allocation or first-touch page fault in it.
        let mut frame = crate::render::FrameContext::default();
        for c in configs {
            let order = match c.method {
                MethodAxis::Lights { .. }
                | MethodAxis::Lightcuts { .. }
                | MethodAxis::Reflection { .. } => 0,
                MethodAxis::Transfer { .. } => c.order,
            };
            let key = (c.method, order);
            if cached.as_ref().map(|x| x.0) != Some(key) {
                let (env, ms) = self.environment(&c.method, c.order)?;
                cached = Some((key, env, ms));
            }
            let (_, env, prep_ms) = cached.as_ref().expect("prepared above");
            let scene = self.scene(c, env)?;
            let mut times = Vec::with_capacity(self.frames);
            let mut image = None;
            for _ in 0..self.frames {
                let start = Instant::now();
                self.pool.install(|| {
                    let opts = crate::render::RenderOptions::default();
                    crate::render::render_into(&scene, &opts, &mut frame);
                });
                times.push(start.elapsed().as_secs_f64() * 1e3);
                image.get_or_insert_with(|| frame.image().clone());
            }
            times.sort_by(f64::total_cmp);
            // Kept at the CSV's precision (1 us), so the Pareto front computed here is the
            // one `--merge` recomputes from the written rows (ties included).
            let frame_ms = (times[times.len() / 2] * 1e3).round() / 1e3;
            let img = image.expect("frames >= 1");
            let e = self.errors(&img)?;
            let row = Row {
                config: *c,
                rel_rmse: e.rel_rmse,
                p99_rel: e.p99_rel,
                max_err: e.max_err,
                flip_mean: e.flip_mean,
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

    /// The errors of an image against the reference ([`super::metrics::Errors`]).
    pub fn errors(&self, img: &Image) -> Result<metrics::Errors> {
        metrics::errors(&self.reference, &self.covered, img)
    }
}
