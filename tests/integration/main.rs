//! The integration tests: one binary, one module per concern (the tiny-skia layout), so the
//! crate is linked once for all of them and the shared helpers ([`common`], the closed-form
//! scenes, the shading paths) are compiled once.
//!
//! Three kinds of test stay in binaries of their own, because they need a process of their
//! own: tests/hostile.rs (a counting global allocator: every allocation of the process is
//! counted, so no other test may run beside it), tests/viewer.rs (a window under Xvfb, one
//! server at a time) and tests/gpu/ (the wgpu build, behind the `gpu` feature).

#[path = "../common/mod.rs"]
mod common;

mod closed_form_common;
mod env_table_common;
mod frame_common;
mod shading_paths;

mod acquire;
mod anisotropic_frame;
mod architecture;
mod cache_command;
mod cli_errors;
mod cli_paths;
mod closed_form_delta;
mod closed_form_env;
mod closed_form_sh;
mod compare;
mod compare_report;
mod determinism;
mod device;
mod docs_examples;
mod docs_paths;
mod env_scene;
mod exact_sphere;
mod export;
mod file_formats;
mod frame_context;
mod frame_invariance;
mod golden;
mod golden_cameras;
mod golden_list;
mod golden_shards;
mod help_text;
mod interrupt;
mod kernel;
mod kernel_mutation;
mod library_radiance;
mod lightcuts_scene;
mod lightset_scene;
mod lookup;
mod material_files;
mod messages;
mod no_hidden_state;
mod output_checks;
mod peer;
mod peer_rgl;
mod perturbation;
mod raster_blocks;
mod reflection_scene;
mod render_options;
mod render_shards;
mod rgl_files;
mod robustness;
mod sh_basis;
mod shading_frame;
mod skips;
mod stability;
mod suspicious_input;
mod sweep;
mod sweep_check;
mod transfer_scene;
mod turntable_env;
mod usage_errors;
mod watertight;
