//! Deterministic filtered importance sampling of an anisotropic D-BRDF under a probe
//! (Krivanek & Colbert, "Real-time shading with filtered importance sampling", EGSR 2008):
//! the path `[env] method = "reflection"` takes for a material a reflection-space table
//! cannot hold ([`super::ReflectionPath`]).
//!
//! # Estimator
//! For the D-BRDF lobe `f` (thesis 2.3.6; [`crate::brdf::DBrdf`], the lobe of a Lambert +
//! D-BRDF) and the residual probe `L` (every texel but the `exact_lights` brightest, which
//! the lights' kernels shade as directional lights), per pixel
//! `L_o(v) = 1/N sum_i f(l_i, v) (l_i.n) L~(l_i, omega_i) / pdf(l_i)`, over a fixed set of
//! `N` half vectors `h_i` in the local shading frame (tangent, bitangent, normal; the
//! frame of anisotropic materials, [`crate::material::Material::frame_rule`]):
//! `l_i = reflect(v, h_i) = 2 (v.h_i) h_i - v`, skipped when `v.h_i <= 0` or `l_i.n <= 0`;
//! `pdf(l) = pdf(h) / (4 |v.h|)` (the Jacobian of the reflection, Walter et al. 2007, eq.
//! 14); `f(l_i, v)` with the lobe's `p(h_i)` looked up once per half vector, not per
//! pixel (`l_i + v = 2 (v.h_i) h_i`, so `h_i` is the pair's half vector and `k.h = v.h_i`); `L~(l, omega)` the probe pre-filtered over the sample's share of solid angle
//! `omega_i = 1 / (N pdf(l_i))`: a trilinear lookup in a radiance pyramid of the residual
//! ([`super::pyramid`], level `0.5 log2(omega / texel) + LOD_BIAS`). The Lambertian term of
//! a Lambert + D-BRDF (`r_d / pi`) is not sampled: it is the reflection table's diffuse
//! part, `r_d / pi` times the residual's irradiance over normals on an octahedral grid of
//! `reflection_grid` cells (parent module doc, "Diffuse term"), bilinear.
//!
//! # The sampler and its pdf
//! `pdf(h)` follows the lobe's own `p(h)` as the renderer evaluates it: the D-BRDF's
//! derived octahedral table (`n x n` texels over the hemisphere's octahedral square
//! `(u, v)` in `[-1, 1]^2`, [`crate::brdf::DBrdf::octahedral_table`]; `p` normalised so
//! that `integral p(h) (h.n) dω_h = 1`) made piecewise constant per texel: texel `t` is
//! chosen with probability `P_t = max(p_t, PDF_FLOOR max p) W_t / sum`, `W_t` its projected
//! solid angle `integral (h.n) dω_h` ([`crate::brdf::dbrdf::octahedral_projected_weights`]),
//! and within it `(u, v)` is uniform; the map `s = (x, y, 1 - |x| - |y|)`,
//! `(x, y) = ((u + v)/2, (u - v)/2)`, `h = s / |s|` has `dω_h = du dv / (2 |s|^3)`, so
//! **`pdf(h) = P_t n^2 |s|^3 / 2`** per steradian of `h`, exact for the samples drawn:
//! the estimator stays unbiased where the bilinear `p` differs from the piecewise-constant
//! one; the floor keeps every texel reachable. (A first sampler over the 64 x 32 file
//! table, piecewise constant in azimuth and `sin^2` polar, left 1.5-2x the error at N = 64:
//! its cells are a third of the lobe's width.)
//! Inversion (Pharr, Jakob & Humphreys, PBRT 3rd ed., 13.6.7, piecewise-constant 2D): the
//! marginal over the texel rows (`v`) by `u1`, the column within the row by `u2`, each continued
//! linearly inside the texel. The points are the Hammersley set
//! `(u1, u2) = ((k + 1/2) / N, radical_inverse_2(k))`, `k = 0..N`: fixed, no random state,
//! the same for every pixel.
//!
//! # Determinism
//! Each pixel sums its own samples in index order in f32: the same bits for any thread
//! count and tile size.

