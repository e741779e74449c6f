//! `[env] method = "reflection"` end to end: a glossy Blinn-Phong sphere against the
//! converged reference (`RenderOptions::converged_reference()` on `sampler = "full"`: f64,
//! every texel a light) under a shipped probe, the same bits for any thread count and tile
//! size, and the scene errors of the method.

use crate::env_table_common::{against_reference, scene};
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::SceneFile;

const GLOSSY: &str =
    "kind = \"blinn-phong\"\nkd = [0.05, 0.05, 0.05]\nks = [0.9, 0.9, 0.9]\nexponent = 50";

/// A small table (24 x 24 cells, 7 + 1 slices: a bake of about a second) with the 64
/// brightest texels exact, under sky (the sun among them) against the converged reference:
/// relative RMSE below 2%; the exact lights alone are far off, so the check sees the table.
#[test]
fn glossy_reflection_table_matches_the_converged_reference() {
    let table = "method = \"reflection\"\nreflection_grid = 24\nreflection_slices = 7";
    let run = against_reference("sky", GLOSSY, table, 64);
    let (s, got, e, e0) = (run.scene, run.image, run.error, run.error_without_table);
    eprintln!("sky: Blinn-Phong 50 reflection table rel RMSE {e:.5}");
    assert!(e < 0.02, "rel RMSE {e}");
    assert!(e0 > 0.05, "the table adds too little ({e0})");
    // Any thread count and tile size: the same bits.
    let opts = RenderOptions {
        threads: Some(1),
        ..RenderOptions::default()
    };
    let mut s2 = s.clone();
    s2.render.tile_size = 8;
    let again = render(&s2, &opts).image;
    assert_eq!(got.pixels, again.pixels);
}

#[test]
fn reflection_fields_are_checked_and_named() {
    for (extra, field) in [
        (
            "method = \"reflection\"\nreflection_grid = 1",
            "env.reflection_grid",
        ),
        (
            "method = \"reflection\"\nreflection_slices = 0",
            "env.reflection_slices",
        ),
        (
            "method = \"reflection\"\nreflection_residual = 100",
            "env.reflection_residual",
        ),
    ] {
        let e = scene("city", GLOSSY, extra).err().unwrap().to_string();
        assert!(e.contains(field), "{extra}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
    // A field of this method under another one.
    let text = "[env]\nfile = \"p.exr\"\nmethod = \"transfer\"\nreflection_grid = 32\n";
    let e = SceneFile::parse(text).err().unwrap().to_string();
    assert!(
        e.contains("reflection_grid") && e.contains("\"reflection\""),
        "{e}"
    );
}
