//! Light clustering: directional lights as a structure of arrays in chunks of [`LANES`],
//! sorted so that each chunk's lights are spatially coherent and bounded by a cone, and the
//! tile normal cones ([`Cone`]) the chunks are culled against.
//!
//! Design rule: culling only skips a chunk whose cone lies wholly below the horizon of every
//! normal of a tile (with the margin [`CULL_MARGIN`]); such lights would have been left out
//! of every pixel's gathered list anyway ([`super::gather`]), so the image is bit-identical
//! with and without culling, for any tile size. Units: directions unit world vectors towards
//! the light, `er, eg, eb` irradiance at normal incidence (W/m^2).

use crate::lanes::LANES;
use crate::light::Light;
use glam::Vec3;

/// Margin (in cosine) of the tile/chunk cone test: cones must be this far below the
/// horizon before a chunk is skipped, so rounding in the per-pixel local directions can
/// never turn a skipped light into a (tiny) contributing one.
pub const CULL_MARGIN: f32 = 1e-3;

/// Directional lights as a structure of arrays, in chunks of [`LANES`] (padded with
/// zero-irradiance lights pointing up), sorted for spatial coherence.
#[derive(Clone, Debug, Default)]
pub struct DirLights {
    pub dx: Vec<f32>,
    pub dy: Vec<f32>,
    pub dz: Vec<f32>,
    /// Irradiance at normal incidence (RGB).
    pub er: Vec<f32>,
    pub eg: Vec<f32>,
    pub eb: Vec<f32>,
    /// Per chunk: cone axis (unit) and the sine of its half-angle (2 for an empty or
    /// all-directions chunk, which no cone test can skip).
    pub chunk_axis: Vec<Vec3>,
    pub chunk_cos: Vec<f32>,
    pub chunk_sin: Vec<f32>,
    /// Per chunk: bit `i` set when lane `i` carries irradiance (not padding, not black).
    pub chunk_live_mask: Vec<u8>,
}

/// A normal cone: every normal `n` of a tile has `n . axis >= cos`, `sin = sqrt(1-cos^2)`
/// (only meaningful when `cos >= 0`; a wider cone skips nothing).
#[derive(Clone, Copy, Debug)]
pub struct Cone {
    pub axis: Vec3,
    pub cos: f32,
    pub sin: f32,
}

impl Cone {
    /// The cone around the normalised sum of `normals`; `None` if they span a half-space or
    /// more (nothing can be culled) or the list is empty.
    pub fn around(normals: impl Iterator<Item = Vec3> + Clone) -> Option<Cone> {
        let axis = normals
            .clone()
            .fold(Vec3::ZERO, |a, n| a + n)
            .try_normalize()?;
        let cos = normals.map(|n| n.dot(axis)).fold(1.0f32, f32::min);
        if !(cos > 0.0) {
            return None;
        }
        Some(Cone {
            axis,
            cos,
            sin: (1.0 - cos * cos).max(0.0).sqrt(),
        })
    }
}

/// Morton-style key of a unit direction on an octahedral map: nearby directions get nearby
/// keys, so consecutive lights form tight chunks.
fn direction_key(d: Vec3) -> u64 {
    let l1 = d.x.abs() + d.y.abs() + d.z.abs();
    let p = if l1 > 0.0 { d / l1 } else { Vec3::Y };
    let (mut u, mut v) = (p.x, p.z);
    if p.y < 0.0 {
        let (ou, ov) = (u, v);
        u = (1.0 - ov.abs()) * ou.signum();
        v = (1.0 - ou.abs()) * ov.signum();
    }
    let q = |x: f32| (((x * 0.5 + 0.5).clamp(0.0, 1.0)) * 65535.0) as u64;
    let (a, b) = (q(u), q(v));
    let mut key = 0u64;
    for bit in 0..16 {
        key |= ((a >> bit) & 1) << (2 * bit);
        key |= ((b >> bit) & 1) << (2 * bit + 1);
    }
    key
}

