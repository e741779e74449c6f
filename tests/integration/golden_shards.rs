//! The golden set in shards: `golden check --shard I/N --json` reports merged into one
//! verdict with the exit status of an unsharded check (0 pass, 1 a failure, 2 unusable
//! input: a shard missing or given twice); `golden bless --shard I/N --records` run at once
//! in N processes, then `golden bless --merge`, leave golden/ byte for byte as one
//! `golden bless` does.

use super::golden::golden_copy;
use crate::common::brdfkit;
use std::path::Path;

/// AOV entries (no shading: quick) and one shaded entry (its fast-vs-reference bound is
/// measured on bless), in manifest order.
const NAMES: &[&str] = &[
    "fig3-1-point-light-polar",
    "fig3-1-point-light-azimuth",
    "fig3-1-point-light-lambert",
    "fig3-2-directional-light-polar",
    "debug-normal",
];

fn args<'a>(head: &[&'a str], tail: &[&'a str]) -> Vec<&'a str> {
    [head, NAMES, tail].concat()
}

#[test]
fn sharded_check_merges_into_one_verdict() {
    let tmp = golden_copy(&[]);
    let dir = tmp.path().display().to_string();
    let cli = brdfkit(tmp.path());
    let check = ["golden", "check", "--dir", &dir];
    let shard = |i: usize, n: usize, out: &str| {
        let spec = format!("{i}/{n}");
        let r = cli.run(&args(&check, &["--shard", &spec, "--json", out]));
        assert_eq!(r.code, Some(0), "shard {spec}: {}{}", r.stdout, r.stderr);
        r.stdout
    };
    // Shard 1/2 takes entries 1 and 3 of the selection.
    let out = shard(1, 2, "r1.json");
    assert!(
        out.contains("fig3-1-point-light-azimuth")
            && out.contains("fig3-2-directional-light-polar")
    );
    assert!(
        !out.contains("fig3-1-point-light-polar ") && !out.contains("debug-normal"),
        "{out}"
    );
    shard(0, 2, "r0.json");
    let merge = |files: &[&str]| {
        let mut a = vec!["golden", "check", "--merge"];
        a.extend(files);
        cli.run(&a)
    };
    let r = merge(&["r1.json", "r0.json"]);
    assert_eq!(r.code, Some(0), "{}{}", r.stdout, r.stderr);
    assert!(
        r.stdout
            .contains("golden check: 5 entries, 5 passed, 0 failed"),
        "{}",
        r.stdout
    );
    // A shard missing, one given twice: unusable input.
    for (files, words) in [
        (&["r0.json"][..], &["--merge", "shard 1/2 missing"][..]),
        (
            &["r0.json", "r0.json", "r1.json"][..],
            &["r0.json", "given twice"][..],
        ),
    ] {
        let r = merge(files);
        assert_eq!(r.code, Some(2), "{files:?}: {}{}", r.stdout, r.stderr);
        assert!(words.iter().all(|w| r.stderr.contains(w)), "{}", r.stderr);
        assert_eq!(r.stderr.trim_end().lines().count(), 1, "{}", r.stderr);
    }
    // A report of another selection (3 shards of all entries would be another split too).
    let r = cli.run(&[
        "golden",
        "check",
        "--dir",
        &dir,
        "debug-normal",
        "--shard",
        "1/2",
        "--json",
        "other.json",
    ]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let r = merge(&["r0.json", "other.json"]);
    assert_eq!(r.code, Some(2));
    assert!(
        r.stderr.contains("other.json") && r.stderr.contains("selection"),
        "{}",
        r.stderr
    );
    // Seeded fault: one stored image changed (its hash no longer matches); the shard that
    // holds it fails, and so does the merge, with status 1 as an unsharded check.
    let img = tmp.path().join("debug-normal.exr");
    let mut bad = brdfkit::image_io::read_exr(&img).unwrap();
    bad.pixels[0].x += 0.25;
    brdfkit::image_io::write_exr(&img, &bad).unwrap();
    let r = cli.run(&args(&check, &["--shard", "0/2", "--json", "r0.json"]));
    assert_eq!(r.code, Some(1), "{}", r.stdout);
    let r = merge(&["r0.json", "r1.json"]);
    assert_eq!(r.code, Some(1), "{}{}", r.stdout, r.stderr);
    assert!(
        r.stdout.contains("debug-normal") && r.stdout.contains("FAIL"),
        "{}",
        r.stdout
    );
    let r = cli.run(&args(&check, &[]));
    assert_eq!(r.code, Some(1), "unsharded: {}", r.stdout);
}

/// The files bless writes for `NAMES`, with their contents.
fn blessed_files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files = vec!["manifest.toml".to_string(), "README.md".to_string()];
    for n in NAMES {
        files.push(format!("{n}.exr"));
        files.push(format!("{n}.png"));
    }
    files
        .into_iter()
        .map(|f| {
            // An EXR's pixel bits (its chunks may be written in any order: the bytes of
            // two writes of one image can differ); every other file's bytes.
            let bytes = match f.ends_with(".exr") {
                true => brdfkit::image_io::read_exr(&dir.join(&f))
                    .unwrap()
                    .pixels
                    .iter()
                    .flat_map(|p| p.to_array().map(f32::to_le_bytes))
                    .flatten()
                    .collect(),
                false => std::fs::read(dir.join(&f)).unwrap(),
            };
            (f, bytes)
        })
        .collect()
}

/// A copy of golden/ whose records are stale (every hash replaced) and without the images
/// of `NAMES`: a bless that does not write them all fails the comparison below.
fn stale_copy() -> tempfile::TempDir {
    let tmp = golden_copy(&[]);
    let m = tmp.path().join("manifest.toml");
    let text = std::fs::read_to_string(&m).unwrap();
    std::fs::write(&m, text.replace("hash = \"xxh3-64:", "hash = \"stale:")).unwrap();
    for n in NAMES {
        for ext in ["exr", "png"] {
            std::fs::remove_file(tmp.path().join(format!("{n}.{ext}"))).unwrap();
        }
    }
    tmp
}

#[test]
fn parallel_bless_shards_leave_what_one_bless_leaves() {
    let one = stale_copy();
    let dir1 = one.path().display().to_string();
    let r = brdfkit(one.path()).run(&args(&["golden", "bless", "--dir", &dir1], &[]));
    assert!(r.success(), "{}", r.stderr);

    let many = stale_copy();
    let dir = many.path().display().to_string();
    let before = std::fs::read(many.path().join("manifest.toml")).unwrap();
    let n = 3;
    std::thread::scope(|s| {
        for i in 0..n {
            let dir = &dir;
            let path = many.path();
            s.spawn(move || {
                let (spec, rec) = (format!("{i}/{n}"), format!("rec{i}.toml"));
                let r = brdfkit(path).run(&args(
                    &["golden", "bless", "--dir", dir],
                    &["--shard", &spec, "--records", &rec],
                ));
                assert!(r.success(), "shard {spec}: {}", r.stderr);
            });
        }
    });
    // The shards wrote images only: the manifest waits for the merge.
    assert_eq!(
        std::fs::read(many.path().join("manifest.toml")).unwrap(),
        before
    );
    let cli = brdfkit(many.path());
    // A shard missing: refused, nothing written.
    let r = cli.run(&[
        "golden",
        "bless",
        "--dir",
        &dir,
        "--merge",
        "rec0.toml",
        "rec2.toml",
    ]);
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert!(r.stderr.contains("shard 1/3 missing"), "{}", r.stderr);
    assert_eq!(
        std::fs::read(many.path().join("manifest.toml")).unwrap(),
        before
    );
    let r = cli.run(&[
        "golden",
        "bless",
        "--dir",
        &dir,
        "--merge",
        "rec2.toml",
        "rec0.toml",
        "rec1.toml",
    ]);
    assert!(r.success(), "{}", r.stderr);
    let (a, b) = (blessed_files(one.path()), blessed_files(many.path()));
    let manifest = String::from_utf8(b[0].1.clone()).unwrap();
    for n in NAMES {
        let at = manifest.find(&format!("name = \"{n}\"")).unwrap();
        assert!(
            manifest[at..]
                .split("[[entry]]")
                .next()
                .unwrap()
                .contains("hash = \"xxh3-64:"),
            "{n} not re-blessed"
        );
    }
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(
            x == y,
            "{name} differs between one bless and {n} merged shards"
        );
    }
}
