//! Baking a [`ReflectionTable`] from a probe and a material: the residual probe, the culled
//! exact sums at every (node, slice, psi sample), the Fourier projection, and the table's
//! own error measured against exact sums over the full-resolution residual
//! (`measure_error`).
//!
//! (Past 400 lines because it is one computation, the bake: the residual pyramid, the
//! culled sums, the Fourier projection and the error measurement all serve the one loop
//! over nodes and are not used elsewhere; the lobe's radial table is `lobe.rs`.)
//!
//! # The sum at one sample
//! A sample `(r, polar_o, psi)` is the normal `n = cos(polar_o) r + sin(polar_o) (cos psi t +
//! sin psi b)` (`(t, b)` the node's chart frame, [`chart_frame`]) and the view
//! `v = 2 (n.r) n - r`; its radiance is `sum_texels P_texel f(l, v) cos(polar_i)` over the
//! residual's texels above `n`'s horizon (texel centre `l`, power `P = L Omega intensity`),
//! the BRDF evaluated in f64 ([`crate::material::Material::eval_f64`]) in the frame with
//! the view at azimuth 0 (any frame gives the same value for an isotropic material).
//!
//! # Residual and culling
//! The residual is the probe without its `exact_lights` brightest texels (summed exactly per
//! pixel instead), downsampled by an integer factor to at most `residual` texels wide, power
//! summed exactly (each coarse texel at its centre). Per node, the residual is summed over a
//! pyramid of it ([`CONE_DEG`]): its own texels within 10 degrees of `r` (where a sharp lobe
//! and, at grazing views, the horizon's cut through it lie), blocks of 2 x 2 of them out to
//! 30 degrees, of 4 x 4 out to 60 and of 8 x 8 beyond, where the lobe's tail varies slowly
//! (fewer levels where the residual is too small to halve; `pyramid`). A block is kept
//! whole or opened by its centre's angle to `r`, so the texels a node sums partition the
//! sphere and every block's power is summed exactly. Against the single 30-degree cone of
//! full-resolution texels (4 x 4 blocks beyond) it replaced, the bake under studio took
//! 31-50 s instead of 55-93 s (Blinn-Phong 50 and 500, gold dust paint; one interleaved run
//! on a loaded 2-core machine) and the rendered error moved by at most 0.3 points of p99.
//! `measure_error` holds the result to the exact sum over every texel of the full probe.
//!
//! # The integrand
//! For Blinn-Phong and the isotropic D-BRDFs the pairs do not call
//! [`Material::eval_f64`]: the lobe's factor in the half vector's polar angle is a per-bake
//! radial table ([`super::lobe`]: 4096 intervals in `sqrt(1 - cos(polar_h))`, measured
//! error at most 7.5e-6 of the peak at Blinn-Phong 500; a D-BRDF's table is its
//! octahedral lookup averaged over azimuth), and the texels where the table's zero tail
//! holds at every sample of a node are dropped from its list (exact, [`super::lobe`],
//! "Culling"). Profiles of the bake before (`perf record`, 16 x 16 image,
//! `examples/reflection_error.rs`): Blinn-Phong 200 under city, glibc `pow` 57%
//! (`__ieee754_pow_fma` and its entry), the sum's own arithmetic 37%; gold dust paint,
//! `DBrdf::eval_f64` with its octahedral lookup 66% (`floorf` 9% of it; its `pow` is
//! `powi(5)` of Schlick's Fresnel, inlined as multiplications: no libm call), the sum 25%.
//! After: the tabulated sum is 69-83% of the profile, `measure_error`'s exact
//! evaluations 10-12%. One interleaved run on the loaded 2-core machine (64 x 64, default
//! parameters): Blinn-Phong 200 18.6 -> 8.3 s (city), 16.7 -> 8.4 s (studio); gold dust
//! paint 30.9 -> 10.9 s, 30.0 -> 13.9 s; the error columns moved by at most 0.04 points of
//! p99 (the bake's own studio p99 of the gold dust paint, 30.09% -> 30.13%). What bounds
//! the bake now is the number of (sample, texel) pairs: `slices x N + 1` samples per
//! node (`N` of [`super::table::psi_samples`]: 105 at the defaults, 13 slices and order 2;
//! 235 at order 6, 313 before `N` fell from `4 order` to `3 order`) times the node's culled texel list, at two square
//! roots, a division and a table lookup each. The list is culled by the tight bound
//! `alpha <= 2 polar_h` ([`super::lobe`], "Culling": about a fifth fewer texels per node
//! than the bound before, and a cull at all for Blinn-Phong 50; order 6 on 64 cells under
//! studio, one interleaved run: Blinn-Phong 200 38.3 -> 33.0 s, 50 43.5 -> 28.7 s).
//!
//! The tabulated sums then moved into the node's frame (`sums.rs`): each texel's
//! components along `(r, t, b)` once per node, so a sample's `l.n` and `l.v` are three
//! multiply-adds and one, the radial table's variable `1 - cos(polar_h)` (one square root
//! and one division per pair instead of two square roots and a division), four partial
//! sums over structure-of-arrays (the compiler's two-lane SSE2 code), the material's
//! constant factors applied once per sum, the psi basis computed once per bake, and
//! chunks of four texels past every lobe at the sample skipped. Order 6 on 64 cells under
//! studio, Blinn-Phong 200 (`kd = 0.05`, `ks = 0.9`), one interleaved pair on the loaded
//! 2-core machine (user CPU seconds of the whole example, 16 x 16 image): 24.6 -> 14.6 s;
//! the rendered error unchanged in the printed digits (docs/rendering.md has the
//! order-6, 128-cell rows). The per-chunk skip alone measured no gain in one pair (13.7 s
//! both: the node's list is in pyramid order, so few chunks of four lie wholly outside
//! one sample's lobe); it stays, the same bits either way. Tried and left: before the frame, the texel loop outside and a slice's samples inside over
//! arrays, which the compiler did not vectorise and which baked order 6 slower.
//!
//! # Determinism
//! One rayon task per node of the grid; each node's sums run over its texel list in a
//! fixed order inside that task (`sums.rs`, "Order of the sums"), so the table is the same bits for any thread count. The error's
//! samples come from a fixed SplitMix64 sequence.

