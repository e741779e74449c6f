#![no_main]
//! Scene TOML: parse, then resolve against an empty directory (OBJ and probe paths in the
//! input fail to load unless they name existing files). No cache is written.
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // Device files (e.g. /dev/zero as a mesh or probe) would only measure the OS.
    if text.contains("/dev") || text.contains("/proc") || text.contains("/sys") {
        return;
    }
    // `Scene::resolve` reads and writes no cache (only `resolve_with_cache` does).
    if let Ok(file) = brdfkit::scene::SceneFile::parse(text) {
        let dir = std::env::temp_dir().join("brdfkit-fuzz-empty");
        let _ = std::fs::create_dir_all(&dir);
        let _ = brdfkit::scene::Scene::resolve(&file, &dir);
    }
});