use super::build::{downsample, residual_power};
use super::pyramid::RadiancePyramid;
use super::table::{grid_corners, node_direction};
use crate::brdf::dbrdf::octahedral_projected_weights;
use crate::brdf::{Brdf, DBrdf};
use crate::conventions::{hemi_oct_decode_f64, ShadingFrame};
use crate::env::Probe;
use crate::material::Material;
use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// Added to the level of each lookup (module doc): the filter's radius in octaves beyond
/// the sample's share of solid angle. Krivanek & Colbert add 1; measured for lindt-paper
/// at N = 64 under city and studio (`examples/reflection_error.rs`, 96 x 96), bias 1 gave
/// 4.1% / 2.8% relative RMSE, 0.5 gave 2.3% / 1.7%, 0 gave 1.5% / 1.3%: the blur's bias
/// outweighs the aliasing it removes, so none is added.
pub const LOD_BIAS: f32 = 0.0;

/// Smallest texel weight of the sampler relative to the table's largest value (module doc,
/// "The sampler and its pdf").
pub const PDF_FLOOR: f64 = 1e-3;

/// Residual width the Lambertian term's irradiance is summed over (the reflection table's
/// default residual, [`crate::env::schema::DEFAULT_REFLECTION_RESIDUAL`]).
const DIFFUSE_RESIDUAL: usize = 256;

/// A half vector of the fixed set and its pdf per steradian of `h` (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfSample {
    /// Unit half vector in the local shading frame.
    pub h: Vec3,
    /// `pdf(h)`, 1/sr.
    pub pdf: f32,
    /// The lobe's `p(h)` ([`DBrdf::p`] at `h`), looked up once for every pixel.
    pub p: f32,
}

/// A fault seeded into the estimator, for the tests that must catch it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PdfFault {
    None,
    /// `pdf(l) = pdf(h)`: the reflection's Jacobian `1 / (4 |v.h|)` dropped.
    JacobianDropped,
}

/// What filtered importance sampling holds for one material and probe (module doc).
#[derive(Clone, Debug)]
pub struct FilteredSampler {
    lobe: DBrdf,
    samples: Vec<HalfSample>,
    pyramid: RadiancePyramid,
    /// Cells per side of the diffuse term's octahedral grid, and its RGB per vertex (empty
    /// without a Lambertian term).
    grid: usize,
    diffuse: Vec<[f32; 3]>,
    /// Probe rotation about +y, radians; `sin` and `cos` of its negative.
    rotation: f32,
    unrotate: (f32, f32),
    lod_bias: f32,
    fault: PdfFault,
}

/// The D-BRDF lobe of `material` and its Lambertian term, when the material is a D-BRDF or
/// a Lambert + D-BRDF (whatever its table's symmetry).
pub fn dbrdf_lobe(material: &Material) -> Option<(&DBrdf, Vec3)> {
    match material {
        Material::DBrdf(d) => Some((d, Vec3::ZERO)),
        Material::LambertDbrdf(d) => Some((&d.lobe, d.lambertian_term())),
        Material::Lambert(_)
        | Material::Phong(_)
        | Material::BlinnPhong(_)
        | Material::AshikhminShirley(_)
        | Material::Merl(_)
        | Material::Rgl(_)
        | Material::Sh(_) => None,
    }
}

/// Van der Corput's radical inverse in base 2 of `k` (the second Hammersley coordinate).
fn radical_inverse_2(k: u32) -> f64 {
    k.reverse_bits() as f64 / 4_294_967_296.0
}

