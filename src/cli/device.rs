//! `brdfkit render --device auto|cpu|gpu`: which renderer draws a single frame.
//!
//! `cpu` (the default) is the oracle itself. `gpu` is the wgpu renderer (`crate::gpu`,
//! cargo feature `gpu`): without the feature, without an adapter, or for what it does not
//! render (the `coverage` debug output, `--reference`, `--turntable`, a material or environment method
//! `crate::gpu::unsupported` names) it is a one-line error. `auto` takes the GPU when it
//! can and otherwise says in one line why it renders on the CPU.
//!
//! The environment method is chosen before the device is opened: under `[env] method =
//! "auto"`, `render --device gpu` asks [`crate::scene::env_method::choose`] for a method the
//! GPU runs (never light cuts), so `gpu` refuses light cuts only when the scene states
//! them. `--device auto` keeps the CPU's choice, and falls back to the CPU when that is
//! light cuts. A stated `method = "reflection"` runs on the GPU for isotropic materials;
//! for an anisotropic D-BRDF (filtered importance sampling) `gpu` refuses it once the term
//! is prepared.

use crate::aov::Aov;
use crate::error::{Error, Result};
use crate::image_io::Image;
use crate::scene::Scene;

/// The `--device` values.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Device {
    /// The GPU when there is an adapter (and the build has the `gpu` feature), else the CPU.
    Auto,
    /// The CPU renderer (the oracle).
    #[default]
    Cpu,
    /// The wgpu renderer; an error when there is no adapter or no `gpu` feature.
    Gpu,
}

/// An open GPU for one render (uninhabited without the `gpu` feature).
#[cfg(feature = "gpu")]
pub struct OpenGpu(crate::gpu::Gpu);
/// An open GPU for one render (uninhabited without the `gpu` feature).
#[cfg(not(feature = "gpu"))]
pub enum OpenGpu {}

/// What the frame needs beyond the scene: a debug output, the converged reference, a
/// turntable (the GPU renders single beauty frames only).
pub struct Request {
    pub aov: Option<Aov>,
    pub reference: bool,
    pub turntable: bool,
}

/// Why the GPU renderer cannot draw this request, if it cannot.
fn refused(scene: &Scene, r: &Request) -> Option<String> {
    if r.reference {
        return Some("--reference renders on the CPU (the f64 path)".into());
    }
    if r.turntable {
        return Some("--turntable renders on the CPU".into());
    }
    #[cfg(feature = "gpu")]
    {
        crate::gpu::unsupported(scene, r.aov)
    }
    #[cfg(not(feature = "gpu"))]
    {
        let _ = (scene, r.aov);
        Some("this brdfkit was built without the `gpu` feature (cargo build --features gpu)".into())
    }
}

/// Opens the GPU `device` asks for, or `None` for the CPU (with one line on stderr when
/// `auto` falls back). Error: `gpu` that cannot be had, one line.
pub fn open(device: Device, scene: &Scene, r: &Request) -> Result<Option<OpenGpu>> {
    if device == Device::Cpu {
        return Ok(None);
    }
    if let Some(why) = refused(scene, r) {
        if device == Device::Gpu {
            return Err(Error::Message(format!("--device gpu: {why}")));
        }
        eprintln!("device: cpu ({why})");
        return Ok(None);
    }
    #[cfg(feature = "gpu")]
    {
        match crate::gpu::Gpu::new() {
            Ok(g) => {
                eprintln!("device: gpu ({}, {:?})", g.info.name, g.info.backend);
                Ok(Some(OpenGpu(g)))
            }
            Err(e) if device == Device::Gpu => Err(e),
            Err(e) => {
                eprintln!(
                    "device: cpu ({})",
                    e.to_string().trim_start_matches("--device gpu: ")
                );
                Ok(None)
            }
        }
    }
    #[cfg(not(feature = "gpu"))]
    unreachable!("refused without the gpu feature")
}

/// Renders `scene`'s beauty image, or the debug output `aov`, on the open GPU.
pub fn render(gpu: &OpenGpu, scene: &Scene, aov: Option<Aov>) -> Result<Image> {
    #[cfg(feature = "gpu")]
    {
        gpu.0.render_aov(scene, aov, crate::gpu::Faults::NONE)
    }
    #[cfg(not(feature = "gpu"))]
    {
        let _ = (scene, aov);
        match *gpu {}
    }
}
