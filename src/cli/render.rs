//! `brdfkit render`: the run (outputs checked first, the scene resolved, rendered,
//! written) and `scene_file`, the command-line options applied to a scene file, which
//! `brdfkit view` shares. It stays one file past 400 lines: both halves are the command
//! line of one command, and `run` reads `scene_file`'s result field by field.

use super::{CullArg, RenderArgs, SceneArgs};
use crate::aov;
use crate::env::{
    lightset::prepare::CacheDir,
    schema::{EnvMethod, EnvSpec},
};
use crate::error::{Error, Result};
use crate::image_io::{self, Format};
use crate::library::Representation;
use crate::progress::Progress;
use crate::raster::Cull;
use crate::render;
use crate::scene::env_method::{self, Renderer};
use crate::scene::{MaterialSpec, Precision, Scene, SceneFile, MAX_SIDE};
use crate::sh::Lookup;
use crate::shard::Shard;

use std::path::{Path, PathBuf};

/// Pixels from which a render on the kernels shows a progress bar: about a second of
/// shading (8192 x 8192, four times as many, takes 3.7 s on two cores).
const FAST_BAR_PIXELS: u64 = 4096 * 4096;

fn check_side(name: &str, v: u32) -> Result<u32> {
    if v == 0 || v > MAX_SIDE {
        return Err(Error::field(
            name,
            format!("{v} is out of range (1 to {MAX_SIDE} pixels)"),
        ));
    }
    Ok(v)
}