use super::lobe::Lobe;
use super::sums::{frame_sum, FrameTexels};
use super::table::{
    chart_frame, chart_is_z, coeffs, node_direction, psi_samples, slice_angle, value_count,
    BakeError, ReflectionTable, MAX_COEFFS, MAX_ORDER, MIN_ORDER,
};
use crate::conventions::{
    probe_direction, probe_texel_solid_angle, texel_center_f64, view_frame_f64,
};
use crate::env::{Probe, LUMINANCE_WEIGHTS};
use crate::error::{Error, Result};
use crate::lanes::Dispatch;
use crate::material::Material;
use crate::progress::Progress;
use glam::DVec3;
use rayon::prelude::*;

/// Angles from the reflected direction out to which the residual's pyramid levels 0, 1 and 2
/// (its own texels, 2 x 2 and 4 x 4 blocks) are summed, degrees; level 3 (8 x 8 blocks)
/// beyond (module doc, "Residual and culling").
pub const CONE_DEG: [f64; 3] = [10.0, 30.0, 60.0];

/// Narrowest level of the pyramid, texels: a level is made only if it stays this wide.
pub const MIN_LEVEL_WIDTH: usize = 32;

/// One level of the residual's pyramid: `width` texels wide, row-major.
struct Level {
    width: usize,
    texels: Texels,
}

/// The residual's pyramid (module doc, "Residual and culling"): level 0 is the residual
/// (`rw x rh`, powers `power`), level `k + 1` the 2 x 2 block sums of level `k`, as long as
/// both sides halve evenly, the level stays [`MIN_LEVEL_WIDTH`] wide and there is a cone
/// for it in [`CONE_DEG`].
fn pyramid(power: Vec<[f64; 3]>, rw: usize, rh: usize, fine: Texels) -> Vec<Level> {
    let mut levels = vec![Level {
        width: rw,
        texels: fine,
    }];
    let (mut pw, mut w, mut h) = (power, rw, rh);
    while levels.len() <= CONE_DEG.len()
        && w.is_multiple_of(2)
        && h.is_multiple_of(2)
        && w / 2 >= MIN_LEVEL_WIDTH
    {
        let (next, texels) = downsample(&pw, w, h, 2);
        (pw, w, h) = (next, w / 2, h / 2);
        levels.push(Level { width: w, texels });
    }
    levels
}

