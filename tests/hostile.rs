//! Hostile input for every parser brdfkit owns: empty files, truncations of valid files,
//! wrong magic, wrong dimensions, absurd declared sizes and NaN fields. Each must give one
//! clear error naming the file, never a panic, and must not allocate more than the file's
//! size justifies.
//!
//! (Past 400 lines because it is one concept, the hostile-input suite: every parser's bad
//! files share the counting allocator, the deadline and the one-error-line check defined
//! here, and a parser added to brdfkit gets its list of bad files beside the others.)
//!
//! Allocation is measured two ways:
//! - in this process, by a counting global allocator that records the largest single
//!   allocation request made while a parser runs ([`measure`]); the bound is
//!   [`ALLOC_PER_BYTE`] x file size + [`ALLOC_CONST`];
//! - through the `brdfkit` binary, run under `prlimit --as` ([`CLI_AS_LIMIT`]): an
//!   allocation beyond it aborts the child, which the exit-code check catches.
//!
//! The counting allocator also shows that a frame rendered into a frame context kept from
//! the previous frame allocates no frame buffer ([`a_steady_state_frame_allocates_no_frame_buffer`]).
//!
//! Special files (directories, `/dev/zero`, FIFOs) are refused by every reader before it
//! opens them ([`special_files_are_refused_by_every_reader`]); a hang is a failure, never a
//! stuck run: library calls run on a thread with a deadline ([`no_hang`]) and the binary
//! under `timeout -s KILL` ([`CLI_TIMEOUT_S`]).

mod common;
use brdfkit::brdf::merl::{MerlBrdf, MERL_FILE_SIZE};
use brdfkit::brdf::Lambert;
use brdfkit::env::lightset::file::{read_csv, read_json, write_csv, write_json, LightSetHeader};
use brdfkit::env::{LightSet, LoadOptions, Probe, SamplerConfig};
use brdfkit::scene::{Scene, SceneFile};
use brdfkit::sh::{read_sh_dataset, write_sh_dataset, ShDataset};
use glam::Vec3;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, OnceLock};

// ---------------------------------------------------------------------------------------
// Counting allocator

/// Forwards to [`System`] and, while [`ARMED`] is set, records the largest single request.
struct Counting;

static ARMED: AtomicBool = AtomicBool::new(false);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every method forwards its arguments unchanged to `System`, which upholds the
// `GlobalAlloc` contract; the only addition is bookkeeping on atomics, which neither
// allocates nor touches the returned memory.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: same layout the caller gave us (see the impl's comment).
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: as above.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was returned by `System` for this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note(new_size);
        // SAFETY: `ptr` was returned by `System` for `layout`; `new_size` as requested.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

fn note(size: usize) {
    if ARMED.load(Ordering::Relaxed) {
        PEAK.fetch_max(size, Ordering::Relaxed);
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Tests that allocate much, or measure, hold this lock so that no other test's
/// allocations are counted.
fn serial() -> MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    LOCK.lock().unwrap_or_else(|e| e.into_inner())
}

/// Runs `f` and returns its result with the largest allocation request it made (bytes).
fn measure<T>(_guard: &MutexGuard<'static, ()>, f: impl FnOnce() -> T) -> (T, usize) {
    PEAK.store(0, Ordering::SeqCst);
    ARMED.store(true, Ordering::SeqCst);
    let r = f();
    ARMED.store(false, Ordering::SeqCst);
    (r, PEAK.load(Ordering::SeqCst))
}

/// Largest allocation a parser may make per byte of input, beyond [`ALLOC_CONST`].
const ALLOC_PER_BYTE: usize = 16;
/// Allocation every parser may make whatever the input (the decoders' fixed slack).
const ALLOC_CONST: usize = 32 << 20;

/// Runs a parser on `path` (a hostile file of `len` bytes) and checks the outcome: an error
/// whose message is one line naming the file, and bounded allocation. `what` labels the case.
fn expect_err<T, E: std::fmt::Display>(
    guard: &MutexGuard<'static, ()>,
    what: &str,
    path: &Path,
    parse: impl FnOnce() -> Result<T, E>,
) -> String {
    let len = std::fs::metadata(path)
        .map(|m| m.len() as usize)
        .unwrap_or(0);
    let (r, peak) = measure(guard, parse);
    let msg = match r {
        Ok(_) => panic!("{what}: {} was accepted", path.display()),
        Err(e) => e.to_string(),
    };
    check_message(what, path, &msg);
    assert!(
        peak <= ALLOC_PER_BYTE * len + ALLOC_CONST,
        "{what}: largest allocation {peak} bytes for a {len}-byte file ({msg})"
    );
    msg
}

/// Like [`expect_err`] for inputs that may also be valid (a truncation at a line end):
/// either outcome is fine, but an error must be one line naming the file.
fn expect_err_or_ok<T, E: std::fmt::Display>(
    guard: &MutexGuard<'static, ()>,
    what: &str,
    path: &Path,
    parse: impl FnOnce() -> Result<T, E>,
) {
    let len = std::fs::metadata(path)
        .map(|m| m.len() as usize)
        .unwrap_or(0);
    let (r, peak) = measure(guard, parse);
    if let Err(e) = r {
        check_message(what, path, &e.to_string());
    }
    assert!(
        peak <= ALLOC_PER_BYTE * len + ALLOC_CONST,
        "{what}: largest allocation {peak} bytes for a {len}-byte file"
    );
}

fn check_message(what: &str, path: &Path, msg: &str) {
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(
        !msg.contains('\n'),
        "{what}: message is not one line: {msg:?}"
    );
    assert!(
        msg.contains(&*name),
        "{what}: message does not name {name}: {msg}"
    );
}

/// Offsets to cut a valid file of `len` bytes at: the first bytes, the header region,
/// the middle and the last byte.
fn cuts(len: usize) -> Vec<usize> {
    let mut v: Vec<usize> = [1, 4, 8, 11, 16, 40, 100, 300, len / 3, len / 2, len - 1]
        .into_iter()
        .filter(|&c| c < len)
        .collect();
    v.dedup();
    v
}

/// Finds `needle` in `hay` (the offset of its first byte).
fn find(hay: &[u8], needle: &[u8]) -> usize {
    hay.windows(needle.len())
        .position(|w| w == needle)
        .unwrap_or_else(|| panic!("{:?} not found", String::from_utf8_lossy(needle)))
}

/// Patches an EXR header's `dataWindow` (and `displayWindow`) to `w x h` pixels.
fn patch_exr_size(bytes: &mut [u8], w: i32, h: i32) {
    for name in [&b"dataWindow\0box2i\0"[..], &b"displayWindow\0box2i\0"[..]] {
        let at = find(bytes, name) + name.len() + 4;
        bytes[at + 8..at + 12].copy_from_slice(&(w - 1).to_le_bytes());
        bytes[at + 12..at + 16].copy_from_slice(&(h - 1).to_le_bytes());
    }
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// A small EXR light probe (16 x 8, RGB f32) with one texel set to `bad`.
fn probe_exr(bad: f32) -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("p.exr");
    exr::prelude::write_rgb_file(&p, 16, 8, |x, y| {
        if (x, y) == (3, 2) {
            (bad, 0.5, 0.5)
        } else {
            (0.25 + x as f32 * 0.01, 0.5, 0.75 - y as f32 * 0.01)
        }
    })
    .unwrap();
    std::fs::read(p).unwrap()
}

/// A small Radiance HDR light probe (8 x 4).
fn probe_hdr() -> Vec<u8> {
    let data: Vec<image::Rgb<f32>> = (0..32)
        .map(|i| image::Rgb([i as f32 * 0.1, 0.5, 1.0]))
        .collect();
    let mut out = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut out)
        .encode(&data, 8, 4)
        .unwrap();
    out
}

