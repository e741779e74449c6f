//! Messages of a user report, each reproduced through the binary: a scene file's bad field
//! named at its own line with the file and the field; an output that cannot be written
//! named by the user's path, never a temporary file's; a scene's missing probe named by
//! the scene file, `env.file` and the path as written; a debug output the environment
//! method does not produce refused (naming both) instead of written black; and no Rust
//! debug text (`Some("...")`) in a material file's error.

use crate::cli_errors::{assert_error, brdfkit, dir_with};
use crate::common;

#[test]
fn a_bad_field_is_named_at_its_line_with_the_scene_file() {
    // A misspelled field of an internally tagged table (serde reads [material] whole
    // before its fields, so toml's own span is the table's header on line 1).
    let d = dir_with(&[(
        "s.toml",
        "[material]\nkind = \"lambert\"\nalbedoo = [0.5, 0.5, 0.5]\n",
    )]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &[
            "s.toml: line 3: ",
            "material.albedoo",
            "unknown field `albedoo`",
        ],
    );
    // The same in a plain table and in the second [[light]].
    let d = dir_with(&[("s.toml", "[render]\nwidth = 40\nwidht = 30\n")]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml: line 3: ", "render.widht", "unknown field `widht`"],
    );
    let light = "[[light]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\n";
    let d = dir_with(&[(
        "s.toml",
        &format!("{light}{light}colour = [1.0, 1.0, 1.0]\n"),
    )]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &[
            "s.toml: line 7: ",
            "light[1].colour",
            "unknown field `colour`",
        ],
    );
    // A value of the wrong type: its line and its field.
    let d = dir_with(&[(
        "s.toml",
        "# size\n[render]\nheight = 30\nwidth = \"wide\"\n",
    )]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml: line 4: ", "render.width: "],
    );
}

#[test]
fn an_output_error_names_the_user_s_path_and_no_temporary_file() {
    let d = dir_with(&[]);
    for (args, path) in [
        (
            &[
                "render",
                "--width",
                "8",
                "--height",
                "8",
                "-o",
                "no/such/dir/a.png",
            ][..],
            "no/such/dir/a.png",
        ),
        (
            &[
                "render",
                "--width",
                "8",
                "--height",
                "8",
                "-o",
                "gone/b.exr",
            ],
            "gone/b.exr",
        ),
        (
            &[
                "acquire",
                "lambert",
                "--bands",
                "2",
                "--no-table",
                "-o",
                "gone/c.exr",
            ],
            "gone/c.exr",
        ),
    ] {
        let r = brdfkit(d.path(), args);
        assert_eq!(r.code, Some(2), "{args:?}: {}", r.stderr);
        let line = r.stderr.trim();
        assert!(!line.contains('\n'), "{args:?}: {line}");
        assert!(line.contains(path), "{args:?}: {line} does not name {path}");
        assert!(
            !line.contains(".tmp") && !line.contains("at path"),
            "{args:?}: {line} names a temporary file"
        );
        assert!(!line.contains("Some(") && !line.contains("Os {"), "{line}");
    }
}

#[test]
fn a_missing_probe_names_the_scene_file_env_file_and_the_path() {
    let d = dir_with(&[(
        "s.toml",
        "[env]\nfile = \"../x.exr\"\n[render]\nwidth = 8\nheight = 8\n",
    )]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml: env.file: \"../x.exr\": no such file"],
    );
    // Every method reads the probe.
    for method in ["lights", "transfer", "lightcuts"] {
        let d = dir_with(&[(
            "s.toml",
            &format!(
                "[material]\nkind = \"lambert\"\n[env]\nfile = \"p.exr\"\nmethod = \"{method}\"\n"
            ),
        )]);
        assert_error(
            d.path(),
            &["render", "s.toml", "-o", "a.png"],
            &["s.toml: env.file: \"p.exr\": no such file"],
        );
    }
    // On the command line: the option and the path as given.
    let d = dir_with(&[]);
    assert_error(
        d.path(),
        &["render", "--env", "sub/nothere.exr", "-o", "a.png"],
        &["--env: sub/nothere.exr: no such file"],
    );
}

#[test]
fn a_light_aov_the_environment_method_does_not_produce_is_refused() {
    let probe = common::city_probe();
    // A transfer table without exact lights has no light list either.
    let transfer = format!(
        "[material]\nkind = \"lambert\"\n[env]\nfile = \"{probe}\"\nmethod = \"transfer\"\n\
         transfer_azimuth = 32\ntransfer_polar = 17\nexact_lights = 0\n"
    );
    let d = dir_with(&[("t.toml", &transfer)]);
    let size = ["--width", "16", "--height", "12"];
    for (args, method) in [
        // A library D-BRDF: `auto` is light cuts.
        (
            vec![
                "render",
                "--env",
                probe.as_str(),
                "--material",
                "lindt-paper",
                "--aov",
                "light-polar",
            ],
            "lightcuts",
        ),
        (
            vec![
                "render",
                "--env",
                probe.as_str(),
                "--env-method",
                "lightcuts",
                "--aov",
                "light-azimuth",
            ],
            "lightcuts",
        ),
        (vec!["render", "t.toml", "--aov", "light-polar"], "transfer"),
    ] {
        let args: Vec<&str> = args
            .into_iter()
            .chain(size)
            .chain(["-o", "a.png"])
            .collect();
        let r = brdfkit(d.path(), &args);
        assert_eq!(r.code, Some(2), "{args:?}: {}", r.stderr);
        let last = r.stderr.lines().last().unwrap_or_default();
        assert!(
            last.starts_with("brdfkit: error: --aov: light-"),
            "{args:?}: {last}"
        );
        assert!(last.contains(&format!("\"{method}\"")), "{args:?}: {last}");
        assert!(!d.path().join("a.png").exists(), "{args:?}: wrote an image");
    }
    // Delta lights have a first light: the AOV is produced, and it is not black.
    let args = [
        "render",
        "--env",
        probe.as_str(),
        "--env-method",
        "lights",
        "--aov",
        "light-polar",
    ];
    let args: Vec<&str> = args
        .into_iter()
        .chain(size)
        .chain(["-o", "b.exr"])
        .collect();
    let r = brdfkit(d.path(), &args);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let img = brdfkit::image_io::read_exr(&d.path().join("b.exr")).unwrap();
    assert!(
        img.pixels.iter().any(|p| p.x > 0.0),
        "an all-black light-polar AOV"
    );
}

#[test]
fn a_material_file_of_the_other_kind_is_named_without_debug_text() {
    // An SH data set named as a D-BRDF: the format attribute as written, not `Some("...")`.
    let sh =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("golden/magenta-plastic-5b-8x4.exr");
    let d = dir_with(&[(
        "s.toml",
        &format!(
            "[material]\nkind = \"dbrdf-file\"\npath = \"{}\"\n",
            sh.display()
        ),
    )]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &[
            "s.toml: material.path: ",
            "magenta-plastic-5b-8x4.exr: not a brdfkit D-BRDF file",
            "brdfkit.format is 'brdfkit-sh'",
        ],
    );
    let r = brdfkit(d.path(), &["render", "s.toml", "-o", "a.png"]);
    assert!(
        !r.stderr.contains("Some(") && !r.stderr.contains("None"),
        "{}",
        r.stderr
    );
}
