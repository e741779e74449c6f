//! No hidden state: `brdfkit golden check` gives the same verdicts with a cold light-set
//! cache and with a deliberately corrupted one, because it never reads (nor writes) a
//! cache; `brdfkit render`, which does read one, is shown to consume the same corrupted
//! cache (so the corruption is one a cache reader would act on, and it would fail the
//! golden check if the check read it).
//!
//! Every child process gets its own `BRDFKIT_CACHE_DIR`, `XDG_CACHE_HOME` and `HOME` in a
//! temporary directory (set on the child only: this process's environment is never changed),
//! so nothing here reads or writes the user's cache.

use brdfkit::env::lightset::prepare::{lights_checksum, CacheEntry};
use brdfkit::golden::{self, KERNEL_DISPATCH};
use brdfkit::image_io::read_exr;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Golden entries lit by an environment (each entry's scene file is `<name>.toml`), both at
/// the `kernel-dispatch` tolerance: median cut on the city probe, Lloyd on the studio probe.
const ENTRIES: [&str; 2] = ["fig3-8-median-cut-city", "fig3-8-lloyd-studio"];

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("golden")
}

use crate::common;

/// Runs the binary in `cwd` with every cache variable pointing into `cache` (which
/// `BRDFKIT_CACHE_DIR` names, the first one consulted).
fn brdfkit(cwd: &Path, cache: &Path, args: &[&str]) -> common::Run {
    common::brdfkit(cwd)
        .cache(cache)
        .env("XDG_CACHE_HOME", cache.join("xdg"))
        .env("HOME", cache.join("home"))
        .run(args)
}

/// Every file under `dir` (recursively) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut m = BTreeMap::new();
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd {
            let p = e.unwrap().path();
            if p.is_dir() {
                m.extend(snapshot(&p));
            } else {
                m.insert(p.clone(), std::fs::read(&p).unwrap());
            }
        }
    }
    m
}

