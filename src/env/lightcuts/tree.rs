//! The light tree: a binary tree over every probe texel of positive weight, nodes stored as
//! plain arrays (structure of arrays), root at index 0 (parent module doc, "The tree").

use crate::env::probe::ProbeTables;
use crate::env::Probe;
use glam::{DVec3, Vec3};

/// Widening of every cluster cone, subtracted from the cosine of its half angle, so that
/// the f32 texel directions (the representatives, and the lights of the converged
/// reference) pass an f32 test `axis . d >= cos_half` for a cone built from the f64 ones:
/// an f32 dot product of unit vectors is within a few 1e-7 of the exact one. (A cone of a
/// single texel becomes one of ~1.4 mrad, a tenth of a 512 x 256 probe's texel spacing.)
pub const CONE_SLACK: f64 = 1e-6;

/// Marks a node without children in [`LightTree::left`].
pub const LEAF: u32 = u32::MAX;

/// A binary light tree over probe texels (parent module doc). Node `i`'s values are the
/// `i`-th entries of every array; all arrays have [`LightTree::len`] entries. Directions are
/// unit world directions **towards** the light (probe rotation applied), irradiances are at
/// normal incidence (radiance x solid angle x `intensity`, W/m^2 for a probe in W/(m^2 sr)).
#[derive(Clone, Debug, Default)]
pub struct LightTree {
    /// Total RGB irradiance of the cluster's texels (`sum L Omega`, summed in f64).
    pub irradiance: Vec<Vec3>,
    /// Representative direction: the cluster's luminance-weighted mean texel direction,
    /// normalised (weights luminance x solid angle), when it lies inside the bounding cone;
    /// else (and for a single texel) the centre of its brightest texel (lowest texel index
    /// on ties), Lightcuts' choice. Parent module doc, "Why the mean direction".
    pub rep: Vec<Vec3>,
    /// Bounding cone axis (unit): every texel centre of the cluster is within
    /// `acos(cos_half)` of it.
    pub axis: Vec<Vec3>,
    /// Cosine of the bounding cone's half angle `alpha`.
    pub cos_half: Vec<f32>,
    /// Sine of `alpha` (>= 0; `alpha` may exceed pi/2).
    pub sin_half: Vec<f32>,
    /// `sin(alpha / 2)`, half the largest chord from the axis to a member direction.
    pub sin_quarter: Vec<f32>,
    /// Left child, or [`LEAF`].
    pub left: Vec<u32>,
    /// Right child (unused for a leaf).
    pub right: Vec<u32>,
    /// For a leaf, the texel index `row * width + col` (unused otherwise).
    pub texel: Vec<u32>,
}

impl LightTree {
    /// Number of nodes (`2 x leaves - 1`, 0 for a black probe).
    pub fn len(&self) -> usize {
        self.irradiance.len()
    }

    /// True when the probe had no texel of positive weight.
    pub fn is_empty(&self) -> bool {
        self.irradiance.is_empty()
    }

    /// True when node `i` is a single texel.
    #[inline]
    pub fn is_leaf(&self, i: usize) -> bool {
        self.left[i] == LEAF
    }

    /// Sum of the leaves' irradiances in f64 (equals the root's, up to f32 rounding, and
    /// [`Probe::total_power`] x intensity).
    pub fn leaf_irradiance_sum(&self) -> DVec3 {
        (0..self.len())
            .filter(|&i| self.is_leaf(i))
            .map(|i| self.irradiance[i].as_dvec3())
            .sum()
    }

