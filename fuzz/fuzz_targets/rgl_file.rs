#![no_main]
//! RGL `.bsdf` tensor file parser: any bytes give a value or an error, never a panic, and no
//! allocation larger than a small multiple of the input.
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = brdfkit::brdf::RglBrdf::from_bytes(data, std::path::Path::new("fuzz.bsdf"));
});
