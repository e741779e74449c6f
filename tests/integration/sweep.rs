//! `brdfkit sweep` and `brdfkit render --turntable` on many machines: shards merge into
//! exactly what one run writes.
//!
//! The sweep's CSV has deterministic columns (index .. default: the configuration, its errors
//! against the reference, the default flag) and measured ones (prep_ms, frame_ms and the
//! pareto flag computed from frame_ms). Only the deterministic columns can agree between
//! two runs, so only they are compared; the measured ones differ run to run by nature.
//! The scene is tiny (32x24, a 16x8 probe, so the full-probe reference has 128 lights) to
//! keep the test fast. Its grid has both methods: lights (sampler x count) and transfer (an
//! 8x5 table with 0 or 2 exact lights), and a transfer row's error is checked against
//! `brdfkit render` of the same `[env] method = "transfer"` scene, an independent path.

use std::path::{Path, PathBuf};

use crate::common;

/// Runs `brdfkit args` in `dir` (light-set cache in `dir/env-cache`), asserting success;
/// returns stderr.
fn brdfkit(dir: &Path, args: &[&str]) -> String {
    let r = common::brdfkit(dir).cache(&dir.join("env-cache")).run(args);
    assert!(r.success(), "{args:?} failed: {}", r.stderr);
    r.stderr
}

/// A small probe: dim sky, a bright warm sun and a blue patch, 16x8 texels.
fn write_probe(path: &Path) {
    exr::prelude::write_rgb_file(path, 16, 8, |x, y| {
        if (x, y) == (5, 2) {
            (40.0f32, 30.0, 20.0)
        } else if (x, y) == (12, 3) {
            (1.0, 2.0, 8.0)
        } else if y < 4 {
            (0.4, 0.5, 0.7)
        } else {
            (0.1, 0.1, 0.1)
        }
    })
    .unwrap();
}

fn setup() -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    write_probe(&d.path().join("probe.exr"));
    std::fs::write(
        d.path().join("scene.toml"),
        "[material]\nkind = \"library\"\nname = \"blue-silk\"\n\n[env]\nfile = \"probe.exr\"\ncount = 4\n\n[render]\nwidth = 32\nheight = 24\n",
    )
    .unwrap();
    d
}

const GRID: [&str; 16] = [
    "--samplers",
    "lloyd,importance",
    "--counts",
    "1,4,16",
    "--orders",
    "2,8",
    "--lookups",
    "bilinear",
    "--transfer-grids",
    "8x5",
    "--exact-lights",
    "0,2",
    "--frames",
    "1",
    "--cache",
    "ref-cache",
];