impl DirLights {
    /// Collects the directional lights of `lights` (point lights are left to the caller),
    /// sorted by `direction_key` (ties by original index), padded to whole chunks.
    pub fn from_lights(lights: &[Light]) -> DirLights {
        let mut dirs: Vec<(u64, usize, Vec3, Vec3)> = lights
            .iter()
            .enumerate()
            .filter_map(|(i, l)| match *l {
                Light::Directional {
                    to_light,
                    irradiance,
                } => Some((direction_key(to_light), i, to_light, irradiance)),
                Light::Point { .. } => None,
            })
            .collect();
        dirs.sort_by_key(|&(k, i, _, _)| (k, i));
        let mut s = DirLights::default();
        for &(_, _, d, e) in &dirs {
            s.dx.push(d.x);
            s.dy.push(d.y);
            s.dz.push(d.z);
            s.er.push(e.x);
            s.eg.push(e.y);
            s.eb.push(e.z);
        }
        while s.dx.len() % LANES != 0 {
            for (v, x) in [
                (&mut s.dx, 0.0),
                (&mut s.dy, 1.0),
                (&mut s.dz, 0.0),
                (&mut s.er, 0.0),
                (&mut s.eg, 0.0),
                (&mut s.eb, 0.0),
            ] {
                v.push(x);
            }
        }
        for c in 0..s.chunks() {
            let r = c * LANES..(c + 1) * LANES;
            let live_mask = r
                .clone()
                .filter(|&i| s.er[i] != 0.0 || s.eg[i] != 0.0 || s.eb[i] != 0.0)
                .fold(0u8, |m, i| m | 1 << (i - c * LANES));
            s.chunk_live_mask.push(live_mask);
            let live: Vec<Vec3> = r
                .clone()
                .filter(|&i| s.er[i] != 0.0 || s.eg[i] != 0.0 || s.eb[i] != 0.0)
                .map(|i| Vec3::new(s.dx[i], s.dy[i], s.dz[i]))
                .collect();
            match Cone::around(live.iter().copied()) {
                Some(cone) if !live.is_empty() => {
                    s.chunk_axis.push(cone.axis);
                    s.chunk_cos.push(cone.cos);
                    s.chunk_sin.push(cone.sin);
                }
                _ if live.is_empty() => {
                    // No irradiance at all: always skippable.
                    s.chunk_axis.push(Vec3::Y);
                    s.chunk_cos.push(f32::INFINITY);
                    s.chunk_sin.push(0.0);
                }
                _ => {
                    s.chunk_axis.push(Vec3::Y);
                    s.chunk_cos.push(-1.0);
                    s.chunk_sin.push(2.0);
                }
            }
        }
        s
    }

    /// Number of chunks of [`LANES`] lights.
    pub fn chunks(&self) -> usize {
        self.dx.len() / LANES
    }

    /// Number of real (unpadded) lights is not tracked; this is the padded count.
    pub fn len(&self) -> usize {
        self.dx.len()
    }

    pub fn is_empty(&self) -> bool {
        self.dx.is_empty()
    }

    /// Indices of the chunks that can light some normal of `tile` (all chunks when the
    /// tile has no usable cone).
    pub fn chunks_for(&self, tile: Option<Cone>) -> Vec<u32> {
        (0..self.chunks() as u32)
            .filter(|&c| {
                let c = c as usize;
                if self.chunk_cos[c] == f32::INFINITY {
                    return false; // zero irradiance
                }
                let Some(t) = tile else { return true };
                if self.chunk_sin[c] > 1.0 {
                    return true;
                }
                // Largest n.l over the two cones is cos(max(0, angle - a_t - a_c)); the chunk
                // is skippable when angle >= pi/2 + a_t + a_c, i.e.
                // cos(angle) <= cos(pi/2 + a) = -sin(a), a = a_t + a_c.
                let cos_a = t.cos * self.chunk_cos[c] - t.sin * self.chunk_sin[c];
                let sin_a = t.sin * self.chunk_cos[c] + t.cos * self.chunk_sin[c];
                if cos_a <= 0.0 {
                    return true; // combined cone reaches past 90 degrees
                }
                t.axis.dot(self.chunk_axis[c]) > -sin_a - CULL_MARGIN
            })
            .collect()
    }
}
