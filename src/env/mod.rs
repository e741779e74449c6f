//! Environment lighting: light probes collapsed into sets of directional lights
//! (thesis 3.2: light probe 3.2.1, importance sampling 3.2.2 / Algorithm 1, median cut
//! 3.2.3 / Algorithm 2; Dirac-delta lights 2.3.2).
//!
//! Design rule: every light set carries **exactly** the probe's energy. A light set is N
//! directional lights, each a unit direction towards the light and an RGB irradiance
//! `E_k` = radiance integrated over the light's solid angle (the irradiance it gives a
//! surface facing it, W/m^2 for a probe in W/(m^2 sr); the thesis calls it the light's
//! "power"), so the illumination integral becomes
//! `L_o = sum_k f_r(w_k, w_o) cos(polar_k) E_k` (thesis 2.3.2: each light is a Dirac
//! delta in direction). Every sampler's light irradiances sum to the probe's integral
//! `sum_texels RGB x solid angle` ([`Probe::total_power`]) to 1e-5 relative; the samplers
//! differ only in where they put the lights and how they split the energy.
//!
//! Everything reads the probe through [`crate::conventions`]: texel centres, directions,
//! exact texel solid angles ([`crate::conventions::probe_texel_solid_angle`]; the
//! thesis's `cos(linspace)` weight gives the pole rows zero weight, we use the true area).
//!
//! Samplers live in [`samplers`]: uniform random, importance (Algorithm 1) and its
//! stratified variant, median cut (Algorithm 2, Debevec 2005), Lloyd relaxation (weighted
//! spherical k-means seeded from median cut), and the full probe (the converged
//! reference).
//!
//! Beside the light sets (`[env] method = "lights"`), three methods shade the full probe
//! without collapsing it: [`transfer`] (a table over normals), [`reflection`] (a table
//! over reflected directions, for glossy isotropic materials) and [`lightcuts`] (a light
//! tree cut per pixel); `auto`, the default, chooses per material
//! ([`prepare::EnvMethod`], [`crate::scene::env_method`]).
//!
//! The disk caches of light sets and transfer tables share one entry header and its check
//! ([`cache_entry`]).

pub mod cache_entry;
pub mod lightcuts;
pub mod lightset_io;
pub mod overlay;
pub mod prepare;
pub mod probe;
pub mod reflection;
pub mod samplers;
pub mod transfer;

pub use probe::{LoadOptions, LoadReport, Probe, ProbeError};
/// The samplers under their former module name: every `env::sampling::X` path is
/// `env::samplers::X`.
pub use samplers as sampling;
pub use samplers::{MedianCut, Region, SamplerConfig};

use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Rec. 709 / sRGB luminance weights `(R, G, B)`.
///
/// We use the values ITU-R BT.709 and IEC 61966-2-1 (sRGB) publish, 0.2126 / 0.7152 /
/// 0.0722, which are the Y row of the RGB-to-XYZ matrix of the 709 primaries with a D65
/// white and sum to exactly 1. The thesis's MATLAB code (3.2.2) uses 0.2125 / 0.7154 /
/// 0.0721, an older rounding (SMPTE 240M-era) that is labelled "BT.709" but is not what
/// the standard gives. Radiance `.hdr` and Poly Haven EXR probes are linear Rec. 709 /
/// sRGB primaries, so the standard weights are the right ones; the difference is below
/// 0.05% of any luminance and only moves sample positions, never total power.
pub const LUMINANCE_WEIGHTS: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// Luminance of a linear RGB value with [`LUMINANCE_WEIGHTS`], channels clamped to
/// `>= 0` first (so a dirty texel can never give a negative weight).
#[inline]
pub fn luminance(rgb: [f32; 3]) -> f64 {
    LUMINANCE_WEIGHTS[0] * (rgb[0].max(0.0) as f64)
        + LUMINANCE_WEIGHTS[1] * (rgb[1].max(0.0) as f64)
        + LUMINANCE_WEIGHTS[2] * (rgb[2].max(0.0) as f64)
}

