#![no_main]
//! Light-set CSV reader.
use libfuzzer_sys::fuzz_target;
#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let p = common::scratch("csv", data);
    let _ = brdfkit::env::lightset::file::read_csv(&p);
});
