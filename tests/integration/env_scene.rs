//! Environment lighting through the whole renderer: white furnace per sampler, the
//! teapot under real probes with every sampler against the full-probe reference, and the
//! light-set cache (keys, validation on read). Scenes resolve without a cache
//! ([`Scene::resolve`]); only the cache test uses one, in a temporary directory.
//!
//! (Past 400 lines because the cases share the probe, scene and cache fixtures at the top;
//! they test one thing, an environment as the scene file states it.)

use brdfkit::env::lightset::prepare::{prepare, CacheEntry};
use brdfkit::env::schema::{EnvSpec, SamplerKind};
use brdfkit::image_io::Image;
use brdfkit::render::render;
use brdfkit::scene::{Scene, SceneFile};
use std::path::{Path, PathBuf};

const SAMPLERS: [SamplerKind; 5] = [
    SamplerKind::Uniform,
    SamplerKind::Importance,
    SamplerKind::Stratified,
    SamplerKind::MedianCut,
    SamplerKind::Lloyd,
];

fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes")
}

/// A constant-radiance probe written as an EXR.
fn constant_probe(dir: &Path, w: usize, h: usize, value: f32) -> PathBuf {
    let p = dir.join("constant.exr");
    exr::prelude::write_rgb_file(&p, w, h, |_, _| (value, value, value)).unwrap();
    p
}

fn scene(toml: &str, w: u32, h: u32) -> Scene {
    let mut f = SceneFile::parse(toml).unwrap();
    f.render.width = w;
    f.render.height = h;
    Scene::resolve(&f, Path::new("/")).unwrap()
}

fn covered(img: &Image) -> Vec<glam::Vec3> {
    img.pixels
        .iter()
        .copied()
        .filter(|p| p.max_element() > 0.0)
        .collect()
}

#[test]
fn white_furnace_lambert_sphere_per_sampler() {
    // Constant radiance L = 2 and albedo 0.5: every visible point reflects 0.5 * 2 = 1,
    // whatever its normal. The delta-light approximation converges to it as N grows.
    let tmp = tempfile::tempdir().unwrap();
    let probe = constant_probe(tmp.path(), 64, 32, 2.0);
    for sampler in SAMPLERS {
        let mut errs = Vec::new();
        for n in [16, 128, 1024] {
            let s = scene(&format!("[mesh]\nsource = \"sphere\"\nsegments = 24\n[material]\nkind = \"lambert\"\nalbedo = [0.5, 0.5, 0.5]\n[env]\nfile = \"{}\"\nsampler = \"{}\"\ncount = {n}\n", probe.display(), serde_plain(sampler)), 48, 48);
            let img = render(&s, &Default::default()).image;
            let px = covered(&img);
            assert!(px.len() > 800, "{sampler:?} N={n}: sphere not visible");
            let rms = (px
                .iter()
                .map(|p| ((*p - glam::Vec3::ONE).length_squared() / 3.0) as f64)
                .sum::<f64>()
                / px.len() as f64)
                .sqrt();
            errs.push(rms);
        }
        assert!(
            errs[2] < errs[0],
            "{sampler:?}: error does not fall with N: {errs:?}"
        );
        assert!(
            errs[2] < 0.05,
            "{sampler:?}: N=1024 white furnace RMS error {:.4} (errors {errs:?})",
            errs[2]
        );
    }
}

fn serde_plain(s: SamplerKind) -> &'static str {
    match s {
        SamplerKind::Uniform => "uniform",
        SamplerKind::Importance => "importance",
        SamplerKind::Stratified => "stratified",
        SamplerKind::MedianCut => "median-cut",
        SamplerKind::Lloyd => "lloyd",
        SamplerKind::Full => "full",
    }
}