    /// Builds the tree of `probe` (texel radiance times `intensity`): one leaf per texel of
    /// positive weight (luminance x solid angle > 0; a black texel adds nothing to any
    /// sum), split top-down (parent module doc). Deterministic: sorts break ties by texel
    /// index, and the build is sequential.
    pub fn build(probe: &Probe, intensity: f32) -> LightTree {
        let t = ProbeTables::new(probe);
        let mut items: Vec<usize> = (0..t.weight.len()).filter(|&i| t.weight[i] > 0.0).collect();
        let mut tree = LightTree::default();
        if items.is_empty() {
            return tree;
        }
        let n = items.len();
        for v in [&mut tree.left, &mut tree.right, &mut tree.texel] {
            v.resize(2 * n - 1, 0);
        }
        tree.irradiance.resize(2 * n - 1, Vec3::ZERO);
        tree.rep.resize(2 * n - 1, Vec3::ZERO);
        tree.axis.resize(2 * n - 1, Vec3::ZERO);
        tree.cos_half.resize(2 * n - 1, 0.0);
        tree.sin_half.resize(2 * n - 1, 0.0);
        tree.sin_quarter.resize(2 * n - 1, 0.0);
        let scale = intensity as f64;
        // Pre-order layout; explicit stack of (node, range of `items`).
        let mut stack = vec![(0usize, 0usize, n)];
        while let Some((node, lo, hi)) = stack.pop() {
            let members = &mut items[lo..hi];
            let power: DVec3 = members.iter().map(|&i| t.power[i]).sum::<DVec3>() * scale;
            tree.irradiance[node] = power.as_vec3();
            let brightest = *members
                .iter()
                .max_by(|&&a, &&b| t.weight[a].total_cmp(&t.weight[b]).then(b.cmp(&a)))
                .expect("non-empty cluster");
            let (axis, alpha) = bounding_cone(members.iter().map(|&i| t.dir[i]));
            let alpha = (alpha.cos() - CONE_SLACK).max(-1.0).acos();
            tree.axis[node] = axis.as_vec3();
            let centroid = members
                .iter()
                .map(|&i| t.dir[i] * t.weight[i])
                .sum::<DVec3>()
                .try_normalize();
            tree.rep[node] = match centroid {
                Some(c) if members.len() > 1 && c.dot(axis) >= alpha.cos() => c.as_vec3(),
                _ => t.dir[brightest].as_vec3(),
            };
            tree.cos_half[node] = alpha.cos() as f32;
            tree.sin_half[node] = alpha.sin().max(0.0) as f32;
            tree.sin_quarter[node] = (alpha / 2.0).sin() as f32;
            if members.len() == 1 {
                tree.left[node] = LEAF;
                tree.right[node] = LEAF;
                tree.texel[node] = members[0] as u32;
                continue;
            }
            let k = split(members, &t);
            // Node `node`'s subtree occupies `node .. node + 2 m - 1` (m members): the
            // left child follows it, the right one follows the left subtree.
            let (l, r) = (node + 1, node + 2 * k);
            tree.left[node] = l as u32;
            tree.right[node] = r as u32;
            tree.texel[node] = LEAF;
            // Right pushed first so the left subtree is built first (order is irrelevant to
            // the result: indices are fixed by the sizes).
            stack.push((r, lo + k, hi));
            stack.push((l, lo, lo + k));
        }
        tree
    }
}

/// A cone around `dirs` (unit): axis the normalised centre of their bounding box (+y when
/// that centre is the origin), half angle the largest angle from the axis to a member,
/// radians (exact over the members, f64).
pub fn bounding_cone(dirs: impl Iterator<Item = DVec3> + Clone) -> (DVec3, f64) {
    let (lo, hi) = dirs.clone().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), d| (lo.min(d), hi.max(d)),
    );
    let axis = ((lo + hi) * 0.5).try_normalize().unwrap_or(DVec3::Y);
    let min_cos = dirs.fold(1.0f64, |m, d| m.min(axis.dot(d)));
    (axis, min_cos.clamp(-1.0, 1.0).acos())
}

/// Sorts `members` along the largest extent of their directions' bounding box (ties by
/// texel index) and returns the split `k` (`1 <= k < len`): the first `k` carry the first
/// half of the cluster's luminance weight (the luminance-weighted median).
fn split(members: &mut [usize], t: &ProbeTables) -> usize {
    let (lo, hi) = members.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &i| (lo.min(t.dir[i]), hi.max(t.dir[i])),
    );
    let ext = hi - lo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    members.sort_unstable_by(|&a, &b| t.dir[a][axis].total_cmp(&t.dir[b][axis]).then(a.cmp(&b)));
    let total: f64 = members.iter().map(|&i| t.weight[i]).sum();
    let mut acc = 0.0;
    let mut k = members.len() / 2;
    for (j, &i) in members.iter().enumerate() {
        acc += t.weight[i];
        if acc >= 0.5 * total {
            k = j + 1;
            break;
        }
    }
    k.clamp(1, members.len() - 1)
}
