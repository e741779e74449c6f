//! The render threads: a scene file in, a displayed frame out, off the event-loop thread.
//!
//! Each worker takes the newest [`Job`] waiting (older ones are dropped unrendered),
//! resolves the scene file into a [`Scene`] (kept while only the camera, the frame size or
//! the environment's rotation change), renders it with [`crate::render::render_into`] — the
//! renderer of `brdfkit render`, into the worker's [`FrameContext`], whose buffers the
//! next job reuses — on its own thread pool, and encodes it for display with
//! the one display encoding [`crate::image_io::display`] (the PNG's).
//!
//! A *preview* job of a delta-light environment (no transfer table, no light cuts: those
//! are resolved again at the new rotation) may turn the kept scene's environment lights
//! rigidly, as `render --turntable-env` does, instead of preparing the light set of the
//! rotated probe again: that keeps a shift-drag fast. Its frame is marked not exact, and
//! the viewer asks for the exact one when the view is still.

use super::background::Background;
use crate::aov::Aov;
use crate::env::lightset::prepare::CacheDir;
use crate::image_io::display::display_u8;
use crate::image_io::Image;
use crate::render::{self, FrameContext, RenderOptions};
use crate::scene::{resolve_camera, Scene, SceneFile};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::Mutex;
use std::time::Instant;

/// One frame to render.
#[derive(Clone, Debug)]
pub struct Job {
    /// The view state's generation (it counts changes); replies carry it back.
    pub generation: u64,
    /// Refinement step ([`super::refine`]); 0 is the document itself.
    pub step: usize,
    /// What to render (the document, or a refinement step of it).
    pub file: SceneFile,
    pub aov: Option<Aov>,
    /// Whether turning the kept scene's lights rigidly may stand in for the rotated probe.
    pub preview: bool,
    /// Whether the refinement worker renders it (echoed in the reply).
    pub refine: bool,
    /// Show the probe behind the object ([`super::background`]; display only).
    pub background: bool,
}

/// A rendered frame.
pub struct Frame {
    pub generation: u64,
    pub step: usize,
    pub refine: bool,
    /// False when the environment was turned rigidly (a preview): not `render` of `file`.
    pub exact: bool,
    pub file: SceneFile,
    pub aov: Option<Aov>,
    /// The rendered image (linear radiance, or the AOV), as `render` writes it.
    pub image: Image,
    /// The image as displayed: 0x00RRGGBB per pixel, row 0 at the top.
    pub pixels: Vec<u32>,
    /// Time to resolve (when needed), render and encode, milliseconds.
    pub frame_ms: f64,
    /// Time in `render::render_into` alone, milliseconds.
    pub render_ms: f64,
    /// Lights shaded per pixel at most (explicit plus the environment's).
    pub lights: usize,
}

/// What a worker sends back.
pub enum Reply {
    Frame(Box<Frame>),
    Failed {
        generation: u64,
        refine: bool,
        message: String,
    },
}

/// Stack of the worker threads and their pools: the main thread's 8 MiB (resolving a
/// library material recurses deeper than rayon's default 2 MiB allows in a debug build).
const STACK_BYTES: usize = 8 << 20;

/// The scene kept between jobs, and what it was resolved from.
struct Kept {
    key: String,
    rotation: Option<f64>,
    scene: Scene,
}

/// The part of `file` that needs a new [`Scene`] when it changes: all but the camera, the
/// frame size and the environment's rotation.
fn scene_key(file: &SceneFile) -> String {
    let mut f = file.clone();
    f.camera = None;
    f.render.width = 1;
    f.render.height = 1;
    if let Some(e) = f.env.as_mut() {
        e.rotation = 0.0;
    }
    format!("{f:?}")
}

/// Starts a worker thread named `name` rendering on `threads` threads (0: one per core),
/// reading and writing light sets in `cache`; `deliver` hands a reply to the window and
/// returns false once the window is gone (the worker then ends).
pub fn spawn(
    name: &str,
    threads: usize,
    cache: CacheDir,
    deliver: impl Fn(Reply) -> bool + Send + 'static,
) -> Sender<Job> {
    let (tx, rx) = channel::<Job>();
    std::thread::Builder::new()
        .name(name.to_string())
        .stack_size(STACK_BYTES)
        .spawn(move || {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .stack_size(STACK_BYTES)
                .build()
                .expect("thread pool");
            let mut kept: Option<Kept> = None;
            let mut probe: Option<Background> = None;
            // The frame's buffers, kept from one job to the next.
            let mut frame = FrameContext::default();
            while let Some(job) = newest(&rx) {
                let reply = match pool
                    .install(|| run_job(&job, &cache, &mut kept, &mut probe, &mut frame))
                {
                    Ok(frame) => Reply::Frame(Box::new(frame)),
                    Err(message) => Reply::Failed {
                        generation: job.generation,
                        refine: job.refine,
                        message,
                    },
                };
                if !deliver(reply) {
                    break;
                }
            }
        })
        .expect("spawn a render thread");
    tx
}

