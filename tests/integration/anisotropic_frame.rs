//! An anisotropic material's grain follows the mesh, not the world's up axis.
//!
//! A sphere with texture coordinates (an OBJ file written here, poles on the x axis) is
//! rendered, and again turned a quarter turn about +z with the camera and the light turned
//! with it (exact: a quarter turn only swaps and negates coordinates). An anisotropic
//! material takes azimuth 0 from the mesh's tangent (`conventions`, "Frame of anisotropic
//! materials"), which turns with the object, so both renders must agree within
//! `TURN_TOLERANCE`. The seeded fault shades in the world-up frame (the thesis's frame,
//! `FrameCheck::Unaligned`), which does not turn with the object: it must miss the bound
//! for every anisotropic material, which shows the check sees the frame.

use crate::frame_common::{rel_rmse, shade};
use brdfkit::library::LIBRARY;
use brdfkit::scene::{Scene, SceneFile};
use brdfkit::shade::FrameCheck;
use std::fmt::Write as _;
use std::path::Path;

/// Largest relative RMSE over covered pixels between the turned and the plain render: the
/// two agree to f32 rounding in the frames and the rasterizer's snapping.
const TURN_TOLERANCE: f64 = 1e-3;

/// The quarter turn about +z: exact in f32.
fn turn(p: [f32; 3]) -> [f32; 3] {
    [-p[1], p[0], p[2]]
}

/// A unit lat-long sphere about the x axis with `u` the longitude and `v` the latitude, as
/// OBJ text, each vertex passed through `map`; triangles counter-clockwise seen from outside.
fn sphere_obj(map: fn([f32; 3]) -> [f32; 3]) -> String {
    let (stacks, slices) = (16usize, 32usize);
    let mut s = String::new();
    for i in 0..=stacks {
        let polar = std::f32::consts::PI * i as f32 / stacks as f32;
        for j in 0..=slices {
            let az = std::f32::consts::TAU * j as f32 / slices as f32;
            let p = [polar.cos(), polar.sin() * az.cos(), polar.sin() * az.sin()];
            let [x, y, z] = map(p);
            let _ = writeln!(s, "v {x} {y} {z}\nvn {x} {y} {z}");
            let _ = writeln!(
                s,
                "vt {} {}",
                j as f32 / slices as f32,
                i as f32 / stacks as f32
            );
        }
    }
    let idx = |i: usize, j: usize| i * (slices + 1) + j + 1;
    for i in 0..stacks {
        for j in 0..slices {
            let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
            // (b - a) x (c - a) points outwards: counter-clockwise seen from outside, the
            // winding `Mesh` front faces have. The other winding makes every triangle a back
            // face, whose normal the renderer turns inwards: only a thin crescent is lit.
            let _ = writeln!(s, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}");
            let _ = writeln!(s, "f {a}/{a}/{a} {c}/{c}/{c} {d}/{d}/{d}");
        }
    }
    s
}

fn scene(dir: &Path, obj: &str, material: &str, map: fn([f32; 3]) -> [f32; 3]) -> Scene {
    let [ux, uy, uz] = map([0.0, 1.0, 0.0]);
    let [lx, ly, lz] = map([0.3, 0.8, 0.6]);
    let text = format!(
        "[mesh]\nsource = \"{obj}\"\n\
         [camera]\nposition = [0.0, 0.0, 4.0]\ntarget = [0.0, 0.0, 0.0]\nup = [{ux}, {uy}, {uz}]\n\
         [material]\n{material}\n\
         [[light]]\nkind = \"directional\"\nto_light = [{lx}, {ly}, {lz}]\nintensity = 2.0\n\
         [render]\nwidth = 96\nheight = 96\n"
    );
    let file = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    Scene::resolve(&file, dir).unwrap()
}

#[test]
fn anisotropic_materials_turn_with_the_mesh() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("plain.obj"), sphere_obj(|p| p)).unwrap();
    std::fs::write(dir.path().join("turned.obj"), sphere_obj(turn)).unwrap();
    let mut cases: Vec<(String, String)> = Vec::new();
    for entry in LIBRARY {
        let m = brdfkit::library::build(entry.name).unwrap();
        if !m.is_isotropic() {
            assert!(
                m.frame_rule().mesh_tangent,
                "{}: anisotropic, world-up frame",
                entry.name
            );
            cases.push((
                format!("kind = \"library\"\nname = \"{}\"", entry.name),
                entry.name.into(),
            ));
        }
    }
    assert!(cases.len() >= 2, "anisotropic materials: {}", cases.len());
    let mut failures = Vec::new();
    for (spec, name) in &cases {
        let plain = scene(dir.path(), "plain.obj", spec, |p| p);
        let turned = scene(dir.path(), "turned.obj", spec, turn);
        assert!(
            !plain.mesh.tangents.is_empty(),
            "the OBJ's texture coordinates give tangents"
        );
        let ok = rel_rmse(
            &shade(&turned, FrameCheck::None),
            &shade(&plain, FrameCheck::None),
        );
        let fault = rel_rmse(
            &shade(&turned, FrameCheck::Unaligned),
            &shade(&plain, FrameCheck::Unaligned),
        );
        eprintln!("{name:<28} turned with the mesh {ok:.2e}, world-up frame (fault) {fault:.2e}");
        if ok > TURN_TOLERANCE {
            failures.push(format!(
                "{name}: turning the object changes its image by {ok:.2e} > {TURN_TOLERANCE:.0e}"
            ));
        }
        if fault <= TURN_TOLERANCE {
            failures.push(format!("{name}: the world-up frame changes the image by only {fault:.2e}: the check does not see the frame"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
