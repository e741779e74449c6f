//! `camera.json` of an export: the resolved camera, its matrices exactly as the rasterizer
//! forms them, and the conventions that take clip space to pixels and depth.

use crate::scene::Scene;
use serde_json::json;

/// The conventions that map `clip_from_world` to pixels and depth, as `camera.json` states
/// them (see [`crate::scene::camera`], [`crate::raster::setup`], [`crate::raster::clip`]).
pub const CONVENTIONS: [(&str, &str); 7] = [
    (
        "world",
        "right-handed, +y up (crate::conventions); view space right-handed, looking down -z",
    ),
    (
        "matrices",
        "f32, column-major (16 values, column after column, as WGSL/GLSL mat4x4 and glam), \
         column vectors: clip = clip_from_view * view_from_world * (x, y, z, 1)",
    ),
    (
        "projection",
        "glam perspective_infinite_reverse_rh: clip.w = view distance (-z_view), clip.z = near; \
         no far plane",
    ),
    (
        "depth",
        "reversed-Z in [0, 1]: ndc_z = near / w, 1 at the near plane, towards 0 at infinity; \
         larger is nearer (depth test GREATER, clear to 0)",
    ),
    (
        "viewport",
        "pixel_x = (x/w * 0.5 + 0.5) * width, pixel_y = (0.5 - y/w * 0.5) * height: \
         y down, origin at the top-left corner of the top-left pixel",
    ),
    (
        "samples",
        "pixel (i, j) covers [i, i+1) x [j, j+1) and is sampled at its centre (i + 0.5, j + 0.5); \
         vertices snapped to 1/256 pixel; top-left fill rule",
    ),
    (
        "clipping",
        "triangles clipped against the near plane (w >= near); render.cull = \"back\" drops \
         triangles clockwise on screen, \"none\" shades back faces with the normal flipped",
    ),
];

/// An f32 as a JSON number printed in its shortest round-trip form (a JSON number is
/// an f64; widening would print 17 digits). Parsed as f32 it gives the same bits.
pub(super) fn fj(x: f32) -> serde_json::Value {
    json!(x.to_string().parse::<f64>().expect("an f32's decimal form"))
}

pub(super) fn fa(v: &[f32]) -> serde_json::Value {
    serde_json::Value::Array(v.iter().map(|&x| fj(x)).collect())
}

/// The resolved camera and matrices as `camera.json`.
pub fn camera_json(scene: &Scene) -> serde_json::Value {
    let r = &scene.render;
    let c = &scene.camera;
    let aspect = r.width as f32 / r.height as f32;
    let view = c.view_from_world();
    let proj = c.clip_from_view(aspect);
    // The product as crate::render::clip_positions forms it.
    let clip_from_world = proj * view;
    let conventions: serde_json::Map<String, serde_json::Value> = CONVENTIONS
        .iter()
        .map(|(k, v)| (k.to_string(), json!(v)))
        .collect();
    json!({
        "eye": fa(&c.position.to_array()),
        "target": fa(&c.target.to_array()),
        "up": fa(&c.up.to_array()),
        "fov_y_deg": fj(c.fov_y_deg),
        "near": fj(c.near),
        "far": null,
        "aspect": fj(aspect),
        "viewport": { "width": r.width, "height": r.height },
        "view_from_world": fa(&view.to_cols_array()),
        "clip_from_view": fa(&proj.to_cols_array()),
        "clip_from_world": fa(&clip_from_world.to_cols_array()),
        "conventions": conventions,
    })
}
