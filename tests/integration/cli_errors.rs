//! Bad input on the command line: one clear error line naming the file or field, a
//! non-zero exit, and no output file (nor a temporary one) left behind.

use std::path::{Path, PathBuf};

use crate::common;

/// Runs `brdfkit args` in `dir`, killed after 60 s; never the user's light-set cache
/// (`render --env` looks an entry up before it decodes the probe), and nothing is written
/// there by a failing run.
pub(crate) fn brdfkit(dir: &Path, args: &[&str]) -> common::Run {
    common::brdfkit(dir)
        .cache(&dir.join(".brdfkit-cache"))
        .timeout(60)
        .run(args)
}

/// Asserts an error run: exit 2, exactly one stderr line, containing every `needle`, and
/// the directory holds only the files that were there before.
pub(crate) fn assert_error(dir: &Path, args: &[&str], needles: &[&str]) {
    let before: Vec<PathBuf> = list(dir);
    let r = brdfkit(dir, args);
    assert_eq!(
        r.code,
        Some(2),
        "{args:?}: exit code {:?} (stderr: {})",
        r.code,
        r.stderr
    );
    let lines: Vec<&str> = r.stderr.lines().collect();
    assert_eq!(
        lines.len(),
        1,
        "{args:?}: expected one error line, got {:?}",
        lines
    );
    assert!(lines[0].starts_with("brdfkit: error: "), "{}", lines[0]);
    for n in needles {
        assert!(
            lines[0].contains(n),
            "{args:?}: error line {:?} does not mention {n:?}",
            lines[0]
        );
    }
    assert_eq!(list(dir), before, "{args:?}: files were written");
}

pub(crate) fn list(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v
}

/// A temporary directory holding `files` (name, text).
pub(crate) fn dir_with(files: &[(&str, &str)]) -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(d.path().join(name), text).unwrap();
    }
    d
}

#[test]
fn missing_scene_file() {
    let d = dir_with(&[]);
    assert_error(
        d.path(),
        &["render", "nope.toml", "-o", "a.png"],
        &["nope.toml", "cannot read scene file"],
    );
}

#[test]
fn malformed_scene_file() {
    let d = dir_with(&[("bad.toml", "[render]\nwidth = = 3\n")]);
    assert_error(
        d.path(),
        &["render", "bad.toml", "-o", "a.png"],
        &["bad.toml", "line 2"],
    );
}

#[test]
fn unknown_field_is_an_error() {
    let d = dir_with(&[("s.toml", "[render]\nwidht = 100\n")]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml", "unknown field", "widht"],
    );
    let d = dir_with(&[(
        "s.toml",
        "[[light]]\nkind = \"directional\"\nto_light = [0.0, 1.0, 0.0]\ncolour = [1.0, 1.0, 1.0]\n",
    )]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml", "colour"],
    );
    let d = dir_with(&[("s.toml", "[material]\nkind = \"chrome\"\n")]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml", "chrome"],
    );
}

#[test]
fn zero_and_absurd_resolution() {
    let d = dir_with(&[]);
    assert_error(
        d.path(),
        &["render", "--width", "0", "-o", "a.png"],
        &["--width", "out of range"],
    );
    assert_error(
        d.path(),
        &["render", "--height", "100000", "-o", "a.png"],
        &["--height", "100000"],
    );
    let d = dir_with(&[("s.toml", "[render]\nwidth = 0\n")]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml", "render.width", "out of range"],
    );
    let d = dir_with(&[("s.toml", "[render]\nheight = 99999999\n")]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml", "render.height"],
    );
}

#[test]
fn bad_field_values() {
    let d = dir_with(&[(
        "s.toml",
        "[[light]]\nkind = \"directional\"\nto_light = [0.0, 0.0, 0.0]\n",
    )]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml", "light[0].to_light", "zero"],
    );
    let d = dir_with(&[(
        "s.toml",
        "[material]\nkind = \"lambert\"\nalbedo = [0.5, -1.0, 0.5]\n",
    )]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml", "material.albedo"],
    );
    let d = dir_with(&[("s.toml", "[camera]\nfov_y_deg = 0.0\n")]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml", "camera.fov_y_deg"],
    );
    let d = dir_with(&[("s.toml", "[render]\ndrop_lights = 1.0\n")]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["s.toml", "render.drop_lights", "out of range"],
    );
    assert_error(
        d.path(),
        &["render", "--drop-lights", "-0.5", "-o", "a.png"],
        &["--drop-lights", "out of range"],
    );
    assert_error(
        d.path(),
        &[
            "acquire",
            "lambert:albedo=0.5",
            "--band-threshold",
            "1",
            "-o",
            "a.exr",
        ],
        &["--band-threshold", "out of range"],
    );
}