pub fn run(a: RenderArgs) -> Result<()> {
    if let Some(n) = a.turntable {
        crate::turntable::check_frames(n)?;
        if let Some(s) = &a.shard {
            Shard::parse(s)?;
        }
        if a.assemble {
            let out = super::turntable::turntable_output(a.output.clone())?;
            let gif = crate::turntable::assemble_gif(&out, n, a.fps)?;
            eprintln!("wrote {} ({n} frames)", gif.display());
            return Ok(());
        }
    }
    if !a.merge.is_empty() {
        return super::render_shard::merge(&a);
    }
    let (mut file, base) = scene_file(&a.common, a.reference)?;
    // How the probe's warnings name it: as the user gave it.
    let probe_name = file.env.as_ref().map(|env| probe_label(&a.common, env));
    // `[env] method = "auto"` made concrete for this material and renderer before anything
    // is prepared (the progress bar below names the method's preparation); `--device gpu`
    // gets a method the GPU runs, with one line saying so.
    let auto_method = file
        .env
        .as_ref()
        .is_some_and(|e| e.method == EnvMethod::Auto);
    if let Some(env) = &file.env {
        let renderer = match a.device {
            super::device::Device::Gpu => Renderer::Gpu,
            super::device::Device::Cpu | super::device::Device::Auto => Renderer::Cpu,
        };
        let (chosen, note) = env_method::choose(env, &file.material, renderer);
        if let Some(note) = note {
            eprintln!("{note}");
        }
        file.env = Some(chosen);
    }
    file.resolve_env_method();
    // Light cuts stated for the GPU: refused before the tree is built (seconds for a large
    // probe), in the words the GPU renderer uses.
    if a.device == super::device::Device::Gpu {
        if let Some(why) = file
            .env
            .as_ref()
            .and_then(|e| env_method::gpu_unsupported(e.method))
        {
            return Err(Error::Message(format!("--device gpu: {why}")));
        }
    }
    let outputs: Vec<PathBuf> = match a.output.clone().or(file.output.path.clone()) {
        Some(p) => vec![p],
        None => vec![PathBuf::from("out.png"), PathBuf::from("out.exr")],
    };
    // Every output is checked before the slow work (environment, mesh, render): its
    // extension and that its directory takes a new file. A turntable writes OUT_0000.png
    // ... and OUT.gif beside its PNG output (outputs[0]: -o, the scene's, or out.png).
    {
        let flag = if a.output.is_some() {
            "--output"
        } else {
            "output path"
        };
        let (checked, allowed): (&[PathBuf], &[&str]) = match a.turntable {
            Some(_) => {
                // Its own message first: why a turntable needs a .png.
                super::turntable::turntable_output(Some(outputs[0].clone()))?;
                (&outputs[..1], &["png"])
            }
            None => (&outputs, &["png", "exr"]),
        };
        for p in checked {
            image_io::check_output(p, allowed, flag)?;
        }
    }
    let part = super::render_shard::plan(&a, &file, &base, &outputs)?;
    let formats = outputs
        .iter()
        .map(|p| image_io::format_of(p))
        .collect::<Result<Vec<_>>>()?;
    // The user's light-set cache (crate::env::lightset::prepare), unless --no-cache.
    let cache = if a.common.no_cache {
        CacheDir::None
    } else {
        CacheDir::user()?
    };
    let resolve_base = base.as_path();
    // Counts the light set's preparation when it is computed (nothing on a cache hit).
    let light_set = match file
        .env
        .as_ref()
        .and_then(|env| env.method.preparation_progress(env))
    {
        // Length 0: drawn only once the preparation sets it (nothing on a cache hit).
        Some((what, unit)) => Progress::bar(0, &what, unit),
        None => Progress::hidden(),
    };
    let scene = Scene::resolve_with_progress(&file, resolve_base, &cache, &light_set);
    light_set.finish();
    let scene = match &a.common.scene {
        Some(p) => scene.map_err(|e| match e {
            Error::Field { .. } => Error::format(p, e.to_string()),
            other => other,
        })?,
        None => scene?,
    };
    if let Some(e) = &scene.env {
        // Once per run: the scene holds the one probe (every turntable frame reuses it).
        let label = probe_name
            .clone()
            .unwrap_or_else(|| e.file.display().to_string());
        if let Some(w) = e.probe_report.and_then(|r| r.negative_warning(&label)) {
            eprintln!("warning: {w}");
        }
        if let Some((w, h)) = e.probe_size {
            if w != 2 * h {
                eprintln!(
                    "warning: {label}: {w}x{h} is not 2:1; read as an equirectangular (latitude-longitude) probe anyway"
                );
            }
        }
        if e.total_irradiance.iter().all(|&p| p <= 0.0) {
            eprintln!(
                "warning: {label}: the probe carries no light (every texel black or negative): the environment adds nothing"
            );
        }
        let (cached, what) = scene.environment.report(e.lights);
        // Say what `auto` chose, and how to choose otherwise.
        let what = match file.env.as_ref().filter(|_| auto_method) {
            Some(env) => format!(
                "{what} ([env] method \"auto\" is \"{}\" for {}; set method or --env-method to choose)",
                env.method.name(),
                scene.material.name()
            ),
            None => what,
        };
        if let Some(why) = &e.cache_rejected {
            eprintln!("warning: {cached} cache entry ignored and rewritten: {why}");
        }
        eprintln!(
            "environment: {what} from {}{}",
            e.file.display(),
            if e.cache_hit { " (cached)" } else { "" }
        );
    }
    let gpu = super::device::open(
        a.device,
        &scene,
        &super::device::Request {
            aov: a.common.aov,
            reference: a.reference,
            turntable: a.turntable.is_some(),
        },
    )?;
    if let Some(aov) = a.common.aov {
        aov::check_available(&scene, aov)?;
    }
    if let Some(n) = a.turntable {
        return super::turntable::run_turntable(
            &a,
            &scene,
            n,
            a.output.clone().or(file.output.path.clone()),
            &cache,
        );
    }
    let start = std::time::Instant::now();
    let reference = a.reference && a.common.aov.is_none();
    let mut opts = if reference {
        render::RenderOptions::converged_reference()
    } else {
        render::RenderOptions::default()
    };
    opts.aov = a.common.aov;
    opts.threads = Some(scene.render.threads);
    opts.stats = a.common.stats && !reference;
    opts.rows = part.as_ref().map(|p| p.bands);
    // Tiles counted by the shading loop: a bar with an ETA on a terminal, nothing off one,
    // for the renders that can take more than about a second (the reference takes
    // minutes, the f64 path seconds; the kernels only at FAST_BAR_PIXELS and beyond).
    let what = match (reference, scene.render.precision) {
        _ if a.common.aov.is_some() => None,
        (true, _) => Some("reference"),
        (false, Precision::F64) => Some("render (f64)"),
        (false, Precision::F32) => {
            let pixels = scene.render.width as u64 * scene.render.height as u64;
            (pixels >= FAST_BAR_PIXELS).then_some("render")
        }
    };
    if let Some(what) = what {
        let what = part.as_ref().map_or(what.to_string(), |p| p.label(what));
        opts.shading.progress =
            Progress::bar(render::tile_count_in(&scene, opts.rows), &what, "tiles");
    }
    let rendered = match &gpu {
        Some(g) => render::Rendered {
            image: super::device::render(g, &scene, a.common.aov)?,
            stats: None,
        },
        None => render::render(&scene, &opts),
    };
    opts.shading.progress.finish();
    let (img, stats) = (rendered.image, rendered.stats);
    let elapsed = start.elapsed();
    if a.common.stats {
        match &stats {
            Some(s) => eprintln!("{s}"),
            None if gpu.is_some() => eprintln!("stats: gpu frame (upload, draw, read-back)"),
            None => eprintln!("stats: none for --reference (every light, every band, no skips)"),
        }
        if let Some(term) = scene.environment.reflection_term() {
            eprintln!("reflection: {}", term.path().describe());
        }
        if let Some(t) = scene.environment.reflection_term().and_then(|t| t.table()) {
            let e = t.error();
            eprintln!(
                "reflection table: {g} x {g} cells, {} + 1 slices, psi order {}, {} MB; error \
                 measured at bake against exact f64 sums ({} samples per set, luminance): rel \
                 RMSE {:.3}%, p99 {:.2}%, max {:.2}%; view polar 70-89.9 deg: rel RMSE \
                 {:.3}%, p99 {:.2}%, max {:.2}%",
                t.slices(),
                t.order(),
                format_args!("{:.1}", t.bytes() as f64 / 1e6),
                e.samples,
                100.0 * e.rel_rmse,
                100.0 * e.p99,
                100.0 * e.max,
                100.0 * e.grazing_rel_rmse,
                100.0 * e.grazing_p99,
                100.0 * e.grazing_max,
                g = t.grid(),
            );
        }
        // Of the image itself, whatever rendered it: a PNG clips these to black.
        if a.common.aov.is_none() {
            let neg = crate::metrics::negative_pixels(&img);
            eprintln!(
                "negative pixels: {} of {} (min {:.3e})",
                neg.pixels,
                img.pixels.len(),
                neg.min
            );
        }
    }
    if let Some(p) = &part {
        let path = p.write(&img)?;
        eprintln!(
            "wrote {} (shard {} of {}x{}, {:.1} ms)",
            path.display(),
            p.bands.shard,
            img.width,
            img.height,
            elapsed.as_secs_f64() * 1e3
        );
        return Ok(());
    }
    for (path, fmt) in outputs.iter().zip(formats) {
        match (fmt, a.common.aov) {
            (Format::Exr, _) => image_io::write_exr(path, &img)?,
            (Format::Png, None) => {
                image_io::write_png(path, &img, scene.output.exposure, scene.output.tonemap)?
            }
            (Format::Png, Some(aov)) => {
                image_io::write_png_bytes(path, img.width, img.height, aov::png_bytes(&img, aov))?
            }
        }
        eprintln!(
            "wrote {} ({}x{}, {:.1} ms)",
            path.display(),
            img.width,
            img.height,
            elapsed.as_secs_f64() * 1e3
        );
    }
    Ok(())
}

