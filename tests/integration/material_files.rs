//! Material files on the command line (`--material FILE`) and in a scene file
//! (`[material] path`): a MERL table (`.binary`) renders, as `acquire` and `fit-dbrdf` read
//! it, under point lights and, with delta lights, under an environment; a file of a kind
//! brdfkit does not read is refused in one line that says which kinds it takes.

use brdfkit::brdf::{Lambert, MerlBrdf};
use glam::Vec3;
use std::path::Path;

use crate::cli_errors::{assert_error, brdfkit};
use crate::common;

/// A MERL table (a tabulated Lambert, albedo 0.5/0.6/0.7) written to `dir/name`.
fn merl_file(dir: &Path, name: &str) {
    MerlBrdf::tabulate(&Lambert {
        albedo: Vec3::new(0.5, 0.6, 0.7),
    })
    .write(&dir.join(name))
    .unwrap();
}

fn render(dir: &Path, args: &[&str]) -> brdfkit::image_io::Image {
    let out = args.last().expect("-o PATH last");
    let r = brdfkit(dir, args);
    assert_eq!(r.code, Some(0), "{args:?}: {}", r.stderr);
    brdfkit::image_io::read_exr(&dir.join(out)).unwrap()
}

#[test]
fn a_merl_table_renders_from_the_command_line_and_a_scene_file() {
    let d = tempfile::tempdir().unwrap();
    merl_file(d.path(), "m.binary");
    let size = ["--width", "24", "--height", "18"];
    let args: Vec<&str> = ["render", "--material", "m.binary"]
        .into_iter()
        .chain(size)
        .chain(["-o", "cli.exr"])
        .collect();
    let cli = render(d.path(), &args);
    assert!(
        cli.pixels.iter().any(|p| p.min_element() > 0.0),
        "the MERL material shades nothing"
    );
    // The scene file's `merl-file`, relative to the scene: the same bits.
    std::fs::create_dir(d.path().join("sub")).unwrap();
    merl_file(&d.path().join("sub"), "m.binary");
    std::fs::write(
        d.path().join("sub/s.toml"),
        "[material]\nkind = \"merl-file\"\npath = \"m.binary\"\n",
    )
    .unwrap();
    let args: Vec<&str> = ["render", "sub/s.toml"]
        .into_iter()
        .chain(size)
        .chain(["-o", "scene.exr"])
        .collect();
    let scene = render(d.path(), &args);
    assert_eq!(cli.pixels, scene.pixels);
    // Under an environment: delta lights (`auto` is `lights` for a MERL table).
    let probe = common::city_probe();
    let args: Vec<&str> = ["render", "--material", "m.binary", "--env", probe.as_str()]
        .into_iter()
        .chain(size)
        .chain(["-o", "env.exr"])
        .collect();
    let r = brdfkit(d.path(), &args);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(
        r.stderr.contains("\"auto\" is \"lights\""),
        "not shaded with delta lights: {}",
        r.stderr
    );
    // --lookup is for SH data sets only.
    assert_error(
        d.path(),
        &[
            "render",
            "--material",
            "m.binary",
            "--lookup",
            "nearest",
            "-o",
            "x.png",
        ],
        &["--lookup", "MERL table", "m.binary"],
    );
}

#[test]
fn a_material_file_of_an_unknown_kind_says_which_kinds_are_read() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("notes.txt"), "not a material").unwrap();
    std::fs::write(d.path().join("short.binary"), "twelve bytes").unwrap();
    assert_error(
        d.path(),
        &["render", "--material", "notes.txt", "-o", "a.png"],
        &[
            "--material",
            "notes.txt",
            ".exr",
            "SH data set",
            "D-BRDF",
            ".binary",
            "MERL",
        ],
    );
    // A .binary file that is not a MERL table: the MERL reader's error, naming the file.
    assert_error(
        d.path(),
        &["render", "--material", "short.binary", "-o", "a.png"],
        &["short.binary", "[90, 90, 180]"],
    );
    // An EXR that is not a material (a light probe): what the kinds are, .binary included.
    let probe = common::city_probe();
    assert_error(
        d.path(),
        &["render", "--material", probe.as_str(), "-o", "a.png"],
        &["city.exr", "brdfkit.format is missing", ".binary"],
    );
}
