//! `brdfkit cache` shows the caches and `cache clean` empties them, deleting nothing else;
//! the user's cache keeps to its cap.

use crate::common;

#[test]
fn cache_shows_and_cleans_only_its_own_files() {
    let tmp = tempfile::tempdir().unwrap();
    let lights = tmp.path().join("lights");
    let sweep = tmp.path().join("sweep");
    std::fs::create_dir_all(&lights).unwrap();
    std::fs::create_dir_all(&sweep).unwrap();
    std::fs::write(lights.join("lights-0123456789abcdef.json"), "{}").unwrap();
    std::fs::write(lights.join("notes.txt"), "keep me").unwrap();
    std::fs::write(sweep.join("reference-0123456789abcdef.exr"), [0u8; 100]).unwrap();
    std::fs::write(sweep.join("reference-0123456789abcdef.exr.xxh3"), "1").unwrap();
    let run = |args: &[&str]| {
        let mut all = vec!["cache"];
        all.extend(args);
        all.extend(["--sweep-cache", sweep.to_str().unwrap()]);
        let out = common::brdfkit(tmp.path()).cache(&lights).run(&all);
        assert!(out.success(), "{}", out.stderr);
        out.stdout
    };
    let shown = run(&[]);
    assert!(
        shown.contains("1 files, 2 B") && shown.contains("2 files, 101 B"),
        "{shown}"
    );
    let cleaned = run(&["clean"]);
    assert!(
        cleaned.contains("removed 1 files") && cleaned.contains("removed 2 files"),
        "{cleaned}"
    );
    assert!(
        lights.join("notes.txt").exists(),
        "a file the cache did not write was deleted"
    );
    assert_eq!(std::fs::read_dir(&sweep).unwrap().count(), 0);
    assert!(run(&[]).contains("0 files, 0 B"));
}

/// The user's cache keeps to its cap: with `BRDFKIT_CACHE_MAX_MB` just above one light-set
/// entry, a second render with other settings evicts the first entry (the least recently
/// used) and keeps its own; `brdfkit cache` states the cap; a cap that is not a number is
/// one error line naming the variable.
#[test]
fn the_user_cache_evicts_the_least_recently_used_past_its_cap() {
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let probe = common::city_probe();
    let render = |count: &str, cap: &str| {
        let out = common::brdfkit(tmp.path())
            .cache(&cache)
            .env("BRDFKIT_CACHE_MAX_MB", cap)
            .run(&[
                "render",
                "--env",
                &probe,
                "--env-method",
                "lights",
                "--lights",
                count,
                "--width",
                "16",
                "--height",
                "12",
                "-o",
                "x.png",
            ]);
        assert!(out.success(), "{}", out.stderr);
    };
    let entries = || -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(&cache)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with("lights-"))
            .collect();
        v.sort();
        v
    };
    render("8", "100");
    let first = entries();
    assert_eq!(first.len(), 1, "{first:?}");
    let one = std::fs::metadata(cache.join(&first[0])).unwrap().len();
    // A cap of 1.5 entries (in MB): the second entry evicts the first.
    let cap = format!("{}", 1.5 * one as f64 / 1e6);
    render("16", &cap);
    let second = entries();
    assert_eq!(second.len(), 1, "{second:?}");
    assert_ne!(
        second, first,
        "the new entry was evicted instead of the old one"
    );
    let shown = common::brdfkit(tmp.path())
        .cache(&cache)
        .env("BRDFKIT_CACHE_MAX_MB", "250")
        .run(&["cache"]);
    assert!(shown.success(), "{}", shown.stderr);
    assert!(shown.stdout.contains("cap 250.0 MB"), "{}", shown.stdout);
    let bad = common::brdfkit(tmp.path())
        .cache(&cache)
        .env("BRDFKIT_CACHE_MAX_MB", "lots")
        .run(&["cache"]);
    assert!(!bad.success());
    assert!(
        bad.stderr.trim().lines().count() == 1 && bad.stderr.contains("BRDFKIT_CACHE_MAX_MB"),
        "{}",
        bad.stderr
    );
}
