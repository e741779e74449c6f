//! The light tree's invariants on the shipped probes (each checked against the probe's own
//! texels, not against the tree).

use super::tree::{LightTree, LEAF};
use crate::env::probe::ProbeTables;
use crate::env::{LoadOptions, Probe};
use glam::DVec3;
use std::path::Path;

fn load(name: &str, rotation: f64) -> Probe {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("assets/probes/{name}.exr"));
    let opts = LoadOptions {
        rotation,
        ..LoadOptions::default()
    };
    Probe::load(&path, &opts).unwrap().0
}

/// Every texel of positive weight is exactly one leaf; each node's irradiance is the sum of
/// its texels' (f32 rounding of an f64 sum: 1e-6 relative) times the intensity; every
/// texel direction lies in the cone of each of its ancestors; each node's representative
/// is its texels' weighted mean direction (inside the cone) or its brightest texel; the
/// layout is pre-order with `2 n - 1` nodes.
#[test]
fn tree_invariants_on_the_shipped_probes() {
    for (name, rotation, intensity) in [("studio", 0.0, 1.0f32), ("city", 0.7, 2.5)] {
        let probe = load(name, rotation);
        let t = ProbeTables::new(&probe);
        let tree = LightTree::build(&probe, intensity);
        let n = t.weight.iter().filter(|w| **w > 0.0).count();
        assert_eq!(tree.len(), 2 * n - 1, "{name}");
        // Texels per node, gathered by walking the tree.
        let mut seen = vec![0u32; t.weight.len()];
        // (node, ancestors' cones checked by carrying the chain)
        let mut stack = vec![(0usize, Vec::<usize>::new())];
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); tree.len()];
        while let Some((i, chain)) = stack.pop() {
            if tree.is_leaf(i) {
                let texel = tree.texel[i] as usize;
                seen[texel] += 1;
                let d = t.dir[texel];
                for &a in chain.iter().chain([i].iter()) {
                    members[a].push(texel);
                    let c = tree.axis[a].as_dvec3().dot(d);
                    assert!(
                        c >= tree.cos_half[a] as f64 - 1e-6,
                        "{name}: texel {texel} outside the cone of node {a}"
                    );
                    // The f32 direction too (the representative's, the reference's light).
                    let c32 = tree.axis[a].dot(d.as_vec3());
                    assert!(c32 >= tree.cos_half[a], "{name}: f32 direction outside");
                }
                continue;
            }
            assert_eq!(tree.left[i] as usize, i + 1, "pre-order");
            assert_ne!(tree.left[i], LEAF);
            let mut c = chain.clone();
            c.push(i);
            stack.push((tree.left[i] as usize, c.clone()));
            stack.push((tree.right[i] as usize, c));
        }
        for (k, w) in t.weight.iter().enumerate() {
            assert_eq!(seen[k], (*w > 0.0) as u32, "{name}: texel {k}");
        }
        for (i, m) in members.iter().enumerate() {
            let sum: DVec3 = m.iter().map(|&k| t.power[k]).sum::<DVec3>() * intensity as f64;
            let got = tree.irradiance[i].as_dvec3();
            assert!(
                (got - sum).abs().max_element() <= 1e-6 * sum.max_element(),
                "{name}: node {i}: {got} vs {sum}"
            );
            // The representative: the weighted mean direction when inside the cone, else
            // the brightest texel (near the cone's rim either may be right).
            let brightest = *m
                .iter()
                .max_by(|&&a, &&b| t.weight[a].total_cmp(&t.weight[b]).then(b.cmp(&a)))
                .unwrap();
            let mean = m
                .iter()
                .map(|&k| t.dir[k] * t.weight[k])
                .sum::<DVec3>()
                .normalize();
            let rep = tree.rep[i].as_dvec3();
            let (axis, cos) = (tree.axis[i].as_dvec3(), tree.cos_half[i] as f64);
            if m.len() > 1 && axis.dot(mean) >= cos + 1e-6 {
                assert!((rep - mean).length() < 1e-6, "{name}: node {i}");
            } else if m.len() == 1 || axis.dot(mean) < cos - 1e-6 {
                assert_eq!(tree.rep[i], t.dir[brightest].as_vec3(), "{name}: node {i}");
            }
            assert!(
                tree.axis[i].dot(tree.rep[i]) >= tree.cos_half[i] - 1e-6,
                "{name}: node {i}: representative outside the cone"
            );
        }
        // The root holds the probe's power.
        let total = probe.total_power() * intensity as f64;
        let root = tree.irradiance[0].as_dvec3();
        assert!((root - total).abs().max_element() <= 1e-6 * total.max_element());
    }
}

/// The same probe gives the same tree, bit for bit, whatever the thread pool (the build is
/// sequential; this pins it).
#[test]
fn build_is_deterministic() {
    let probe = load("sky", 0.0);
    let a = LightTree::build(&probe, 1.0);
    let b = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| LightTree::build(&probe, 1.0));
    assert_eq!(a.irradiance, b.irradiance);
    assert_eq!(a.axis, b.axis);
    assert_eq!(a.cos_half, b.cos_half);
    assert_eq!(a.left, b.left);
    assert_eq!(a.texel, b.texel);
}
