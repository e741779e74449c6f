//! Median cut, thesis Algorithm 2 / Debevec 2005 ([`median_cut()`]): the probe image cut
//! into `n` rectangles of about equal energy, one light per rectangle ([`MedianCut`] keeps
//! the regions and cuts for overlays and tests).
//!
//! Design rule: the cuts decide only where the lights go; each light carries its region's
//! exact summed RGB power, and the regions tile the image, so the total is exact. Energy
//! sums come from a summed-area table (`summed_area.rs`) of `luminance x solid angle`; the
//! longest side is measured on the sphere, not in pixels.

use super::summed_area::SummedAreaTable;
use crate::env::probe::ProbeTables;
use crate::env::{LightSet, Probe};
use crate::progress::Progress;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// A rectangle of texels `[row0, row1) x [col0, col1)` of the probe image.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Region {
    pub row0: usize,
    pub row1: usize,
    pub col0: usize,
    pub col1: usize,
    /// Summed `luminance x solid angle` of its texels.
    pub energy: f64,
}

impl Region {
    /// Number of texels.
    pub fn texels(&self) -> usize {
        (self.row1 - self.row0) * (self.col1 - self.col0)
    }
    /// True if `(row, col)` lies inside.
    pub fn contains(&self, row: usize, col: usize) -> bool {
        (self.row0..self.row1).contains(&row) && (self.col0..self.col1).contains(&col)
    }
}

/// One median cut: `parent` split at `at` (a row index for [`CutAxis::Rows`], a column
/// index for [`CutAxis::Cols`]) into halves of energy `energy_a` (before `at`) and
/// `energy_b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cut {
    pub parent: Region,
    pub axis: CutAxis,
    pub at: usize,
    pub energy_a: f64,
    pub energy_b: f64,
}

/// Direction of a cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CutAxis {
    /// A horizontal cut line between rows `at - 1` and `at` (splits the polar extent).
    Rows,
    /// A vertical cut line between columns `at - 1` and `at` (splits the azimuth extent).
    Cols,
}

/// Result of [`median_cut`]: `lights[i]` belongs to `regions[i]`; `cuts` in the order made.
#[derive(Clone, Debug)]
pub struct MedianCut {
    pub lights: LightSet,
    pub regions: Vec<Region>,
    pub cuts: Vec<Cut>,
    width: usize,
    height: usize,
    rotation: f64,
}

impl MedianCut {
    /// Index of the region (and light) whose texels contain direction `d`: the inverse
    /// map direction -> texel -> region.
    pub fn region_of(&self, d: DVec3) -> usize {
        let (u, v) =
            crate::conventions::probe_uv(crate::conventions::rotate_about_up(d, -self.rotation));
        let (row, col) = crate::conventions::probe_texel(u, v, self.width, self.height);
        self.regions
            .iter()
            .position(|r| r.contains(row, col))
            .expect("regions tile the probe")
    }
}

fn region(sat: &SummedAreaTable, r0: usize, r1: usize, c0: usize, c1: usize) -> Region {
    Region {
        row0: r0,
        row1: r1,
        col0: c0,
        col1: c1,
        energy: sat.sum(r0, r1, c0, c1),
    }
}

/// Splits a region at its energy median along its longest side measured on the sphere:
/// azimuth extent `2 pi (cols / width) sin(mid polar)` against polar extent
/// `pi rows / height` (Debevec 2005; pixels would over-split the poles). Ties and
/// 1-texel-thick sides fall back to the other axis; `None` for a single texel.
/// The cut index minimises `|energy_a - energy_b|` (first minimum), which bounds the
/// difference by the energy of the one strip that straddles the median.
fn split(
    sat: &SummedAreaTable,
    r: &Region,
    width: usize,
    height: usize,
) -> Option<(Region, Region, Cut)> {
    let rows = r.row1 - r.row0;
    let cols = r.col1 - r.col0;
    if rows * cols <= 1 {
        return None;
    }
    let pi = std::f64::consts::PI;
    let mid_polar = pi * (r.row0 + r.row1) as f64 / (2.0 * height as f64);
    let az_len = std::f64::consts::TAU * cols as f64 / width as f64 * mid_polar.sin();
    let polar_len = pi * rows as f64 / height as f64;
    let axis = if cols < 2 || (rows >= 2 && polar_len >= az_len) {
        CutAxis::Rows
    } else {
        CutAxis::Cols
    };
    let (lo, hi) = match axis {
        CutAxis::Rows => (r.row0, r.row1),
        CutAxis::Cols => (r.col0, r.col1),
    };
    let left = |k: usize| match axis {
        CutAxis::Rows => sat.sum(r.row0, k, r.col0, r.col1),
        CutAxis::Cols => sat.sum(r.row0, r.row1, r.col0, k),
    };
    let total = r.energy;
    let mut best = (f64::INFINITY, lo + 1);
    for k in lo + 1..hi {
        let a = left(k);
        let d = (2.0 * a - total).abs();
        if d < best.0 {
            best = (d, k);
        }
        if 2.0 * a >= total {
            break; // the difference only grows from here on
        }
    }
    let k = best.1;
    let (a, b) = match axis {
        CutAxis::Rows => (
            region(sat, r.row0, k, r.col0, r.col1),
            region(sat, k, r.row1, r.col0, r.col1),
        ),
        CutAxis::Cols => (
            region(sat, r.row0, r.row1, r.col0, k),
            region(sat, r.row0, r.row1, k, r.col1),
        ),
    };
    let cut = Cut {
        parent: *r,
        axis,
        at: k,
        energy_a: a.energy,
        energy_b: b.energy,
    };
    Some((a, b, cut))
}

