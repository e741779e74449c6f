//! `[env] lights = "set.json"`: a light set written by `brdfkit lights -o` and read back by
//! `render` gives the bits of the render that sampled the probe itself; errors name the
//! file and the field.

use std::path::Path;

use crate::common;

use common::{city_probe as probe, run_120s as run};

/// A small sphere scene with a Blinn-Phong material under `env` (the `[env]` table's body).
fn scene(dir: &Path, name: &str, env: &str) {
    std::fs::write(
        dir.join(name),
        format!(
            "[mesh]\nsource = \"sphere\"\nsegments = 12\n\
             [material]\nkind = \"blinn-phong\"\nexponent = 40.0\n\
             [render]\nwidth = 40\nheight = 30\n[env]\n{env}"
        ),
    )
    .unwrap();
}

fn render(dir: &Path, scene: &str, out: &str) -> brdfkit::image_io::Image {
    let (code, o, e) = run(dir, &["render", scene, "-o", out]);
    assert_eq!(code, 0, "{scene}: {o}{e}");
    brdfkit::image_io::read_exr(&dir.join(out)).unwrap()
}

fn bits(img: &brdfkit::image_io::Image) -> Vec<u32> {
    img.pixels
        .iter()
        .flat_map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

#[test]
fn a_written_light_set_renders_the_bits_of_the_sampled_probe() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let probe = probe();
    for out in ["sets/set.json", "sets/set.csv"] {
        std::fs::create_dir_all(p.join("sets")).unwrap();
        let (code, o, e) = run(
            p,
            &[
                "lights",
                &probe,
                "--sampler",
                "median-cut",
                "-n",
                "32",
                "-o",
                out,
            ],
        );
        assert_eq!(code, 0, "{o}{e}");
    }
    let common = "intensity = 1.5\nmethod = \"lights\"\n";
    scene(
        p,
        "sampled.toml",
        &format!("file = \"{probe}\"\nsampler = \"median-cut\"\ncount = 32\n{common}"),
    );
    // Paths relative to the scene file, as every other path of a scene.
    scene(
        p,
        "sets/json.toml",
        &format!("lights = \"set.json\"\n{common}"),
    );
    scene(
        p,
        "sets/csv.toml",
        &format!("lights = \"set.csv\"\n{common}"),
    );
    let sampled = render(p, "sampled.toml", "sampled.exr");
    assert!(sampled.pixels.iter().any(|v| v.max_element() > 0.0));
    for s in ["sets/json.toml", "sets/csv.toml"] {
        let img = render(p, s, "from_file.exr");
        assert!(
            bits(&img) == bits(&sampled),
            "{s}: not the sampled render's bits"
        );
    }
    // Seeded fault: one light of the file 1% brighter changes the render, so the equality
    // above is a real check.
    let text = std::fs::read_to_string(p.join("sets/set.csv")).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut f: Vec<f32> = lines[1].split(',').map(|x| x.parse().unwrap()).collect();
    for v in &mut f[3..] {
        *v *= 1.01;
    }
    lines[1] = f
        .iter()
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join(",");
    std::fs::write(p.join("sets/set.csv"), lines.join("\n")).unwrap();
    let img = render(p, "sets/csv.toml", "fault.exr");
    assert!(
        bits(&img) != bits(&sampled),
        "a brighter light left the bits unchanged"
    );
    // --sampler/--lights on the command line sample the probe instead of the file; without
    // a probe that is an error naming env.file.
    let (code, _, err) = run(
        p,
        &["render", "sets/csv.toml", "--lights", "8", "-o", "x.exr"],
    );
    assert_eq!(code, 2);
    assert!(err.contains("env.file"), "{err}");
}

#[test]
fn light_set_errors_name_the_file_and_the_field() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(p.join("bad.json"), "{\"format\": \"brdfkit-lightset\"").unwrap();
    std::fs::write(p.join("set.txt"), "").unwrap();
    std::fs::write(
        p.join("neg.csv"),
        "dir_x,dir_y,dir_z,irradiance_r,irradiance_g,irradiance_b\n0,1,0,1,-1,1\n",
    )
    .unwrap();
    for (env, needles) in [
        ("lights = \"missing.json\"\n", vec!["missing.json"]),
        (
            "lights = \"bad.json\"\n",
            vec!["env.lights", "bad.json", "JSON"],
        ),
        (
            "lights = \"set.txt\"\n",
            vec!["env.lights", "set.txt", ".json or .csv"],
        ),
        (
            "lights = \"neg.csv\"\n",
            vec!["env.lights", "neg.csv", "irradiance_g"],
        ),
        (
            "lights = \"neg.csv\"\nmethod = \"lightcuts\"\n",
            vec!["env.lights", "method"],
        ),
        (
            "lights = \"neg.csv\"\nrotation = 30.0\n",
            vec!["env.rotation"],
        ),
        ("sampler = \"median-cut\"\n", vec!["env.file", "missing"]),
    ] {
        scene(p, "s.toml", env);
        let (code, out, err) = run(p, &["render", "s.toml", "-o", "x.exr"]);
        assert_eq!(code, 2, "{env}: {out}{err}");
        assert_eq!(err.lines().count(), 1, "one line: {err}");
        for n in needles {
            assert!(err.contains(n), "{env}: '{n}' missing from {err}");
        }
        assert!(!p.join("x.exr").exists(), "nothing written");
    }
}
