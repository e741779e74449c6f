//! Paths on the command line are relative to the working directory, paths in a scene file to
//! the scene file's directory, and one never re-bases the other.

use std::path::Path;
use std::process::Command;

use crate::common;
use common::run_in;

#[test]
fn a_mesh_on_the_command_line_keeps_the_scene_files_paths() {
    // The scene lives in scenes/ and names its probe relative to itself; the render runs from
    // elsewhere with --mesh sphere (a built-in) and then --mesh PATH (an OBJ relative to the
    // working directory). Before, any --mesh moved the scene's base to the working directory
    // and the probe was looked up as ./probe.exr.
    let tmp = tempfile::tempdir().unwrap();
    let scenes = tmp.path().join("scenes");
    let work = tmp.path().join("work");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::create_dir_all(&work).unwrap();
    let probe = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/sky.exr");
    std::fs::copy(&probe, scenes.join("probe.exr")).unwrap();
    std::fs::write(
        scenes.join("scene.toml"),
        "[env]\nfile = \"probe.exr\"\nsampler = \"median-cut\"\ncount = 8\n\n[render]\nwidth = 32\nheight = 24\n",
    )
    .unwrap();
    std::fs::write(
        work.join("tri.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    for mesh in ["sphere", "tri.obj"] {
        let out = work.join(format!("{}.exr", mesh.replace('.', "-")));
        let (ok, err) = run_in(
            &work,
            &[
                "render",
                "../scenes/scene.toml",
                "--mesh",
                mesh,
                "-o",
                out.to_str().unwrap(),
            ],
        );
        assert!(ok, "--mesh {mesh}: {err}");
        assert!(out.exists(), "--mesh {mesh}: no image");
    }
    // A mesh path that does not exist in the working directory is an error naming it.
    let (ok, err) = run_in(
        &work,
        &[
            "render",
            "../scenes/scene.toml",
            "--mesh",
            "missing.obj",
            "-o",
            "x.exr",
        ],
    );
    assert!(!ok && err.contains("missing.obj"), "{err}");
}

#[test]
fn a_closed_stdout_ends_every_subcommand_quietly() {
    // `brdfkit ... | head` with the reader gone: no panic message, no exit 101.
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    let tmp = tempfile::tempdir().unwrap();
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden");
    let a = golden.join("fig3-13-teal-paint.exr");
    let b = golden.join("fig3-10-blue-silk-nearest.exr");
    let cases: [Vec<&str>; 3] = [
        vec!["compare", a.to_str().unwrap(), b.to_str().unwrap()],
        vec!["materials"],
        vec!["--help"],
    ];
    for args in cases {
        let mut child = Command::new(env!("CARGO_BIN_EXE_brdfkit"))
            .args(&args)
            .current_dir(tmp.path())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take()); // the reader closes its end before anything is read
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_ne!(out.status.code(), Some(101), "{args:?}: {err}");
        eprintln!(
            "{args:?}: exit {:?}, signal {:?}",
            out.status.code(),
            out.status.signal()
        );
    }
}

#[test]
fn material_files_are_told_apart_by_their_header() {
    // `--material PATH` reads only the EXR headers to tell an SH data set from a D-BRDF
    // (the file itself is read once, when the scene resolves); anything else is refused with
    // the file and the header named.
    use brdfkit::scene::MaterialSpec;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let sh = root.join("golden/magenta-plastic-5b-8x4.exr");
    let dbrdf = root.join("golden/lindt-paper-16x8.exr");
    let probe = root.join("assets/probes/sky.exr");
    assert!(matches!(
        MaterialSpec::from_cli(sh.to_str().unwrap()).unwrap(),
        MaterialSpec::ShFile { .. }
    ));
    assert!(matches!(
        MaterialSpec::from_cli(dbrdf.to_str().unwrap()).unwrap(),
        MaterialSpec::DbrdfFile { .. }
    ));
    let e = MaterialSpec::from_cli(probe.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("--material:") && e.contains("sky.exr") && e.contains("brdfkit.format"),
        "{e}"
    );
    let tmp = tempfile::tempdir().unwrap();
    let junk = tmp.path().join("junk.exr");
    std::fs::write(&junk, b"not an exr").unwrap();
    let e = MaterialSpec::from_cli(junk.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("--material:") && e.contains("junk.exr"),
        "{e}"
    );
}