#[test]
fn teapot_under_real_probes_with_every_sampler() {
    // Each sampler's render at N = 256 is within a few percent of the full-probe reference
    // (every texel a light), on a Lambertian teapot where the error is only the lighting's.
    for probe in ["city.exr", "studio.exr"] {
        let file = assets().join(probe);
        let toml = |sampler: &str, n: usize| {
            format!("[material]\nkind = \"lambert\"\nalbedo = [0.7, 0.7, 0.7]\n[render]\ncull = \"back\"\n[env]\nfile = \"{}\"\nsampler = \"{sampler}\"\ncount = {n}\n", file.display())
        };
        let reference = render(&scene(&toml("full", 1), 40, 30), &Default::default()).image;
        let ref_px = covered(&reference);
        let mean: f64 = ref_px
            .iter()
            .map(|p| p.element_sum() as f64 / 3.0)
            .sum::<f64>()
            / ref_px.len() as f64;
        assert!(ref_px.len() > 200 && mean > 0.0);
        for sampler in SAMPLERS {
            let img = render(
                &scene(&toml(serde_plain(sampler), 256), 40, 30),
                &Default::default(),
            )
            .image;
            assert!(img.pixels.iter().all(|p| p.is_finite()));
            let rel_rmse = (img
                .pixels
                .iter()
                .zip(&reference.pixels)
                .filter(|(_, r)| r.max_element() > 0.0)
                .map(|(a, r)| ((*a - *r).length_squared() / 3.0) as f64)
                .sum::<f64>()
                / ref_px.len() as f64)
                .sqrt()
                / mean;
            let bound = if matches!(
                sampler,
                SamplerKind::Uniform | SamplerKind::Importance | SamplerKind::Stratified
            ) {
                0.25
            } else {
                0.05
            };
            assert!(rel_rmse < bound, "{probe} {sampler:?}: relative RMSE {rel_rmse:.4} against the full probe (bound {bound})");
        }
    }
}

#[test]
fn light_sets_are_cached_by_contents_and_parameters() {
    let tmp = tempfile::tempdir().unwrap();
    let cache_dir = tmp.path().join("cache");
    let cache = Some(cache_dir.as_path());
    let probe = tmp.path().join("p.exr");
    std::fs::copy(assets().join("city.exr"), &probe).unwrap();
    let mut spec = EnvSpec::new(probe.clone());
    spec.sampler = SamplerKind::Lloyd;
    spec.count = 32;
    let first = prepare(&spec, tmp.path(), cache).unwrap();
    assert!(!first.cache_hit && first.report.is_some());
    let second = prepare(&spec, tmp.path(), cache).unwrap();
    assert!(second.cache_hit, "a re-render must skip preprocessing");
    assert_eq!(
        second.report, first.report,
        "a cache hit reports what the entry recorded when the probe was decoded"
    );
    assert_eq!(first.lights, second.lights);
    // Another parameter: another entry.
    spec.count = 16;
    assert!(!prepare(&spec, tmp.path(), cache).unwrap().cache_hit);
    spec.count = 32;
    spec.rotation = 90.0;
    assert!(!prepare(&spec, tmp.path(), cache).unwrap().cache_hit);
    spec.rotation = 0.0;
    // Other contents under the same name: another entry.
    std::fs::copy(assets().join("studio.exr"), &probe).unwrap();
    let other = prepare(&spec, tmp.path(), cache).unwrap();
    assert!(!other.cache_hit);
    assert_ne!(other.lights, first.lights);
    // A damaged cache entry is ignored and rewritten, never trusted.
    let cf = other.cache_file.clone().unwrap();
    std::fs::write(&cf, "{ not json").unwrap();
    let again = prepare(&spec, tmp.path(), cache).unwrap();
    assert!(!again.cache_hit && again.cache_rejected.is_some());
    assert_eq!(again.lights, other.lights);
    assert!(prepare(&spec, tmp.path(), cache).unwrap().cache_hit);
    // No cache: nothing read or written.
    let none = prepare(&spec, tmp.path(), None).unwrap();
    assert!(!none.cache_hit && none.cache_file.is_none());
    assert_eq!(none.lights, other.lights);
}

