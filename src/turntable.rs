//! Turntables (`brdfkit render --turntable N`), as the thesis's animated sequences: N frames
//! of one full turn, written as numbered PNGs and assembled into an animated GIF.
//!
//! Frame `k` of `N` is turned by `2 pi k / N` radians about world up (+y, see
//! [`crate::conventions`]), right-handed (counter-clockwise seen from above, +z towards +x):
//! - [`Motion::Camera`]: the camera position orbits its look-at target
//!   (`target + rotate_about_up(position - target, angle)`), up and field of view kept, so
//!   the object appears to turn clockwise;
//! - [`Motion::Environment`]: the camera stays and the environment turns: frame `k` is the
//!   scene whose `[env] rotation` is `360 k / N` degrees more
//!   ([`Scene::with_environment_turned`]: the environment is built again from the probe at
//!   that rotation, for every method, so frame `k` has the bits of a static render of the
//!   scene file stating that rotation; light sets and transfer tables come from the cache
//!   when it holds them). The scene's own `[[light]]`s stay fixed. An environment not
//!   made from a probe (a light set file, a `[transfer] table` file) is turned rigidly
//!   ([`crate::scene::Environment::turned_rigidly`]).
//!
//! Files: from the output path `DIR/OUT.png`, frame `k` is `DIR/OUT_kkkk.png` (4 digits,
//! more when `N > 10000`) and the GIF is `DIR/OUT.gif`. The GIF is always built from the
//! PNG files on disk ([`assemble_gif`]), so a single run and shards followed by
//! `--assemble` give the same bytes. Shards ([`crate::shard`]) write frames `k` with
//! `k % N_shards == I`; each frame depends only on `k`, so shard frames are bit-identical
//! to a single run's.

use crate::conventions::rotate_about_up;
use crate::env::lightset::prepare::CacheDir;
use crate::error::{Error, Result};
use crate::scene::Scene;
use std::path::{Path, PathBuf};

/// Largest number of frames.
pub const MAX_FRAMES: usize = 100_000;

/// What turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// The camera orbits the look-at point.
    Camera,
    /// The environment turns ([`frame_scene`], module doc); the camera stays.
    Environment,
}

/// Angle of frame `k` of `n`, radians: `2 pi k / n`.
pub fn frame_angle(k: usize, n: usize) -> f64 {
    std::f64::consts::TAU * k as f64 / n as f64
}

/// Angle of frame `k` of `n`, degrees: `360 k / n` (exact where that is an integer).
pub fn frame_degrees(k: usize, n: usize) -> f64 {
    360.0 * k as f64 / n as f64
}

/// The scene of frame `k` of `n` (module doc). [`Motion::Environment`] builds the
/// environment again at the frame's rotation, reading and writing light sets and transfer
/// tables in `cache`; errors are those of building it.
pub fn frame_scene(
    base: &Scene,
    motion: Motion,
    k: usize,
    n: usize,
    cache: &CacheDir,
) -> Result<Scene> {
    frame_scene_seeded(base, motion, k, n, cache, TurnFault::None)
}

/// A seeded fault of turning (tests only): what the turntable test must catch.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TurnFault {
    #[default]
    None,
    /// Every frame is the unturned scene: nothing turns.
    NothingTurns,
}

/// [`frame_scene`] with a seeded fault (tests only).
#[doc(hidden)]
pub fn frame_scene_seeded(
    base: &Scene,
    motion: Motion,
    k: usize,
    n: usize,
    cache: &CacheDir,
    fault: TurnFault,
) -> Result<Scene> {
    if fault == TurnFault::NothingTurns {
        return Ok(base.clone());
    }
    match motion {
        Motion::Camera => {
            let mut s = base.clone();
            let c = &mut s.camera;
            let rel = (c.position - c.target).as_dvec3();
            c.position = c.target + rotate_about_up(rel, frame_angle(k, n)).as_vec3();
            Ok(s)
        }
        Motion::Environment => base.with_environment_turned(frame_degrees(k, n), cache),
    }
}

/// Checks a turntable's frame count (1 to [`MAX_FRAMES`]).
pub fn check_frames(n: usize) -> Result<()> {
    if n == 0 || n > MAX_FRAMES {
        return Err(Error::field(
            "--turntable",
            format!("{n} frames is out of range (1 to {MAX_FRAMES})"),
        ));
    }
    Ok(())
}