/// The bytes of a valid MERL file (a tabulated Lambert), built once.
fn merl_bytes() -> &'static [u8] {
    static B: OnceLock<Vec<u8>> = OnceLock::new();
    B.get_or_init(|| {
        MerlBrdf::tabulate(&Lambert {
            albedo: Vec3::new(0.5, 0.6, 0.7),
        })
        .to_bytes()
    })
}

fn small_lightset() -> LightSet {
    let t: Vec<[f32; 3]> = (0..32).map(|i| [i as f32 * 0.3, 0.5, 0.1]).collect();
    let (p, _) = Probe::from_texels("ls", 8, 4, t, &LoadOptions::default()).unwrap();
    SamplerConfig::MedianCut { n: 4 }.run(&p)
}

/// A small SH data set file (6 x 3 texels, 2 bands, with a basis table).
fn sh_file_bytes() -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("sh.exr");
    let nt = 4;
    let c: Vec<f32> = (0..6 * 3 * 3 * nt)
        .map(|i| (i as f32 * 0.37).sin())
        .collect();
    let mut ds = ShDataset::new(6, 3, 2, true, "hostile test", c).unwrap();
    ds.set_basis_table(Some(brdfkit::sh::ShBasisTable::tabulate(5, 4, 2).unwrap()))
        .unwrap();
    write_sh_dataset(&p, &ds).unwrap();
    std::fs::read(p).unwrap()
}

// ---------------------------------------------------------------------------------------
// Library API, one test per input kind

#[test]
fn merl_hostile_files() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = merl_bytes().to_vec();
    assert_eq!(good.len(), MERL_FILE_SIZE);
    let p = write(d, "empty.binary", b"");
    expect_err(&g, "MERL empty", &p, || MerlBrdf::read(&p));
    for cut in cuts(good.len()) {
        let p = write(d, "cut.binary", &good[..cut]);
        expect_err(&g, &format!("MERL cut at {cut}"), &p, || MerlBrdf::read(&p));
    }
    // wrong magic: the header's dimensions are the only magic MERL has
    let mut magic = good[..4096].to_vec();
    magic[..12].copy_from_slice(b"MERLBRDFDATA");
    let p = write(d, "magic.binary", &magic);
    expect_err(&g, "MERL magic", &p, || MerlBrdf::read(&p));
    // wrong dimensions, with the full length
    let mut dims = good.clone();
    dims[4..8].copy_from_slice(&45i32.to_le_bytes());
    let p = write(d, "dims.binary", &dims);
    let m = expect_err(&g, "MERL dims", &p, || MerlBrdf::read(&p));
    assert!(m.contains("45"), "{m}");
    drop(dims);
    // absurd declared size: 2^30 samples per channel, negative, and overflowing products
    for claim in [
        [1024, 1024, 1024],
        [-90, -90, 180],
        [i32::MAX, i32::MAX, i32::MAX],
    ] {
        let mut h = Vec::new();
        for v in claim {
            h.extend_from_slice(&v.to_le_bytes());
        }
        h.extend_from_slice(&[0u8; 64]);
        let p = write(d, "absurd.binary", &h);
        expect_err(&g, &format!("MERL claims {claim:?}"), &p, || {
            MerlBrdf::read(&p)
        });
        // from_bytes on the same bytes: same error, no allocation beyond the input
        let (r, peak) = measure(&g, || MerlBrdf::from_bytes(&h, &p, "absurd"));
        assert!(r.is_err() && peak <= 4096, "{claim:?}: peak {peak}");
    }
    // NaN and infinite samples
    for (bad, at) in [(f64::NAN, 12 + 8 * 1000), (f64::INFINITY, good.len() - 8)] {
        let mut b = good.clone();
        b[at..at + 8].copy_from_slice(&bad.to_le_bytes());
        let p = write(d, "nan.binary", &b);
        let m = expect_err(&g, &format!("MERL {bad}"), &p, || MerlBrdf::read(&p));
        assert!(m.contains("must be finite"), "{m}");
    }
    // the valid file still reads
    let p = write(d, "good.binary", &good);
    MerlBrdf::read(&p).unwrap();
}

#[test]
fn sh_dataset_hostile_files() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = sh_file_bytes();
    let p = write(d, "empty.exr", b"");
    expect_err(&g, "SH empty", &p, || read_sh_dataset(&p));
    for cut in cuts(good.len()) {
        let p = write(d, "cut.exr", &good[..cut]);
        expect_err(&g, &format!("SH cut at {cut}"), &p, || read_sh_dataset(&p));
    }
    let mut magic = good.clone();
    magic[..4].copy_from_slice(b"PNG\0");
    let p = write(d, "magic.exr", &magic);
    expect_err(&g, "SH magic", &p, || read_sh_dataset(&p));
    // wrong dimensions: the image size disagrees with brdfkit.nu/nv (first part only)
    let mut dims = good.clone();
    let at = find(&dims, b"dataWindow\0box2i\0") + 21;
    dims[at + 8..at + 12].copy_from_slice(&6i32.to_le_bytes());
    let p = write(d, "dims.exr", &dims);
    expect_err(&g, "SH dims", &p, || read_sh_dataset(&p));
    // absurd declared sizes
    // (2^22 x 3 keeps the chunk count of the 6 x 3 original.)
    for (w, h) in [
        (1_000_000, 1_000_000),
        (8192, 8192),
        (1 << 20, 1),
        (1 << 22, 3),
        (i32::MAX, 3),
    ] {
        let mut b = good.clone();
        patch_exr_size(&mut b, w, h);
        let p = write(d, "absurd.exr", &b);
        expect_err(&g, &format!("SH claims {w}x{h}"), &p, || {
            read_sh_dataset(&p)
        });
    }
    // Only the first part's data window widened (chunk counts stay consistent).
    for w in [1 << 22, 1 << 26] {
        let mut b = good.clone();
        let at = find(&b, b"dataWindow\0box2i\0") + 21;
        b[at + 8..at + 12].copy_from_slice(&(w - 1i32).to_le_bytes());
        let p = write(d, "wide.exr", &b);
        expect_err(&g, &format!("SH claims {w}x3"), &p, || read_sh_dataset(&p));
    }
    // NaN coefficient
    let nan = {
        use exr::prelude::*;
        let src = write(d, "src.exr", &good);
        let mut img = read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .all_layers()
            .all_attributes()
            .from_file(&src)
            .unwrap();
        if let FlatSamples::F32(v) = &mut img.layer_data[0].channel_data.list[3].sample_data {
            v[7] = f32::NAN;
        }
        let p = d.join("nan.exr");
        img.write().to_file(&p).unwrap();
        p
    };
    let m = expect_err(&g, "SH NaN", &nan, || read_sh_dataset(&nan));
    assert!(m.contains("non-finite"), "{m}");
    let p = write(d, "good.exr", &good);
    read_sh_dataset(&p).unwrap();
}