fn deterministic(csv: &Path) -> Vec<String> {
    std::fs::read_to_string(csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .take(brdfkit::sweep::DETERMINISTIC_COLUMNS)
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect()
}

#[test]
fn shards_merge_into_the_single_run() {
    let d = setup();
    let dir = d.path();
    let run = |extra: &[&str]| {
        let mut args = vec!["sweep", "--scene", "scene.toml"];
        args.extend_from_slice(&GRID);
        args.extend_from_slice(extra);
        brdfkit(dir, &args)
    };
    let first = run(&["-o", "all.csv", "--plot", "all.png"]);
    assert!(first.contains("rendering the reference"), "{first}");
    assert!(dir.join("all.png").is_file());
    let all = deterministic(&dir.join("all.csv"));
    // 12 lights rows (2 samplers x 3 counts x 2 orders), then 4 transfer rows (2 exact
    // light counts x 2 orders).
    assert_eq!(all.len(), 16);
    assert!(
        all[11].starts_with("11,lights,importance,16,-,-,-,-,-,-,8,"),
        "{all:?}"
    );
    assert!(
        all[12].starts_with("12,transfer,-,-,8,5,0,-,-,-,2,"),
        "{all:?}"
    );
    assert!(
        all[15].starts_with("15,transfer,-,-,8,5,2,-,-,-,8,"),
        "{all:?}"
    );
    // Exactly one default row: the scene's lloyd (default sampler), 4 lights, 8 bands,
    // bilinear (the library's lookup), f32.
    let defaults: Vec<&String> = all.iter().filter(|l| l.ends_with(",1")).collect();
    assert_eq!(defaults.len(), 1, "{all:?}");
    assert!(
        defaults[0].contains(",lights,lloyd,4,-,-,-,-,-,-,8,bilinear,f32,"),
        "{defaults:?}"
    );
    // The last transfer row (8x5 table, 2 exact lights, 8 bands) against `brdfkit render`
    // of that scene: the same relative RMSE against the cached reference (the background
    // is black in both images, so the whole frame's sums are the covered pixels').
    std::fs::write(
        dir.join("transfer.toml"),
        "[material]\nkind = \"library\"\nname = \"blue-silk\"\n\n[env]\nfile = \"probe.exr\"\nmethod = \"transfer\"\ntransfer_azimuth = 8\ntransfer_polar = 5\nexact_lights = 2\n\n[render]\nwidth = 32\nheight = 24\n",
    )
    .unwrap();
    brdfkit(dir, &["render", "transfer.toml", "-o", "transfer.exr"]);
    let reference: Vec<PathBuf> = std::fs::read_dir(dir.join("ref-cache"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "exr"))
        .collect();
    let reference = brdfkit::image_io::read_exr(&reference[0]).unwrap();
    let rendered = brdfkit::image_io::read_exr(&dir.join("transfer.exr")).unwrap();
    let want = brdfkit::metrics::relative_rmse(&reference, &rendered, None);
    let stored: f64 = all[15].split(',').nth(13).unwrap().parse().unwrap();
    assert!(
        want > 0.0 && (stored - want).abs() <= 1e-12 * want,
        "sweep {stored}, render {want}"
    );
    // Seeded faults: a sweep that built another table for that row (no exact lights, row
    // 13; 2 bands, row 14) would fail this comparison.
    for wrong in [13, 14] {
        let e: f64 = all[wrong].split(',').nth(13).unwrap().parse().unwrap();
        assert!((e - want).abs() > 1e-6 * want, "row {wrong}: {e} vs {want}");
    }

    for n in [2usize, 3] {
        let mut parts = Vec::new();
        for i in 0..n {
            let name = format!("s{i}of{n}.csv");
            let shard = format!("{i}/{n}");
            let err = run(&["--shard", &shard, "-o", &name]);
            assert!(err.contains("(cached)"), "the reference is reused: {err}");
            let rows = deterministic(&dir.join(&name));
            assert!(rows.iter().all(|r| {
                let k: usize = r.split(',').next().unwrap().parse().unwrap();
                k % n == i
            }));
            parts.push(name);
        }
        let mut args = vec!["sweep", "--merge"];
        args.extend(parts.iter().map(String::as_str));
        args.extend(["-o", "merged.csv"]);
        brdfkit(dir, &args);
        assert_eq!(deterministic(&dir.join("merged.csv")), all, "{n} shards");
        // Every shard but one: the gap in the row indices is an error naming the rows.
        for left_out in 0..n {
            let mut args = vec!["sweep", "--merge"];
            args.extend(
                parts
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| *k != left_out)
                    .map(|(_, p)| p.as_str()),
            );
            args.extend(["-o", "partial.csv"]);
            let out = common::brdfkit(dir)
                .cache(&dir.join("env-cache"))
                .run(&args);
            let err = out.stderr;
            assert_eq!(out.code, Some(2), "shard {left_out}/{n} left out: {err}");
            assert!(
                err.contains("missing from the merge")
                    && err.contains(&format!("rows {left_out} to")),
                "{err}"
            );
            assert!(!dir.join("partial.csv").exists());
        }
    }

    // The cached reference is checked on read: an edited one (every pixel +1%, still a
    // valid EXR) is refused, rendered again and rewritten, with the same rows.
    let cached: Vec<PathBuf> = std::fs::read_dir(dir.join("ref-cache"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "exr"))
        .collect();
    assert_eq!(cached.len(), 1, "{cached:?}");
    let mut img = brdfkit::image_io::read_exr(&cached[0]).unwrap();
    for p in &mut img.pixels {
        *p *= 1.01;
    }
    brdfkit::image_io::write_exr(&cached[0], &img).unwrap();
    let err = run(&["-o", "edited.csv"]);
    assert!(
        err.contains("cached reference ignored") && err.contains("rendering the reference"),
        "an edited reference was used: {err}"
    );
    assert_eq!(deterministic(&dir.join("edited.csv")), all);
    assert!(
        run(&["-o", "edited.csv"]).contains("(cached)"),
        "not rewritten"
    );
    // --no-cache: the same rows, and no cache directory is created.
    let mut args = vec!["sweep", "--scene", "scene.toml"];
    args.extend_from_slice(&GRID[..GRID.len() - 2]);
    args.extend(["--no-cache", "-o", "nocache.csv"]);
    let err = brdfkit(dir, &args);
    assert!(err.contains("--no-cache: not stored"), "{err}");
    assert_eq!(deterministic(&dir.join("nocache.csv")), all);
    assert!(
        !dir.join("target").exists(),
        "--no-cache wrote the default cache"
    );

    // Merging is exact on every column: one run's CSV merged alone is itself.
    brdfkit(dir, &["sweep", "--merge", "all.csv", "-o", "again.csv"]);
    assert_eq!(
        std::fs::read_to_string(dir.join("all.csv")).unwrap(),
        std::fs::read_to_string(dir.join("again.csv")).unwrap()
    );
    // Errors fall as the light count grows on the largest order (Lloyd is a deterministic
    // sampler; 16 lights beat 1 light by far under this probe).
    let rmse = |l: &str| l.split(',').nth(13).unwrap().parse::<f64>().unwrap();
    let mc: Vec<&String> = all
        .iter()
        .filter(|l| l.contains(",lloyd,") && l.contains(",8,bilinear,"))
        .collect();
    assert!(rmse(mc[2]) < rmse(mc[0]), "{mc:?}");
}

