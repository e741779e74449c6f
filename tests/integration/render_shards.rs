//! A still image rendered in shards (`render --shard I/N -o part.exr`) and merged
//! (`render --merge`): the merged image has the bits of the unsharded render, for any N, with
//! any thread count per shard, on the fast path and on the converged reference; the seeded
//! faults (a shard of another scene, of another size, one missing, one given twice, a plain
//! image) are each refused with one line naming the file (or the missing shard), and nothing
//! is written.

use crate::common::{brdfkit, city_probe};
use std::path::Path;

/// The pixels' f32 bits of an EXR.
fn bits(p: &Path) -> Vec<u32> {
    let img = brdfkit::image_io::read_exr(p).unwrap();
    img.pixels
        .iter()
        .flat_map(|v| v.to_array().map(f32::to_bits))
        .collect()
}

/// Renders `scene` whole to `full.exr`, then as `n` shards (shard i on i % 2 + 1 threads)
/// merged into `merged-n.exr`, and asserts identical bits; returns the unsharded bits.
fn assert_shards_merge_exactly(dir: &Path, scene: &[&str], n: usize) -> Vec<u32> {
    let cli = brdfkit(dir);
    let full = dir.join("full.exr");
    if !full.exists() {
        let r = cli.run(&[scene, &["-o", "full.exr"]].concat());
        assert!(r.success(), "{}", r.stderr);
    }
    let mut parts = Vec::new();
    for i in 0..n {
        let (spec, out, threads) = (
            format!("{i}/{n}"),
            format!("part-{i}-of-{n}.exr"),
            (i % 2 + 1).to_string(),
        );
        let r = cli.run(
            &[
                scene,
                &["--shard", &spec, "--threads", &threads, "-o", &out],
            ]
            .concat(),
        );
        assert!(r.success(), "shard {spec}: {}", r.stderr);
        parts.push(out);
    }
    // Given in reverse order: the merge places each by its header.
    parts.reverse();
    let merged = format!("merged-{n}.exr");
    let mut args = vec!["render", "--merge"];
    args.extend(parts.iter().map(String::as_str));
    args.extend(["-o", &merged]);
    let r = cli.run(&args);
    assert!(r.success(), "merge of {n}: {}", r.stderr);
    let want = bits(&full);
    assert!(want.iter().any(|&b| b != 0), "the scene renders something");
    assert!(bits(&dir.join(&merged)) == want, "{n} shards differ");
    want
}

/// The default scene (teapot, point lights, the fast kernels) at 48 x 40 in 8-pixel tiles:
/// 5 bands of 8 rows.
const FAST: &[&str] = &[
    "render",
    "--width",
    "48",
    "--height",
    "40",
    "--tile-size",
    "8",
];

#[test]
fn sharded_still_merges_to_the_unsharded_bits() {
    let d = tempfile::tempdir().unwrap();
    for n in [1, 2, 3] {
        assert_shards_merge_exactly(d.path(), FAST, n);
    }
    // A part holds only its own rows, and a shard's rows are not all black: each shard
    // rendered its part, not the whole frame.
    let part = brdfkit::image_io::shard_part::read_part(&d.path().join("part-1-of-3.exr")).unwrap();
    assert_eq!(part.pixels.len(), 48 * 16, "bands 1 and 4 of 8 rows");
    assert!(part.pixels.iter().any(|p| p.x > 0.0));
    // The PNG of a merge is the PNG of the unsharded render.
    let cli = brdfkit(d.path());
    assert!(cli.run(&[FAST, &["-o", "full.png"]].concat()).success());
    let r = cli.run(&[
        "render",
        "--merge",
        "part-0-of-2.exr",
        "part-1-of-2.exr",
        "-o",
        "merged.png",
    ]);
    assert!(r.success(), "{}", r.stderr);
    assert_eq!(
        std::fs::read(d.path().join("merged.png")).unwrap(),
        std::fs::read(d.path().join("full.png")).unwrap()
    );
}

#[test]
fn sharded_reference_merges_to_the_unsharded_reference() {
    let d = tempfile::tempdir().unwrap();
    let probe = city_probe();
    let scene = [
        "render",
        "--reference",
        "--mesh",
        "sphere",
        "--env",
        &probe,
        "--width",
        "16",
        "--height",
        "24",
        "--tile-size",
        "8",
    ];
    assert_shards_merge_exactly(d.path(), &scene, 3);
}