#[test]
fn probe_hostile_files() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let opts = LoadOptions::default();
    let exr = probe_exr(0.5);
    let hdr = probe_hdr();
    for (ext, good) in [("exr", &exr), ("hdr", &hdr)] {
        let p = write(d, &format!("empty.{ext}"), b"");
        expect_err(&g, "probe empty", &p, || Probe::load(&p, &opts));
        for cut in cuts(good.len()) {
            let p = write(d, &format!("cut.{ext}"), &good[..cut]);
            expect_err(&g, &format!("probe .{ext} cut at {cut}"), &p, || {
                Probe::load(&p, &opts)
            });
        }
        let mut magic = good.to_vec();
        magic[..4].copy_from_slice(b"\x89PNG");
        let p = write(d, &format!("magic.{ext}"), &magic);
        expect_err(&g, "probe magic", &p, || Probe::load(&p, &opts));
        let p = write(d, &format!("good.{ext}"), good);
        Probe::load(&p, &opts).unwrap();
    }
    // absurd declared sizes: EXR data window, HDR resolution line
    for (w, h) in [(1_000_000, 1_000_000), (8192, 8192), (1 << 22, 16), (0, 8)] {
        let mut b = exr.clone();
        patch_exr_size(&mut b, w, h);
        let p = write(d, "absurd.exr", &b);
        expect_err(&g, &format!("probe EXR claims {w}x{h}"), &p, || {
            Probe::load(&p, &opts)
        });
    }
    // Only the width patched, so the chunk count still matches: the decoder would reach
    // its pixel allocation (400 MiB for 2^22 x 8) if the size were not checked first.
    for w in [1 << 22, 1 << 28, i32::MAX] {
        let mut b = probe_exr_scanlines();
        patch_exr_size(&mut b, w, 8);
        let p = write(d, "wide.exr", &b);
        expect_err(&g, &format!("probe EXR claims {w}x8"), &p, || {
            Probe::load(&p, &opts)
        });
    }
    for res in [
        "-Y 1000000 +X 1000000",
        "-Y 8192 +X 8192",
        "-Y 4 +X 16777216",
        "-Y 0 +X 8",
    ] {
        let at = find(&hdr, b"-Y 4 +X 8");
        let mut b = hdr[..at].to_vec();
        b.extend_from_slice(res.as_bytes());
        b.extend_from_slice(&hdr[at + 9..]);
        let p = write(d, "absurd.hdr", &b);
        expect_err(&g, &format!("probe HDR {res}"), &p, || {
            Probe::load(&p, &opts)
        });
    }
    // NaN and infinite texels
    for bad in [f32::NAN, f32::INFINITY] {
        let p = write(d, "nan.exr", &probe_exr(bad));
        let m = expect_err(&g, "probe NaN", &p, || Probe::load(&p, &opts));
        assert!(m.contains("non-finite"), "{m}");
    }
}

#[test]
fn lightset_hostile_files() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let ls = small_lightset();
    let header = LightSetHeader::new(&SamplerConfig::MedianCut { n: 4 }, Some("x.exr"), &ls);
    let jp = d.join("good.json");
    write_json(&jp, &header, &ls).unwrap();
    let cp = d.join("good.csv");
    write_csv(&cp, &ls).unwrap();
    let json = std::fs::read(&jp).unwrap();
    let csv = std::fs::read(&cp).unwrap();
    assert_eq!(read_json(&jp).unwrap().1, ls);
    assert_eq!(read_csv(&cp).unwrap(), ls);

    let p = write(d, "empty.json", b"");
    expect_err(&g, "JSON empty", &p, || read_json(&p));
    let p = write(d, "empty.csv", b"");
    expect_err(&g, "CSV empty", &p, || read_csv(&p));
    for cut in cuts(json.len()) {
        let p = write(d, "cut.json", &json[..cut]);
        expect_err(&g, &format!("JSON cut at {cut}"), &p, || read_json(&p));
    }
    for cut in cuts(csv.len()) {
        // a cut at a line end is a valid, shorter light set
        let p = write(d, "cut.csv", &csv[..cut]);
        expect_err_or_ok(&g, &format!("CSV cut at {cut}"), &p, || read_csv(&p));
    }
    let text = String::from_utf8(json.clone()).unwrap();
    let cases: Vec<(&str, String)> = vec![
        (
            "magic",
            text.replace("brdfkit-lightset", "brdfkit-lightsex"),
        ),
        ("binary", "\u{0}\u{1}\u{2}garbage".into()),
        (
            "version",
            text.replace("\"version\": 1", "\"version\": 4294967295"),
        ),
        // wrong dimensions: arrays of different lengths, and a count that disagrees
        (
            "dims",
            text.replacen("\"dir_x\": [", "\"dir_x\": [0.0, ", 1),
        ),
        ("count", text.replace("\"n\": 4", "\"n\": 5")),
        // absurd declared size
        (
            "absurd",
            text.replace("\"n\": 4", "\"n\": 18446744073709551615"),
        ),
        ("overflow", text.replace("\"n\": 4", "\"n\": 1e300")),
        // NaN fields: JSON has no NaN; the usual spellings and an f32 overflow
        (
            "nan",
            text.replacen("\"irradiance_r\": [", "\"irradiance_r\": [NaN, ", 1),
        ),
        (
            "null",
            text.replacen("\"dir_y\": [\n", "\"dir_y\": [\n null,", 1),
        ),
        (
            "inf",
            text.replacen("\"irradiance_g\": [\n", "\"irradiance_g\": [\n 1e39,", 1),
        ),
    ];
    for (what, body) in cases {
        let p = write(d, &format!("{what}.json"), body.as_bytes());
        expect_err(&g, &format!("JSON {what}"), &p, || read_json(&p));
    }
    let ctext = String::from_utf8(csv).unwrap();
    let row = ctext.lines().nth(1).unwrap().to_string();
    let cases: Vec<(&str, String)> = vec![
        ("magic", ctext.replacen("dir_x", "dir_q", 1)),
        ("binary", "\u{0}\u{1}\u{2}garbage".into()),
        ("dims", format!("{ctext}1,0,0\n")),
        ("wide", format!("{ctext}{row},1\n")),
        ("nan", format!("{ctext}NaN,0,0,1,1,1\n")),
        ("nanpow", format!("{ctext}0,1,0,1,nan,1\n")),
        ("inf", format!("{ctext}0,1,0,inf,1,1\n")),
        ("huge", format!("{ctext}0,1,0,1e39,1,1\n")),
    ];
    for (what, body) in cases {
        let p = write(d, &format!("{what}.csv"), body.as_bytes());
        expect_err(&g, &format!("CSV {what}"), &p, || read_csv(&p));
    }
    let p = write(
        d,
        "utf8.csv",
        b"dir_x,dir_y,dir_z,irradiance_r,irradiance_g,irradiance_b\n\xff\xfe\n",
    );
    expect_err(&g, "CSV not UTF-8", &p, || read_csv(&p));
}

const SCENE: &str = "[camera]\nposition = [4.0, 4.0, 9.0]\ntarget = [0.0, 1.2, 0.0]\n\
fov_y_deg = 35.0\n[mesh]\nsource = \"sphere\"\nsegments = 8\n[material]\nkind = \"lambert\"\n\
albedo = [0.5, 0.5, 0.5]\n[[light]]\nkind = \"point\"\nposition = [1.0, 2.0, 3.0]\n\
intensity = 2.0\n[render]\nwidth = 32\nheight = 24\n[output]\nexposure = 0.5\n";

fn load_scene(p: &Path) -> brdfkit::error::Result<Scene> {
    let f = SceneFile::load(p)?;
    Scene::resolve(&f, p.parent().unwrap())
        .map_err(|e| brdfkit::error::Error::format(p, e.to_string()))
}

/// Scene variants that must be rejected: wrong magic, wrong and absurd dimensions, NaN.
fn bad_scenes() -> Vec<(&'static str, String)> {
    let mut v: Vec<(&str, String)> = vec![
        ("binary", "\u{0}\u{1}\u{2}\u{3}".into()),
        ("not-toml", "<scene/>".into()),
        ("width0", SCENE.replace("width = 32", "width = 0")),
        (
            "width-huge",
            SCENE.replace("width = 32", "width = 4294967295"),
        ),
        (
            "width-over",
            SCENE.replace("width = 32", "width = 4294967296"),
        ),
        ("width-neg", SCENE.replace("width = 32", "width = -1")),
        (
            "segments",
            SCENE.replace("segments = 8", "segments = 4000000000"),
        ),
        (
            "threads",
            SCENE.replace("height = 24", "height = 24\nthreads = 18446744073709551615"),
        ),
        (
            "tile",
            SCENE.replace("height = 24", "height = 24\ntile_size = 0"),
        ),
        (
            "env-count",
            format!("{SCENE}[env]\nfile = \"p.exr\"\ncount = 1000000000000\n"),
        ),
    ];
    for (field, from, to) in [
        ("fov", "fov_y_deg = 35.0", "fov_y_deg = nan"),
        ("position", "[4.0, 4.0, 9.0]", "[nan, 4.0, 9.0]"),
        ("target", "[0.0, 1.2, 0.0]", "[0.0, -nan, 0.0]"),
        ("albedo", "[0.5, 0.5, 0.5]", "[0.5, nan, 0.5]"),
        ("light-pos", "[1.0, 2.0, 3.0]", "[1.0, inf, 3.0]"),
        ("intensity", "intensity = 2.0", "intensity = nan"),
        ("exposure", "exposure = 0.5", "exposure = nan"),
        ("near", "fov_y_deg = 35.0", "fov_y_deg = 35.0\nnear = nan"),
        (
            "up",
            "fov_y_deg = 35.0",
            "fov_y_deg = 35.0\nup = [0.0, nan, 0.0]",
        ),
    ] {
        v.push((field, SCENE.replace(from, to)));
    }
    v.push((
        "env-nan",
        format!("{SCENE}[env]\nfile = \"p.exr\"\nrotation = nan\n"),
    ));
    v.push((
        "env-intensity",
        format!("{SCENE}[env]\nfile = \"p.exr\"\nintensity = nan\n"),
    ));
    v
}