/// Pushes onto `out` the texels node `r` sums for texel `idx` of pyramid level `level`:
/// the texel whole if it is on level 0 or its centre is outside that level's cone
/// (`cos_cone[level - 1]`), else its four children, recursively, in row-major order.
fn gather(
    levels: &[Level],
    cos_cone: &[f64],
    r: DVec3,
    level: usize,
    idx: usize,
    out: &mut Texels,
) {
    let l = &levels[level];
    if level == 0 || l.texels.dir[idx].dot(r) < cos_cone[level - 1] {
        out.push(l.texels.dir[idx], l.texels.power[idx]);
        return;
    }
    let (row, col) = (idx / l.width, idx % l.width);
    let cw = levels[level - 1].width;
    for cr in 2 * row..2 * row + 2 {
        for cc in 2 * col..2 * col + 2 {
            gather(levels, cos_cone, r, level - 1, cr * cw + cc, out);
        }
    }
}

/// Largest table: 2^24 values (64 MiB of f32).
pub const MAX_VALUES: usize = 1 << 24;

/// **Test only**: faults seeded into the bake, for the tests that show the measured error
/// and the comparisons fail on them.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BakeFault {
    /// No fault: the shipped bake.
    #[default]
    None,
    /// The sine coefficients stored negated: psi measured the other way round (a
    /// handedness slip between bake and lookup).
    SineTermsNegated,
    /// The Lambertian term left in the lobes' series and the diffuse term over normals
    /// zero (the table before "Diffuse term" of the parent module doc).
    DiffuseInSeries,
}

/// The table's parameters (the `[env]` fields `reflection_grid`, `reflection_slices`,
/// `reflection_residual`, `reflection_order`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BakeParams {
    /// Cells per side of the octahedral grid of reflected directions.
    pub grid: usize,
    /// Uniform view slices over 0-85 degrees (the horizon slice is one more).
    pub slices: usize,
    /// Largest width of the residual probe the table is baked from, texels.
    pub residual: usize,
    /// Order of the Fourier series in psi, [`MIN_ORDER`] to [`MAX_ORDER`] (parent module
    /// doc, "Order of the series in psi").
    pub order: usize,
}

impl BakeParams {
    /// Checks the parameters against themselves and the probe's size; errors name the field.
    pub fn check(&self, width: usize, height: usize) -> Result<()> {
        if !(2..=1024).contains(&self.grid) {
            return Err(Error::field(
                "env.reflection_grid",
                format!("{} is out of range (2 to 1024 cells per side)", self.grid),
            ));
        }
        if !(2..=256).contains(&self.slices) {
            return Err(Error::field(
                "env.reflection_slices",
                format!("{} is out of range (2 to 256)", self.slices),
            ));
        }
        if !(MIN_ORDER..=MAX_ORDER).contains(&self.order) {
            return Err(Error::field(
                "env.reflection_order",
                format!(
                    "{} is out of range ({MIN_ORDER} to {MAX_ORDER}: the order of the series \
                     in psi)",
                    self.order
                ),
            ));
        }
        let values = value_count(self.grid, self.slices, self.order);
        if values > MAX_VALUES {
            return Err(Error::field(
                "env.reflection_grid",
                format!(
                    "{} cells per side, {} slices and order {} are {values} values, over 2^24 \
                     (64 MiB)",
                    self.grid, self.slices, self.order
                ),
            ));
        }
        if self.residual < 4 || !self.residual.is_multiple_of(2) {
            return Err(Error::field(
                "env.reflection_residual",
                format!("{} must be an even number of texels >= 4", self.residual),
            ));
        }
        if width > self.residual
            && (!width.is_multiple_of(self.residual) || !height.is_multiple_of(self.residual / 2))
        {
            return Err(Error::field(
                "env.reflection_residual",
                format!(
                    "{} must divide the probe's width {width} (and half of it its height {height})",
                    self.residual
                ),
            ));
        }
        Ok(())
    }
}

