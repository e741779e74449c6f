//! The tile bound (`tile.rs`) checked against brute force: over every pixel of a square
//! and every texel of a cluster, `f(wi_p, wo_p) cos(polar_i)` never exceeds the cluster's
//! tile bound; and the seeded fault (no widening by the tile's frame and view spread) is
//! shown to break it.

use super::super::{for_each_visible, frame_and_view};
use super::tile::{node_cone, tile_f_cos_max, TileFrame, TilePixel, CUT_TILE, MAX_SPREAD};
use crate::env::lightcuts::{LightTree, TileFault};
use crate::material::cone_bound::{BoundFault, ConeBound};
use crate::material::Material;
use crate::render::rasterize;
use crate::scene::{Scene, SceneFile};
use glam::Vec3;
use std::path::Path;

/// Relative slack of the comparison (f32 rounding of the bound and of `f`), as
/// `material::cone_bound`'s own tests.
const SLACK: f32 = 1e-4;

/// A 32 x 32 view of the sphere's limb region at about the pixel density of the 640 x 480
/// bench frame (pixels 0.0046 sphere radii apart).
fn patch_scene(material: &str) -> Scene {
    let text = format!(
        "[camera]\nposition = [0.0, 0.0, 3.5]\ntarget = [0.64, 0.64, 0.0]\nfov_y_deg = 2.4\n\
         [mesh]\nsource = \"sphere\"\nsegments = 64\n[material]\n{material}\n\
         [env]\nfile = \"assets/probes/city.exr\"\nmethod = \"lightcuts\"\n\
         [render]\nwidth = 32\nheight = 32\ntile_size = 8\n"
    );
    Scene::resolve(
        &SceneFile::parse(&text).unwrap(),
        Path::new(env!("CARGO_MANIFEST_DIR")),
    )
    .unwrap()
}

/// The covered 8 x 8 squares of the scene as pixel lists (vis tile size 8 = `CUT_TILE`).
fn squares(scene: &Scene) -> Vec<Vec<TilePixel>> {
    let vis = rasterize(scene, false);
    assert_eq!(vis.tile_size, CUT_TILE);
    let mut out = Vec::new();
    for t in 0..vis.tile_occupied.len() {
        let mut px = Vec::new();
        let rect = vis.tile_rect(t);
        for_each_visible(&scene.mesh, &vis, rect, rect.y0, |p| {
            let rule = scene.material.frame_rule();
            let (frame, wo) = frame_and_view(&p.surface, scene.camera.position, &rule);
            px.push(TilePixel {
                at: 0,
                x: p.x,
                y: p.y,
                frame,
                wo,
            });
        });
        if px.len() > 1 {
            out.push(px);
        }
    }
    out
}

/// The nodes `depth` levels below the root, and every leaf under each.
fn nodes_at(tree: &LightTree, depth: usize) -> Vec<(usize, Vec<usize>)> {
    let mut level = vec![0usize];
    for _ in 0..depth {
        level = level
            .iter()
            .flat_map(|&i| {
                if tree.is_leaf(i) {
                    vec![i]
                } else {
                    vec![tree.left(i), tree.right(i)]
                }
            })
            .collect();
    }
    level
        .into_iter()
        .filter(|&i| !tree.is_leaf(i))
        .map(|i| {
            let (mut leaves, mut stack) = (Vec::new(), vec![i]);
            while let Some(j) = stack.pop() {
                if tree.is_leaf(j) {
                    leaves.push(j);
                } else {
                    stack.push(tree.left(j));
                    stack.push(tree.right(j));
                }
            }
            (i, leaves)
        })
        .collect()
}

/// Counts (cluster, square) pairs whose brute-force maximum of `f cos` (RGB, per channel)
/// over pixels and member texels exceeds the tile bound with `fault`; also returns the
/// number of pairs checked and the largest tile spread seen.
fn violations(material: &str, fault: TileFault) -> (usize, usize, f32) {
    let scene = patch_scene(material);
    let cuts = scene.environment.light_cuts().unwrap();
    let tree = &cuts.tree;
    let bound = ConeBound::new(&scene.material).unwrap();
    let m: &Material = &scene.material;
    // ~130k leaves: depth 13 leaves ~16 texels per cluster, cones of a few texels, where
    // a missing widening matters most.
    let nodes = nodes_at(tree, 13);
    let (mut bad, mut checked, mut spread) = (0, 0, 0.0f32);
    for px in squares(&scene) {
        let tf = TileFrame::of(&px, m, &m.frame_rule());
        if tf.frame_spread + tf.view_spread > MAX_SPREAD {
            continue; // the shading path splits such a square
        }
        spread = spread.max(tf.frame_spread + tf.view_spread);
        for (i, leaves) in &nodes {
            let cone = node_cone(tree, *i, &tf.frame);
            let b = tile_f_cos_max(&bound, &tf, &cone, (BoundFault::None, fault), m);
            let mut worst = Vec3::ZERO;
            for p in &px {
                for &l in leaves {
                    let wi = p.frame.to_local(tree.rep[l]);
                    if wi.z > 0.0 {
                        worst = worst.max(m.eval(wi, p.wo) * wi.z);
                    }
                }
            }
            checked += 1;
            if (worst - b * (1.0 + SLACK)).max_element() > 1e-7 {
                bad += 1;
            }
        }
    }
    (bad, checked, spread)
}

const BLINN_PHONG_200: &str = "kind = \"blinn-phong\"\nexponent = 200";
const LINDT: &str = "kind = \"library\"\nname = \"lindt-paper\"";

#[test]
fn tile_bound_holds_over_every_pixel_and_texel() {
    for (name, material) in [("blinn-phong-200", BLINN_PHONG_200), ("lindt-paper", LINDT)] {
        let (bad, checked, spread) = violations(material, TileFault::None);
        eprintln!("{name}: {bad} of {checked} cluster-square pairs over the bound, largest spread {spread:.4} rad");
        assert!(checked > 1000, "{name}: {checked} pairs");
        assert!(
            spread > 0.005,
            "{name}: spread {spread}: the squares share nothing"
        );
        assert_eq!(bad, 0, "{name}: the tile bound fails");
    }
}

/// Seeded fault: without widening the cone by the square's frame and view spread, the
/// bound at the central frame misses pixels whose lobe sees more of the cluster.
#[test]
fn tile_bound_without_widening_fails() {
    for (name, material) in [("blinn-phong-200", BLINN_PHONG_200), ("lindt-paper", LINDT)] {
        let (bad, checked, _) = violations(material, TileFault::NoWidening);
        eprintln!("{name} NoWidening: {bad} of {checked} cluster-square pairs over the bound");
        assert!(bad > 0, "{name}: the unwidened bound passed");
    }
}