#[test]
fn scene_hostile_files() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("p.exr"), probe_exr(0.5)).unwrap();
    let p = write(d, "good.toml", SCENE.as_bytes());
    load_scene(&p).unwrap();
    // An empty scene file is the default scene, by design (scene module doc).
    let p = write(d, "empty.toml", b"");
    assert!(SceneFile::load(&p).is_ok());
    for cut in cuts(SCENE.len()) {
        let p = write(d, "cut.toml", &SCENE.as_bytes()[..cut]);
        expect_err_or_ok(&g, &format!("scene cut at {cut}"), &p, || load_scene(&p));
    }
    for (what, text) in bad_scenes() {
        let p = write(d, &format!("{what}.toml"), text.as_bytes());
        expect_err(&g, &format!("scene {what}"), &p, || load_scene(&p));
    }
}

const OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 2 4\n";

fn bad_objs() -> Vec<(&'static str, String)> {
    vec![
        ("binary", "\u{0}\u{1}\u{2}\u{3}\u{ff}".into()),
        ("no-faces", "v 0 0 0\nv 1 0 0\n".into()),
        ("index", format!("{OBJ}f 1 2 4000000\n")),
        ("index-huge", format!("{OBJ}f 1 2 99999999999999999999\n")),
        ("index-neg", format!("{OBJ}f -1 -2 -4000000\n")),
        ("index-zero", format!("{OBJ}f 0 1 2\n")),
        ("nan", OBJ.replacen("v 1 0 0", "v nan 0 0", 1)),
        ("inf", OBJ.replacen("v 1 0 0", "v 1 inf 0", 1)),
    ]
}

#[test]
fn obj_hostile_files() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let p = write(d, "good.obj", OBJ.as_bytes());
    brdfkit::mesh::obj::load_obj(&p).unwrap();
    let p = write(d, "empty.obj", b"");
    expect_err(&g, "OBJ empty", &p, || brdfkit::mesh::obj::load_obj(&p));
    for cut in cuts(OBJ.len()) {
        let p = write(d, "cut.obj", &OBJ.as_bytes()[..cut]);
        expect_err_or_ok(&g, &format!("OBJ cut at {cut}"), &p, || {
            brdfkit::mesh::obj::load_obj(&p)
        });
    }
    for (what, text) in bad_objs() {
        let p = write(d, &format!("{what}.obj"), text.as_bytes());
        expect_err(&g, &format!("OBJ {what}"), &p, || {
            brdfkit::mesh::obj::load_obj(&p)
        });
    }
}

/// A valid EXR image and PNG image (8 x 6) for `compare` and the golden set.
fn images() -> (Vec<u8>, Vec<u8>) {
    let dir = tempfile::tempdir().unwrap();
    let mut img = brdfkit::image_io::Image::new(8, 6);
    for (i, p) in img.pixels.iter_mut().enumerate() {
        *p = Vec3::new(i as f32 / 48.0, 0.5, 0.25);
    }
    let e = dir.path().join("a.exr");
    let n = dir.path().join("a.png");
    brdfkit::image_io::write_exr(&e, &img).unwrap();
    brdfkit::image_io::write_png(&n, &img, 0.0, brdfkit::image_io::Tonemap::Aces).unwrap();
    (std::fs::read(e).unwrap(), std::fs::read(n).unwrap())
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// Patches a PNG's IHDR to `w x h` (with a correct CRC, so only the size is hostile).
fn patch_png_size(png: &[u8], w: u32, h: u32) -> Vec<u8> {
    let mut b = png.to_vec();
    let at = find(&b, b"IHDR");
    b[at + 4..at + 8].copy_from_slice(&w.to_be_bytes());
    b[at + 8..at + 12].copy_from_slice(&h.to_be_bytes());
    let crc = crc32(&b[at..at + 17]);
    b[at + 17..at + 21].copy_from_slice(&crc.to_be_bytes());
    b
}

/// Image variants `compare` must reject: (file name, bytes).
fn bad_images() -> Vec<(String, Vec<u8>)> {
    let (exr, png) = images();
    let mut v = vec![
        ("empty.exr".to_string(), vec![]),
        ("empty.png".to_string(), vec![]),
        ("magic.exr".to_string(), png.clone()),
        ("magic.png".to_string(), exr.clone()),
    ];
    for cut in cuts(exr.len()) {
        v.push((format!("cut{cut}.exr"), exr[..cut].to_vec()));
    }
    // A PNG cut inside its final IEND chunk still holds the whole image, and the decoder
    // (rightly) accepts it: cuts start before IEND.
    for cut in cuts(png.len()).into_iter().filter(|&c| c < png.len() - 12) {
        v.push((format!("cut{cut}.png"), png[..cut].to_vec()));
    }
    for (w, h) in [(1_000_000, 1_000_000), (8192, 8192), (30000, 30000)] {
        let mut b = exr.clone();
        patch_exr_size(&mut b, w, h);
        v.push((format!("absurd{w}x{h}.exr"), b));
        v.push((
            format!("absurd{w}x{h}.png"),
            patch_png_size(&png, w as u32, h as u32),
        ));
    }
    for w in [1 << 22, i32::MAX] {
        let mut b = probe_exr_scanlines();
        patch_exr_size(&mut b, w, 8);
        v.push((format!("wide{w}.exr"), b));
    }
    v
}

#[test]
fn compare_image_hostile_files() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in bad_images() {
        let p = write(dir.path(), &name, &bytes);
        expect_err(&g, &name, &p, || brdfkit::compare::load(&p));
    }
}

const MANIFEST: &str =
    "[[entry]]\nname = \"a\"\nscene = \"a.toml\"\ntolerance = \"cross-platform\"\nhash = \"\"\n";

#[test]
fn golden_manifest_hostile_files() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("empty", vec![]),
        ("binary", b"\0\x01\xff\xfe".to_vec()),
        ("magic", b"{\"entry\": []}".to_vec()),
        ("cut", MANIFEST.as_bytes()[..30].to_vec()),
        ("cut2", MANIFEST.as_bytes()[..MANIFEST.len() - 12].to_vec()),
        ("unknown", format!("{MANIFEST}colour = 1\n").into_bytes()),
        (
            "nan",
            MANIFEST.replace("hash = \"\"", "hash = nan").into_bytes(),
        ),
    ];
    for (what, bytes) in cases {
        let sub = d.join(what);
        std::fs::create_dir_all(&sub).unwrap();
        let p = write(&sub, "manifest.toml", &bytes);
        expect_err(&g, &format!("manifest {what}"), &p, || {
            brdfkit::golden::load_manifest(&sub)
        });
    }
}

// ---------------------------------------------------------------------------------------
// Through the binary

/// Address-space limit for the child: the binary's threads and libraries take ~100 MiB of
/// address space; every hostile case must stay under this.
const CLI_AS_LIMIT: &str = "768MiB";

