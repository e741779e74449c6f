//! `brdfkit render --turntable N`: the frames of an orbit (or, with `--turntable-env`,
//! the environment turning: [`crate::turntable`]),
//! sharded over machines with `--shard`, assembled into a GIF.

use super::RenderArgs;
use crate::aov;
use crate::env::lightset::prepare::CacheDir;
use crate::error::{Error, Result};
use crate::image_io::{self, Format};
use crate::progress::Progress;
use crate::render;
use crate::scene::Scene;
use crate::shard::Shard;
use crate::turntable::{self, Motion};
use std::path::PathBuf;

/// The turntable's output path: `-o` (or the scene's output path), default `out.png`; PNG only.
pub(super) fn turntable_output(out: Option<PathBuf>) -> Result<PathBuf> {
    let out = out.unwrap_or_else(|| PathBuf::from("out.png"));
    match image_io::format_of(&out)? {
        Format::Png => Ok(out),
        Format::Exr => Err(Error::field(
            "--output",
            format!(
                "{}: --turntable writes PNG frames and a GIF; give a .png path",
                out.display()
            ),
        )),
    }
}

/// `render --turntable N`: the frames of this shard (all without `--shard`), then the GIF
/// when every frame was rendered here.
pub(super) fn run_turntable(
    a: &RenderArgs,
    scene: &Scene,
    n: usize,
    out: Option<PathBuf>,
    cache: &CacheDir,
) -> Result<()> {
    let out = turntable_output(out)?;
    let shard = match &a.shard {
        Some(s) => Shard::parse(s)?,
        None => Shard::ALL,
    };
    let motion = if a.turntable_env {
        if scene.environment.method().is_none() {
            return Err(Error::field(
                "--turntable-env",
                "needs an environment: give --env PROBE or an [env] table",
            ));
        }
        Motion::Environment
    } else {
        Motion::Camera
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(scene.render.threads)
        .build()
        .expect("thread pool");
    let opts = render::RenderOptions {
        aov: a.common.aov,
        ..if a.reference && a.common.aov.is_none() {
            render::RenderOptions::converged_reference()
        } else {
            render::RenderOptions::default()
        }
    };
    let frames: Vec<usize> = (0..n).filter(|&k| shard.contains(k)).collect();
    let pb = Progress::bar(frames.len() as u64, "turntable", "frames");
    let start = std::time::Instant::now();
    // Every frame has the size of the first: its buffers are reused.
    let mut frame = render::FrameContext::default();
    for &k in &frames {
        let s = turntable::frame_scene(scene, motion, k, n, cache)?;
        let img = pool
            .install(|| render::render_into(&s, &opts, &mut frame))
            .image;
        let path = turntable::frame_path(&out, k, n);
        match a.common.aov {
            None => image_io::write_png(&path, img, s.output.exposure, s.output.tonemap)?,
            Some(aov) => {
                image_io::write_png_bytes(&path, img.width, img.height, aov::png_bytes(img, aov))?
            }
        }
        pb.inc(1);
    }
    pb.finish();
    eprintln!(
        "wrote {} frames ({} ... ) in {:.1} s",
        frames.len(),
        frames
            .first()
            .map(|&k| turntable::frame_path(&out, k, n).display().to_string())
            .unwrap_or_default(),
        start.elapsed().as_secs_f64()
    );
    if shard.is_all() {
        let gif = turntable::assemble_gif(&out, n, a.fps)?;
        eprintln!("wrote {} ({n} frames)", gif.display());
    } else {
        eprintln!("shard {shard}: no GIF; after every shard, run the same command with --assemble");
    }
    Ok(())
}
