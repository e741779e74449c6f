#![no_main]
//! Light-probe loader: the first byte picks the decoder (.exr or .hdr), the rest is the file.
use libfuzzer_sys::fuzz_target;
#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let Some((&sel, rest)) = data.split_first() else {
        return;
    };
    let p = common::scratch(if sel & 1 == 0 { "exr" } else { "hdr" }, rest);
    let _ = brdfkit::env::Probe::load(&p, &brdfkit::env::LoadOptions::default());
});