/// Seconds a `brdfkit` child may run before it is killed (a hang on a FIFO or a device is
/// then a failing test, not a stuck CI job). Every case here takes well under a second.
const CLI_TIMEOUT_S: u32 = 60;

/// `brdfkit args` in `dir` under the address-space limit, two rayon threads, killed after
/// [`CLI_TIMEOUT_S`].
fn brdfkit_limited(dir: &Path, args: &[&str]) -> common::Run {
    common::brdfkit(dir)
        .cache(&dir.join(".cache-dir-unused"))
        .timeout(CLI_TIMEOUT_S)
        .address_space(as_bytes())
        .env("RAYON_NUM_THREADS", "2")
        .run(args)
}

fn as_bytes() -> u64 {
    let n: u64 = CLI_AS_LIMIT.trim_end_matches("MiB").parse().unwrap();
    n << 20
}

fn list(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v
}

/// Exit 2, exactly one stderr line starting `brdfkit: error:` and naming `name`, no new
/// file (output or temporary) in `dir`.
fn assert_cli_error(dir: &Path, args: &[&str], name: &str) {
    let before = list(dir);
    let r = brdfkit_limited(dir, args);
    assert_eq!(
        r.code,
        Some(2),
        "{args:?}: exit {:?}, stderr {}",
        r.code,
        r.stderr
    );
    let lines: Vec<&str> = r.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: stderr {lines:?}");
    assert!(lines[0].starts_with("brdfkit: error: "), "{}", lines[0]);
    assert!(
        lines[0].contains(name),
        "{args:?}: {} does not name {name}",
        lines[0]
    );
    assert_eq!(list(dir), before, "{args:?}: files were left behind");
}

#[test]
fn cli_valid_inputs_run_under_the_address_space_limit() {
    // The control for the tests below: with valid files the same limit is no obstacle.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("p.exr"), probe_exr(0.5)).unwrap();
    std::fs::write(d.join("p.hdr"), probe_hdr()).unwrap();
    std::fs::write(d.join("s.toml"), SCENE).unwrap();
    for args in [
        &["lights", "p.exr", "-n", "4", "-o", "l.json"][..],
        &["lights", "p.hdr", "-n", "4", "-o", "l.csv"][..],
        &["render", "s.toml", "-o", "o.png"][..],
    ] {
        let r = brdfkit_limited(d, args);
        assert_eq!(r.code, Some(0), "{args:?}: {}", r.stderr);
    }
}

#[test]
fn cli_hostile_probes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let exr = probe_exr(0.5);
    let hdr = probe_hdr();
    let mut files: Vec<(String, Vec<u8>)> = vec![
        ("empty.exr".into(), vec![]),
        ("empty.hdr".into(), vec![]),
        ("magic.exr".into(), hdr.clone()),
        ("magic.hdr".into(), exr.clone()),
        ("nan.exr".into(), probe_exr(f32::NAN)),
        ("cut.exr".into(), exr[..exr.len() / 2].to_vec()),
        ("cut.hdr".into(), hdr[..hdr.len() / 2].to_vec()),
    ];
    for (w, h) in [(1_000_000, 1_000_000), (8192, 8192)] {
        let mut b = exr.clone();
        patch_exr_size(&mut b, w, h);
        files.push((format!("absurd{w}.exr"), b));
        let at = find(&hdr, b"-Y 4 +X 8");
        let mut b = hdr[..at].to_vec();
        b.extend_from_slice(format!("-Y {h} +X {w}").as_bytes());
        b.extend_from_slice(&hdr[at + 9..]);
        files.push((format!("absurd{w}.hdr"), b));
    }
    let mut b = probe_exr_scanlines();
    patch_exr_size(&mut b, 1 << 26, 8);
    files.push(("wide.exr".into(), b));
    for (name, bytes) in &files {
        std::fs::write(d.join(name), bytes).unwrap();
    }
    for (name, _) in &files {
        assert_cli_error(d, &["lights", name, "-n", "4", "-o", "l.json"], name);
        assert_cli_error(d, &["render", "--env", name, "-o", "o.png"], name);
    }
}

#[test]
fn cli_hostile_scenes_and_objs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("p.exr"), probe_exr(0.5)).unwrap();
    for (what, text) in bad_scenes() {
        let name = format!("{what}.toml");
        std::fs::write(d.join(&name), text).unwrap();
        assert_cli_error(d, &["render", &name, "-o", "o.png"], &name);
        std::fs::remove_file(d.join(&name)).unwrap();
    }
    // A scene naming a device as its mesh or probe: refused, not read without end.
    for (what, text) in [
        ("dev-obj", SCENE.replace("\"sphere\"", "\"/dev/zero\"")),
        ("dev-probe", format!("{SCENE}[env]\nfile = \"/dev/zero\"\n")),
    ] {
        let name = format!("{what}.toml");
        std::fs::write(d.join(&name), text).unwrap();
        assert_cli_error(d, &["render", &name, "-o", "o.png"], "/dev/zero");
        std::fs::remove_file(d.join(&name)).unwrap();
    }
    let mut objs = bad_objs();
    objs.push(("empty", String::new()));
    // A material library that never ends: materials are ignored, so it must not be read.
    objs.push(("mtllib", format!("mtllib /dev/zero\n{OBJ}")));
    for (what, text) in objs {
        let name = format!("{what}.obj");
        std::fs::write(d.join(&name), &text).unwrap();
        if what == "mtllib" {
            let r = brdfkit_limited(d, &["render", "--mesh", &name, "-o", "o.png"]);
            assert_eq!(r.code, Some(0), "{what}: {}", r.stderr);
            std::fs::remove_file(d.join("o.png")).unwrap();
        } else {
            assert_cli_error(d, &["render", "--mesh", &name, "-o", "o.png"], &name);
        }
        std::fs::remove_file(d.join(&name)).unwrap();
    }
}

#[test]
fn cli_hostile_images_and_manifests() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (exr, png) = images();
    std::fs::write(d.join("ok.exr"), &exr).unwrap();
    std::fs::write(d.join("ok.png"), &png).unwrap();
    for (name, bytes) in bad_images() {
        std::fs::write(d.join(&name), bytes).unwrap();
        let ok = if name.ends_with(".exr") {
            "ok.exr"
        } else {
            "ok.png"
        };
        assert_cli_error(d, &["compare", ok, &name], &name);
        assert_cli_error(d, &["compare", &name, ok], &name);
        std::fs::remove_file(d.join(&name)).unwrap();
    }
    // golden check: hostile manifests and a manifest naming a hostile golden image
    let g = d.join("golden");
    std::fs::create_dir_all(&g).unwrap();
    std::fs::write(g.join("a.toml"), SCENE).unwrap();
    for manifest in ["", "\0\u{1}", &MANIFEST[..30], "[[entry]]\nname = 1\n"] {
        std::fs::write(g.join("manifest.toml"), manifest).unwrap();
        assert_cli_error(d, &["golden", "check", "--dir", "golden"], "manifest.toml");
    }
    std::fs::write(g.join("manifest.toml"), MANIFEST).unwrap();
    let mut b = exr.clone();
    patch_exr_size(&mut b, 1_000_000, 1_000_000);
    std::fs::write(g.join("a.exr"), b).unwrap();
    assert_cli_error(d, &["golden", "check", "--dir", "golden"], "a.exr");
    let mut b = probe_exr_scanlines();
    patch_exr_size(&mut b, 1 << 26, 8);
    std::fs::write(g.join("a.exr"), b).unwrap();
    assert_cli_error(d, &["golden", "check", "--dir", "golden"], "a.exr");
}
/// A 16 x 8 RGB f32 EXR in uncompressed scan lines (one line per chunk, no chunkCount
/// attribute): patching its width keeps the chunk count consistent.
fn probe_exr_scanlines() -> Vec<u8> {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("s.exr");
    let chans = SpecificChannels::rgb(|pos: Vec2<usize>| (pos.x() as f32 * 0.1, 0.5f32, 0.25f32));
    let layer = Layer::new(
        (16, 8),
        LayerAttributes::default(),
        Encoding::UNCOMPRESSED,
        chans,
    );
    Image::from_layer(layer).write().to_file(&p).unwrap();
    std::fs::read(p).unwrap()
}

