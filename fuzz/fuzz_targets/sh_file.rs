#![no_main]
//! SH data-set reader (multi-part EXR).
use libfuzzer_sys::fuzz_target;
#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let p = common::scratch("exr", data);
    let _ = brdfkit::sh::read_sh_dataset(&p);
});
