//! [`ProbeTables`]: the per-texel numbers every sampler, the light tree and the reference
//! irradiance read (weight, RGB power, centre direction), computed once per probe.
//!
//! Design rule: the samplers never read the probe's texels themselves; they read these
//! tables, so every sampler sees the same weight (the "monochrome map" of thesis
//! Algorithms 1 and 2: `luminance(RGB) x exact solid angle`, [`crate::env::luminance`],
//! [`crate::conventions::probe_texel_solid_angle`]) and the same texel-centre directions
//! (rotation applied, no half-texel offset).

use super::Probe;
use crate::env::luminance;
use glam::DVec3;

/// Per-texel tables shared by the samplers, row-major like the probe.
#[derive(Clone, Debug)]
pub struct ProbeTables {
    pub width: usize,
    pub height: usize,
    /// `luminance x solid angle` (sr-weighted luminance), f64, `>= 0`.
    pub weight: Vec<f64>,
    /// `RGB x solid angle`, f64.
    pub power: Vec<DVec3>,
    /// Texel centre directions, rotation applied.
    pub dir: Vec<DVec3>,
    /// Sum of `weight`.
    pub total_weight: f64,
    /// Sum of `power` (equals [`Probe::total_power`] up to summation order).
    pub total_power: DVec3,
}

impl ProbeTables {
    /// Builds the tables of a probe (O(texels)).
    pub fn new(probe: &Probe) -> Self {
        let (w, h) = (probe.width(), probe.height());
        let mut weight = Vec::with_capacity(w * h);
        let mut power = Vec::with_capacity(w * h);
        let mut dir = Vec::with_capacity(w * h);
        for row in 0..h {
            let omega = probe.solid_angle(row);
            for col in 0..w {
                let t = probe.texel(row, col);
                weight.push(luminance(t) * omega);
                power.push(DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64) * omega);
                dir.push(probe.direction(row, col));
            }
        }
        let total_weight = weight.iter().sum();
        let total_power = power.iter().copied().sum();
        ProbeTables {
            width: w,
            height: h,
            weight,
            power,
            dir,
            total_weight,
            total_power,
        }
    }
}
