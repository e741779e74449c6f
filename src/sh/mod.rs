//! Spherical-harmonic (SH) representation of acquired BRDF data (thesis 2.3.3-2.3.4,
//! 3.1.3-3.1.5).
//!
//! Design rule: the SH basis is defined once, in [`basis`], in the *local shading frame*
//! (polar angle from local +z = the normal); tables, files and projections call it and
//! never restate the convention.
//!
//! # Layout
//! - [`basis`] -- the real SH basis `Y_lm` (f32 and f64), its indexing and convention;
//! - [`quadrature`] -- quadrature for projecting onto the basis;
//! - [`rotate`] -- coefficients turned about the normal between two shading frames;
//! - [`dataset`] -- the data set [`ShDataset`] (one file per concern: coefficient lookups,
//!   evaluation and the [`Brdf`](crate::brdf::Brdf) impl, the optional basis table, the
//!   band skip policy);
//! - [`mod@file`] -- the self-describing OpenEXR file format (format doc, writer, reader); its
//!   bytes are read through the crate's one guarded EXR reader,
//!   [`crate::image_io::exr_guard`].

pub mod basis;
pub mod dataset;
pub mod file;
pub mod quadrature;
pub mod rotate;

pub use basis::{eval_sh_f32, eval_sh_f64, num_terms, sh_index, sh_lm, ShLanes, SH_LANES};
pub use dataset::{Lookup, ShBasisTable, ShDataError, ShDataset, MAX_BANDS};
pub use file::{read_sh_dataset, write_sh_dataset, ShFileError};
pub use rotate::rotate_about_z;