/// Rewrites the cache entry `cf` after `edit` changed it (keeping everything else).
fn rewrite_entry(cf: &Path, edit: impl FnOnce(&mut CacheEntry)) {
    let mut e: CacheEntry = serde_json::from_slice(&std::fs::read(cf).unwrap()).unwrap();
    edit(&mut e);
    std::fs::write(cf, serde_json::to_vec(&e).unwrap()).unwrap();
}

#[test]
fn edited_truncated_or_foreign_cache_entries_are_never_used() {
    // Each seeded corruption of a valid entry must be rejected (with a reason), the light
    // set recomputed bit for bit, and the entry rewritten so the next read hits.
    let tmp = tempfile::tempdir().unwrap();
    let cache_dir = tmp.path().join("cache");
    let cache = Some(cache_dir.as_path());
    let mut spec = EnvSpec::new(assets().join("city.exr"));
    spec.sampler = SamplerKind::MedianCut;
    spec.count = 16;
    let fresh = prepare(&spec, tmp.path(), cache).unwrap();
    let cf = fresh.cache_file.clone().unwrap();
    assert!(prepare(&spec, tmp.path(), cache).unwrap().cache_hit);
    type Edit = Box<dyn Fn(&Path)>;
    let cases: Vec<(&str, &str, Edit)> = vec![
        (
            "every irradiance +1% (valid JSON, valid lights)",
            "checksum",
            Box::new(|cf| {
                rewrite_entry(cf, |e| {
                    for p in e
                        .lights
                        .irradiance_r
                        .iter_mut()
                        .chain(&mut e.lights.irradiance_g)
                    {
                        *p *= 1.01;
                    }
                })
            }),
        ),
        (
            "one irradiance +1%",
            "checksum",
            Box::new(|cf| rewrite_entry(cf, |e| e.lights.irradiance_b[3] *= 1.01)),
        ),
        (
            "truncated to half",
            "not a cache entry",
            Box::new(|cf| {
                let b = std::fs::read(cf).unwrap();
                std::fs::write(cf, &b[..b.len() / 2]).unwrap();
            }),
        ),
        (
            "written by another crate version",
            "crate version",
            Box::new(|cf| rewrite_entry(cf, |e| e.crate_version = "0.0.1".into())),
        ),
        (
            "written by another light-set algorithm",
            "algorithm version",
            Box::new(|cf| rewrite_entry(cf, |e| e.algorithm_version += 1)),
        ),
        (
            "another key's entry under this name",
            "key",
            Box::new(|cf| rewrite_entry(cf, |e| e.key = "0123456789abcdef".into())),
        ),
    ];
    for (what, reason, edit) in cases {
        edit(&cf);
        let p = prepare(&spec, tmp.path(), cache).unwrap();
        assert!(!p.cache_hit, "{what}: the corrupted entry was used");
        let why = p.cache_rejected.unwrap_or_default();
        assert!(why.contains(reason), "{what}: rejected for {why:?}");
        assert_eq!(p.lights, fresh.lights, "{what}: recomputed set differs");
        let p = prepare(&spec, tmp.path(), cache).unwrap();
        assert!(p.cache_hit, "{what}: entry not rewritten");
        assert_eq!(p.lights, fresh.lights);
    }
}

#[test]
fn scenes_without_env_never_touch_a_probe() {
    // The default scene has no [env]: nothing is prepared.
    let s = Scene::default_scene();
    assert!(s.env.is_none());
    assert_eq!(s.lights.len(), 1);
}

