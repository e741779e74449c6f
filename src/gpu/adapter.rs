//! The adapter and device: the first adapter wgpu offers (any backend built in, high
//! performance preferred), opened with the adapter's own limits, which [`Gpu::limits`]
//! then reports to every check (`upload.rs`). Nothing here assumes lavapipe's numbers.

use crate::error::{Error, Result};

/// An open device and what its adapter is and allows.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// The adapter's name, driver and backend (for messages and reports).
    pub info: wgpu::AdapterInfo,
    /// The limits the device was opened with: the adapter's own.
    pub limits: wgpu::Limits,
}

fn instance() -> wgpu::Instance {
    wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env())
}

fn request_adapter(instance: &wgpu::Instance) -> Option<wgpu::Adapter> {
    pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
        ..Default::default()
    }))
    .ok()
}

/// The name and backend of the adapter [`Gpu::new`] would open ("llvmpipe (LLVM 15.0.6,
/// 256 bits), Vulkan"), or `None` when there is none.
pub fn adapter_name() -> Option<String> {
    let adapter = request_adapter(&instance())?;
    let info = adapter.get_info();
    Some(format!("{}, {:?}", info.name, info.backend))
}

impl Gpu {
    /// Opens the first adapter with its own limits. Error: no adapter, or the device could
    /// not be opened (one line).
    pub fn new() -> Result<Gpu> {
        let instance = instance();
        let adapter = request_adapter(&instance).ok_or_else(|| {
            Error::Message(
                "--device gpu: no GPU adapter found (no Vulkan driver? on Debian: apt-get \
                 install mesa-vulkan-drivers libvulkan1)"
                    .into(),
            )
        })?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("brdfkit"),
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| Error::Message(format!("--device gpu: cannot open '{}': {e}", info.name)))?;
        Ok(Gpu {
            device,
            queue,
            info,
            limits,
        })
    }

    /// A limit error: the scene needs `needed` of the limit `name`, the adapter allows
    /// `allowed`.
    pub(super) fn over_limit(&self, what: &str, name: &str, needed: u64, allowed: u64) -> Error {
        Error::Message(format!(
            "--device gpu: {what} needs {needed} but adapter '{}' allows {allowed} ({name})",
            self.info.name
        ))
    }
}