fn stem(out: &Path) -> String {
    out.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into())
}

/// Path of frame `k` of `n` for the output path `out` (`OUT_0007.png`).
pub fn frame_path(out: &Path, k: usize, n: usize) -> PathBuf {
    let digits = (n.saturating_sub(1)).to_string().len().max(4);
    out.with_file_name(format!("{}_{k:0digits$}.png", stem(out)))
}

/// Path of the GIF for the output path `out` (`OUT.gif`).
pub fn gif_path(out: &Path) -> PathBuf {
    out.with_file_name(format!("{}.gif", stem(out)))
}

/// Builds the animated GIF (looping forever, `fps` frames per second; GIF delays are in
/// 1/100 s, so the rate is rounded to that) from the `n` frame PNGs of `out`. Errors name a
/// missing or unreadable frame, or frames of different sizes. Returns the GIF's path.
pub fn assemble_gif(out: &Path, n: usize, fps: u32) -> Result<PathBuf> {
    use image::codecs::gif::{GifEncoder, Repeat};
    use image::{Delay, Frame};
    if fps == 0 || fps > 100 {
        return Err(Error::field(
            "--fps",
            format!("{fps} is out of range (1 to 100)"),
        ));
    }
    let gif = gif_path(out);
    let mut frames = Vec::with_capacity(n);
    let mut size = None;
    for k in 0..n {
        let p = frame_path(out, k, n);
        if !p.is_file() {
            return Err(Error::format(
                &p,
                format!("frame {k} of {n} is missing (render every shard before --assemble)"),
            ));
        }
        let img = image::open(&p)
            .map_err(|e| Error::format(&p, format!("cannot read frame: {e}")))?
            .to_rgba8();
        let dims = img.dimensions();
        if *size.get_or_insert(dims) != dims {
            return Err(Error::format(
                &p,
                format!(
                    "frame is {}x{}, frame 0 is {}x{}",
                    dims.0,
                    dims.1,
                    size.unwrap().0,
                    size.unwrap().1
                ),
            ));
        }
        let delay = Delay::from_numer_denom_ms(1000, fps);
        frames.push(Frame::from_parts(img, 0, 0, delay));
    }
    crate::image_io::write_atomically(&gif, |tmp| {
        let err = |e: image::ImageError| Error::format(&gif, format!("cannot write GIF: {e}"));
        let file =
            std::fs::File::create(tmp).map_err(|e| Error::io(&gif, "cannot write GIF", e))?;
        let mut enc = GifEncoder::new_with_speed(std::io::BufWriter::new(file), 10);
        enc.set_repeat(Repeat::Infinite).map_err(err)?;
        enc.encode_frames(frames).map_err(err)?;
        Ok(())
    })?;
    Ok(gif)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths() {
        let out = Path::new("dir/spin.png");
        assert_eq!(frame_path(out, 7, 60), Path::new("dir/spin_0007.png"));
        assert_eq!(frame_path(out, 7, 20001), Path::new("dir/spin_00007.png"));
        assert_eq!(gif_path(out), Path::new("dir/spin.gif"));
    }

    #[test]
    fn camera_orbit_keeps_distance_and_height() {
        let base = Scene::default_scene();
        for k in 0..8 {
            let s = frame_scene(&base, Motion::Camera, k, 8, &CacheDir::None).unwrap();
            let (a, b) = (
                base.camera.position - base.camera.target,
                s.camera.position - s.camera.target,
            );
            assert!((a.length() - b.length()).abs() < 1e-4);
            assert!((a.y - b.y).abs() < 1e-5);
            assert_eq!(s.camera.target, base.camera.target);
        }
        // A quarter turn takes +z towards +x.
        let mut b = base.clone();
        b.camera.target = glam::Vec3::ZERO;
        b.camera.position = glam::Vec3::Z;
        let s = frame_scene(&b, Motion::Camera, 1, 4, &CacheDir::None).unwrap();
        assert!((s.camera.position - glam::Vec3::X).length() < 1e-6);
        let s0 = frame_scene(&b, Motion::Camera, 0, 4, &CacheDir::None).unwrap();
        assert_eq!(s0.camera, b.camera);
    }
}