/// Texels as directions in the probe's own frame (rotation not applied) and powers
/// (`L Omega intensity`, RGB).
#[derive(Clone, Debug, Default)]
pub(super) struct Texels {
    pub(super) dir: Vec<DVec3>,
    pub(super) power: Vec<[f64; 3]>,
}

impl Texels {
    pub(super) fn push(&mut self, d: DVec3, p: [f64; 3]) {
        self.dir.push(d);
        self.power.push(p);
    }
}

/// Power per texel of a `w x h` equirectangular image (row-major), summed `f x f` to a
/// `w/f x h/f` one, with each coarse texel's centre direction.
pub(super) fn downsample(
    power: &[[f64; 3]],
    w: usize,
    h: usize,
    f: usize,
) -> (Vec<[f64; 3]>, Texels) {
    let (cw, ch) = (w / f, h / f);
    let mut out = vec![[0.0f64; 3]; cw * ch];
    for row in 0..h {
        for col in 0..w {
            let o = &mut out[(row / f) * cw + col / f];
            for (oc, pc) in o.iter_mut().zip(power[row * w + col]) {
                *oc += pc;
            }
        }
    }
    let mut t = Texels::default();
    for row in 0..ch {
        for col in 0..cw {
            let d = probe_direction(texel_center_f64(col, cw), texel_center_f64(row, ch));
            t.push(d, out[row * cw + col]);
        }
    }
    (out, t)
}

/// The full probe's texel powers times `intensity`, the texels `exclude` zero.
pub(super) fn residual_power(probe: &Probe, exclude: &[usize], intensity: f32) -> Vec<[f64; 3]> {
    let w = probe.width();
    let mut power: Vec<[f64; 3]> = probe
        .texels()
        .iter()
        .enumerate()
        .map(|(idx, t)| {
            let o = probe_texel_solid_angle(idx / w, w, probe.height()) * intensity as f64;
            [t[0] as f64 * o, t[1] as f64 * o, t[2] as f64 * o]
        })
        .collect();
    for &idx in exclude {
        power[idx] = [0.0; 3];
    }
    power
}

/// The exact sum of the module doc at normal `n` and view `v` (unit, probe frame) over
/// `texels`, in f64, of `f - minus` (`minus`: the Lambertian term the table holds over
/// normals instead, or zero for the whole BRDF), every pair through
/// [`Material::eval_f64`].
pub(super) fn radiance_sum(
    material: &Material,
    cosine: bool,
    minus: DVec3,
    n: DVec3,
    v: DVec3,
    texels: &Texels,
) -> DVec3 {
    let (x, y, wo) = view_frame_f64(n, v);
    let mut sum = DVec3::ZERO;
    for (l, p) in texels.dir.iter().zip(&texels.power) {
        let z = l.dot(n);
        if z <= 0.0 {
            continue;
        }
        let wi = DVec3::new(l.dot(x), l.dot(y), z);
        let f = material.eval_f64(wi, wo) - minus;
        let f = if cosine { f } else { f * z };
        sum += f * DVec3::from_array(*p);
    }
    sum
}

/// The bake's sum at normal `n` and view `v` over `texels` (module doc, "The sum at one
/// sample"), the integrand `lobe`: its radial table where it has one (Blinn-Phong and
/// isotropic D-BRDFs, [`super::lobe`]), summed as the bake sums a node's samples (in the
/// frame of `r = 2 (n.v) n - v`, `sums.rs`), else [`radiance_sum`]. f64.
#[cfg(test)]
pub(super) fn lobe_sum(lobe: &Lobe, cosine: bool, n: DVec3, v: DVec3, texels: &Texels) -> DVec3 {
    let c = n.dot(v).clamp(0.0, 1.0);
    if c <= 0.0 {
        return radiance_sum(lobe.material, cosine, lobe.minus, n, v, texels);
    }
    let r = (2.0 * c * n - v).normalize();
    // n = c r + s t: t the normal's part normal to r (any tangent where there is none).
    let side = n - n.dot(r) * r;
    let s = side.length();
    let t = if s > 1e-12 {
        side / s
    } else {
        chart_frame(r, chart_is_z(r)).0
    };
    let frame = FrameTexels::new(&texels.dir, &texels.power, r, t, r.cross(t));
    frame_sum(Dispatch::detect(), &lobe.form, cosine, &frame, c, s, 0.0)
        .unwrap_or_else(|| radiance_sum(lobe.material, cosine, lobe.minus, n, v, texels))
}

