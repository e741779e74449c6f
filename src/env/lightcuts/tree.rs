//! The light tree: a binary tree over every probe texel of positive weight, nodes stored as
//! plain arrays (structure of arrays), root at index 0 (parent module doc, "The tree").
//!
//! (Past 400 lines because it is one data structure, the tree, with the build that defines
//! its layout: the split, the cluster bounds and the weighted median are used only by that
//! build.)

use crate::conventions::texel_center_f64;
use crate::env::{luminance, Probe};
use crate::progress::Progress;
use glam::{DVec3, Vec3};

/// Widening of every cluster cone, subtracted from the cosine of its half angle, so that
/// the f32 texel directions (the representatives, and the lights of the converged
/// reference) pass an f32 test `axis . d >= cos_half` for a cone built from the f64 ones:
/// an f32 dot product of unit vectors is within a few 1e-7 of the exact one. (A cone of a
/// single texel becomes one of ~1.4 mrad, a tenth of a 512 x 256 probe's texel spacing.)
pub const CONE_SLACK: f64 = 1e-6;

/// Marks a leaf in [`LightTree::right`].
pub const LEAF: u32 = u32::MAX;

/// Clusters from which the build splits its two halves over two rayon tasks (both halves
/// at least this many texels; below, one task builds the whole subtree).
const PARALLEL_MEMBERS: usize = 1 << 15;

/// A binary light tree over probe texels (parent module doc). Node `i`'s values are the
/// `i`-th entries of the node arrays ([`LightTree::len`] entries); an interior node's
/// bounding cone is entry [`LightTree::cone_slot`]`(i)` of the cone arrays (one per interior
/// node: a leaf is exact, its cone is never read). Directions are unit world directions
/// **towards** the light (probe rotation applied), irradiances are at normal incidence
/// (radiance x solid angle x `intensity`, W/m^2 for a probe in W/(m^2 sr)).
///
/// Layout: pre-order, so an interior node's left child is the next node
/// ([`LightTree::left`]) and its subtree of `m` texels occupies the `2 m - 1` nodes from it;
/// cone slots are pre-order over the interior nodes alone. 32 bytes per node and 24 per
/// interior node: about 56 bytes per texel (a 4096 x 2048 probe, 8.4 M texels: 470 MB).
#[derive(Clone, Debug, Default)]
pub struct LightTree {
    /// Total RGB irradiance of the cluster's texels (`sum L Omega`, summed in f64).
    pub irradiance: Vec<Vec3>,
    /// Representative direction: the cluster's luminance-weighted mean texel direction,
    /// normalised (weights luminance x solid angle), when it lies inside the bounding cone;
    /// else (and for a single texel) the centre of its brightest texel (lowest texel index
    /// on ties), Lightcuts' choice. Parent module doc, "Why the mean direction".
    pub rep: Vec<Vec3>,
    /// Right child of an interior node, [`LEAF`] for a leaf.
    pub right: Vec<u32>,
    /// An interior node's slot in the cone arrays; a leaf's texel index `row * width + col`.
    pub slot: Vec<u32>,
    /// Bounding cone axis (unit), per cone slot: every texel centre of the cluster is within
    /// `acos(cos_half)` of it.
    pub axis: Vec<Vec3>,
    /// Cosine of the bounding cone's half angle `alpha`, per cone slot.
    pub cos_half: Vec<f32>,
    /// Sine of `alpha` (>= 0; `alpha` may exceed pi/2), per cone slot.
    pub sin_half: Vec<f32>,
    /// `sin(alpha / 2)`, half the largest chord from the axis to a member direction, per
    /// cone slot.
    pub sin_quarter: Vec<f32>,
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
        self.right[i] == LEAF
    }

    /// Left child of interior node `i` (pre-order: the next node).
    #[inline]
    pub fn left(&self, i: usize) -> usize {
        i + 1
    }

    /// Right child of interior node `i`.
    #[inline]
    pub fn right(&self, i: usize) -> usize {
        self.right[i] as usize
    }

    /// The cone slot of interior node `i` (its index in [`LightTree::axis`],
    /// [`LightTree::cos_half`], [`LightTree::sin_half`], [`LightTree::sin_quarter`]).
    #[inline]
    pub fn cone_slot(&self, i: usize) -> usize {
        debug_assert!(!self.is_leaf(i));
        self.slot[i] as usize
    }

    /// The texel index (`row * width + col`) of leaf `i`.
    #[inline]
    pub fn texel(&self, i: usize) -> usize {
        debug_assert!(self.is_leaf(i));
        self.slot[i] as usize
    }

    /// Sum of the leaves' irradiances in f64 (equals the root's, up to f32 rounding, and
    /// [`Probe::total_power`] x intensity).
    pub fn leaf_irradiance_sum(&self) -> DVec3 {
        (0..self.len())
            .filter(|&i| self.is_leaf(i))
            .map(|i| self.irradiance[i].as_dvec3())
            .sum()
    }

    /// [`LightTree::build_with_progress`] with nothing drawn.
    pub fn build(probe: &Probe, intensity: f32) -> LightTree {
        Self::build_with_progress(probe, intensity, &Progress::hidden())
    }

    /// Builds the tree of `probe` (texel radiance times `intensity`): one leaf per texel of
    /// positive weight (luminance x solid angle > 0; a black texel adds nothing to any
    /// sum), split top-down (parent module doc). `progress` counts texels visited (each
    /// cluster's members), its length the count of a balanced tree, made exact at the end.
    ///
    /// Memory: the tree, and 8 bytes per texel while it is built (texel directions, powers
    /// and weights are computed from the probe's texels when needed, not stored).
    /// Deterministic: each cluster is split by one task, from its members in the order its
    /// parent's split left them (selection by direction, ties by texel index), so the tree is
    /// the same bits for any thread count.
    pub fn build_with_progress(probe: &Probe, intensity: f32, progress: &Progress) -> LightTree {
        let texels = TexelSource::new(probe, intensity);
        let mut items: Vec<Item> = (0..probe.width() * probe.height())
            .filter(|&i| texels.weight(i as u32) > 0.0)
            .map(|i| Item {
                key: 0.0,
                texel: i as u32,
            })
            .collect();
        let mut tree = LightTree::default();
        let n = items.len();
        if n == 0 {
            return tree;
        }
        assert!(
            2 * n - 1 < LEAF as usize,
            "{n} texels: too many for u32 node indices"
        );
        tree.irradiance = vec![Vec3::ZERO; 2 * n - 1];
        tree.rep = vec![Vec3::ZERO; 2 * n - 1];
        tree.right = vec![0; 2 * n - 1];
        tree.slot = vec![0; 2 * n - 1];
        tree.axis = vec![Vec3::ZERO; n - 1];
        tree.cos_half = vec![0.0; n - 1];
        tree.sin_half = vec![0.0; n - 1];
        tree.sin_quarter = vec![0.0; n - 1];
        let levels = usize::BITS - (n - 1).leading_zeros() + 1;
        progress.set_length(n as u64 * levels as u64);
        let out = Out {
            node0: 0,
            slot0: 0,
            irradiance: &mut tree.irradiance,
            rep: &mut tree.rep,
            right: &mut tree.right,
            slot: &mut tree.slot,
            axis: &mut tree.axis,
            cos_half: &mut tree.cos_half,
            sin_half: &mut tree.sin_half,
            sin_quarter: &mut tree.sin_quarter,
        };
        build_subtree(&texels, &mut items, out, progress);
        progress.set_length(progress.position());
        tree
    }
}