/// The environment's probe as the user named it, for warnings: `--env PROBE` as typed
/// (relative to the working directory); a scene file's `[env] file` as written there
/// (relative to the scene file), after the scene file's path as given; the default scene's
/// probe path. `env` is the scene's `[env]` after [`scene_file`].
fn probe_label(a: &SceneArgs, env: &EnvSpec) -> String {
    match (&a.env, &a.scene) {
        (Some(given), _) => given.display().to_string(),
        (None, Some(scene)) => format!("{}: env.file {}", scene.display(), env.file.display()),
        (None, None) => env.file.display().to_string(),
    }
}

/// The scene file `render` renders: the scene's file (or the default scene) with every
/// command-line option applied, and the directory its relative paths resolve against;
/// `reference` is `render --reference` (the full probe). `brdfkit view` starts from the
/// same, without the reference ([`crate::cli::view`]).
pub(super) fn scene_file(a: &SceneArgs, reference: bool) -> Result<(SceneFile, PathBuf)> {
    let (mut file, base) = match &a.scene {
        Some(p) => (
            SceneFile::load(p)?,
            p.parent().map(Path::to_path_buf).unwrap_or_default(),
        ),
        None => (SceneFile::default(), PathBuf::from(".")),
    };
    if let Some(w) = a.width {
        file.render.width = check_side("--width", w)?;
    }
    if let Some(h) = a.height {
        file.render.height = check_side("--height", h)?;
    }
    if let Some(t) = a.threads {
        file.render.threads = t;
    }
    if let Some(t) = a.tile_size {
        file.render.tile_size = t;
    }
    if let Some(c) = a.cull {
        file.render.cull = match c {
            CullArg::None => Cull::None,
            CullArg::Back => Cull::Back,
        };
    }
    if let Some(f) = a.drop_lights {
        if !(0.0..1.0).contains(&f) {
            return Err(Error::field(
                "--drop-lights",
                format!("{f} is out of range (0 <= fraction < 1)"),
            ));
        }
        file.render.drop_lights = f;
    }
    if a.no_band_skip {
        file.render.band_skip = false;
    }
    if let Some(k) = a.kernel {
        if crate::lanes::Dispatch::choose(k).is_none() {
            return Err(Error::field(
                "--kernel",
                format!("'{}' is not available on this CPU", k.name()),
            ));
        }
        file.render.kernel = k;
    }
    if let Some(e) = a.exposure {
        file.output.exposure = e;
    }
    if let Some(t) = a.tonemap {
        file.output.tonemap = t;
    }
    if let Some(m) = &a.mesh {
        // A mesh path given on the command line is relative to the working directory (made
        // absolute here, so the scene file's own relative paths keep their base: the
        // scene's directory).
        file.mesh.source = match m.as_str() {
            "teapot" | "sphere" => m.clone(),
            path => std::env::current_dir()
                .map(|d| d.join(path))
                .unwrap_or_else(|_| PathBuf::from(path))
                .to_string_lossy()
                .into_owned(),
        };
    }
    if let Some(p) = &a.env {
        // A probe given on the command line is relative to the working directory.
        let abs = std::env::current_dir()
            .map(|d| d.join(p))
            .unwrap_or_else(|_| p.clone());
        if std::fs::metadata(&abs).is_err_and(|e| e.kind() == std::io::ErrorKind::NotFound) {
            return Err(Error::field(
                "--env",
                format!("{}: no such file", p.display()),
            ));
        }
        file.env = Some(EnvSpec::new(abs));
    }
    if a.sampler.is_some() || a.lights.is_some() {
        let Some(env) = file.env.as_mut() else {
            return Err(Error::field(
                "--sampler/--lights",
                "need an environment: give --env PROBE or an [env] table",
            ));
        };
        // Sampling asked for on the command line replaces a light set file
        // (`[env] lights`): the probe is sampled (and must be named).
        env.lights = None;
        if let Some(s) = a.sampler {
            env.sampler = s;
        }
        if let Some(n) = a.lights {
            env.count = n;
        }
        // Asking for a sampler or a light count asks for a delta light set.
        if env.method == EnvMethod::Auto {
            env.method = EnvMethod::Lights;
        }
        if a.lights.is_some() && (reference || env.sampler == crate::env::schema::SamplerKind::Full)
        {
            eprintln!(
                "warning: --lights is ignored with the full probe (--sampler full or --reference): every texel is a light"
            );
        }
    }
    if let Some(m) = a.env_method {
        let Some(env) = file.env.as_mut() else {
            return Err(Error::field(
                "--env-method",
                "needs an environment: the scene has no [env] table; give --env PROBE or add one",
            ));
        };
        env.method = m;
    }
    if reference {
        if let Some(env) = file.env.as_mut() {
            env.use_full_probe();
        }
    }
    if let Some(m) = &a.material {
        file.material = crate::scene::MaterialSpec::from_cli(m)?;
    }
    if let Some(l) = a.lookup {
        set_lookup(&mut file.material, l)?;
    }
    Ok((file, base))
}

