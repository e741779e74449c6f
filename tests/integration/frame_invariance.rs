//! An isotropic material's image does not depend on the tangent frame.
//!
//! Every isotropic material of the library, plus Lambert and Blinn-Phong, renders the
//! teapot (whose lid and knob sit at `n = +y`, where the world-up tangent turns fastest)
//! three ways: as `brdfkit render` does, with every pixel's world-up frame first turned
//! about the normal by a pseudo-random angle (`FrameCheck::Scramble`), and with that turn
//! but without the material's view alignment (`FrameCheck::ScrambleUnaligned`, the seeded
//! fault). The scrambled image must match the plain one within `FRAME_TOLERANCE` under
//! delta lights (a directional key light and median-cut lights of the studio probe) and,
//! for SH data sets, under a transfer table; the tabulated materials (SH data sets,
//! D-BRDF lobes) must miss it without alignment, which shows the check sees a frame
//! dependence where one exists. The analytic models are exact functions of the angles and
//! match even without alignment.

use crate::frame_common::{rel_rmse, shade};
use brdfkit::library::LIBRARY;
use brdfkit::material::Material;
use brdfkit::scene::{Scene, SceneFile};
use brdfkit::shade::FrameCheck;
use std::path::Path;

/// Largest relative RMSE over covered pixels between the image with scrambled frames and
/// the plain one: the frames agree to f32 rounding (a few 1e-7), which moves a nearest
/// lookup across a polar texel boundary on a rare pixel.
const FRAME_TOLERANCE: f64 = 1e-4;

fn scene(material: &str, env: &str) -> Scene {
    let text = format!(
        "[mesh]\nsegments = 8\n\
         [material]\n{material}\n\
         [[light]]\nkind = \"directional\"\nto_light = [0.3, 1.0, 0.5]\nintensity = 2.0\n\
         {env}\n\
         [render]\nwidth = 96\nheight = 72\n"
    );
    let file = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap()
}

#[test]
fn isotropic_materials_render_the_same_in_any_tangent_frame() {
    let lights = "[env]\nmethod = \"lights\"\nfile = \"assets/probes/studio.exr\"\n\
                  sampler = \"median-cut\"\ncount = 32\n";
    let transfer = "[env]\nmethod = \"transfer\"\nfile = \"assets/probes/studio.exr\"\n";
    let mut cases: Vec<(String, String, bool)> = vec![
        ("kind = \"lambert\"".into(), "lambert".into(), false),
        (
            "kind = \"blinn-phong\"\nexponent = 60.0".into(),
            "blinn-phong".into(),
            false,
        ),
    ];
    for entry in LIBRARY {
        let m = brdfkit::library::build(entry.name).unwrap();
        if m.as_brdf().is_isotropic() {
            let tabulated = matches!(
                m,
                Material::Sh(_) | Material::DBrdf(_) | Material::LambertDbrdf(_)
            );
            assert!(
                !tabulated || m.frame_rule().view_azimuth.is_some(),
                "{}: isotropic and tabulated, but shaded in the world-up frame",
                entry.name
            );
            let spec = format!("kind = \"library\"\nname = \"{}\"", entry.name);
            cases.push((spec, entry.name.to_string(), tabulated));
        }
    }
    assert!(cases.len() >= 6, "isotropic materials: {}", cases.len());
    let mut failures = Vec::new();
    for (spec, name, tabulated) in &cases {
        let is_sh = spec.contains("lambert\"")
            || brdfkit::library::build(name).is_ok_and(|m| m.as_sh().is_some());
        let envs: &[(&str, &str)] = if is_sh {
            &[("lights", lights), ("transfer", transfer)]
        } else {
            &[("lights", lights)]
        };
        for (env_name, env) in envs {
            let s = scene(spec, env);
            let plain = shade(&s, FrameCheck::None);
            let scrambled = rel_rmse(&shade(&s, FrameCheck::Scramble), &plain);
            let unaligned = rel_rmse(&shade(&s, FrameCheck::ScrambleUnaligned), &plain);
            eprintln!(
                "{name:<26} {env_name:<8} scrambled {scrambled:.2e}, scrambled without alignment {unaligned:.2e}"
            );
            if scrambled > FRAME_TOLERANCE {
                failures.push(format!(
                    "{name} ({env_name}): scrambled frames change the image by rel RMSE {scrambled:.2e} > {FRAME_TOLERANCE:.0e}"
                ));
            }
            if *tabulated && unaligned <= FRAME_TOLERANCE {
                failures.push(format!(
                    "{name} ({env_name}): without view alignment scrambled frames change the image by only {unaligned:.2e}: the check does not see the frame"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