/// N directional lights as a structure of arrays.
///
/// `dir_*`: unit world directions **towards** the light (y up, see
/// [`crate::conventions`]). `irradiance_*`: RGB irradiance at normal incidence =
/// radiance x solid angle, the irradiance the light gives a surface facing it (W/m^2
/// when the probe is in W/(m^2 sr); the thesis's "power" of a light, 2.3.2). All arrays
/// have the same length.
///
/// Serialized names: `irradiance_r`, `irradiance_g`, `irradiance_b`; the former names
/// `power_r`, `power_g`, `power_b` are still read ([`lightset_io`]).
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
    /// [`Probe::total_power`], the probe's `sum L Omega`, for every sampler).
    pub fn total_irradiance(&self) -> DVec3 {
        (0..self.len()).map(|i| self.light_irradiance(i)).sum()
    }

    /// Index of the light nearest to direction `d` (largest `d.l`, lowest index on ties);
    /// `None` for an empty set. For the Voronoi samplers ([`sampling::uniform`],
    /// [`sampling::lloyd`]) this is the inverse map direction -> light whose cell holds
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

/// `n` nearly uniform unit directions on the sphere (Fibonacci lattice, golden-angle
/// spiral, `y_i = 1 - (2 i + 1)/n`). Deterministic; used as the normals of the
/// render-free error metric.
pub fn fibonacci_sphere(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let a = golden * i as f64;
            DVec3::new(r * a.cos(), y, r * a.sin())
        })
        .collect()
}

/// Exact irradiance from the probe's texels at unit normal `n`, f64:
/// `E(n) = sum_texels max(0, n.d_t) L_t Omega_t` with `d_t` the texel centre direction and
/// `Omega_t` its exact solid angle. This is the converged reference every light set is
/// measured against (it equals [`SamplerConfig::Full`]'s light set evaluated in f64).
pub fn reference_irradiance(probe: &Probe, n: DVec3) -> DVec3 {
    let mut e = DVec3::ZERO;
    for row in 0..probe.height() {
        let omega = probe.solid_angle(row);
        let mut acc = DVec3::ZERO;
        for col in 0..probe.width() {
            let c = n.dot(probe.direction(row, col));
            if c > 0.0 {
                let t = probe.texel(row, col);
                acc += DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64) * c;
            }
        }
        e += acc * omega;
    }
    e
}

/// [`reference_irradiance`] for many normals, in parallel (texel directions and powers
/// are tabulated once; same f64 sums, grouped per texel instead of per row).
pub fn reference_irradiance_many(probe: &Probe, normals: &[DVec3]) -> Vec<DVec3> {
    let t = sampling::ProbeTables::new(probe);
    normals
        .par_iter()
        .map(|&n| {
            let mut e = DVec3::ZERO;
            for (d, p) in t.dir.iter().zip(&t.power) {
                let c = n.dot(*d);
                if c > 0.0 {
                    e += *p * c;
                }
            }
            e
        })
        .collect()
}

/// Exact outgoing radiance of a Lambertian surface (thesis 2.2.1, `f_r = albedo/pi`) with
/// unit normal `n` under the probe: `albedo / pi x E(n)`, f64, RGB.
pub fn reference_lambert(probe: &Probe, n: DVec3, albedo: DVec3) -> DVec3 {
    albedo * reference_irradiance(probe, n) / std::f64::consts::PI
}

/// Relative RMS irradiance error of a light set against reference irradiances `reference`
/// (from [`reference_irradiance_many`]) at the same `normals`:
/// `sqrt(sum_n |E_lights(n) - E_ref(n)|^2 / sum_n |E_ref(n)|^2)`, `|.|` the Euclidean
/// norm over RGB ([`crate::metrics::relative_l2`]: 0 when the reference is all zero and
/// the lights are too, infinite when only the reference is).
pub fn irradiance_error(lights: &LightSet, normals: &[DVec3], reference: &[DVec3]) -> f64 {
    assert_eq!(normals.len(), reference.len());
    // Irradiances in parallel, summed in index order: a reduction across rayon tasks would
    // group the sum by the thread count's split, and so change its last bits.
    let got: Vec<DVec3> = normals.par_iter().map(|&n| lights.irradiance(n)).collect();
    let (num, den) = crate::metrics::squared_error_sums(&got, reference);
    crate::metrics::relative_l2(num, den)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fibonacci_normals_cover_the_sphere() {
        let n = fibonacci_sphere(256);
        let mean: DVec3 = n.iter().copied().sum::<DVec3>() / 256.0;
        assert!(mean.length() < 1e-2);
        assert!(n.iter().all(|d| (d.length() - 1.0).abs() < 1e-12));
    }
}