/// Sets `--lookup` on an SH material (library SH material or SH file), overriding the scene's
/// `material.lookup` and the file's recorded lookup; a field error naming `--lookup` for any
/// other material.
fn set_lookup(material: &mut MaterialSpec, mode: Lookup) -> Result<()> {
    let not_sh = |what: &str| {
        Error::field(
            "--lookup",
            format!("the material is {what}, not an SH data set; only SH materials have a coefficient lookup"),
        )
    };
    match material {
        MaterialSpec::Library { name, lookup } => match crate::library::find(name) {
            Some(m) if matches!(m.representation, Representation::Dbrdf) => {
                Err(not_sh(&format!("the D-BRDF library material {name:?}")))
            }
            // An unknown name is reported (naming material.name) when the scene resolves.
            _ => {
                *lookup = Some(mode);
                Ok(())
            }
        },
        MaterialSpec::ShFile { lookup, .. } => {
            *lookup = Some(mode);
            Ok(())
        }
        MaterialSpec::DbrdfFile { path } => {
            Err(not_sh(&format!("the D-BRDF file {}", path.display())))
        }
        MaterialSpec::MerlFile { path } => {
            Err(not_sh(&format!("the MERL table {}", path.display())))
        }
        MaterialSpec::RglFile { path } => {
            Err(not_sh(&format!("the RGL material {}", path.display())))
        }
        MaterialSpec::Lambert { .. } => Err(not_sh("analytic (lambert)")),
        MaterialSpec::BlinnPhong { .. } => Err(not_sh("analytic (blinn-phong)")),
    }
}
