//! brdfkit: a CPU renderer and GPU oracle for acquired BRDF data (architecture doc: see below).

pub mod brdf;
pub mod conventions;
pub mod env;
