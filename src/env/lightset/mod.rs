//! Light sets: a probe collapsed into N directional lights ([`LightSet`], thesis 2.3.2,
//! 3.2), how they are sampled ([`samplers`]), written and read ([`file`](mod@file)),
//! prepared for a scene and cached ([`prepare`]), and measured against the converged
//! reference ([`reference`](mod@reference)).
//!
//! Design rule: every light set carries **exactly** the probe's energy (the parent
//! module's doc).

pub mod file;
pub mod prepare;
pub mod reference;
pub mod samplers;

pub use reference::{
    fibonacci_sphere, irradiance_error, reference_irradiance, reference_irradiance_many,
    reference_lambert,
};

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// N directional lights as a structure of arrays.
///
/// `dir_*`: unit world directions **towards** the light (y up, see
/// [`crate::conventions`]). `irradiance_*`: RGB irradiance at normal incidence =
/// radiance x solid angle, the irradiance the light gives a surface facing it (W/m^2
/// when the probe is in W/(m^2 sr); the thesis's "power" of a light, 2.3.2). All arrays
/// have the same length.
///
/// Serialized names: `irradiance_r`, `irradiance_g`, `irradiance_b`; the former names
/// `power_r`, `power_g`, `power_b` are still read ([`file`](mod@file)).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LightSet {
    pub dir_x: Vec<f32>,
    pub dir_y: Vec<f32>,
    pub dir_z: Vec<f32>,
    #[serde(alias = "power_r")]
    pub irradiance_r: Vec<f32>,
    #[serde(alias = "power_g")]
    pub irradiance_g: Vec<f32>,
    #[serde(alias = "power_b")]
    pub irradiance_b: Vec<f32>,
}

impl LightSet {
    /// An empty set with room for `n` lights.
    pub fn with_capacity(n: usize) -> Self {
        LightSet {
            dir_x: Vec::with_capacity(n),
            dir_y: Vec::with_capacity(n),
            dir_z: Vec::with_capacity(n),
            irradiance_r: Vec::with_capacity(n),
            irradiance_g: Vec::with_capacity(n),
            irradiance_b: Vec::with_capacity(n),
        }
    }

    /// Number of lights.
    pub fn len(&self) -> usize {
        self.dir_x.len()
    }

    /// True when there are no lights.
    pub fn is_empty(&self) -> bool {
        self.dir_x.is_empty()
    }

    /// Appends a light with RGB irradiance `irradiance` (at normal incidence, W/m^2);
    /// `dir` is normalised (a zero direction becomes +y).
    pub fn push(&mut self, dir: DVec3, irradiance: DVec3) {
        let d = dir.try_normalize().unwrap_or(DVec3::Y);
        self.dir_x.push(d.x as f32);
        self.dir_y.push(d.y as f32);
        self.dir_z.push(d.z as f32);
        self.irradiance_r.push(irradiance.x as f32);
        self.irradiance_g.push(irradiance.y as f32);
        self.irradiance_b.push(irradiance.z as f32);
    }

    /// Direction of light `i` (f64). Panics if out of range.
    pub fn direction(&self, i: usize) -> DVec3 {
        DVec3::new(
            self.dir_x[i] as f64,
            self.dir_y[i] as f64,
            self.dir_z[i] as f64,
        )
    }

    /// RGB irradiance of light `i` at normal incidence (f64, W/m^2). Panics if out of
    /// range.
    pub fn light_irradiance(&self, i: usize) -> DVec3 {
        DVec3::new(
            self.irradiance_r[i] as f64,
            self.irradiance_g[i] as f64,
            self.irradiance_b[i] as f64,
        )
    }

    /// Sum of every light's irradiance at normal incidence, accumulated in f64 (equals
    /// [`super::Probe::total_power`], the probe's `sum L Omega`, for every sampler).
    pub fn total_irradiance(&self) -> DVec3 {
        (0..self.len()).map(|i| self.light_irradiance(i)).sum()
    }

    /// Index of the light nearest to direction `d` (largest `d.l`, lowest index on ties);
    /// `None` for an empty set. For the Voronoi samplers ([`samplers::uniform`],
    /// [`samplers::lloyd`]) this is the inverse map direction -> light whose cell holds
    /// `d`, up to f32 ties on cell borders.
    pub fn nearest(&self, d: DVec3) -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for i in 0..self.len() {
            let dot = d.dot(self.direction(i));
            if best.is_none_or(|(_, b)| dot > b) {
                best = Some((i, dot));
            }
        }
        best.map(|(i, _)| i)
    }

    /// Multiplies every light's irradiance by `factor` (one f32 product per channel
    /// value; directions unchanged).
    pub fn scale_irradiance(&mut self, factor: f32) {
        for e in self
            .irradiance_r
            .iter_mut()
            .chain(self.irradiance_g.iter_mut())
            .chain(self.irradiance_b.iter_mut())
        {
            *e *= factor;
        }
    }

    /// Irradiance at a surface with unit normal `n`: `sum_k max(0, n.l_k) E_k`, f64.
    pub fn irradiance(&self, n: DVec3) -> DVec3 {
        (0..self.len())
            .map(|i| self.light_irradiance(i) * n.dot(self.direction(i)).max(0.0))
            .sum()
    }
}

/// The light set as scene lights (directional, each with its irradiance).
pub fn to_scene_lights(ls: &LightSet) -> Vec<crate::light::Light> {
    (0..ls.len())
        .map(|i| crate::light::Light::Directional {
            to_light: glam::Vec3::new(ls.dir_x[i], ls.dir_y[i], ls.dir_z[i]),
            irradiance: glam::Vec3::new(ls.irradiance_r[i], ls.irradiance_g[i], ls.irradiance_b[i]),
        })
        .collect()
}