// ---------------------------------------------------------------------------------------
// D-BRDF tables, huge finite values, special files

use brdfkit::brdf::dbrdf::file::{read_dbrdf, write_dbrdf};

/// The bytes of a small valid D-BRDF file (8 x 4 table).
fn dbrdf_bytes() -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("d.exr");
    let mut d =
        brdfkit::brdf::DBrdf::from_fn(8, 4, Vec3::new(0.1, 0.5, 0.9), |h| h.z.powi(8) + 0.1);
    d.c = 0.3;
    write_dbrdf(&p, &d, "hostile test").unwrap();
    std::fs::read(p).unwrap()
}

/// Rewrites the EXR `bytes` (all parts, all attributes) after `edit` on its first part.
fn edit_exr(
    bytes: &[u8],
    edit: impl FnOnce(&mut exr::prelude::Layer<exr::prelude::AnyChannels<exr::prelude::FlatSamples>>),
) -> Vec<u8> {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    let src = write(dir.path(), "src.exr", bytes);
    let mut img = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(&src)
        .unwrap();
    edit(&mut img.layer_data[0]);
    let p = dir.path().join("out.exr");
    img.write().to_file(&p).unwrap();
    std::fs::read(p).unwrap()
}

fn set_sample(bytes: &[u8], channel: usize, at: usize, v: f32) -> Vec<u8> {
    edit_exr(bytes, |l| {
        if let exr::prelude::FlatSamples::F32(s) = &mut l.channel_data.list[channel].sample_data {
            s[at] = v;
        }
    })
}

#[test]
fn dbrdf_hostile_files() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = dbrdf_bytes();
    let p = write(d, "good.exr", &good);
    read_dbrdf(&p).unwrap();
    let p = write(d, "empty.exr", b"");
    expect_err(&g, "D-BRDF empty", &p, || read_dbrdf(&p));
    for cut in cuts(good.len()) {
        let p = write(d, "cut.exr", &good[..cut]);
        expect_err(&g, &format!("D-BRDF cut at {cut}"), &p, || read_dbrdf(&p));
    }
    let mut magic = good.clone();
    magic[..4].copy_from_slice(b"PNG\0");
    let p = write(d, "magic.exr", &magic);
    expect_err(&g, "D-BRDF magic", &p, || read_dbrdf(&p));
    // the right magic, another brdfkit format: an SH data set
    let p = write(d, "sh.exr", &sh_file_bytes());
    let m = expect_err(&g, "D-BRDF given an SH file", &p, || read_dbrdf(&p));
    assert!(m.contains("not a brdfkit D-BRDF file"), "{m}");
    // wrong dimensions: the data window disagrees with the chunks present
    let mut dims = good.clone();
    patch_exr_size(&mut dims, 8, 64);
    let p = write(d, "dims.exr", &dims);
    expect_err(&g, "D-BRDF dims", &p, || read_dbrdf(&p));
    // Absurd declared sizes. Regression: the reader decoded (and so allocated) every
    // declared pixel before comparing it with the file length: 64 MiB for 4096 x 4096 from
    // a ~1 KB file. The width-only patches keep the chunk count consistent, so only the
    // declared-size check stands between them and the allocation.
    for (w, h) in [(4096, 4096), (1_000_000, 1_000_000), (i32::MAX, 4)] {
        let mut b = good.clone();
        patch_exr_size(&mut b, w, h);
        let p = write(d, "absurd.exr", &b);
        expect_err(&g, &format!("D-BRDF claims {w}x{h}"), &p, || read_dbrdf(&p));
    }
    for w in [1 << 22, 1 << 26] {
        let mut b = good.clone();
        let at = find(&b, b"dataWindow\0box2i\0") + 21;
        b[at + 8..at + 12].copy_from_slice(&(w - 1i32).to_le_bytes());
        let p = write(d, "wide.exr", &b);
        expect_err(&g, &format!("D-BRDF claims {w}x4"), &p, || read_dbrdf(&p));
    }
    // NaN, negative, infinite and huge finite table values
    for (bad, expect) in [
        (f32::NAN, "non-finite"),
        (-1.0, "negative"),
        (f32::INFINITY, "non-finite"),
        (1e38, "exceeds the limit"),
        (5e10, "exceeds the limit"),
    ] {
        let p = write(d, "bad.exr", &set_sample(&good, 0, 5, bad));
        let m = expect_err(&g, &format!("D-BRDF p = {bad}"), &p, || read_dbrdf(&p));
        assert!(m.contains(expect) && m.contains("(5, 0)"), "{m}");
    }
    // c = 1e38 with ordinary table values: c p overflows just the same
    let huge_c = edit_exr(&good, |l| {
        let key = exr::prelude::Text::from("brdfkit.c");
        l.attributes
            .other
            .insert(key, exr::meta::attribute::AttributeValue::F32(1e38));
    });
    let p = write(d, "huge-c.exr", &huge_c);
    let m = expect_err(&g, "D-BRDF c = 1e38", &p, || read_dbrdf(&p));
    assert!(m.contains("c * p") && m.contains("1e38"), "{m}");
    // the largest accepted value shades to a finite image (no Inf in shading)
    let near = set_sample(&good, 0, 5, 3e10);
    let p = write(d, "near.exr", &near);
    read_dbrdf(&p).unwrap();
    let s = SCENE.replace(
        "kind = \"lambert\"\nalbedo = [0.5, 0.5, 0.5]",
        "kind = \"dbrdf-file\"\npath = \"near.exr\"",
    );
    let f = SceneFile::parse(&s).unwrap();
    let scene = Scene::resolve(&f, d).unwrap();
    let img = brdfkit::render::render(&scene, &Default::default()).image;
    assert!(img.pixels.iter().all(|p| p.is_finite()));
}

#[test]
fn sh_dataset_huge_finite_coefficients_are_refused() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    let good = sh_file_bytes();
    for bad in [1e38f32, -1e38, 2e10] {
        let p = write(dir.path(), "huge.exr", &set_sample(&good, 3, 7, bad));
        let m = expect_err(&g, &format!("SH coefficient {bad}"), &p, || {
            read_sh_dataset(&p)
        });
        assert!(
            m.contains("exceeds the limit") && m.contains("channel"),
            "{m}"
        );
    }
}

#[test]
fn merl_huge_finite_samples_are_refused() {
    let g = serial();
    let dir = tempfile::tempdir().unwrap();
    let mut b = merl_bytes().to_vec();
    b[12 + 8 * 77..12 + 8 * 78].copy_from_slice(&1e38f64.to_le_bytes());
    let p = write(dir.path(), "huge.binary", &b);
    let m = expect_err(&g, "MERL 1e38", &p, || MerlBrdf::read(&p));
    assert!(m.contains("sample 77"), "{m}");
}

/// Runs `f` on its own thread and fails the test if it has not returned within 60 s: a
/// reader blocked on a FIFO is then a failure, not a stuck run.
fn no_hang<T: Send + 'static>(what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(std::time::Duration::from_secs(60))
        .unwrap_or_else(|_| panic!("{what}: still reading after 60 s"))
}

/// In `dir`, for each extension: `zero.EXT` (a symlink to `/dev/zero`), `fifo.EXT` (a
/// FIFO nobody writes to) and `dir.EXT` (a directory).
fn special_files(dir: &Path, exts: &[&str]) -> Vec<PathBuf> {
    let mut v = Vec::new();
    for ext in exts {
        let zero = dir.join(format!("zero.{ext}"));
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        let fifo = dir.join(format!("fifo.{ext}"));
        let ok = Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(ok.success(), "mkfifo {}", fifo.display());
        let d = dir.join(format!("dir.{ext}"));
        std::fs::create_dir(&d).unwrap();
        v.extend([zero, fifo, d]);
    }
    v
}

