//! [`ProbeTables`]: the per-texel numbers every sampler, the light tree and the reference
//! irradiance read (weight, RGB power, centre direction), computed once per probe.
//!
//! Design rule: the samplers never read the probe's texels themselves; they read these
//! tables, so every sampler sees the same weight (the "monochrome map" of thesis
//! Algorithms 1 and 2: `luminance(RGB) x exact solid angle`, [`crate::env::luminance`],
//! [`crate::conventions::probe_texel_solid_angle`]) and the same texel-centre directions
//! (rotation applied, no half-texel offset).

use super::Probe;
use crate::conventions::texel_center_f64;
use crate::env::luminance;
use glam::DVec3;
use rayon::prelude::*;

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
    /// Builds the tables of a probe (O(texels)), parallel over rows. The directions are
    /// [`Probe::direction`]'s arithmetic (the same bits) from sines and cosines computed once
    /// per row and per column.
    pub fn new(probe: &Probe) -> Self {
        let (w, h) = (probe.width(), probe.height());
        let cols: Vec<(f64, f64)> = (0..w)
            .map(|c| (std::f64::consts::TAU * texel_center_f64(c, w)).sin_cos())
            .collect();
        let (s, c) = probe.rotation().sin_cos();
        let mut weight = vec![0.0f64; w * h];
        let mut power = vec![DVec3::ZERO; w * h];
        let mut dir = vec![DVec3::ZERO; w * h];
        weight
            .par_chunks_mut(w)
            .zip(power.par_chunks_mut(w))
            .zip(dir.par_chunks_mut(w))
            .enumerate()
            .for_each(|(row, ((wr, pr), dr))| {
                let omega = probe.solid_angle(row);
                let (sp, cp) = (std::f64::consts::PI * texel_center_f64(row, h)).sin_cos();
                for col in 0..w {
                    let t = probe.texel(row, col);
                    wr[col] = luminance(t) * omega;
                    pr[col] = DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64) * omega;
                    let (sa, ca) = cols[col];
                    let d = DVec3::new(-sp * sa, cp, sp * ca);
                    dr[col] = DVec3::new(d.x * c + d.z * s, d.y, -d.x * s + d.z * c);
                }
            });
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