/// A cluster member while the tree is built: its texel and its coordinate along the axis
/// its cluster is split on (set by the split).
#[derive(Clone, Copy, Debug)]
struct Item {
    key: f32,
    texel: u32,
}

/// Per-texel values of the probe computed when needed (the build keeps nothing per
/// texel): direction, power and weight, the same bits as [`crate::env::probe::ProbeTables`]
/// (its direction is [`Probe::direction`]'s arithmetic from per-row and per-column sines
/// and cosines).
struct TexelSource<'a> {
    width: usize,
    texels: &'a [[f32; 3]],
    /// Per row: `(sin polar, cos polar, solid angle)`.
    rows: Vec<(f64, f64, f64)>,
    /// Per column: `(sin azimuth, cos azimuth)`.
    cols: Vec<(f64, f64)>,
    /// `sin` and `cos` of the probe rotation.
    turn: (f64, f64),
    scale: f64,
}

impl<'a> TexelSource<'a> {
    fn new(probe: &'a Probe, intensity: f32) -> TexelSource<'a> {
        let (w, h) = (probe.width(), probe.height());
        let rows = (0..h)
            .map(|r| {
                let (sp, cp) = (std::f64::consts::PI * texel_center_f64(r, h)).sin_cos();
                (sp, cp, probe.solid_angle(r))
            })
            .collect();
        let cols = (0..w)
            .map(|c| (std::f64::consts::TAU * texel_center_f64(c, w)).sin_cos())
            .collect();
        TexelSource {
            width: w,
            texels: probe.texels(),
            rows,
            cols,
            turn: probe.rotation().sin_cos(),
            scale: intensity as f64,
        }
    }

    /// The centre direction of texel `i`, rotation applied: [`Probe::direction`].
    #[inline]
    fn dir(&self, i: u32) -> DVec3 {
        let i = i as usize;
        let (sp, cp, _) = self.rows[i / self.width];
        let (sa, ca) = self.cols[i % self.width];
        let d = DVec3::new(-sp * sa, cp, sp * ca);
        let (s, c) = self.turn;
        DVec3::new(d.x * c + d.z * s, d.y, -d.x * s + d.z * c)
    }

    /// `luminance x solid angle` ([`crate::env::luminance`]).
    #[inline]
    fn weight(&self, i: u32) -> f64 {
        let i = i as usize;
        luminance(self.texels[i]) * self.rows[i / self.width].2
    }

    /// `RGB x solid angle` (not yet times the intensity).
    #[inline]
    fn power(&self, i: u32) -> DVec3 {
        let i = i as usize;
        let t = self.texels[i];
        DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64) * self.rows[i / self.width].2
    }
}

