//! brdfkit: a CPU renderer and GPU oracle for acquired BRDF data (architecture doc: see below).

pub mod aov;
pub mod brdf;
pub mod cli;
pub mod conventions;
pub mod error;
pub mod golden;
pub mod image_io;
pub mod light;
pub mod mesh;
pub mod raster;
pub mod render;
pub mod scene;
pub mod shade;