fn turntable(dir: &Path, out: &str, extra: &[&str]) -> String {
    let mut args = vec![
        "render",
        "--env",
        "probe.exr",
        "--material",
        "blue-silk",
        "--lights",
        "8",
        "--width",
        "32",
        "--height",
        "24",
        "--turntable",
        "5",
        "-o",
        out,
    ];
    args.extend_from_slice(extra);
    brdfkit(dir, &args)
}

fn frames(dir: &Path, stem: &str) -> Vec<PathBuf> {
    (0..5)
        .map(|k| dir.join(format!("{stem}_{k:04}.png")))
        .collect()
}

fn gif_frames(path: &Path) -> usize {
    use image::AnimationDecoder;
    let f = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    image::codecs::gif::GifDecoder::new(f)
        .unwrap()
        .into_frames()
        .count()
}

#[test]
fn turntable_shards_are_bit_identical_and_the_gif_has_every_frame() {
    let d = setup();
    let dir = d.path();
    turntable(dir, "spin.png", &[]);
    let single = frames(dir, "spin");
    assert_eq!(gif_frames(&dir.join("spin.gif")), 5);

    std::fs::create_dir(dir.join("sh")).unwrap();
    write_probe(&dir.join("sh/probe.exr"));
    let sh = dir.join("sh");
    for s in ["0/2", "1/2"] {
        let err = turntable(&sh, "spin.png", &["--shard", s]);
        assert!(err.contains("no GIF"), "{err}");
    }
    assert!(!sh.join("spin.gif").exists());
    for (a, b) in single.iter().zip(frames(&sh, "spin")) {
        assert_eq!(
            std::fs::read(a).unwrap(),
            std::fs::read(&b).unwrap(),
            "{}",
            b.display()
        );
    }
    // Frames differ from one another (the camera moves).
    assert_ne!(
        std::fs::read(&single[0]).unwrap(),
        std::fs::read(&single[1]).unwrap()
    );
    turntable(&sh, "spin.png", &["--assemble"]);
    assert_eq!(
        std::fs::read(dir.join("spin.gif")).unwrap(),
        std::fs::read(sh.join("spin.gif")).unwrap()
    );

    // Turning the probe: frame 0 is the unturned scene, later frames differ.
    turntable(dir, "env.png", &["--turntable-env"]);
    let env = frames(dir, "env");
    assert_eq!(
        std::fs::read(&env[0]).unwrap(),
        std::fs::read(&single[0]).unwrap()
    );
    assert_ne!(
        std::fs::read(&env[0]).unwrap(),
        std::fs::read(&env[2]).unwrap()
    );
    assert_eq!(gif_frames(&dir.join("env.gif")), 5);
}
