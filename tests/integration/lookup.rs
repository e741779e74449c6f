//! `brdfkit render --lookup` and the lookup an SH file records (`brdfkit.lookup`, see
//! `src/sh/file/mod.rs`): an acquired file renders with the lookup it records (bilinear)
//! unless `--lookup` says otherwise; a file without the attribute keeps nearest; `--lookup`
//! on a material without a coefficient table is an error naming `--lookup`.
//!
//! Each render is compared with the same file rendered with an explicit `--lookup`: the
//! expectation is the meaning of the flag, not a stored image.

use brdfkit::image_io::read_exr;
use brdfkit::sh::{read_sh_dataset, Lookup};
use exr::prelude::{read, ReadChannels, ReadLayers, WritableImage};
use std::path::{Path, PathBuf};

use crate::common;
use common::run_in;

/// Renders `material` (48x36, teapot/8) with the extra `args` into `dir/name.exr`; returns the
/// linear pixels.
fn render(dir: &Path, material: &str, args: &[&str], name: &str) -> Vec<f32> {
    let out = dir.join(format!("{name}.exr"));
    let mut all = vec![
        "render",
        "--material",
        material,
        "--width",
        "48",
        "--height",
        "36",
        "--no-cache",
        "-o",
        out.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    let (ok, err) = run_in(dir, &all);
    assert!(ok, "render {all:?}: {err}");
    let img = read_exr(&out).unwrap();
    img.pixels.iter().flat_map(|p| p.to_array()).collect()
}

/// `brdfkit acquire teal-paint` (3 bands, 8x4 view texels, no table) into `dir/name`.
fn acquire(dir: &Path, name: &str) -> PathBuf {
    let (ok, err) = run_in(
        dir,
        &[
            "acquire",
            "teal-paint",
            "--bands",
            "3",
            "--method",
            "lsq",
            "--grid",
            "8x4",
            "--no-table",
            "-o",
            name,
        ],
    );
    assert!(ok, "acquire: {err}");
    dir.join(name)
}

/// Rewrites an SH file without its `brdfkit.lookup` attribute (a file from before it existed).
fn strip_lookup(p: &Path) {
    let mut img = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(p)
        .unwrap();
    for l in &mut img.layer_data {
        l.attributes.other.retain(|k, _| !k.eq("brdfkit.lookup"));
    }
    img.write().to_file(p).unwrap();
}

#[test]
fn an_acquired_file_renders_with_its_recorded_bilinear_lookup() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let file = acquire(dir, "teal.exr");
    assert_eq!(
        read_sh_dataset(&file).unwrap().coeff_lookup,
        Lookup::Bilinear
    );
    let f = file.to_str().unwrap();
    let plain = render(dir, f, &[], "plain");
    let bilinear = render(dir, f, &["--lookup", "bilinear"], "bilinear");
    let nearest = render(dir, f, &["--lookup", "nearest"], "nearest");
    assert_eq!(
        plain, bilinear,
        "no flag: the file's recorded lookup (bilinear)"
    );
    assert_ne!(
        bilinear, nearest,
        "the two lookups must give different images"
    );
    // A scene file's lookup overrides the file's; --lookup overrides the scene's.
    std::fs::write(
        dir.join("scene.toml"),
        "[material]\nkind = \"sh-file\"\npath = \"teal.exr\"\nlookup = \"nearest\"\n",
    )
    .unwrap();
    let scene_render = |args: &[&str], name: &str| {
        let out = dir.join(format!("{name}.exr"));
        let mut all = vec![
            "render",
            "scene.toml",
            "--width",
            "48",
            "--height",
            "36",
            "-o",
            out.to_str().unwrap(),
        ];
        all.extend_from_slice(args);
        let (ok, err) = run_in(dir, &all);
        assert!(ok, "{err}");
        let img = read_exr(&out).unwrap();
        img.pixels
            .iter()
            .flat_map(|p| p.to_array())
            .collect::<Vec<f32>>()
    };
    assert_eq!(scene_render(&[], "scene"), nearest);
    assert_eq!(
        scene_render(&["--lookup", "bilinear"], "scene-bil"),
        bilinear
    );
    // Seeded fault: the same file without the attribute renders nearest, so the first
    // check above (no flag == bilinear) fails on it.
    strip_lookup(&file);
    let stripped = render(dir, f, &[], "stripped");
    assert_ne!(
        stripped, bilinear,
        "the check must catch a file without the record"
    );
    assert_eq!(stripped, nearest);
}

#[test]
fn an_old_file_without_the_attribute_keeps_nearest_and_lookup_overrides_it() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let old = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden/magenta-plastic-5b-8x4.exr");
    assert_eq!(read_sh_dataset(&old).unwrap().coeff_lookup, Lookup::Nearest);
    let o = old.to_str().unwrap();
    let plain = render(dir, o, &[], "plain");
    let nearest = render(dir, o, &["--lookup", "nearest"], "nearest");
    let bilinear = render(dir, o, &["--lookup", "bilinear"], "bilinear");
    assert_eq!(plain, nearest);
    assert_ne!(plain, bilinear);
    // The library material is bilinear; --lookup nearest overrides it.
    let lib = render(dir, "magenta-plastic", &[], "lib");
    let lib_nearest = render(dir, "magenta-plastic", &["--lookup", "nearest"], "lib-n");
    let lib_bilinear = render(dir, "magenta-plastic", &["--lookup", "bilinear"], "lib-b");
    assert_eq!(lib, lib_bilinear);
    assert_ne!(lib, lib_nearest);
}

#[test]
fn lookup_on_a_material_without_a_coefficient_table_is_an_error_naming_the_flag() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (ok, err) = run_in(
        dir,
        &[
            "fit-dbrdf",
            "lindt-paper",
            "--grid",
            "8x8",
            "-o",
            "lindt.exr",
        ],
    );
    assert!(ok, "fit-dbrdf: {err}");
    std::fs::write(dir.join("lambert.toml"), "[material]\nkind = \"lambert\"\n").unwrap();
    for args in [
        &["render", "--material", "lindt-paper"][..],
        &["render", "--material", "lindt.exr"],
        &["render"],
        &["render", "lambert.toml"],
    ] {
        let mut all = args.to_vec();
        all.extend([
            "--lookup", "nearest", "--width", "8", "--height", "6", "-o", "x.exr",
        ]);
        let (ok, err) = run_in(dir, &all);
        assert!(!ok, "{all:?} succeeded");
        assert!(
            err.contains("--lookup") && err.contains("not an SH data set"),
            "{all:?}: {err}"
        );
        assert!(!dir.join("x.exr").exists(), "{all:?} wrote an image");
    }
}
