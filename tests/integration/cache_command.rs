//! `brdfkit cache` shows both caches and `cache clean` empties them, deleting nothing else.

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