#[test]
fn merge_refuses_missing_duplicated_and_foreign_shards() {
    let d = tempfile::tempdir().unwrap();
    let cli = brdfkit(d.path());
    let shard = |extra: &[&str], spec: &str, out: &str| {
        let r = cli.run(&[FAST, extra, &["--shard", spec, "-o", out]].concat());
        assert!(r.success(), "{out}: {}", r.stderr);
    };
    shard(&[], "0/3", "a0.exr");
    shard(&[], "1/3", "a1.exr");
    shard(&[], "2/3", "a2.exr");
    // Seeded faults: another material, another size, the same shard of another split.
    shard(&["--material", "teal-paint"], "2/3", "teal2.exr");
    let r = cli.run(&[
        "render",
        "--width",
        "40",
        "--height",
        "40",
        "--tile-size",
        "8",
        "--shard",
        "2/3",
        "-o",
        "narrow2.exr",
    ]);
    assert!(r.success(), "{}", r.stderr);
    shard(&[], "2/4", "a2of4.exr");
    assert!(cli.run(&[FAST, &["-o", "plain.exr"]].concat()).success());
    let refused = |parts: &[&str], words: &[&str]| {
        let mut args = vec!["render", "--merge"];
        args.extend(parts);
        args.extend(["-o", "out.exr"]);
        let r = cli.run(&args);
        assert_eq!(r.code, Some(2), "{parts:?} merged: {}", r.stderr);
        let line = r.stderr.trim_end();
        assert!(!line.contains('\n'), "one line: {line}");
        for w in words {
            assert!(line.contains(w), "{parts:?}: {w:?} not in {line}");
        }
        assert!(
            !d.path().join("out.exr").exists(),
            "{parts:?} wrote out.exr"
        );
    };
    refused(&["a0.exr", "a1.exr"], &["--merge", "shard 2/3 missing"]);
    refused(
        &["a0.exr", "a1.exr", "a1.exr", "a2.exr"],
        &["a1.exr", "given twice"],
    );
    refused(
        &["a0.exr", "a1.exr", "teal2.exr"],
        &["teal2.exr", "another scene"],
    );
    refused(
        &["a0.exr", "a1.exr", "narrow2.exr"],
        &["narrow2.exr", "another"],
    );
    refused(
        &["a0.exr", "a1.exr", "a2of4.exr"],
        &["a2of4.exr", "another split"],
    );
    refused(&["a0.exr", "plain.exr"], &["plain.exr", "not a shard"]);
    // The parts carry the scene and its size: a flag that would change them is refused,
    // not ignored.
    for flag in [
        &["--width", "64"][..],
        &["--material", "teal-paint"],
        &["--mesh", "sphere"],
    ] {
        let mut args = vec!["render", "--merge", "a0.exr", "a1.exr", "a2.exr"];
        args.extend(flag);
        args.extend(["-o", "out.exr"]);
        let r = cli.run(&args);
        assert_eq!(r.code, Some(2), "{flag:?}: {}", r.stderr);
        assert!(
            r.stderr.lines().next().is_some_and(|l| l.contains(flag[0])),
            "{flag:?}: {}",
            r.stderr
        );
        assert!(!d.path().join("out.exr").exists(), "{flag:?} wrote out.exr");
    }
    // The three right parts merge (the refusals above were the faults').
    let r = cli.run(&[
        "render", "--merge", "a0.exr", "a1.exr", "a2.exr", "-o", "out.exr",
    ]);
    assert!(r.success(), "{}", r.stderr);
    // A shard needs a partial EXR to write, and bands to split.
    let r = cli.run(&[FAST, &["--shard", "0/2", "-o", "x.png"]].concat());
    assert!(
        !r.success() && r.stderr.contains("-o PART.exr"),
        "{}",
        r.stderr
    );
    let r = cli.run(&[FAST, &["--shard", "0/6", "-o", "x.exr"]].concat());
    assert!(
        !r.success() && r.stderr.contains("only 5 bands"),
        "{}",
        r.stderr
    );
}
