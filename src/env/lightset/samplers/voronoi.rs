//! Voronoi assignment on the sphere: each texel to its nearest light
//! ([`nearest_light_cells`]), and lights that carry their cells' power.
//!
//! Design rule: a Voronoi light carries the exact summed `RGB x solid angle` of the texels
//! whose nearest light it is, so the total power of a Voronoi light set is the probe's
//! whatever the light directions ([`super::uniform()`], [`super::lloyd()`]). Nearness is
//! the largest `d.l` computed in f32 with ties to the lowest light index, the same rule as
//! [`crate::env::LightSet::nearest`] (which agrees up to f32 ties on cell borders).

use crate::env::probe::ProbeTables;
use crate::env::LightSet;
use glam::DVec3;
use rayon::prelude::*;

/// Index of the nearest light (largest dot product) for every texel with non-zero weight,
/// `u32::MAX` for the others. Brute force over lights, parallel over texels: O(texels x
/// lights). Ties go to the lowest light index.
pub fn nearest_light_cells(tables: &ProbeTables, dirs: &[DVec3]) -> Vec<u32> {
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
            let (x, y, z) = (d.x as f32, d.y as f32, d.z as f32);
            let mut best = f32::NEG_INFINITY;
            let mut arg = 0u32;
            for k in 0..lx.len() {
                let dot = x * lx[k] + y * ly[k] + z * lz[k];
                if dot > best {
                    best = dot;
                    arg = k as u32;
                }
            }
            arg
        })
        .collect()
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
