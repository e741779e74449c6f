//! Spherical-harmonic (SH) representation of acquired BRDF data (thesis 2.3.3-2.3.4,
//! 3.1.3-3.1.5).
//!
//! Design rule: the SH basis is defined once, in [`basis`], in the *local shading frame*
//! (polar angle from local +z = the normal); tables, files and projections call it and
//! never restate the convention.

pub mod basis;
pub mod dataset;
pub mod file;
pub mod quadrature;

pub use basis::{eval_sh_f32, eval_sh_f64, num_terms, sh_index, sh_lm};
pub use dataset::{Lookup, ShBasisTable, ShDataError, ShDataset, MAX_BANDS};
pub use file::{read_sh_dataset, write_sh_dataset, ShFileError};
