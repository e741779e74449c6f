//! A mip pyramid of a probe's radiance in its own equirectangular (lat-long)
//! parameterisation, for filtered lookups ([`super::filtered`]): level 0 the residual probe
//! at full resolution, each next level the 2 x 2 blocks of the one before.
//!
//! # Solid-angle weighting
//! A lat-long texel's solid angle shrinks towards the poles
//! (`(2 pi / w) (cos(polar_top) - cos(polar_bottom))`,
//! [`crate::conventions::probe_texel_solid_angle`]: `cos(latitude)` times the equator's), so
//! a block is not the plain mean of its four texels: each level holds its texels' *power*
//! (radiance times solid angle, W/m^2 for a probe in W/(m^2 sr)) summed exactly, divided
//! by the block's summed solid angle. Every level therefore carries exactly the probe's
//! power, and a constant probe stays the same constant on every level.
//!
//! # Lookup
//! Bilinear within a level (texel centres at `((i + 1/2)/w, (j + 1/2)/h)`, azimuth wraps,
//! polar clamps to the first and last rows), linear between the two levels around a
//! fractional level (trilinear). The level of a filter of solid angle `omega` at polar
//! angle `polar` is `0.5 log2(omega / omega_0(polar))`, `omega_0` level 0's texel solid
//! angle there (`2 pi^2 / (w h) sin(polar)`, the sine clamped to that of half a row so the
//! poles stay finite), clamped to the pyramid ([`RadiancePyramid::level_for`]).

use crate::conventions::{floor_f32, probe_texel_solid_angle};
use glam::Vec3;

/// One level: `width x height` texels of RGB radiance, row-major.
#[derive(Clone, Debug)]
struct Level {
    width: usize,
    height: usize,
    radiance: Vec<[f32; 3]>,
}

/// The pyramid (module doc): at least one level; the last is at most 2 texels wide or has
/// an odd side.
#[derive(Clone, Debug)]
pub struct RadiancePyramid {
    levels: Vec<Level>,
}

impl RadiancePyramid {
    /// From texel powers (radiance times solid angle, RGB, f64) of a `w x h` lat-long image
    /// (row-major, [`crate::conventions`] texel convention): level 0 their radiance, then
    /// 2 x 2 block sums while both sides halve evenly (module doc, "Solid-angle weighting").
    pub fn from_power(power: &[[f64; 3]], w: usize, h: usize) -> RadiancePyramid {
        assert_eq!(power.len(), w * h, "pyramid from a {w} x {h} image");
        let mut omega: Vec<f64> = (0..h)
            .map(|row| probe_texel_solid_angle(row, w, h))
            .collect();
        let mut pw = power.to_vec();
        let (mut cw, mut ch) = (w, h);
        let mut levels = Vec::new();
        loop {
            let radiance = pw
                .iter()
                .enumerate()
                .map(|(idx, p)| {
                    let o = omega[idx / cw];
                    [(p[0] / o) as f32, (p[1] / o) as f32, (p[2] / o) as f32]
                })
                .collect();
            levels.push(Level {
                width: cw,
                height: ch,
                radiance,
            });
            if cw <= 2 || cw % 2 != 0 || ch % 2 != 0 {
                break;
            }
            let (nw, nh) = (cw / 2, ch / 2);
            let mut next = vec![[0.0f64; 3]; nw * nh];
            for row in 0..ch {
                for col in 0..cw {
                    let o = &mut next[(row / 2) * nw + col / 2];
                    for (oc, pc) in o.iter_mut().zip(pw[row * cw + col]) {
                        *oc += pc;
                    }
                }
            }
            omega = (0..nh)
                .map(|r| omega[2 * r] * 2.0 + omega[2 * r + 1] * 2.0)
                .collect();
            (pw, cw, ch) = (next, nw, nh);
        }
        RadiancePyramid { levels }
    }

    /// Levels (1 or more).
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// `(width, height)` of level 0.
    pub fn size(&self) -> (usize, usize) {
        (self.levels[0].width, self.levels[0].height)
    }

    /// Bytes of the radiance held on every level.
    pub fn bytes(&self) -> usize {
        self.levels.iter().map(|l| 12 * l.radiance.len()).sum()
    }

    /// The fractional level whose texels at polar angle `polar` (given as `sin(polar)`)
    /// cover the solid angle `omega` (sr), clamped to `[0, levels - 1]` (module doc).
    #[inline]
    pub fn level_for(&self, omega: f32, sin_polar: f32) -> f32 {
        let l0 = &self.levels[0];
        let half_row = (std::f32::consts::FRAC_PI_2 / l0.height as f32).sin();
        let texel = 2.0 * std::f32::consts::PI * std::f32::consts::PI
            / (l0.width * l0.height) as f32
            * sin_polar.max(half_row);
        (0.5 * (omega / texel).log2()).clamp(0.0, (self.levels.len() - 1) as f32)
    }

    /// Radiance at image coordinates `(u, v)` (`u` in [0, 1) wraps, `v` in [0, 1] the polar
    /// angle over pi) on fractional level `level` (clamped to the pyramid): trilinear
    /// (module doc, "Lookup").
    #[inline]
    pub fn lookup(&self, u: f32, v: f32, level: f32) -> Vec3 {
        let top = (self.levels.len() - 1) as f32;
        let level = level.clamp(0.0, top);
        let k0 = (floor_f32(level) as usize).min(self.levels.len() - 1);
        let t = level - k0 as f32;
        let a = self.bilinear(k0, u, v);
        if t > 0.0 && k0 + 1 < self.levels.len() {
            a * (1.0 - t) + self.bilinear(k0 + 1, u, v) * t
        } else {
            a
        }
    }

    /// Bilinear lookup on level `k` (module doc, "Lookup").
    #[inline]
    fn bilinear(&self, k: usize, u: f32, v: f32) -> Vec3 {
        let l = &self.levels[k];
        let (w, h) = (l.width, l.height);
        let x = u * w as f32 - 0.5;
        let x0 = floor_f32(x);
        let fx = x - x0;
        // Azimuth wraps: `x0` is in `[-1, w - 1]` for `u` in `[0, 1]`, so one compare each
        // instead of an integer division (`rem_euclid` stays for anything else, the same
        // texel either way).
        let (xi, wi) = (x0 as i64, w as i64);
        let i0 = if (0..wi).contains(&xi) {
            xi
        } else if (-wi..0).contains(&xi) {
            xi + wi
        } else {
            xi.rem_euclid(wi)
        } as usize;
        let i1 = if i0 + 1 == w { 0 } else { i0 + 1 };
        let y = (v * h as f32 - 0.5).clamp(0.0, (h - 1) as f32);
        let j0 = (floor_f32(y) as usize).min(h - 1);
        let j1 = (j0 + 1).min(h - 1);
        let fy = y - j0 as f32;
        let at = |i: usize, j: usize| Vec3::from_array(l.radiance[j * w + i]);
        let top = at(i0, j0) * (1.0 - fx) + at(i1, j0) * fx;
        let bottom = at(i0, j1) * (1.0 - fx) + at(i1, j1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}