/// The arrays of one subtree: node `node0 + k` is entry `k` of the node slices, cone slot
/// `slot0 + k` entry `k` of the cone slices.
struct Out<'a> {
    node0: usize,
    slot0: usize,
    irradiance: &'a mut [Vec3],
    rep: &'a mut [Vec3],
    right: &'a mut [u32],
    slot: &'a mut [u32],
    axis: &'a mut [Vec3],
    cos_half: &'a mut [f32],
    sin_half: &'a mut [f32],
    sin_quarter: &'a mut [f32],
}

impl<'a> Out<'a> {
    /// The left subtree of `k` texels and the right one, after this node (entry 0).
    fn split(self, k: usize) -> (Out<'a>, Out<'a>) {
        let (_, irradiance) = self.irradiance.split_at_mut(1);
        let (li, ri) = irradiance.split_at_mut(2 * k - 1);
        let (_, rep) = self.rep.split_at_mut(1);
        let (lr, rr) = rep.split_at_mut(2 * k - 1);
        let (_, right) = self.right.split_at_mut(1);
        let (lt, rt) = right.split_at_mut(2 * k - 1);
        let (_, slot) = self.slot.split_at_mut(1);
        let (ls, rs) = slot.split_at_mut(2 * k - 1);
        let (_, axis) = self.axis.split_at_mut(1);
        let (la, ra) = axis.split_at_mut(k - 1);
        let (_, cos_half) = self.cos_half.split_at_mut(1);
        let (lc, rc) = cos_half.split_at_mut(k - 1);
        let (_, sin_half) = self.sin_half.split_at_mut(1);
        let (lsh, rsh) = sin_half.split_at_mut(k - 1);
        let (_, sin_quarter) = self.sin_quarter.split_at_mut(1);
        let (lq, rq) = sin_quarter.split_at_mut(k - 1);
        (
            Out {
                node0: self.node0 + 1,
                slot0: self.slot0 + 1,
                irradiance: li,
                rep: lr,
                right: lt,
                slot: ls,
                axis: la,
                cos_half: lc,
                sin_half: lsh,
                sin_quarter: lq,
            },
            Out {
                node0: self.node0 + 2 * k,
                slot0: self.slot0 + k,
                irradiance: ri,
                rep: rr,
                right: rt,
                slot: rs,
                axis: ra,
                cos_half: rc,
                sin_half: rsh,
                sin_quarter: rq,
            },
        )
    }
}

/// Builds the subtree of the cluster `members` into `out`: clusters are taken from an
/// explicit stack (a chain of lopsided splits, one bright texel split off at a time, needs
/// no recursion); a split whose halves are both at least [`PARALLEL_MEMBERS`] texels goes to
/// two rayon tasks.
fn build_subtree(texels: &TexelSource, members: &mut [Item], out: Out, progress: &Progress) {
    let mut stack = vec![(members, out)];
    let mut visited = 0u64;
    while let Some((members, out)) = stack.pop() {
        visited += members.len() as u64;
        if visited >= 1 << 16 {
            progress.inc(visited);
            visited = 0;
        }
        let mut out = out;
        let Some(k) = cluster(texels, members, &mut out) else {
            continue;
        };
        let (lm, rm) = members.split_at_mut(k);
        let (lo, ro) = out.split(k);
        if lm.len() >= PARALLEL_MEMBERS && rm.len() >= PARALLEL_MEMBERS {
            rayon::join(
                || build_subtree(texels, lm, lo, progress),
                || build_subtree(texels, rm, ro, progress),
            );
        } else {
            stack.push((rm, ro));
            stack.push((lm, lo));
        }
    }
    progress.inc(visited);
}