/// Renders an entry's scene to `<name>.exr` in `cwd` through the light-set cache `cache`;
/// returns the image and stderr.
fn render(cwd: &Path, cache: &Path, name: &str) -> (brdfkit::image_io::Image, String) {
    let scene = golden_dir().join(format!("{name}.toml"));
    let out = cwd.join(format!("{name}.exr"));
    let o = brdfkit(
        cwd,
        cache,
        &[
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
    );
    let err = o.stderr.clone();
    assert!(o.success(), "render {name}: {err}");
    (read_exr(&out).unwrap(), err)
}

/// Pixels of `actual` outside the entry's tolerance against the stored golden image.
fn pixels_over(name: &str, actual: &brdfkit::image_io::Image) -> (f32, usize) {
    let stored = read_exr(&golden_dir().join(format!("{name}.exr"))).unwrap();
    golden::compare(&stored, actual, KERNEL_DISPATCH).expect("same size")
}

#[test]
fn golden_check_ignores_cold_and_corrupted_caches_alike() {
    let tmp = tempfile::tempdir().unwrap();
    let (cold, warm) = (tmp.path().join("cold"), tmp.path().join("warm"));
    std::fs::create_dir_all(&cold).unwrap();
    let golden = golden_dir();
    let check = |cache: &Path| {
        let mut args = vec!["golden", "check", "--dir", golden.to_str().unwrap()];
        args.extend(ENTRIES);
        brdfkit(tmp.path(), cache, &args)
    };

    // 1. Cold cache: every entry passes, and nothing is written to any cache directory.
    let first = check(&cold);
    let first_out = first.stdout.clone();
    assert!(first.success(), "cold: {first_out}{}", first.stderr);
    for name in ENTRIES {
        assert!(
            first_out
                .lines()
                .any(|l| l.starts_with(name) && l.contains(" pass ")),
            "cold: {name} does not pass:\n{first_out}"
        );
    }
    assert!(
        snapshot(&cold).is_empty(),
        "golden check wrote a cache: {:?}",
        snapshot(&cold).keys()
    );

    // `render --no-cache` neither writes nor reads the cache either.
    let scene = golden.join(format!("{}.toml", ENTRIES[0]));
    let o = brdfkit(
        tmp.path(),
        &cold,
        &[
            "render",
            scene.to_str().unwrap(),
            "--no-cache",
            "-o",
            "nc.exr",
        ],
    );
    assert!(o.success(), "{}", o.stderr);
    assert!(
        snapshot(&cold).is_empty(),
        "render --no-cache wrote a cache"
    );

    // 2. Fill a cache the way a user's fills: `brdfkit render` of each entry's scene.
    //    Renders through it match the stored images (0 pixels over the tolerance).
    let mut entries = Vec::new();
    for name in ENTRIES {
        let before = snapshot(&warm);
        let (img, err) = render(tmp.path(), &warm, name);
        assert!(
            !err.contains("(cached)"),
            "{name}: the cache was not empty: {err}"
        );
        let (max_abs, over) = pixels_over(name, &img);
        eprintln!(
            "{name}: render through a fresh cache: max abs {max_abs:.3e}, {over} pixels over"
        );
        assert_eq!(
            over, 0,
            "{name}: a fresh render does not match its golden image"
        );
        let added: Vec<PathBuf> = snapshot(&warm)
            .into_keys()
            .filter(|p| !before.contains_key(p))
            .collect();
        assert_eq!(
            added.len(),
            1,
            "{name}: one light-set entry expected: {added:?}"
        );
        entries.push(added[0].clone());
    }

    // 3. Corrupt it. Entry 0: every light's power +1%, the checksum recomputed so the entry
    //    is self-consistent (as one written by a changed sampler under the same key would
    //    be): a reader that trusts the cache uses it. Entry 1: truncated to half.
    let mut e: CacheEntry = serde_json::from_slice(&std::fs::read(&entries[0]).unwrap()).unwrap();
    let ls = &mut e.lights;
    for p in ls
        .irradiance_r
        .iter_mut()
        .chain(&mut ls.irradiance_g)
        .chain(&mut ls.irradiance_b)
    {
        *p *= 1.01;
    }
    e.lights_checksum = brdfkit::hash::tagged(lights_checksum(&e.lights));
    std::fs::write(&entries[0], serde_json::to_vec(&e).unwrap()).unwrap();
    let bytes = std::fs::read(&entries[1]).unwrap();
    std::fs::write(&entries[1], &bytes[..bytes.len() / 2]).unwrap();
    let corrupted = snapshot(&warm);

    // 4. The corruption matters to a cache reader: `render` uses the forged entry and its
    //    image fails the entry's tolerance (the golden check would fail if it read the
    //    cache); the truncated entry is refused and recomputed.
    let (img, err) = render(tmp.path(), &warm, ENTRIES[0]);
    assert!(
        err.contains("(cached)"),
        "the forged entry was not read: {err}"
    );
    let (max_abs, over) = pixels_over(ENTRIES[0], &img);
    eprintln!(
        "{}: render through the forged entry: max abs {max_abs:.3e}, {over} pixels over",
        ENTRIES[0]
    );
    assert!(
        over > 0,
        "a 1% light-power change is within the golden tolerance"
    );
    let (img, err) = render(tmp.path(), &warm, ENTRIES[1]);
    assert!(
        err.contains("ignored") && !err.contains("(cached)"),
        "the truncated entry was not refused: {err}"
    );
    assert_eq!(pixels_over(ENTRIES[1], &img).1, 0);
    // Restore the corrupted state (render rewrote the truncated entry).
    for (p, b) in &corrupted {
        std::fs::write(p, b).unwrap();
    }

    // 5. Golden check with the corrupted cache: the same verdicts, line for line, and the
    //    cache untouched (a reader that refused the truncated entry would rewrite it).
    let second = check(&warm);
    let second_out = second.stdout.clone();
    assert!(second.success(), "corrupted: {second_out}{}", second.stderr);
    assert_eq!(
        first_out, second_out,
        "verdicts differ between a cold and a corrupted cache"
    );
    assert!(
        snapshot(&warm) == corrupted,
        "golden check changed the cache"
    );
}