/// The `n` half vectors of `lobe`'s sampler and their pdf (module doc, "The sampler and
/// its pdf"), in Hammersley order.
pub fn half_samples(lobe: &DBrdf, n: usize) -> Vec<HalfSample> {
    let side = lobe.octahedral_grid();
    let p = lobe.octahedral_table();
    let proj = octahedral_projected_weights(side);
    let pmax = p.iter().copied().fold(0.0f32, f32::max) as f64;
    let floor = PDF_FLOOR * pmax.max(f64::MIN_POSITIVE);
    let weight = |i: usize, j: usize| (p[j * side + i] as f64).max(floor) * proj[j * side + i];
    let rows: Vec<f64> = (0..side)
        .map(|j| (0..side).map(|i| weight(i, j)).sum())
        .collect();
    let total: f64 = rows.iter().sum();
    // Finds the cell of `u` in `[0, 1)` among `w` (summing to `sum`) and the position in it.
    let pick = |u: f64, w: &mut dyn Iterator<Item = f64>, sum: f64| -> (usize, f64) {
        let target = u * sum;
        let (mut acc, mut last) = (0.0, (0, 0.5));
        for (k, wk) in w.enumerate() {
            if wk > 0.0 {
                last = (k, ((target - acc) / wk).clamp(0.0, 1.0));
                if target < acc + wk {
                    return last;
                }
            }
            acc += wk;
        }
        last
    };
    let coord = |i: usize, f: f64| -1.0 + 2.0 * (i as f64 + f) / side as f64;
    (0..n)
        .map(|k| {
            let u1 = (k as f64 + 0.5) / n as f64;
            let u2 = radical_inverse_2(k as u32);
            let (j, f1) = pick(u1, &mut rows.iter().copied(), total);
            let (i, f2) = pick(u2, &mut (0..side).map(|i| weight(i, j)), rows[j]);
            let (u, v) = (coord(i, f2), coord(j, f1));
            // The map's point before normalisation, `s`, and `d omega = du dv / (2 |s|^3)`.
            let (x, y) = (0.5 * (u + v), 0.5 * (u - v));
            let s = DVec3::new(x, y, (1.0 - x.abs() - y.abs()).max(0.0));
            let h = hemi_oct_decode_f64(u, v);
            let texel_uv = 4.0 / (side * side) as f64;
            let pdf = weight(i, j) / total / texel_uv * 2.0 * s.length().powi(3);
            let h = h.as_vec3();
            HalfSample {
                h,
                pdf: pdf as f32,
                p: lobe.p(h),
            }
        })
        .collect()
}

impl FilteredSampler {
    /// The sampler of `material` (a D-BRDF or Lambert + D-BRDF, [`dbrdf_lobe`]; `None` for
    /// any other) under `probe` times `intensity`, the texels `exclude` left out (summed
    /// exactly as lights elsewhere): `samples` half vectors, the residual's pyramid, and the
    /// Lambertian term over normals on a grid of `grid` cells.
    pub fn new(
        probe: &Probe,
        material: &Material,
        exclude: &[usize],
        intensity: f32,
        samples: usize,
        grid: usize,
        fault: PdfFault,
    ) -> Option<FilteredSampler> {
        let (lobe, lambertian) = dbrdf_lobe(material)?;
        let (w, h) = (probe.width(), probe.height());
        let power = residual_power(probe, exclude, intensity);
        let pyramid = RadiancePyramid::from_power(&power, w, h);
        let diffuse = if lambertian == Vec3::ZERO {
            Vec::new()
        } else {
            // The reflection table's diffuse part (parent module doc, "Diffuse term").
            let factor = if w > DIFFUSE_RESIDUAL && w % DIFFUSE_RESIDUAL == 0 {
                w / DIFFUSE_RESIDUAL
            } else {
                1
            };
            let (_, texels) = downsample(&power, w, h, factor);
            let c = lambertian.as_dvec3();
            (0..(grid + 1) * (grid + 1))
                .into_par_iter()
                .map(|k| {
                    let n = node_direction(k % (grid + 1), k / (grid + 1), grid);
                    let mut e = DVec3::ZERO;
                    for (l, p) in texels.dir.iter().zip(&texels.power) {
                        let z = l.dot(n);
                        if z > 0.0 {
                            e += z * DVec3::from_array(*p);
                        }
                    }
                    (c * e).as_vec3().to_array()
                })
                .collect()
        };
        let rotation = probe.rotation() as f32;
        Some(FilteredSampler {
            lobe: lobe.clone(),
            samples: half_samples(lobe, samples),
            pyramid,
            grid,
            diffuse,
            rotation,
            unrotate: (-rotation).sin_cos(),
            lod_bias: LOD_BIAS,
            fault,
        })
    }