/// Writes the node of the cluster `members` (entry 0 of `out`): its irradiance, cone and
/// representative; returns the split `k` (the first `k` members, in place, are the left
/// child) or `None` for a single texel.
fn cluster(texels: &TexelSource, members: &mut [Item], out: &mut Out) -> Option<usize> {
    // One pass: power, brightest texel, bounding box, weighted direction sum, weight.
    let mut power = DVec3::ZERO;
    let mut brightest = (f64::NEG_INFINITY, u32::MAX);
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let mut centroid = DVec3::ZERO;
    let mut total = 0.0f64;
    for m in members.iter() {
        let (d, wt) = (texels.dir(m.texel), texels.weight(m.texel));
        power += texels.power(m.texel);
        if wt > brightest.0 || (wt == brightest.0 && m.texel < brightest.1) {
            brightest = (wt, m.texel);
        }
        lo = lo.min(d);
        hi = hi.max(d);
        centroid += d * wt;
        total += wt;
    }
    out.irradiance[0] = (power * texels.scale).as_vec3();
    let brightest_dir = texels.dir(brightest.1);
    if members.len() == 1 {
        out.rep[0] = brightest_dir.as_vec3();
        out.right[0] = LEAF;
        out.slot[0] = members[0].texel;
        return None;
    }
    let axis = ((lo + hi) * 0.5).try_normalize().unwrap_or(DVec3::Y);
    let ext = hi - lo;
    let split_axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    // Second pass: the cone's half angle, and each member's coordinate along the split axis.
    let mut min_cos = 1.0f64;
    for m in members.iter_mut() {
        let d = texels.dir(m.texel);
        min_cos = min_cos.min(axis.dot(d));
        m.key = d[split_axis] as f32;
    }
    let alpha = min_cos.clamp(-1.0, 1.0).acos();
    let alpha = (alpha.cos() - CONE_SLACK).max(-1.0).acos();
    out.rep[0] = match centroid.try_normalize() {
        Some(c) if c.dot(axis) >= alpha.cos() => c.as_vec3(),
        _ => brightest_dir.as_vec3(),
    };
    out.axis[0] = axis.as_vec3();
    out.cos_half[0] = alpha.cos() as f32;
    out.sin_half[0] = alpha.sin().max(0.0) as f32;
    out.sin_quarter[0] = (alpha / 2.0).sin() as f32;
    let k = weighted_median(members, texels, total);
    out.right[0] = (out.node0 + 2 * k) as u32;
    out.slot[0] = out.slot0 as u32;
    Some(k)
}

/// Orders `members` (at least two) by their key (ties by texel index) far enough to split
/// them at the luminance-weighted median and returns the split `k` (`1 <= k < len`): the
/// first `k` members, in place, are the `k` lowest, the fewest that carry at least half of
/// `total` (their summed weight). Selection, not a sort: each step puts the middle of the
/// open range in place (`select_nth_unstable_by`, deterministic) and keeps the half the
/// median lies in, O(len) in all.
fn weighted_median(members: &mut [Item], texels: &TexelSource, total: f64) -> usize {
    let order = |a: &Item, b: &Item| a.key.total_cmp(&b.key).then(a.texel.cmp(&b.texel));
    let half = 0.5 * total;
    // The answer's index lies in `lo..hi`; `below` is the weight of `members[..lo]`.
    let (mut lo, mut hi, mut below) = (0usize, members.len(), 0.0f64);
    let k = loop {
        if hi - lo <= 16 {
            members[lo..hi].sort_unstable_by(order);
            let mut acc = below;
            let mut found = hi;
            for (j, m) in members[lo..hi].iter().enumerate() {
                acc += texels.weight(m.texel);
                if acc >= half {
                    found = lo + j + 1;
                    break;
                }
            }
            break found;
        }
        let mid = lo + (hi - lo) / 2;
        members[lo..hi].select_nth_unstable_by(mid - lo, order);
        let left: f64 = members[lo..=mid]
            .iter()
            .map(|m| texels.weight(m.texel))
            .sum();
        if below + left >= half {
            hi = mid + 1;
        } else {
            below += left;
            lo = mid + 1;
        }
    };
    k.clamp(1, members.len() - 1)
}