#[test]
fn missing_and_malformed_obj() {
    let d = dir_with(&[
        ("broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n"),
        ("empty.obj", "# nothing\n"),
        ("nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    ]);
    assert_error(
        d.path(),
        &["render", "--mesh", "missing.obj", "-o", "a.png"],
        &["missing.obj"],
    );
    assert_error(
        d.path(),
        &["render", "--mesh", "broken.obj", "-o", "a.png"],
        &["broken.obj"],
    );
    assert_error(
        d.path(),
        &["render", "--mesh", "empty.obj", "-o", "a.png"],
        &["empty.obj", "no faces"],
    );
    assert_error(
        d.path(),
        &["render", "--mesh", "nan.obj", "-o", "a.png"],
        &["nan.obj", "non-finite"],
    );
    // A scene's OBJ path resolves against the scene file's directory.
    let d = dir_with(&[("s.toml", "[mesh]\nsource = \"gone.obj\"\n")]);
    assert_error(
        d.path(),
        &["render", "s.toml", "-o", "a.png"],
        &["gone.obj"],
    );
}

#[test]
fn unknown_output_format_and_unwritable_output() {
    let d = dir_with(&[]);
    assert_error(
        d.path(),
        &["render", "-o", "a.jpg"],
        &["a.jpg", ".png or .exr"],
    );
    assert_error(
        d.path(),
        &[
            "render",
            "--width",
            "8",
            "--height",
            "8",
            "-o",
            "no/such/dir/a.png",
        ],
        &["no/such/dir/a.png"],
    );
}

#[test]
fn good_input_writes_exactly_the_requested_files() {
    let d = dir_with(&[("s.toml", "[render]\nwidth = 40\nheight = 30\n")]);
    let r = brdfkit(d.path(), &["render", "s.toml", "-o", "x.exr"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let names: Vec<String> = list(d.path())
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["s.toml", "x.exr"]);
    let r = brdfkit(d.path(), &["render", "--width", "40", "--height", "30"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(d.path().join("out.png").exists() && d.path().join("out.exr").exists());
    let png = image::open(d.path().join("out.png")).unwrap();
    assert_eq!((png.width(), png.height()), (40, 30));
}

#[test]
fn environment_flags_and_lights_command_errors() {
    let d = dir_with(&[("junk.exr", "not an exr at all")]);
    assert_error(
        d.path(),
        &["render", "--sampler", "lloyd", "-o", "a.png"],
        &["--sampler", "--env"],
    );
    assert_error(
        d.path(),
        &["render", "--env", "nothere.exr", "-o", "a.png"],
        &["nothere.exr"],
    );
    assert_error(
        d.path(),
        &["render", "--env", "junk.exr", "-o", "a.png"],
        &["junk.exr"],
    );
    assert_error(
        d.path(),
        &["lights", "junk.exr", "-o", "l.json"],
        &["junk.exr"],
    );
    assert_error(
        d.path(),
        &["lights", "junk.exr", "-o", "l.txt"],
        &["l.txt", ".json or .csv"],
    );
    assert_error(
        d.path(),
        &["lights", "junk.exr", "-n", "0"],
        &["-n", "out of range"],
    );
}

#[test]
fn bad_shard_specs() {
    let d = dir_with(&[]);
    for spec in ["3/2", "0/0", "x"] {
        assert_error(
            d.path(),
            &["sweep", "--shard", spec, "-o", "s.csv"],
            &["--shard", spec],
        );
        assert_error(
            d.path(),
            &["render", "--turntable", "4", "--shard", spec, "-o", "t.png"],
            &["--shard", spec],
        );
    }
    assert_error(
        d.path(),
        &["render", "--turntable", "0", "-o", "t.png"],
        &["--turntable", "out of range"],
    );
    assert_error(
        d.path(),
        &["render", "--turntable", "3", "-o", "t.exr"],
        &["t.exr", "PNG"],
    );
    assert_error(
        d.path(),
        &["render", "--turntable", "3", "--assemble", "-o", "t.png"],
        &["t_0000.png", "missing"],
    );
    assert_error(
        d.path(),
        &["sweep", "--frames", "0", "-o", "s.csv"],
        &["--frames"],
    );
    assert_error(
        d.path(),
        &["sweep", "--lookups", "trilinear", "-o", "s.csv"],
        &["--lookups", "trilinear"],
    );
}

#[test]
fn unreadable_sweep_csv_in_merge() {
    let header = brdfkit::sweep::CSV_HEADER;
    let good = format!(
        "{header}\n0,lights,median-cut,1,-,-,-,-,-,-,8,bilinear,f32,0.5,0.6,1,0.1,0,1.000,2.000,1\n"
    );
    let bad = format!("{header}\n1,lights,median-cut,2,-,-,-,-,-,-,8,bilinear,f32,0.4,0.5,1,0.1,0,1.000,2.000,1\n2,transfer,-,-,32,17,0,-,-,-,8,bilinear,f32,zero,0.5,1,0.1,0,1.000,2.000,1\n");
    // A shard written before the method axis.
    let old = "index,sampler,lights,order,lookup,precision,rel_rmse,max_err,flip_mean,default,prep_ms,frame_ms,pareto\n1,median-cut,2,8,bilinear,f32,0.4,1,0.1,0,1.000,2.000,1\n";
    let d = dir_with(&[
        ("a.csv", &good),
        ("b.csv", &bad),
        ("c.csv", "name,value\n1,2\n"),
        ("old.csv", old),
    ]);
    assert_error(
        d.path(),
        &["sweep", "--merge", "a.csv", "old.csv", "-o", "all.csv"],
        &["old.csv", "line 1", "before the method axis", "regenerate"],
    );
    assert_error(
        d.path(),
        &["sweep", "--merge", "a.csv", "b.csv", "-o", "all.csv"],
        &["b.csv", "line 3", "rel_rmse"],
    );
    assert_error(
        d.path(),
        &["sweep", "--merge", "a.csv", "c.csv", "-o", "all.csv"],
        &["c.csv", "line 1", "not a sweep CSV"],
    );
    assert_error(
        d.path(),
        &["sweep", "--merge", "a.csv", "missing.csv", "-o", "all.csv"],
        &["missing.csv", "cannot read"],
    );
    assert_error(
        d.path(),
        &["sweep", "--merge", "a.csv", "a.csv", "-o", "all.csv"],
        &["a.csv", "row index 0"],
    );
}
