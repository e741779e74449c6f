//! Lloyd relaxation ([`lloyd()`]): median cut's lights moved by weighted spherical
//! k-means until the Voronoi cells settle.
//!
//! Design rule: the iterations move only the light directions; the final powers are the
//! Voronoi cells' exact summed RGB power ([`super::voronoi`]), so the total is exact
//! whatever the number of iterations.

use super::nearest_light_cells;
use super::voronoi::lights_from_cells;
use super::voronoi::{lights_from_probe_cells, probe_cells};
use crate::env::probe::ProbeTables;
use crate::env::{LightSet, Probe};
use crate::progress::Progress;
use glam::DVec3;

/// Lloyd relaxation on the sphere: weighted spherical k-means of the texel directions
/// (weight `luminance x solid angle`), seeded from [`median_cut`](super::median_cut())'s lights, `iterations`
/// rounds of (assign each texel to its nearest light; move each light to its cell's
/// normalised energy centroid), stopping early when no assignment changes. Each light
/// then carries its final Voronoi cell's summed RGB power (f64), so the total is exact.
/// A light whose cell has no energy stays where it is with zero power.
///
/// Why it beats median cut: k-means minimises `sum weight |d - light|^2`, the
/// second-moment (spread) of each cell around its light, which is what the error of a
/// smooth response such as `max(0, n.l)` depends on to first order; median cut's
/// axis-aligned boxes only balance energy and leave long, thin cells. Cost:
/// O(iterations x texels x n) (brute-force nearest light).
pub fn lloyd(probe: &Probe, n: usize, iterations: usize) -> LightSet {
    lloyd_with_progress(probe, n, iterations, &Progress::hidden())
}

/// Largest probe width Lloyd's relaxation iterates at: a wider probe is relaxed on its
/// copy downsampled by an integer factor ([`crate::env::probe::resample::downsample_box`],
/// power kept exactly), and only the final cells are found, and their powers summed, on
/// the full probe. Why 512: the shipped probes are 512 x 256, so their light sets keep
/// their bits; at 512 x 256 each of the default 128 lights' cells still holds about a
/// thousand texels, so where the lights settle hardly depends on finer texels, while each
/// round costs texels x lights (a 4096 x 2048 probe: 17 rounds of 8 M x 128 dot products,
/// 20 s of CPU, against one at the end).
pub const RELAXATION_WIDTH: usize = 512;

/// [`lloyd()`], counting on `progress` one step for the median-cut seed and its first
/// assignment, then one per relaxation round, then one for the full probe's cells when the
/// rounds ran on a downsampled copy ([`RELAXATION_WIDTH`]); on convergence before
/// `iterations` rounds the length is cut to the steps done. Counting does not change the
/// light set.
pub fn lloyd_with_progress(
    probe: &Probe,
    n: usize,
    iterations: usize,
    progress: &Progress,
) -> LightSet {
    let (w, h) = (probe.width(), probe.height());
    let f = (2..=w)
        .find(|&f| w.is_multiple_of(f) && h.is_multiple_of(f) && w / f <= RELAXATION_WIDTH)
        .filter(|_| w > RELAXATION_WIDTH)
        .unwrap_or(1);
    if f == 1 {
        return match relax(probe, n, iterations, progress) {
            Some((t, dirs, cells)) => lights_from_cells(&t, &dirs, &cells),
            None => LightSet::default(),
        };
    }
    let coarse = crate::env::probe::resample::downsample_box(probe, f);
    let Some((_, dirs, _)) = relax(&coarse, n, iterations, progress) else {
        return LightSet::default();
    };
    progress.set_length(progress.position() + 1);
    let cells = probe_cells(probe, &dirs);
    let lights = lights_from_probe_cells(probe, &dirs, &cells);
    progress.inc(1);
    lights
}

/// The rounds of [`lloyd()`] on `probe`: its tables, the final light directions and cells;
/// `None` for a black probe or `n == 0`.
fn relax(
    probe: &Probe,
    n: usize,
    iterations: usize,
    progress: &Progress,
) -> Option<(ProbeTables, Vec<DVec3>, Vec<u32>)> {
    progress.set_length(iterations as u64 + 1);
    let t = ProbeTables::new(probe);
    let seed = super::median_cut::median_cut_of_tables(probe, &t, n, &Progress::hidden());
    if seed.lights.is_empty() {
        progress.inc(iterations as u64 + 1);
        return None;
    }
    let mut dirs: Vec<DVec3> = (0..seed.lights.len())
        .map(|i| seed.lights.direction(i))
        .collect();
    let mut cells = nearest_light_cells(&t, &dirs);
    progress.inc(1);
    for round in 0..iterations {
        let mut acc = vec![DVec3::ZERO; dirs.len()];
        for (i, &c) in cells.iter().enumerate() {
            if c != u32::MAX {
                acc[c as usize] += t.dir[i] * t.weight[i];
            }
        }
        for (d, a) in dirs.iter_mut().zip(&acc) {
            if let Some(nd) = a.try_normalize() {
                *d = nd;
            }
        }
        let next = nearest_light_cells(&t, &dirs);
        let changed = next != cells;
        cells = next;
        progress.inc(1);
        if !changed {
            progress.set_length(round as u64 + 2);
            break;
        }
    }
    Some((t, dirs, cells))
}