/// Median cut, thesis Algorithm 2 / Debevec, "A Median Cut Algorithm for Light Probe
/// Sampling" (SIGGRAPH 2005 poster), on the `luminance x solid angle` map.
///
/// Rule for the number of regions: while doubling does not exceed `n`, every splittable
/// region is split (the thesis's levels; `n = 2^k` gives exactly `k` levels); then, until
/// there are `n` regions, the splittable region of highest energy is split (first in
/// order on ties). This makes any `n >= 1` work. A 1-texel region cannot be split, so a
/// probe with fewer than `n` texels gives one region per texel (fewer than `n` lights).
/// `n == 0` or a black probe gives no lights and no regions.
///
/// Each region gets one light at its energy centroid in direction space
/// (`sum weight x direction`, normalised; the region's centre texel direction if that sum
/// vanishes, e.g. a uniform region spanning the whole sphere), carrying the region's
/// summed RGB power (f64), so the total is exact.
pub fn median_cut(probe: &Probe, n: usize) -> MedianCut {
    median_cut_with_progress(probe, n, &Progress::hidden())
}

/// [`median_cut()`], counting on `progress` one step per level (`floor(log2 n)` of them,
/// more when some regions cannot be split) and one for the highest-energy splits and the
/// lights. Counting does not change the
/// result.
pub fn median_cut_with_progress(probe: &Probe, n: usize, progress: &Progress) -> MedianCut {
    median_cut_of_tables(probe, &ProbeTables::new(probe), n, progress)
}

/// [`median_cut_with_progress`] from the probe's tables already built (`t`, of `probe`):
/// Lloyd's seed, which keeps its tables.
pub(super) fn median_cut_of_tables(
    probe: &Probe,
    t: &ProbeTables,
    n: usize,
    progress: &Progress,
) -> MedianCut {
    let levels = if n == 0 { 0 } else { n.ilog2() as u64 };
    progress.set_length(levels + 1);
    let mut out = MedianCut {
        lights: LightSet::default(),
        regions: Vec::new(),
        cuts: Vec::new(),
        width: t.width,
        height: t.height,
        rotation: probe.rotation(),
    };
    if n == 0 || t.total_weight <= 0.0 {
        progress.inc(levels + 1);
        return out;
    }
    let sat = SummedAreaTable::new(&t.weight, t.width, t.height);
    let mut regions = vec![region(&sat, 0, t.height, 0, t.width)];
    let mut cuts = Vec::new();
    let mut levels_done = 0;
    // Level by level.
    while regions.len() * 2 <= n {
        let mut next = Vec::with_capacity(regions.len() * 2);
        let mut any = false;
        for r in &regions {
            match split(&sat, r, t.width, t.height) {
                Some((a, b, c)) => {
                    next.push(a);
                    next.push(b);
                    cuts.push(c);
                    any = true;
                }
                None => next.push(*r),
            }
        }
        regions = next;
        levels_done += 1;
        // More levels than floor(log2 n) when regions could not be split: the length
        // grows, keeping one step for the end.
        progress.set_length(levels.max(levels_done) + 1);
        progress.inc(1);
        if !any {
            break;
        }
    }
    // Highest energy first, until n.
    while regions.len() < n {
        let mut best: Option<(usize, (Region, Region, Cut))> = None;
        for (i, r) in regions.iter().enumerate() {
            if best
                .as_ref()
                .is_some_and(|(j, _)| regions[*j].energy >= r.energy)
            {
                continue;
            }
            if let Some(s) = split(&sat, r, t.width, t.height) {
                best = Some((i, s));
            }
        }
        let Some((i, (a, b, c))) = best else { break };
        regions[i] = a;
        regions.insert(i + 1, b);
        cuts.push(c);
    }
    let mut lights = LightSet::with_capacity(regions.len());
    for r in &regions {
        let mut centroid = DVec3::ZERO;
        let mut power = DVec3::ZERO;
        let mut wsum = 0.0;
        for row in r.row0..r.row1 {
            for col in r.col0..r.col1 {
                let i = row * t.width + col;
                centroid += t.dir[i] * t.weight[i];
                power += t.power[i];
                wsum += t.weight[i];
            }
        }
        let dir = if wsum > 0.0 && centroid.length() > 1e-9 * wsum {
            centroid.normalize()
        } else {
            t.dir[((r.row0 + r.row1) / 2) * t.width + (r.col0 + r.col1) / 2]
        };
        lights.push(dir, power);
    }
    out.lights = lights;
    out.regions = regions;
    out.cuts = cuts;
    // Without levels left to split (a probe with few texels), the length is the steps done.
    progress.set_length(levels_done + 1);
    progress.inc(1);
    out
}
