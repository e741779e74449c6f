#![no_main]
//! Light-set JSON reader.
use libfuzzer_sys::fuzz_target;
#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let p = common::scratch("json", data);
    let _ = brdfkit::env::lightset::file::read_json(&p);
});