/// Probes this run has warned about: every worker resolves the same probe again for each
/// rotation, material and refinement step, and the loader's warning is printed once per
/// probe per run.
static WARNED: Mutex<BTreeSet<PathBuf>> = Mutex::new(BTreeSet::new());

/// Prints the probe loader's warning ([`crate::env::LoadReport::negative_warning`]) for
/// `scene`'s environment the first time this run sees that probe. The viewer holds paths
/// absolute (`--env` joined to the working directory); the warning names the probe
/// relative to the working directory when it lies under it, so a relative `--env` reads
/// as typed.
fn warn_once(scene: &Scene) {
    let Some(env) = &scene.env else {
        return;
    };
    let Some(report) = env.probe_report.filter(|r| r.negative_texels > 0) else {
        return;
    };
    let first = WARNED
        .lock()
        .is_ok_and(|mut warned| warned.insert(env.file.clone()));
    if !first {
        return;
    }
    let shown = std::env::current_dir()
        .ok()
        .and_then(|d| env.file.strip_prefix(d).ok().map(Path::to_path_buf))
        .unwrap_or_else(|| env.file.clone());
    if let Some(w) = report.negative_warning(&shown.display().to_string()) {
        eprintln!("warning: {w}");
    }
}

/// The newest job waiting (blocking for one), or `None` when the window hung up.
fn newest(rx: &Receiver<Job>) -> Option<Job> {
    let mut job = rx.recv().ok()?;
    while let Ok(j) = rx.try_recv() {
        job = j;
    }
    Some(job)
}

/// Renders one job (module doc); the error is one line.
fn run_job(
    job: &Job,
    cache: &CacheDir,
    kept: &mut Option<Kept>,
    probe: &mut Option<Background>,
    frame: &mut FrameContext,
) -> std::result::Result<Frame, String> {
    let start = Instant::now();
    let key = scene_key(&job.file);
    let rotation = job.file.env.as_ref().map(|e| e.rotation);
    let reuse = kept.as_ref().is_some_and(|k| {
        k.key == key
            && (k.rotation == rotation || (job.preview && k.scene.environment.previews_rigidly()))
    });
    if !reuse {
        let scene = Scene::resolve_with_cache(&job.file, Path::new("."), cache)
            .map_err(|e| e.to_string())?;
        warn_once(&scene);
        *kept = Some(Kept {
            key,
            rotation,
            scene,
        });
    }
    let k = kept.as_ref().expect("kept above");
    let mut scene = k.scene.clone();
    let exact = k.rotation == rotation;
    if !exact {
        // Turn the environment rigidly (a preview: `Environment::previews_rigidly`).
        let turn = (rotation.unwrap_or(0.0) - k.rotation.unwrap_or(0.0)).to_radians();
        scene.environment = scene
            .environment
            .turned_rigidly(turn)
            .ok_or("a preview turns a light set only")?;
    }
    let r = &job.file.render;
    scene.render.width = r.width;
    scene.render.height = r.height;
    let aspect = r.width as f32 / r.height as f32;
    scene.camera = resolve_camera(
        &job.file.camera.clone().unwrap_or_default(),
        &scene.mesh,
        aspect,
    )
    .map_err(|e| e.to_string())?;
    let opts = RenderOptions {
        aov: job.aov,
        ..RenderOptions::default()
    };
    let t = Instant::now();
    render::render_into(&scene, &opts, frame);
    let render_ms = t.elapsed().as_secs_f64() * 1e3;
    let mut pixels = display_pixels(frame.image(), job.aov, &job.file);
    if let (true, None, Some(env)) = (job.background, job.aov, &job.file.env) {
        Background::of(probe, env)?.paint(
            frame.vis(),
            env.intensity,
            &job.file.output,
            &mut pixels,
        );
    }
    // The image goes to the window with the frame; the next job's is a new one.
    let image = frame.take_image();
    Ok(Frame {
        generation: job.generation,
        step: job.step,
        refine: job.refine,
        exact,
        file: job.file.clone(),
        aov: job.aov,
        image,
        pixels,
        frame_ms: start.elapsed().as_secs_f64() * 1e3,
        render_ms,
        lights: scene.delta_lights().len(),
    })
}

/// The image as displayed (0x00RRGGBB): the PNG's encoding, exposure and tone map for the
/// shaded image, the AOV's PNG encoding for an AOV.
pub fn display_pixels(img: &Image, aov: Option<Aov>, file: &SceneFile) -> Vec<u32> {
    let pack = |r: u8, g: u8, b: u8| (r as u32) << 16 | (g as u32) << 8 | b as u32;
    match aov {
        Some(a) => crate::aov::png_bytes(img, a)
            .chunks_exact(3)
            .map(|c| pack(c[0], c[1], c[2]))
            .collect(),
        None => {
            use rayon::prelude::*;
            let (e, t) = (file.output.exposure, file.output.tonemap);
            img.pixels
                .par_iter()
                .map(|p| {
                    pack(
                        display_u8(p.x, e, t),
                        display_u8(p.y, e, t),
                        display_u8(p.z, e, t),
                    )
                })
                .collect()
        }
    }
}
