#![no_main]
//! D-BRDF table reader (`brdf::dbrdf::file::read_dbrdf`, a single-part EXR): any bytes give
//! a table or an error, never a panic, and never an allocation the file's length does not
//! justify (run with `-malloc_limit_mb`).
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let p = common::scratch("exr", data);
    let _ = brdfkit::brdf::dbrdf::file::read_dbrdf(&p);
});
