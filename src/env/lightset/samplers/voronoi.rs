//! Voronoi assignment on the sphere: each texel to its nearest light
//! ([`nearest_light_cells`]), and lights that carry their cells' power.
//!
//! Design rule: a Voronoi light carries the exact summed `RGB x solid angle` of the texels
//! whose nearest light it is, so the total power of a Voronoi light set is the probe's
//! whatever the light directions ([`super::uniform()`], [`super::lloyd()`]). Nearness is
//! the largest `d.l` computed in f32 with ties to the lowest light index, the same rule as
//! [`crate::env::LightSet::nearest`] (which agrees up to f32 ties on cell borders).

use crate::conventions::texel_center_f64;
use crate::env::probe::ProbeTables;
use crate::env::LightSet;
use glam::DVec3;
use rayon::prelude::*;

/// Index of the nearest light (largest dot product) for every texel with non-zero weight,
/// `u32::MAX` for the others. Brute force over lights, parallel over texels: O(texels x
/// lights), the lights taken eight at a time. Ties go to the
/// lowest light index.
///
/// # Panics
/// With more than 2^24 lights (an index must be exact in f32; light sets are capped at
/// [`crate::env::schema::MAX_LIGHTS`] = 2^16).
pub fn nearest_light_cells(tables: &ProbeTables, dirs: &[DVec3]) -> Vec<u32> {
    assert!(dirs.len() <= 1 << 24, "{} lights: at most 2^24", dirs.len());
    let lx: Vec<f32> = dirs.iter().map(|d| d.x as f32).collect();
    let ly: Vec<f32> = dirs.iter().map(|d| d.y as f32).collect();
    let lz: Vec<f32> = dirs.iter().map(|d| d.z as f32).collect();
    tables
        .dir
        .par_iter()
        .zip(tables.weight.par_iter())
        .with_min_len(256)
        .map(|(d, &w)| {
            if w <= 0.0 || dirs.is_empty() {
                return u32::MAX;
            }
            nearest_light([d.x as f32, d.y as f32, d.z as f32], &lx, &ly, &lz)
        })
        .collect()
}

/// Lights compared side by side in [`nearest_light`]: independent running maxima the
/// compiler keeps in vector registers.
const LANES: usize = 8;

/// Index of the light (directions as f32 columns `lx, ly, lz`, not empty) with the largest
/// `d.l`, ties to the lowest index: the same index as a sequential scan keeping the first
/// strict maximum (each dot product is the same f32 expression, `x lx + y ly + z lz` in
/// that order, so the same bits). Lane `j` keeps the first maximum of the lights
/// `j, j + LANES, ...`; the lanes are then reduced to the largest value and, among equal
/// values, the lowest index; the lights past the last whole group of [`LANES`] follow
/// sequentially (their indices are higher, so a strict `>` keeps the lowest).
fn nearest_light(d: [f32; 3], lx: &[f32], ly: &[f32], lz: &[f32]) -> u32 {
    let [x, y, z] = d;
    let whole = lx.len() / LANES * LANES;
    let mut best = [f32::NEG_INFINITY; LANES];
    // Light indices as f32 (exact: at most `MAX_LIGHTS` = 2^16 lights, below 2^24), so
    // that the index follows the maximum in the same vector select.
    let mut arg = [0f32; LANES];
    let mut index: [f32; LANES] = std::array::from_fn(|j| j as f32);
    let groups = lx[..whole]
        .chunks_exact(LANES)
        .zip(ly[..whole].chunks_exact(LANES))
        .zip(lz[..whole].chunks_exact(LANES));
    for ((cx, cy), cz) in groups {
        for j in 0..LANES {
            let dot = x * cx[j] + y * cy[j] + z * cz[j];
            let better = dot > best[j];
            best[j] = if better { dot } else { best[j] };
            arg[j] = if better { index[j] } else { arg[j] };
            index[j] += LANES as f32;
        }
    }
    let mut top = f32::NEG_INFINITY;
    let mut top_arg = 0u32;
    for j in 0..LANES {
        let a = arg[j] as u32;
        if best[j] > top || (best[j] == top && a < top_arg) {
            top = best[j];
            top_arg = a;
        }
    }
    for k in whole..lx.len() {
        let dot = x * lx[k] + y * ly[k] + z * lz[k];
        if dot > top {
            top = dot;
            top_arg = k as u32;
        }
    }
    top_arg
}