/// The sample `(r, polar_o, psi)` as a normal and a view (module doc), chart frame `tb`.
pub fn sample_normal_view(
    r: DVec3,
    polar: f64,
    psi: f64,
    (t, b): (DVec3, DVec3),
) -> (DVec3, DVec3) {
    let (so, co) = polar.sin_cos();
    let (sp, cp) = psi.sin_cos();
    let n = (co * r + so * (cp * t + sp * b)).normalize();
    let v = (2.0 * n.dot(r) * n - r).normalize();
    (n, v)
}

/// Bakes the table of `material` under `probe` (times `intensity`), the texels `exclude`
/// left out (summed exactly elsewhere), on `params` (module doc), and measures its error
/// (`measure_error`). One progress step per grid node. Errors name the field
/// ([`BakeParams::check`]).
pub fn bake_table(
    probe: &Probe,
    material: &Material,
    params: BakeParams,
    exclude: &[usize],
    intensity: f32,
    progress: &Progress,
    fault: BakeFault,
) -> Result<ReflectionTable> {
    let (w, h) = (probe.width(), probe.height());
    params.check(w, h)?;
    let power = residual_power(probe, exclude, intensity);
    let factor = if w > params.residual {
        w / params.residual
    } else {
        1
    };
    let (rpow, fine) = downsample(&power, w, h, factor);
    let (rw, rh) = (w / factor, h / factor);
    let levels = pyramid(rpow, rw, rh, fine);
    let cos_cone: Vec<f64> = CONE_DEG.iter().map(|d| d.to_radians().cos()).collect();
    let cosine = material.includes_cosine();
    // The Lambertian term, tabulated over normals (parent module doc, "Diffuse term").
    let lambertian = if cosine || fault == BakeFault::DiffuseInSeries {
        DVec3::ZERO
    } else {
        material.lambertian_term().as_dvec3()
    };
    let lobe = Lobe::new(material, lambertian);
    let cull = lobe.cull_cos();
    let g = params.grid;
    let ns = params.slices + 1;
    let (order, nc, samples) = (
        params.order,
        coeffs(params.order),
        psi_samples(params.order),
    );
    // Per psi sample: (sin psi, cos psi) and the basis
    // `[1/2, cos psi, sin psi, ..., cos(order psi), sin(order psi)]`.
    let psi: Vec<(f64, f64)> = (0..samples)
        .map(|m| (std::f64::consts::TAU * m as f64 / samples as f64).sin_cos())
        .collect();
    let bases: Vec<[f64; MAX_COEFFS]> = (0..samples)
        .map(|m| {
            let psi = std::f64::consts::TAU * m as f64 / samples as f64;
            let mut basis = [0.0f64; MAX_COEFFS];
            basis[0] = 0.5;
            for j in 1..=order {
                let (sj, cj) = (j as f64 * psi).sin_cos();
                (basis[2 * j - 1], basis[2 * j]) = (cj, sj);
            }
            basis
        })
        .collect();
    let nodes = (g + 1) * (g + 1);
    progress.set_length(nodes as u64);
    // The widest f64 lanes of this CPU: every path gives the same bits (`sums::frame_sum`).
    let dispatch = Dispatch::detect();
    let per_node: Vec<Vec<f32>> = (0..nodes)
        .into_par_iter()
        .map(|k| {
            let r = node_direction(k % (g + 1), k / (g + 1), g);
            // The node's texels: the pyramid opened by angle to r.
            let mut texels = Texels::default();
            let top = levels.len() - 1;
            for idx in 0..levels[top].texels.dir.len() {
                gather(&levels, &cos_cone, r, top, idx, &mut texels);
            }
            // Texels whose every pair has a zero integrand (lobe module doc, "Culling").
            if let Some(c) = cull {
                let mut kept = Texels::default();
                for (l, p) in texels.dir.iter().zip(&texels.power) {
                    if l.dot(r) > c {
                        kept.push(*l, *p);
                    }
                }
                texels = kept;
            }
            let tb = chart_frame(r, chart_is_z(r));
            let frame = FrameTexels::new(&texels.dir, &texels.power, r, tb.0, tb.1);
            // The sample (polar, psi) over the node's texels (module doc, `sums.rs`).
            let sum = |polar: f64, m: usize| -> DVec3 {
                let (so, co) = polar.sin_cos();
                let (sp, cp) = psi[m];
                frame_sum(dispatch, &lobe.form, cosine, &frame, co, so * cp, so * sp)
                    .unwrap_or_else(|| {
                        let psi = std::f64::consts::TAU * m as f64 / samples as f64;
                        let (n, v) = sample_normal_view(r, polar, psi, tb);
                        radiance_sum(lobe.material, cosine, lobe.minus, n, v, &texels)
                    })
            };
            let mut out = vec![0.0f32; ns * 3 * nc];
            for s in 0..ns {
                let polar = slice_angle(s, params.slices);
                let mut series = [[0.0f64; MAX_COEFFS]; 3];
                if polar == 0.0 {
                    let l = sum(0.0, 0);
                    for (q, lc) in series.iter_mut().zip(l.to_array()) {
                        q[0] = lc;
                    }
                } else {
                    for (m, basis) in bases.iter().enumerate() {
                        let l = sum(polar, m);
                        for (q, lc) in series.iter_mut().zip(l.to_array()) {
                            for (qk, bk) in q[..nc].iter_mut().zip(basis) {
                                *qk += 2.0 / samples as f64 * bk * lc;
                            }
                        }
                    }
                }
                for (c, qc) in series.iter().enumerate() {
                    for (k, &val) in qc[..nc].iter().enumerate() {
                        // b_j, the sine coefficients, at even k > 0.
                        let sine = k > 0 && k.is_multiple_of(2);
                        let val = if fault == BakeFault::SineTermsNegated && sine {
                            -val
                        } else {
                            val
                        };
                        out[(s * 3 + c) * nc + k] = val as f32;
                    }
                }
            }
            progress.inc(1);
            out
        })
        .collect();
    // The diffuse term at each node as a normal: the Lambertian term times the residual's
    // irradiance, every texel of the (downsampled) residual, in index order.
    let diffuse: Vec<[f32; 3]> = (0..nodes)
        .into_par_iter()
        .map(|k| {
            let n = node_direction(k % (g + 1), k / (g + 1), g);
            let mut e = DVec3::ZERO;
            for (l, p) in levels[0].texels.dir.iter().zip(&levels[0].texels.power) {
                let z = l.dot(n);
                if z > 0.0 {
                    e += z * DVec3::from_array(*p);
                }
            }
            (lambertian * e).as_vec3().to_array()
        })
        .collect();
    let values: Vec<f32> = per_node
        .into_iter()
        .flatten()
        .chain(diffuse.into_iter().flatten())
        .collect();
    let unrotated =
        ReflectionTable::from_parts(g, params.slices, order, 0.0, values, BakeError::default());
    // The exact reference: every texel of the full probe but the excluded ones (the
    // residual's powers moved in, the directions allocated once: at 4096 x 2048 each
    // array is 200 MB, and a copy grown by pushes took twice that again).
    let full = Texels {
        dir: (0..w * h)
            .into_par_iter()
            .map(|idx| probe_direction(texel_center_f64(idx % w, w), texel_center_f64(idx / w, h)))
            .collect(),
        power,
    };
    let error = measure_error(&unrotated, material, cosine, &full);
    let ReflectionTable { values, .. } = unrotated;
    Ok(ReflectionTable::from_parts(
        g,
        params.slices,
        order,
        probe.rotation(),
        values,
        error,
    ))
}

