//! Scenes: the TOML scene file, its defaults, and its resolution into renderable parts.
//!
//! Design rule: every field has a default, so an empty file (or no file) is the default
//! scene; unknown fields are errors; every value is checked here, once, with an error
//! that names the file and the field. Later stages trust what a [`Scene`] holds.
//!
//! Layout, one concept per file (private; every public name is re-exported here, so each
//! has the one path `scene::X`): `file.rs`, the schema of the file as written and reading
//! it ([`SceneFile`], [`RenderSpec`], [`LightSpec`], ...); `material.rs`, the material's
//! spec, what a `--material` value names, and building the material
//! ([`MaterialSpec`]); `resolve.rs`, checking every value and loading the parts into a
//! [`Scene`] ([`Scene::resolve`]); `camera.rs`, the camera ([`camera::Camera`]);
//! `env_method.rs`, the method `[env] method = "auto"` stands for ([`env_method`]);
//! `env_table.rs`, the `[env]` table as written ([`method_fields`]);
//! `environment.rs`, the environment as one closed type and the one function that builds
//! it ([`Environment`], [`build_environment`]).
//!
//! The format, every field with its default and examples, is `docs/scene-format.md`,
//! included below as the one description (the README and `brdfkit render --help` point to it;
//! `tests/integration/docs_examples.rs` loads its examples).
//!
#![doc = include_str!("../../docs/scene-format.md")]

pub mod camera;
pub mod env_method;
mod env_table;
mod environment;
mod fields;
mod file;
mod material;
mod resolve;

pub use env_table::method_fields;
pub use environment::EnvSummary;
pub use environment::{build_environment, Environment, ProbeSource};
pub use file::{
    default_lights, CameraSpec, LightSpec, MeshSpec, OutputSpec, Precision, RenderSpec, SceneFile,
    TransferFileSpec, MAX_SCENE_BYTES,
};
pub use material::MaterialSpec;
pub use resolve::{load_mesh, resolve_camera, Scene, MAX_SIDE};