type Reader = fn(&Path) -> Result<(), String>;

fn ok<T, E: std::fmt::Display>(r: Result<T, E>) -> Result<(), String> {
    r.map(|_| ()).map_err(|e| e.to_string())
}

#[test]
fn special_files_are_refused_by_every_reader() {
    // Regression: a scene path naming /dev/zero read until it had allocated ~8 GiB, and a
    // FIFO blocked forever; the same held for the light-set, manifest, SH, D-BRDF and MERL
    // readers. Each now refuses anything but a regular file, unopened.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let readers: Vec<(&str, &str, Reader)> = vec![
        ("scene", "toml", |p| ok(SceneFile::load(p))),
        ("OBJ", "obj", |p| ok(brdfkit::mesh::obj::load_obj(p))),
        ("probe", "exr", |p| {
            ok(Probe::load(p, &LoadOptions::default()))
        }),
        ("probe", "hdr", |p| {
            ok(Probe::load(p, &LoadOptions::default()))
        }),
        ("SH data set", "exr", |p| ok(read_sh_dataset(p))),
        ("D-BRDF", "exr", |p| ok(read_dbrdf(p))),
        ("MERL", "binary", |p| ok(MerlBrdf::read(p))),
        ("light set", "json", |p| ok(read_json(p))),
        ("light set", "csv", |p| ok(read_csv(p))),
        ("manifest", "toml", |p| {
            ok(brdfkit::golden::load_manifest_file(p))
        }),
        ("image", "exr", |p| ok(brdfkit::compare::load(p))),
        ("image", "png", |p| ok(brdfkit::compare::load(p))),
        ("image", "exr", |p| ok(brdfkit::image_io::read_exr(p))),
    ];
    special_files(
        d,
        &["toml", "obj", "exr", "hdr", "binary", "json", "csv", "png"],
    );
    for (what, ext, read) in readers {
        for kind in ["zero", "fifo", "dir"] {
            let p = d.join(format!("{kind}.{ext}"));
            let case = format!("{what} from {}", p.display());
            let q = p.clone();
            let r = no_hang(&case, move || read(&q));
            let msg = r.err().unwrap_or_else(|| panic!("{case}: accepted"));
            check_message(&case, &p, &msg);
            assert!(msg.contains("not a regular file"), "{case}: {msg}");
        }
    }
}

#[test]
fn oversized_text_inputs_are_refused_by_length() {
    // Sparse files: the length alone must refuse them, so nothing is read.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let big = |name: &str, len: u64| {
        let p = d.join(name);
        std::fs::File::create(&p).unwrap().set_len(len).unwrap();
        p
    };
    let p = big("big.toml", brdfkit::scene::MAX_SCENE_BYTES + 1);
    let m = SceneFile::load(&p).unwrap_err().to_string();
    assert!(m.contains("big.toml") && m.contains("limit"), "{m}");
    let p = big("manifest.toml", brdfkit::golden::MAX_MANIFEST_BYTES + 1);
    let m = brdfkit::golden::load_manifest(d).unwrap_err().to_string();
    assert!(m.contains("manifest.toml") && m.contains("limit"), "{m}");
    drop(p);
    let lim = brdfkit::env::lightset::file::MAX_LIGHTSET_BYTES + 1;
    for name in ["big.json", "big.csv"] {
        let p = big(name, lim);
        let m = if name.ends_with("json") {
            ok(read_json(&p))
        } else {
            ok(read_csv(&p))
        }
        .unwrap_err();
        assert!(m.contains(name) && m.contains("limit"), "{m}");
    }
}

#[test]
fn cli_special_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (exr, _) = images();
    std::fs::write(d.join("ok.exr"), &exr).unwrap();
    std::fs::write(d.join("s.toml"), SCENE).unwrap();
    special_files(d, &["toml", "obj", "exr", "hdr"]);
    for kind in ["zero", "fifo", "dir"] {
        let toml = format!("{kind}.toml");
        let exr_name = format!("{kind}.exr");
        assert_cli_error(d, &["render", &toml, "-o", "o.png"], &toml);
        let obj = format!("{kind}.obj");
        assert_cli_error(d, &["render", "--mesh", &obj, "-o", "o.png"], &obj);
        assert_cli_error(d, &["render", "--env", &exr_name, "-o", "o.png"], &exr_name);
        let hdr = format!("{kind}.hdr");
        assert_cli_error(d, &["lights", &hdr, "-n", "4", "-o", "l.json"], &hdr);
        assert_cli_error(
            d,
            &["render", "--material", &exr_name, "-o", "o.png"],
            &exr_name,
        );
        assert_cli_error(d, &["compare", &exr_name, "ok.exr"], &exr_name);
        // material files named by a scene
        for (mkind, extra) in [("sh-file", ""), ("dbrdf-file", "")] {
            let scene = SCENE.replace(
                "kind = \"lambert\"\nalbedo = [0.5, 0.5, 0.5]",
                &format!("kind = \"{mkind}\"\npath = \"{exr_name}\"{extra}"),
            );
            std::fs::write(d.join("m.toml"), scene).unwrap();
            assert_cli_error(d, &["render", "m.toml", "-o", "o.png"], &exr_name);
            std::fs::remove_file(d.join("m.toml")).unwrap();
        }
    }
    // golden check with its manifest a FIFO, /dev/zero or a directory
    for kind in ["zero", "fifo", "dir"] {
        let g = d.join(format!("golden-{kind}"));
        std::fs::create_dir(&g).unwrap();
        let m = g.join("manifest.toml");
        match kind {
            "zero" => std::os::unix::fs::symlink("/dev/zero", &m).unwrap(),
            "fifo" => assert!(Command::new("mkfifo").arg(&m).status().unwrap().success()),
            _ => std::fs::create_dir(&m).unwrap(),
        }
        let gd = format!("golden-{kind}");
        assert_cli_error(d, &["golden", "check", "--dir", &gd], "manifest.toml");
    }
}

#[test]
fn cli_dbrdf_and_sh_hostile_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = dbrdf_bytes();
    let sh = sh_file_bytes();
    let mut files: Vec<(String, Vec<u8>)> = vec![
        ("d-empty.exr".into(), vec![]),
        ("d-cut.exr".into(), good[..good.len() / 2].to_vec()),
        ("d-nan.exr".into(), set_sample(&good, 0, 5, f32::NAN)),
        ("d-huge.exr".into(), set_sample(&good, 0, 5, 1e38)),
        ("s-huge.exr".into(), set_sample(&sh, 3, 7, 1e38)),
        ("s-nan.exr".into(), set_sample(&sh, 3, 7, f32::NAN)),
    ];
    let mut b = good.clone();
    patch_exr_size(&mut b, 4096, 4096);
    files.push(("d-absurd.exr".into(), b));
    let mut b = good.clone();
    let at = find(&b, b"dataWindow\0box2i\0") + 21;
    b[at + 8..at + 12].copy_from_slice(&((1i32 << 26) - 1).to_le_bytes());
    files.push(("d-wide.exr".into(), b));
    for (name, bytes) in &files {
        std::fs::write(d.join(name), bytes).unwrap();
        let mkind = if name.starts_with("d-") {
            "dbrdf-file"
        } else {
            "sh-file"
        };
        let scene = SCENE.replace(
            "kind = \"lambert\"\nalbedo = [0.5, 0.5, 0.5]",
            &format!("kind = \"{mkind}\"\npath = \"{name}\""),
        );
        std::fs::write(d.join("m.toml"), scene).unwrap();
        assert_cli_error(d, &["render", "m.toml", "-o", "o.png"], name);
        std::fs::remove_file(d.join("m.toml")).unwrap();
        assert_cli_error(d, &["render", "--material", name, "-o", "o.exr"], name);
    }
}

