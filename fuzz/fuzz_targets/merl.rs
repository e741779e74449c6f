#![no_main]
//! MERL `.binary` parser: any bytes give a value or an error, never a panic.
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = brdfkit::brdf::MerlBrdf::from_bytes(data, std::path::Path::new("fuzz.binary"), "fuzz");
});
