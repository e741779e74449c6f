//! The GPU build's tests (cargo feature `gpu`, docs/gpu.md): one binary, run on a Vulkan
//! adapter (lavapipe in CI). [`golden`] holds the wgpu renderer to the CPU oracle's golden
//! set and shows each seeded fault failing; [`closed_form`] checks it against a closed form;
//! [`auto_method`] checks what `[env] method = "auto"` renders on the GPU; [`reflection`]
//! that the reflection method's filtered path is refused there.

#[path = "../common/mod.rs"]
mod common;

mod auto_method;
mod closed_form;
mod golden;
mod reflection;