#[test]
fn cli_light_set_cache_entry_that_is_a_fifo_is_ignored() {
    // Light-set files reach the binary only as cache entries: one replaced by a FIFO must
    // be passed over (and rewritten), not block the render.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("p.exr"), probe_exr(0.5)).unwrap();
    let scene = format!("{SCENE}[env]\nfile = \"p.exr\"\ncount = 4\n").replace(
        "[[light]]\nkind = \"point\"\nposition = [1.0, 2.0, 3.0]\nintensity = 2.0\n",
        "",
    );
    std::fs::write(d.join("e.toml"), scene).unwrap();
    let cache = d.join(".cache-dir-unused");
    let r = brdfkit_limited(d, &["render", "e.toml", "-o", "a.png"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let entries = list(&cache);
    assert_eq!(entries.len(), 1, "{entries:?}");
    std::fs::remove_file(&entries[0]).unwrap();
    assert!(Command::new("mkfifo")
        .arg(&entries[0])
        .status()
        .unwrap()
        .success());
    let r = brdfkit_limited(d, &["render", "e.toml", "-o", "b.png"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert_eq!(
        std::fs::read(d.join("a.png")).unwrap(),
        std::fs::read(d.join("b.png")).unwrap()
    );
}

#[test]
fn golden_manifest_names_that_would_escape_the_directory_are_refused() {
    // `name` becomes file names (NAME.exr, reports under target/): anything but a plain
    // stem is refused with the field named, before any file is touched.
    for bad in [
        "../x",
        "..",
        "a/b",
        "",
        "/etc/passwd",
        "a\\\\b",
        ".hidden",
        "A",
    ] {
        let text = MANIFEST.replace("name = \"a\"", &format!("name = \"{bad}\""));
        let e = brdfkit::golden::parse_manifest(&text).unwrap_err();
        assert!(e.contains(".name") && !e.contains('\n'), "{bad:?}: {e}");
    }
    // `scene` is read from the golden directory: it may not leave it either.
    for bad in ["../a.toml", "/etc/passwd", "sub/../../a.toml"] {
        let text = MANIFEST.replace("scene = \"a.toml\"", &format!("scene = \"{bad}\""));
        let e = brdfkit::golden::parse_manifest(&text).unwrap_err();
        assert!(e.contains(".scene") && !e.contains('\n'), "{bad:?}: {e}");
    }
    brdfkit::golden::parse_manifest(&MANIFEST.replace("a.toml", "scenes/a.toml")).unwrap();
    brdfkit::golden::parse_manifest(MANIFEST).unwrap();
}

#[test]
fn cli_hostile_merl_files() {
    // MERL tables reach the binary as `acquire` and `fit-dbrdf` sources.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = merl_bytes();
    let mut files: Vec<(String, Vec<u8>)> = vec![
        ("empty.binary".into(), vec![]),
        ("cut.binary".into(), good[..good.len() / 2].to_vec()),
        ("header.binary".into(), good[..8].to_vec()),
    ];
    let mut b = good.to_vec();
    b[..12].copy_from_slice(b"MERLBRDFDATA");
    files.push(("magic.binary".into(), b));
    let mut b = good.to_vec();
    b[4..8].copy_from_slice(&45i32.to_le_bytes());
    files.push(("dims.binary".into(), b));
    let mut h = Vec::new();
    for v in [i32::MAX; 3] {
        h.extend_from_slice(&v.to_le_bytes());
    }
    files.push(("absurd.binary".into(), h));
    for (name, v) in [("nan.binary", f64::NAN), ("huge.binary", 1e38)] {
        let mut b = good.to_vec();
        b[12 + 8 * 1000..12 + 8 * 1001].copy_from_slice(&v.to_le_bytes());
        files.push((name.into(), b));
    }
    for (name, bytes) in &files {
        std::fs::write(d.join(name), bytes).unwrap();
    }
    let mut names: Vec<String> = files.into_iter().map(|(n, _)| n).collect();
    for p in special_files(d, &["binary"]) {
        names.push(p.file_name().unwrap().to_string_lossy().into_owned());
    }
    for name in &names {
        assert_cli_error(
            d,
            &[
                "acquire", name, "--bands", "2", "--grid", "4x2", "-o", "a.exr",
            ],
            name,
        );
        assert_cli_error(d, &["fit-dbrdf", name, "-o", "f.exr"], name);
    }
}

/// Inputs the fuzz targets found (fuzz/README.md), each named
/// `<target>-<kind>-<hash prefix>.<ext>` under `tests/fuzz-regressions/`.
fn fuzz_regression(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz-regressions")
        .join(name)
}

#[test]
fn fuzz_dbrdf_file_oom_tiled_header_with_huge_tiles() {
    // dbrdf_file, 5-minute run: a 1109-byte tiled EXR whose data window is small but whose
    // tile description declares 4194304 x 64 pixel tiles; the decoder allocated for a whole
    // tile (RSS 702 MB). The declared-size check now counts a tile block's pixels too.
    let g = serial();
    let p = fuzz_regression("dbrdf_file-oom-0486acdd.exr");
    expect_err(&g, "fuzz dbrdf_file oom", &p, || read_dbrdf(&p));
    expect_err(&g, "fuzz dbrdf_file oom as SH", &p, || read_sh_dataset(&p));
    expect_err(&g, "fuzz dbrdf_file oom as probe", &p, || {
        Probe::load(&p, &LoadOptions::default())
    });
    expect_err(&g, "fuzz dbrdf_file oom as image", &p, || {
        brdfkit::compare::load(&p)
    });
}

// ---------------------------------------------------------------------------------------
// Frame buffers kept across frames (the counting allocator's other use)

/// A frame rendered into a frame context kept from a frame of the same size
/// (`render::render_into`) allocates none of the frame's buffers again: its largest
/// allocation request is under [`STEADY_FRAME_ALLOC`], while a render with new buffers
/// (`render::render`, the control that shows the measure sees them) requests at least the
/// image's bytes at once.
#[test]
fn a_steady_state_frame_allocates_no_frame_buffer() {
    use brdfkit::render::{self, FrameContext, RenderOptions};
    let g = serial();
    let mut scene = Scene::default_scene();
    (scene.render.width, scene.render.height) = (320, 240);
    let image_bytes = 320 * 240 * std::mem::size_of::<Vec3>();
    let opts = RenderOptions::default();
    let (_, fresh) = measure(&g, || render::render(&scene, &opts).image.pixels.len());
    assert!(
        fresh >= image_bytes,
        "a new render's largest request: {fresh} bytes"
    );
    // The camera turned about the target: other triangles, other pixels, one size.
    let turned: Vec<(f32, Scene)> = [0.0f32, 0.3, 0.6]
        .into_iter()
        .map(|turn| {
            let mut s = scene.clone();
            let c = &mut s.camera;
            let (sin, cos) = turn.sin_cos();
            let d = c.position - c.target;
            c.position = c.target + Vec3::new(cos * d.x + sin * d.z, d.y, -sin * d.x + cos * d.z);
            (turn, s)
        })
        .collect();
    // One turn round sizes the buffers for the largest of the frames (a view with more
    // triangles set up grows their list once); the next turn round is the steady state.
    let mut ctx = FrameContext::default();
    for (_, s) in &turned {
        render::render_into(s, &opts, &mut ctx);
    }
    for (turn, s) in &turned {
        let (_, steady) = measure(&g, || {
            render::render_into(s, &opts, &mut ctx).image.pixels.len()
        });
        assert!(
            steady < STEADY_FRAME_ALLOC,
            "a steady-state frame (turn {turn}) requested {steady} bytes at once"
        );
    }
}

/// Largest single allocation a steady-state frame may make: the frame's small lists (the
/// light layout decided per frame, per-band results), far below any frame buffer (the
/// 320 x 240 image is 921,600 bytes, its visibility 307,200).
const STEADY_FRAME_ALLOC: usize = 64 << 10;