#[test]
fn env_errors_name_the_field_or_file() {
    let tmp = tempfile::tempdir().unwrap();
    let mut spec = EnvSpec::new(tmp.path().join("missing.exr"));
    let e = prepare(&spec, tmp.path(), None).unwrap_err().to_string();
    assert!(e.contains("missing.exr"), "{e}");
    spec.count = 0;
    let e = prepare(&spec, tmp.path(), None).unwrap_err().to_string();
    assert!(e.contains("env.count"), "{e}");
    let bad = tmp.path().join("bad.exr");
    std::fs::write(&bad, b"not an exr").unwrap();
    let e = prepare(&EnvSpec::new(bad), tmp.path(), None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad.exr"), "{e}");
    let e = SceneFile::parse("[env]\nfile = \"x.exr\"\nsampler = \"magic\"\n").unwrap_err();
    assert!(e.contains("magic"), "{e}");
    let e = SceneFile::parse("[env]\nfile = \"x.exr\"\ncuont = 3\n").unwrap_err();
    assert!(e.contains("cuont"), "{e}");
}

/// A field of another method than the `[env]`'s is an error naming the field (on its line)
/// and the method it belongs to; under `auto` every method's fields are accepted; a table
/// written back states its method and reads back as the same spec.
#[test]
fn a_field_of_another_method_is_an_error_naming_both() {
    let text = "[material]\nkind = \"lambert\"\n[env]\nfile = \"x.exr\"\nmethod = \"transfer\"\ncut_error = 0.02\n";
    let e = SceneFile::parse(text).unwrap_err();
    assert_eq!(
        e,
        "line 6: env.cut_error: belongs to method = \"lightcuts\", not to this [env]'s \
         method \"transfer\""
    );
    for (stated, field, owner) in [
        (
            "method = \"lights\"\nexact_lights = 4",
            "exact_lights",
            "transfer",
        ),
        (
            "method = \"lightcuts\"\nsampler = \"full\"",
            "sampler",
            "lights",
        ),
        (
            "method = \"transfer\"\nlights = \"set.json\"",
            "lights",
            "lights",
        ),
        ("count = 16\ncut_max = 10", "cut_max", "lightcuts"),
    ] {
        let e = SceneFile::parse(&format!("[env]\nfile = \"x.exr\"\n{stated}\n")).unwrap_err();
        assert!(
            e.starts_with(&format!(
                "line 4: env.{field}: belongs to method = \"{owner}\""
            )),
            "{e}"
        );
    }
    let e = SceneFile::parse("[env]\nfile = \"x.exr\"\ncount = 16\ncut_max = 10\n").unwrap_err();
    assert!(
        e.ends_with("(it states sampler or count and no method)"),
        "{e}"
    );
    // Under `auto`, each applies when `auto` chooses its method.
    let auto = "[env]\nfile = \"x.exr\"\nexact_lights = 8\ncut_error = 0.02\nseed = 3\n";
    let f = SceneFile::parse(auto).unwrap();
    let env = f.env.as_ref().unwrap();
    assert_eq!(env.method, brdfkit::env::schema::EnvMethod::Auto);
    assert_eq!((env.exact_lights, env.cut_error, env.seed), (8, 0.02, 3));
    // Written back: each method's table reads back as the same method and fields.
    for method in ["auto", "lights", "transfer", "lightcuts"] {
        let mut f =
            SceneFile::parse(&format!("[env]\nfile = \"x.exr\"\nmethod = \"{method}\"\n")).unwrap();
        f.env.as_mut().unwrap().rotation = 30.0;
        let back = SceneFile::parse(&toml::to_string(&f).unwrap()).unwrap();
        assert_eq!(
            format!("{:?}", back.env),
            format!("{:?}", f.env),
            "{method}"
        );
    }
    // The command line: one line naming the scene file, the line and the field.
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("s.toml");
    std::fs::write(&path, text).unwrap();
    let r =
        crate::common::brdfkit(tmp.path()).run(&["render", path.to_str().unwrap(), "-o", "x.png"]);
    assert!(!r.success());
    let line = r.stderr.trim();
    assert!(
        line.contains("s.toml")
            && line.contains("line 6: env.cut_error: belongs to method = \"lightcuts\"")
            && !line.contains('\n'),
        "{line}"
    );
    assert!(!tmp.path().join("x.png").exists());
}

/// The lines of `stderr` that are the probe loader's negative-texel warning.
fn negative_warnings(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| l.contains("texels with negative values"))
        .collect()
}