/// SplitMix64 (Steele, Lea & Flood 2014): the error samples' fixed sequence.
struct SplitMix(u64);

impl SplitMix {
    fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Samples per set of `measure_error` for a probe of `texels` texels: about 2^24 exact
/// BRDF evaluations per set, 16 to 256 samples.
pub fn error_samples(texels: usize) -> usize {
    ((1usize << 24) / texels.max(1)).clamp(16, 256)
}

/// The table's error ([`BakeError`]) against the exact f64 sum over `full` (the full
/// probe's texels less the exact ones) at [`error_samples`] samples of each set: reflected
/// directions uniform on the sphere, psi uniform, the view's polar angle with `cos^2`
/// uniform (a sphere as a camera sees it) or uniform in 70-89.9 degrees (the grazing band).
/// The table is looked up as shading does ([`ReflectionTable::radiance`], unrotated).
pub(super) fn measure_error(
    table: &ReflectionTable,
    material: &Material,
    cosine: bool,
    full: &Texels,
) -> BakeError {
    let m = error_samples(full.dir.len());
    let mut rng = SplitMix(0x5ee_d0f7_ab1e);
    let mut pts = Vec::with_capacity(2 * m);
    for set in 0..2 {
        for _ in 0..m {
            let (u1, u2, u3, u4) = (
                rng.next_f64(),
                rng.next_f64(),
                rng.next_f64(),
                rng.next_f64(),
            );
            let z = 1.0 - 2.0 * u1;
            let sr = (1.0 - z * z).max(0.0).sqrt();
            let phi = std::f64::consts::TAU * u2;
            let r = DVec3::new(sr * phi.cos(), z, sr * phi.sin());
            let polar = if set == 0 {
                u3.sqrt().acos()
            } else {
                (70.0 + 19.9 * u3).to_radians()
            };
            let psi = std::f64::consts::TAU * u4;
            pts.push(sample_normal_view(
                r,
                polar,
                psi,
                chart_frame(r, chart_is_z(r)),
            ));
        }
    }
    let pairs: Vec<(f64, f64)> = pts
        .par_iter()
        .map(|&(n, v)| {
            let exact = luminance_of(radiance_sum(material, cosine, DVec3::ZERO, n, v, full));
            let got = luminance_of(table.radiance(n.as_vec3(), v.as_vec3()).as_dvec3());
            (exact, got)
        })
        .collect();
    let stats = |set: &[(f64, f64)]| -> (f64, f64, f64) {
        let mean = set.iter().map(|p| p.0.abs()).sum::<f64>() / set.len() as f64;
        let floor = (1e-6 * mean).max(1e-30);
        let (mut se, mut sy) = (0.0, 0.0);
        let mut rel: Vec<f64> = set
            .iter()
            .map(|&(y, t)| {
                se += (t - y) * (t - y);
                sy += y * y;
                (t - y).abs() / y.abs().max(floor)
            })
            .collect();
        rel.sort_by(f64::total_cmp);
        let p99 = rel[((0.99 * rel.len() as f64).ceil() as usize).clamp(1, rel.len()) - 1];
        let rmse = if sy > 0.0 {
            (se / sy).sqrt()
        } else {
            se.sqrt()
        };
        (rmse, p99, *rel.last().unwrap_or(&0.0))
    };
    let (a, b) = pairs.split_at(m);
    let (rel_rmse, p99, max) = stats(a);
    let (grazing_rel_rmse, grazing_p99, grazing_max) = stats(b);
    BakeError {
        samples: m,
        rel_rmse,
        p99,
        max,
        grazing_rel_rmse,
        grazing_p99,
        grazing_max,
    }
}

/// Rec. 709 luminance of an f64 RGB value ([`LUMINANCE_WEIGHTS`], not clamped).
fn luminance_of(c: DVec3) -> f64 {
    let w = LUMINANCE_WEIGHTS;
    w[0] * c.x + w[1] * c.y + w[2] * c.z
}
