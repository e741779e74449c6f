//! The light tree's invariants on the shipped probes (each checked against the probe's own
//! texels, not against the tree).

use super::tree::LightTree;
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
                let texel = tree.texel(i);
                seen[texel] += 1;
                let d = t.dir[texel];
                members[i].push(texel);
                // A leaf is exact: only its ancestors have cones.
                for &a in chain.iter() {
                    members[a].push(texel);
                    let s = tree.cone_slot(a);
                    let c = tree.axis[s].as_dvec3().dot(d);
                    assert!(
                        c >= tree.cos_half[s] as f64 - 1e-6,
                        "{name}: texel {texel} outside the cone of node {a}"
                    );
                    // The f32 direction too (the representative's, the reference's light).
                    let c32 = tree.axis[s].dot(d.as_vec3());
                    assert!(c32 >= tree.cos_half[s], "{name}: f32 direction outside");
                }
                continue;
            }
            // Pre-order: the left child follows, the right one follows the left subtree;
            // cone slots are pre-order over the interior nodes.
            let left_leaves = (tree.right(i) - tree.left(i)).div_ceil(2);
            assert_eq!(tree.right(i), i + 2 * left_leaves, "pre-order");
            if !tree.is_leaf(tree.left(i)) {
                assert_eq!(tree.cone_slot(tree.left(i)), tree.cone_slot(i) + 1);
            }
            if !tree.is_leaf(tree.right(i)) {
                assert_eq!(
                    tree.cone_slot(tree.right(i)),
                    tree.cone_slot(i) + left_leaves
                );
            }
            let mut c = chain.clone();
            c.push(i);
            stack.push((tree.left(i), c.clone()));
            stack.push((tree.right(i), c));
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
            if m.len() == 1 {
                assert!(tree.is_leaf(i));
                assert_eq!(tree.rep[i], t.dir[brightest].as_vec3(), "{name}: node {i}");
                continue;
            }
            let s = tree.cone_slot(i);
            let (axis, cos) = (tree.axis[s].as_dvec3(), tree.cos_half[s] as f64);
            if axis.dot(mean) >= cos + 1e-6 {
                assert!((rep - mean).length() < 1e-6, "{name}: node {i}");
            } else if axis.dot(mean) < cos - 1e-6 {
                assert_eq!(tree.rep[i], t.dir[brightest].as_vec3(), "{name}: node {i}");
            }
            assert!(
                tree.axis[s].dot(tree.rep[i]) >= tree.cos_half[s] - 1e-6,
                "{name}: node {i}: representative outside the cone"
            );
        }
        // The root holds the probe's power.
        let total = probe.total_power() * intensity as f64;
        let root = tree.irradiance[0].as_dvec3();
        assert!((root - total).abs().max_element() <= 1e-6 * total.max_element());
    }
}

/// The same probe gives the same tree, bit for bit, whatever the thread pool (subtrees of
/// at least 2^15 texels are built by parallel tasks; this pins that they write the same
/// nodes).
#[test]
fn build_is_deterministic() {
    let probe = load("sky", 0.0);
    let pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let a = pool(4).install(|| LightTree::build(&probe, 1.0));
    let b = pool(1).install(|| LightTree::build(&probe, 1.0));
    assert_eq!(a.irradiance, b.irradiance);
    assert_eq!(a.rep, b.rep);
    assert_eq!(a.axis, b.axis);
    assert_eq!(a.cos_half, b.cos_half);
    assert_eq!(a.right, b.right);
    assert_eq!(a.slot, b.slot);
}