/// Lights at `dirs`, each carrying the summed power of the texels in its cell (`cells`
/// from [`nearest_light_cells`]; `u32::MAX` texels belong to no light).
pub(super) fn lights_from_cells(tables: &ProbeTables, dirs: &[DVec3], cells: &[u32]) -> LightSet {
    let mut power = vec![DVec3::ZERO; dirs.len()];
    for (i, &c) in cells.iter().enumerate() {
        if c != u32::MAX {
            power[c as usize] += tables.power[i];
        }
    }
    let mut ls = LightSet::with_capacity(dirs.len());
    for (d, p) in dirs.iter().zip(&power) {
        ls.push(*d, *p);
    }
    ls
}

/// [`nearest_light_cells`] on the probe itself, without its tables (4 bytes per texel
/// instead of 56): each texel's direction is [`ProbeTables`]' own (the same bits), computed
/// per row; the same cells.
pub(super) fn probe_cells(probe: &crate::env::Probe, dirs: &[DVec3]) -> Vec<u32> {
    assert!(dirs.len() <= 1 << 24, "{} lights: at most 2^24", dirs.len());
    let (w, h) = (probe.width(), probe.height());
    let lx: Vec<f32> = dirs.iter().map(|d| d.x as f32).collect();
    let ly: Vec<f32> = dirs.iter().map(|d| d.y as f32).collect();
    let lz: Vec<f32> = dirs.iter().map(|d| d.z as f32).collect();
    let cols: Vec<(f64, f64)> = (0..w)
        .map(|c| (std::f64::consts::TAU * texel_center_f64(c, w)).sin_cos())
        .collect();
    let (s, c) = probe.rotation().sin_cos();
    let mut cells = vec![u32::MAX; w * h];
    cells.par_chunks_mut(w).enumerate().for_each(|(row, out)| {
        let omega = probe.solid_angle(row);
        let (sp, cp) = (std::f64::consts::PI * texel_center_f64(row, h)).sin_cos();
        for (col, cell) in out.iter_mut().enumerate() {
            if !(crate::env::luminance(probe.texel(row, col)) * omega > 0.0) || dirs.is_empty() {
                continue;
            }
            let (sa, ca) = cols[col];
            let d = DVec3::new(-sp * sa, cp, sp * ca);
            let d = DVec3::new(d.x * c + d.z * s, d.y, -d.x * s + d.z * c);
            *cell = nearest_light([d.x as f32, d.y as f32, d.z as f32], &lx, &ly, &lz);
        }
    });
    cells
}

/// [`lights_from_cells`] on the probe itself: each light carries the summed `RGB x solid
/// angle` of its cell's texels, in texel order (the same bits).
pub(super) fn lights_from_probe_cells(
    probe: &crate::env::Probe,
    dirs: &[DVec3],
    cells: &[u32],
) -> LightSet {
    let w = probe.width();
    let mut power = vec![DVec3::ZERO; dirs.len()];
    for (i, &c) in cells.iter().enumerate() {
        if c != u32::MAX {
            let t = probe.texels()[i];
            power[c as usize] +=
                DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64) * probe.solid_angle(i / w);
        }
    }
    let mut ls = LightSet::with_capacity(dirs.len());
    for (d, p) in dirs.iter().zip(&power) {
        ls.push(*d, *p);
    }
    ls
}

#[cfg(test)]
mod tests {
    use super::nearest_light;

    /// The sequential scan [`nearest_light`] must agree with: the first strict maximum.
    fn sequential(d: [f32; 3], lx: &[f32], ly: &[f32], lz: &[f32]) -> u32 {
        let mut best = f32::NEG_INFINITY;
        let mut arg = 0u32;
        for k in 0..lx.len() {
            let dot = d[0] * lx[k] + d[1] * ly[k] + d[2] * lz[k];
            if dot > best {
                best = dot;
                arg = k as u32;
            }
        }
        arg
    }

    #[test]
    fn lanes_pick_the_same_light_as_a_sequential_scan_ties_included() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
        };
        for n in [1usize, 3, 7, 8, 9, 16, 17, 129] {
            let mut l: Vec<[f32; 3]> = (0..n).map(|_| [next(), next(), next()]).collect();
            // Repeated directions: ties, across lanes, within a lane and in the tail.
            if n > 2 {
                l[n - 1] = l[0];
                l[n / 2] = l[1];
            }
            let (lx, ly, lz): (Vec<f32>, Vec<f32>, Vec<f32>) = (
                l.iter().map(|v| v[0]).collect(),
                l.iter().map(|v| v[1]).collect(),
                l.iter().map(|v| v[2]).collect(),
            );
            for i in 0..400 {
                // Half the texels point exactly at a light (its ties decide), half anywhere.
                let d = if i % 2 == 0 {
                    l[i / 2 % n]
                } else {
                    [next(), next(), next()]
                };
                assert_eq!(
                    nearest_light(d, &lx, &ly, &lz),
                    sequential(d, &lx, &ly, &lz),
                    "n = {n}, texel {i}"
                );
            }
        }
    }
}