    /// The same sampler with the lookups' level bias `bias` instead of [`LOD_BIAS`] (for
    /// measurements).
    pub fn with_lod_bias(mut self, bias: f32) -> FilteredSampler {
        self.lod_bias = bias;
        self
    }

    /// The same sampler read with the probe turned by `angle` radians more about +y.
    pub fn turned(&self, angle: f64) -> FilteredSampler {
        let rotation = (self.rotation as f64 + angle) as f32;
        FilteredSampler {
            rotation,
            unrotate: (-rotation).sin_cos(),
            ..self.clone()
        }
    }

    /// Half vectors per pixel (`N`).
    pub fn sample_count(&self) -> usize {
        self.samples.len()
    }

    /// The fixed half vectors and their pdf.
    pub fn samples(&self) -> &[HalfSample] {
        &self.samples
    }

    /// The residual's pyramid.
    pub fn pyramid(&self) -> &RadiancePyramid {
        &self.pyramid
    }

    /// Bytes held: the pyramid, the samples and the diffuse grid.
    pub fn bytes(&self) -> usize {
        self.pyramid.bytes() + 16 * self.samples.len() + 12 * self.diffuse.len()
    }

    /// `d` in the probe's frame (rotation undone).
    #[inline]
    fn unrotated(&self, d: Vec3) -> Vec3 {
        let (s, c) = self.unrotate;
        Vec3::new(d.x * c + d.z * s, d.y, -d.x * s + d.z * c)
    }

    /// The term's radiance (RGB, W/(m^2 sr) for a probe in W/(m^2 sr)) at a pixel with
    /// world shading frame `frame` and local view `wo` (unit, above the horizon): the
    /// estimator of the module doc plus the Lambertian term at `frame.n`. f32, samples in
    /// index order.
    #[inline]
    pub fn radiance(&self, frame: &ShadingFrame, wo: Vec3) -> Vec3 {
        let n = self.samples.len() as f32;
        let mut sum = Vec3::ZERO;
        // `DBrdf::eval`'s guards: the view above the horizon (once for every sample, the same
        // test: a NaN `wo.z` passes it as before), `|l + wo| = 2 v.h` above 1e-6 and `l`
        // above the horizon per sample.
        let samples: &[HalfSample] = if wo.z <= 0.0 { &[] } else { &self.samples };
        for s in samples {
            let vh = wo.dot(s.h);
            if 2.0 * vh <= 1e-6 {
                continue;
            }
            let l = 2.0 * vh * s.h - wo;
            if l.z <= 0.0 {
                continue;
            }
            let pdf_l = match self.fault {
                PdfFault::None => s.pdf / (4.0 * vh),
                PdfFault::JacobianDropped => s.pdf,
            };
            if pdf_l <= 0.0 {
                continue;
            }
            // `l + wo = 2 (v.h) h`: the lobe's half vector is `h` and `k.h = v.h`, so the
            // sample's `p(h)` serves every pixel ([`DBrdf::eval_at_half`]).
            let f = self.lobe.eval_at_half(s.p, vh.min(1.0), l.z, wo.z);
            let d = self.unrotated(frame.to_world(l));
            let polar = d.y.clamp(-1.0, 1.0).acos();
            let mut u = (-d.x).atan2(d.z) * (0.5 * std::f32::consts::FRAC_1_PI);
            if u < 0.0 {
                u += 1.0;
            }
            let v = polar * std::f32::consts::FRAC_1_PI;
            let sin_polar = (1.0 - d.y * d.y).max(0.0).sqrt();
            let level = self.pyramid.level_for(1.0 / (n * pdf_l), sin_polar) + self.lod_bias;
            sum += f * (l.z / pdf_l) * self.pyramid.lookup(u, v, level);
        }
        let mut out = sum / n;
        if !self.diffuse.is_empty() {
            for (node, wc) in grid_corners(self.unrotated(frame.n), self.grid) {
                out += wc * Vec3::from_array(self.diffuse[node]);
            }
        }
        out
    }
}