#[test]
fn a_dirty_probe_warns_once_naming_the_path_as_given() {
    // The original DWAB sky (tests/data/probes/README.md), under relative paths: the
    // probe in probes/, a scene naming it relative to itself in scenes/, all run from the
    // temporary directory.
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    std::fs::create_dir_all(d.join("probes")).unwrap();
    std::fs::create_dir_all(d.join("scenes")).unwrap();
    let original = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/probes/sky-dwab.exr");
    std::fs::copy(&original, d.join("probes/sky.exr")).unwrap();
    std::fs::write(
        d.join("scenes/scene.toml"),
        "[env]\nfile = \"../probes/sky.exr\"\nsampler = \"median-cut\"\ncount = 8\n\n\
         [render]\nwidth = 24\nheight = 18\n",
    )
    .unwrap();
    let small = ["--width", "24", "--height", "18"];
    let lights = ["--sampler", "median-cut", "--lights", "8"];
    let cases: Vec<(&str, Vec<&str>, &str)> = vec![
        (
            "--env, light set",
            [
                &["render", "--env", "probes/sky.exr", "-o", "a.png"][..],
                &small,
                &lights,
            ]
            .concat(),
            "warning: probes/sky.exr: ",
        ),
        // The same again: the light set from the cache, the warning from its entry.
        (
            "--env, cached",
            [
                &["render", "--env", "probes/sky.exr", "-o", "a.png"][..],
                &small,
                &lights,
            ]
            .concat(),
            "warning: probes/sky.exr: ",
        ),
        // auto for a D-BRDF is light cuts, which load the probe on a path of their own.
        (
            "--env, light cuts",
            [
                &[
                    "render",
                    "--env",
                    "probes/sky.exr",
                    "--material",
                    "lindt-paper",
                ][..],
                &["-o", "b.png"],
                &small,
            ]
            .concat(),
            "warning: probes/sky.exr: ",
        ),
        // Four frames, one warning.
        (
            "turntable",
            [
                &[
                    "render",
                    "--env",
                    "probes/sky.exr",
                    "--turntable",
                    "4",
                    "-o",
                    "t.png",
                ][..],
                &small,
                &lights,
            ]
            .concat(),
            "warning: probes/sky.exr: ",
        ),
        (
            "scene file",
            vec!["render", "scenes/scene.toml", "-o", "c.png"],
            "warning: scenes/scene.toml: env.file ../probes/sky.exr: ",
        ),
        (
            "lights",
            vec!["lights", "probes/sky.exr", "-n", "8"],
            "warning: probes/sky.exr: ",
        ),
    ];
    let root = d.display().to_string();
    for (what, args, start) in cases {
        let r = crate::common::brdfkit(d).run(&args);
        assert!(r.success(), "{what}: {}", r.stderr);
        if what == "--env, cached" {
            assert!(r.stderr.contains("(cached)"), "{what}: {}", r.stderr);
        }
        let w = negative_warnings(&r.stderr);
        assert_eq!(w.len(), 1, "{what}: one warning:\n{}", r.stderr);
        assert!(w[0].starts_with(start), "{what}: {}", w[0]);
        assert!(w[0].contains("% of the probe's"), "{what}: {}", w[0]);
        assert!(!w[0].contains(&root), "{what}: an absolute path: {}", w[0]);
    }
    // The shipped (cleaned) sky: nothing to warn about.
    let shipped = assets().join("sky.exr");
    let r = crate::common::brdfkit(d).run(
        &[
            &["render", "--env", shipped.to_str().unwrap(), "-o", "s.png"][..],
            &small,
            &lights,
        ]
        .concat(),
    );
    assert!(r.success(), "{}", r.stderr);
    assert!(!r.stderr.contains("warning"), "{}", r.stderr);
}
