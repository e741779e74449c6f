//! Samplers that collapse a [`Probe`] into a [`LightSet`] (thesis 3.2.2-3.2.3).
//!
//! Design rule: a sampler decides *where* lights go; the energy is always the probe's.
//! Every sampler returns lights whose powers sum to [`Probe::total_power`] (to f32
//! rounding, far below 1e-5 relative), either because each light carries the exact
//! summed power of a set of texels that tile the probe (uniform, median cut, Lloyd,
//! full), or, for the Monte Carlo samplers (importance, stratified), because the
//! estimator's per-channel sums are rescaled to the exact totals (see [`importance`]).
//!
//! Per-texel weight (the "monochrome map" of Algorithms 1 and 2) is
//! `luminance(RGB) x exact solid angle` ([`crate::env::luminance`],
//! [`crate::conventions::probe_texel_solid_angle`]); light positions are texel centres or
//! energy centroids, never image corners, so there is no half-texel offset.
//!
//! A black probe (zero total weight) yields an empty light set from every sampler: it
//! has no energy to carry.

use super::{luminance, Fnv1a, LightSet, Probe};
use glam::DVec3;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

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

/// Which sampler and its parameters: the unit of caching ([`crate::env::prepare::file_cache_key`]) and
/// of light-set file headers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "sampler", rename_all = "kebab-case")]
pub enum SamplerConfig {
    /// [`uniform`]: `n` uniform random directions, each carrying its Voronoi cell.
    Uniform { n: usize, seed: u64 },
    /// [`importance`]: thesis Algorithm 1, i.i.d. uniform numbers.
    Importance { n: usize, seed: u64 },
    /// [`importance_stratified`]: Algorithm 1 fed stratified numbers.
    Stratified { n: usize, seed: u64 },
    /// [`median_cut`]: thesis Algorithm 2 / Debevec 2005.
    MedianCut { n: usize },
    /// [`lloyd`]: median cut relaxed by weighted spherical k-means.
    Lloyd { n: usize, iterations: usize },
    /// [`full_probe`]: every texel a light (the converged reference).
    Full,
}

impl SamplerConfig {
    /// Short name: `uniform`, `importance`, `stratified`, `median-cut`, `lloyd`, `full`.
    pub fn name(&self) -> &'static str {
        match self {
            SamplerConfig::Uniform { .. } => "uniform",
            SamplerConfig::Importance { .. } => "importance",
            SamplerConfig::Stratified { .. } => "stratified",
            SamplerConfig::MedianCut { .. } => "median-cut",
            SamplerConfig::Lloyd { .. } => "lloyd",
            SamplerConfig::Full => "full",
        }
    }

    /// Requested number of lights (`None` for the full probe).
    pub fn n(&self) -> Option<usize> {
        match *self {
            SamplerConfig::Uniform { n, .. }
            | SamplerConfig::Importance { n, .. }
            | SamplerConfig::Stratified { n, .. }
            | SamplerConfig::MedianCut { n }
            | SamplerConfig::Lloyd { n, .. } => Some(n),
            SamplerConfig::Full => None,
        }
    }

    /// Seed of the random samplers.
    pub fn seed(&self) -> Option<u64> {
        match *self {
            SamplerConfig::Uniform { seed, .. }
            | SamplerConfig::Importance { seed, .. }
            | SamplerConfig::Stratified { seed, .. } => Some(seed),
            _ => None,
        }
    }

    /// Runs the sampler on a probe.
    pub fn run(&self, probe: &Probe) -> LightSet {
        match *self {
            SamplerConfig::Uniform { n, seed } => uniform(probe, n, seed),
            SamplerConfig::Importance { n, seed } => importance(probe, n, seed),
            SamplerConfig::Stratified { n, seed } => importance_stratified(probe, n, seed),
            SamplerConfig::MedianCut { n } => median_cut(probe, n).lights,
            SamplerConfig::Lloyd { n, iterations } => lloyd(probe, n, iterations),
            SamplerConfig::Full => full_probe(probe),
        }
    }

    /// Feeds the configuration into a stable hash: name, then each parameter as a u64
    /// (absent ones as `u64::MAX`).
    pub fn hash_into(&self, h: &mut Fnv1a) {
        h.write(self.name().as_bytes());
        h.write(&[0]);
        h.write_u64(self.n().map_or(u64::MAX, |n| n as u64));
        h.write_u64(self.seed().unwrap_or(u64::MAX));
        let iters = match *self {
            SamplerConfig::Lloyd { iterations, .. } => iterations as u64,
            _ => u64::MAX,
        };
        h.write_u64(iters);
    }
}

/// The full probe as a light set: one light per texel with non-zero weight, at the texel
/// centre, carrying `RGB x solid angle` (computed in f64). Evaluating it equals
/// [`crate::env::reference_irradiance`] up to f32 storage of the powers.
pub fn full_probe(probe: &Probe) -> LightSet {
    let t = ProbeTables::new(probe);
    let mut ls = LightSet::with_capacity(t.weight.len());
    for i in 0..t.weight.len() {
        if t.weight[i] > 0.0 {
            ls.push(t.dir[i], t.power[i]);
        }
    }
    ls
}

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

/// Lights at `dirs`, each carrying the summed power of the texels in its cell.
fn lights_from_cells(tables: &ProbeTables, dirs: &[DVec3], cells: &[u32]) -> LightSet {
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

/// Uniform random directions (thesis 3.2.2, "unweighted sampling"): `n` directions
/// uniform on the sphere (`y = 1 - 2 xi_1`, azimuth `2 pi xi_2`, `Pcg64` seeded with
/// `seed`), pdf `1 / (4 pi)` ([`uniform_pdf`]). Instead of the Monte Carlo estimate
/// `L(d) 4 pi / n` (whose total power is random, and zero when no sample hits a small
/// light), each light carries the exact summed power of its Voronoi cell (texels nearer
/// to it than to any other light), so the total is exact and no energy is lost.
/// Deterministic per seed. Returns `n` lights (zero-power ones included); empty for
/// `n == 0` or a black probe.
pub fn uniform(probe: &Probe, n: usize, seed: u64) -> LightSet {
    let t = ProbeTables::new(probe);
    if n == 0 || t.total_weight <= 0.0 {
        return LightSet::default();
    }
    let mut rng = Pcg64::seed_from_u64(seed);
    let dirs: Vec<DVec3> = (0..n)
        .map(|_| uniform_direction(rng.gen::<f64>(), rng.gen::<f64>()))
        .collect();
    let cells = nearest_light_cells(&t, &dirs);
    lights_from_cells(&t, &dirs, &cells)
}

/// Uniform sphere map of `[0,1)^2`: `y = 1 - 2 xi_1`, azimuth `2 pi xi_2` with direction
/// `(r cos a, y, r sin a)`. Inverse: [`uniform_inverse`].
pub fn uniform_direction(xi1: f64, xi2: f64) -> DVec3 {
    let y = 1.0 - 2.0 * xi1;
    let r = (1.0 - y * y).max(0.0).sqrt();
    let a = std::f64::consts::TAU * xi2;
    DVec3::new(r * a.cos(), y, r * a.sin())
}

/// Inverse of [`uniform_direction`]: the `(xi_1, xi_2)` of a unit direction.
pub fn uniform_inverse(d: DVec3) -> (f64, f64) {
    let xi1 = (1.0 - d.y.clamp(-1.0, 1.0)) / 2.0;
    let mut xi2 = d.z.atan2(d.x) / std::f64::consts::TAU;
    if xi2 < 0.0 {
        xi2 += 1.0;
    }
    (xi1, xi2)
}

/// Density of [`uniform_direction`] in 1/sr: `1 / (4 pi)` everywhere.
pub fn uniform_pdf(_d: DVec3) -> f64 {
    1.0 / (4.0 * std::f64::consts::PI)
}

/// Thesis Algorithm 1 as a reusable 2D distribution over texels: the marginal row CDF is
/// built from row sums of `luminance x solid angle` (the solid angle replaces the thesis's
/// `cos(linspace)` factor), the conditional column CDFs from each row's weights; a pair
/// of numbers in `[0,1)^2` picks a row and then a column by binary search.
///
/// The discrete texel probability is `p_t = weight_t / total`; as a density over
/// directions (texel centres standing for their texel) it is `p_t / Omega_t` in 1/sr
/// ([`ImportanceSampler::pdf`]).
#[derive(Clone, Debug)]
pub struct ImportanceSampler {
    tables: ProbeTables,
    /// Inclusive, normalised cumulative row sums; last entry exactly 1.
    row_cdf: Vec<f64>,
    /// Per row, inclusive normalised cumulative weights; last entry of a non-zero row 1.
    col_cdf: Vec<f64>,
    rotation: f64,
}

impl ImportanceSampler {
    /// Builds the CDFs (O(texels)). Returns `None` for a black probe.
    pub fn new(probe: &Probe) -> Option<Self> {
        let tables = ProbeTables::new(probe);
        if tables.total_weight <= 0.0 {
            return None;
        }
        let (w, h) = (tables.width, tables.height);
        let mut col_cdf = vec![0.0; w * h];
        let mut row_sums = vec![0.0; h];
        for row in 0..h {
            let mut acc = 0.0;
            for col in 0..w {
                acc += tables.weight[row * w + col];
                col_cdf[row * w + col] = acc;
            }
            row_sums[row] = acc;
            if acc > 0.0 {
                for c in &mut col_cdf[row * w..(row + 1) * w] {
                    *c /= acc;
                }
                col_cdf[(row + 1) * w - 1] = 1.0;
            }
        }
        let total: f64 = row_sums.iter().sum();
        let mut acc = 0.0;
        let mut row_cdf: Vec<f64> = row_sums
            .iter()
            .map(|s| {
                acc += s;
                acc / total
            })
            .collect();
        // Exactly 1 from the last non-zero row on, so u < 1 never runs past it.
        let last = row_sums.iter().rposition(|&s| s > 0.0).unwrap_or(h - 1);
        for c in &mut row_cdf[last..] {
            *c = 1.0;
        }
        Some(ImportanceSampler {
            tables,
            row_cdf,
            col_cdf,
            rotation: probe.rotation(),
        })
    }

    /// The texel `(row, col)` that `(xi_1, xi_2)` in `[0,1)^2` selects: the first row whose
    /// CDF exceeds `xi_1`, then the first column of that row whose CDF exceeds `xi_2`
    /// (binary search; zero-weight texels are never selected).
    pub fn sample_texel(&self, xi1: f64, xi2: f64) -> (usize, usize) {
        let (w, h) = (self.tables.width, self.tables.height);
        let row = self.row_cdf.partition_point(|&c| c <= xi1).min(h - 1);
        let cdf = &self.col_cdf[row * w..(row + 1) * w];
        let col = cdf.partition_point(|&c| c <= xi2).min(w - 1);
        (row, col)
    }

    /// Discrete probability of texel `(row, col)`: `weight / total`.
    pub fn texel_probability(&self, row: usize, col: usize) -> f64 {
        self.tables.weight[row * self.tables.width + col] / self.tables.total_weight
    }

    /// Texel containing world direction `d` (the inverse of [`Self::direction`]).
    pub fn texel_of(&self, d: DVec3) -> (usize, usize) {
        let (u, v) =
            crate::conventions::probe_uv(crate::conventions::rotate_about_up(d, -self.rotation));
        crate::conventions::probe_texel(u, v, self.tables.width, self.tables.height)
    }

    /// Direction of the light a sample of texel `(row, col)` produces: its centre.
    pub fn direction(&self, row: usize, col: usize) -> DVec3 {
        self.tables.dir[row * self.tables.width + col]
    }

    /// Density over directions in 1/sr: `p_texel / Omega_texel` of the texel containing
    /// `d` (piecewise constant; integrates to 1 over the sphere).
    pub fn pdf(&self, d: DVec3) -> f64 {
        let (row, col) = self.texel_of(d);
        self.texel_probability(row, col)
            / crate::conventions::probe_texel_solid_angle(
                row,
                self.tables.width,
                self.tables.height,
            )
    }

    /// Lights from a list of uniform pairs: each sample of texel `t` becomes a light at
    /// its centre with power `L_t / (n pdf_t) = L_t Omega_t / (n p_t)` (so every light
    /// carries luminance power `total / n`); then each RGB channel is scaled by
    /// `exact total / estimated total` ([`rescale_to_total`]). Because the pdf is
    /// proportional to luminance, the luminance total is already exact and the scale only
    /// corrects colour noise.
    pub fn lights_from_uniforms(&self, xis: &[(f64, f64)]) -> LightSet {
        let n = xis.len() as f64;
        let mut ls = LightSet::with_capacity(xis.len());
        let mut lum = Vec::with_capacity(xis.len());
        for &(a, b) in xis {
            let (row, col) = self.sample_texel(a, b);
            let i = row * self.tables.width + col;
            let p = self.tables.weight[i] / self.tables.total_weight;
            ls.push(self.tables.dir[i], self.tables.power[i] / (n * p));
            lum.push(self.tables.total_weight / n);
        }
        rescale_to_total(&mut ls, self.tables.total_power, &lum);
        ls
    }
}

/// Scales each RGB channel of the powers so the channel totals equal `target` (f64).
/// If a channel sums to zero but its target is not (possible with few samples of a
/// coloured probe), that channel's target is spread over the lights in proportion to
/// `fallback` (their luminance power).
pub fn rescale_to_total(ls: &mut LightSet, target: DVec3, fallback: &[f64]) {
    let fb_total: f64 = fallback.iter().sum();
    for (ch, t) in [
        (&mut ls.power_r, target.x),
        (&mut ls.power_g, target.y),
        (&mut ls.power_b, target.z),
    ] {
        let s: f64 = ch.iter().map(|&p| p as f64).sum();
        if s > 0.0 {
            let k = t / s;
            for p in ch.iter_mut() {
                *p = (*p as f64 * k) as f32;
            }
        } else if t > 0.0 && fb_total > 0.0 {
            for (p, f) in ch.iter_mut().zip(fallback) {
                *p = (t * f / fb_total) as f32;
            }
        }
    }
}

/// Importance sampling, thesis Algorithm 1: `n` i.i.d. pairs from `Pcg64` seeded with
/// `seed` fed to [`ImportanceSampler`]; see [`ImportanceSampler::lights_from_uniforms`]
/// for the powers. Deterministic per seed; empty for `n == 0` or a black probe.
pub fn importance(probe: &Probe, n: usize, seed: u64) -> LightSet {
    let Some(s) = ImportanceSampler::new(probe) else {
        return LightSet::default();
    };
    let mut rng = Pcg64::seed_from_u64(seed);
    let xis: Vec<(f64, f64)> = (0..n).map(|_| (rng.gen(), rng.gen())).collect();
    s.lights_from_uniforms(&xis)
}

/// `n` stratified pairs in `[0,1)^2` (Latin hypercube): `xi_1 = (i + u_i)/n` in order,
/// `xi_2 = (pi(i) + v_i)/n` for a random permutation `pi`, so each marginal has exactly
/// one sample per `1/n` stratum. Works for any `n` (a square jittered grid would not).
pub fn stratified_uniforms(n: usize, seed: u64) -> Vec<(f64, f64)> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut perm: Vec<usize> = (0..n).collect();
    perm.shuffle(&mut rng);
    (0..n)
        .map(|i| {
            let a = (i as f64 + rng.gen::<f64>()) / n as f64;
            let b = (perm[i] as f64 + rng.gen::<f64>()) / n as f64;
            // (i + u)/n can round to 1.0 for u close to 1; keep it in [0,1).
            (a.min(1.0 - f64::EPSILON), b.min(1.0 - f64::EPSILON))
        })
        .collect()
}

/// Importance sampling (Algorithm 1) fed [`stratified_uniforms`]: the row choice is
/// stratified along the marginal CDF, which removes most clumping.
pub fn importance_stratified(probe: &Probe, n: usize, seed: u64) -> LightSet {
    let Some(s) = ImportanceSampler::new(probe) else {
        return LightSet::default();
    };
    s.lights_from_uniforms(&stratified_uniforms(n, seed))
}

/// A rectangle of texels `[row0, row1) x [col0, col1)` of the probe image.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Region {
    pub row0: usize,
    pub row1: usize,
    pub col0: usize,
    pub col1: usize,
    /// Summed `luminance x solid angle` of its texels.
    pub energy: f64,
}

impl Region {
    /// Number of texels.
    pub fn texels(&self) -> usize {
        (self.row1 - self.row0) * (self.col1 - self.col0)
    }
    /// True if `(row, col)` lies inside.
    pub fn contains(&self, row: usize, col: usize) -> bool {
        (self.row0..self.row1).contains(&row) && (self.col0..self.col1).contains(&col)
    }
}

/// One median cut: `parent` split at `at` (a row index for [`CutAxis::Rows`], a column
/// index for [`CutAxis::Cols`]) into halves of energy `energy_a` (before `at`) and
/// `energy_b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cut {
    pub parent: Region,
    pub axis: CutAxis,
    pub at: usize,
    pub energy_a: f64,
    pub energy_b: f64,
}

/// Direction of a cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CutAxis {
    /// A horizontal cut line between rows `at - 1` and `at` (splits the polar extent).
    Rows,
    /// A vertical cut line between columns `at - 1` and `at` (splits the azimuth extent).
    Cols,
}

/// Result of [`median_cut`]: `lights[i]` belongs to `regions[i]`; `cuts` in the order made.
#[derive(Clone, Debug)]
pub struct MedianCut {
    pub lights: LightSet,
    pub regions: Vec<Region>,
    pub cuts: Vec<Cut>,
    width: usize,
    height: usize,
    rotation: f64,
}

impl MedianCut {
    /// Index of the region (and light) whose texels contain direction `d`: the inverse
    /// map direction -> texel -> region.
    pub fn region_of(&self, d: DVec3) -> usize {
        let (u, v) =
            crate::conventions::probe_uv(crate::conventions::rotate_about_up(d, -self.rotation));
        let (row, col) = crate::conventions::probe_texel(u, v, self.width, self.height);
        self.regions
            .iter()
            .position(|r| r.contains(row, col))
            .expect("regions tile the probe")
    }
}

/// Summed-area table of the weights, `(h+1) x (w+1)`.
struct Sat {
    w: usize,
    s: Vec<f64>,
}

impl Sat {
    fn new(t: &ProbeTables) -> Self {
        let (w, h) = (t.width, t.height);
        let mut s = vec![0.0; (w + 1) * (h + 1)];
        for r in 0..h {
            let mut row_acc = 0.0;
            for c in 0..w {
                row_acc += t.weight[r * w + c];
                s[(r + 1) * (w + 1) + c + 1] = s[r * (w + 1) + c + 1] + row_acc;
            }
        }
        Sat { w, s }
    }
    fn sum(&self, r0: usize, r1: usize, c0: usize, c1: usize) -> f64 {
        let at = |r: usize, c: usize| self.s[r * (self.w + 1) + c];
        (at(r1, c1) - at(r0, c1) - at(r1, c0) + at(r0, c0)).max(0.0)
    }
}

fn region(sat: &Sat, r0: usize, r1: usize, c0: usize, c1: usize) -> Region {
    Region {
        row0: r0,
        row1: r1,
        col0: c0,
        col1: c1,
        energy: sat.sum(r0, r1, c0, c1),
    }
}

/// Splits a region at its energy median along its longest side measured on the sphere:
/// azimuth extent `2 pi (cols / width) sin(mid polar)` against polar extent
/// `pi rows / height` (Debevec 2005; pixels would over-split the poles). Ties and
/// 1-texel-thick sides fall back to the other axis; `None` for a single texel.
/// The cut index minimises `|energy_a - energy_b|` (first minimum), which bounds the
/// difference by the energy of the one strip that straddles the median.
fn split(sat: &Sat, r: &Region, width: usize, height: usize) -> Option<(Region, Region, Cut)> {
    let rows = r.row1 - r.row0;
    let cols = r.col1 - r.col0;
    if rows * cols <= 1 {
        return None;
    }
    let pi = std::f64::consts::PI;
    let mid_polar = pi * (r.row0 + r.row1) as f64 / (2.0 * height as f64);
    let az_len = std::f64::consts::TAU * cols as f64 / width as f64 * mid_polar.sin();
    let polar_len = pi * rows as f64 / height as f64;
    let axis = if cols < 2 || (rows >= 2 && polar_len >= az_len) {
        CutAxis::Rows
    } else {
        CutAxis::Cols
    };
    let (lo, hi) = match axis {
        CutAxis::Rows => (r.row0, r.row1),
        CutAxis::Cols => (r.col0, r.col1),
    };
    let left = |k: usize| match axis {
        CutAxis::Rows => sat.sum(r.row0, k, r.col0, r.col1),
        CutAxis::Cols => sat.sum(r.row0, r.row1, r.col0, k),
    };
    let total = r.energy;
    let mut best = (f64::INFINITY, lo + 1);
    for k in lo + 1..hi {
        let a = left(k);
        let d = (2.0 * a - total).abs();
        if d < best.0 {
            best = (d, k);
        }
        if 2.0 * a >= total {
            break; // the difference only grows from here on
        }
    }
    let k = best.1;
    let (a, b) = match axis {
        CutAxis::Rows => (
            region(sat, r.row0, k, r.col0, r.col1),
            region(sat, k, r.row1, r.col0, r.col1),
        ),
        CutAxis::Cols => (
            region(sat, r.row0, r.row1, r.col0, k),
            region(sat, r.row0, r.row1, k, r.col1),
        ),
    };
    let cut = Cut {
        parent: *r,
        axis,
        at: k,
        energy_a: a.energy,
        energy_b: b.energy,
    };
    Some((a, b, cut))
}

/// Median cut, thesis Algorithm 2 / Debevec, "A Median Cut Algorithm for Light Probe
/// Sampling" (SIGGRAPH 2005 poster), on the `luminance x solid angle` map.
///
/// Rule for the number of regions: while doubling does not exceed `n`, every splittable
/// region is split (the thesis's levels; `n = 2^k` gives exactly `k` levels); then, until
/// there are `n` regions, the splittable region of highest energy is split (first in
/// order on ties). This makes any `n >= 1` work. A 1-texel region cannot be split, so a
/// probe with fewer than `n` texels gives one region per texel (fewer than `n` lights).
/// `n == 0` or a black probe gives no lights and no regions.
///
/// Each region gets one light at its energy centroid in direction space
/// (`sum weight x direction`, normalised; the region's centre texel direction if that sum
/// vanishes, e.g. a uniform region spanning the whole sphere), carrying the region's
/// summed RGB power (f64), so the total is exact.
pub fn median_cut(probe: &Probe, n: usize) -> MedianCut {
    let t = ProbeTables::new(probe);
    let mut out = MedianCut {
        lights: LightSet::default(),
        regions: Vec::new(),
        cuts: Vec::new(),
        width: t.width,
        height: t.height,
        rotation: probe.rotation(),
    };
    if n == 0 || t.total_weight <= 0.0 {
        return out;
    }
    let sat = Sat::new(&t);
    let mut regions = vec![region(&sat, 0, t.height, 0, t.width)];
    let mut cuts = Vec::new();
    // Level by level.
    while regions.len() * 2 <= n {
        let mut next = Vec::with_capacity(regions.len() * 2);
        let mut any = false;
        for r in &regions {
            match split(&sat, r, t.width, t.height) {
                Some((a, b, c)) => {
                    next.push(a);
                    next.push(b);
                    cuts.push(c);
                    any = true;
                }
                None => next.push(*r),
            }
        }
        regions = next;
        if !any {
            break;
        }
    }
    // Highest energy first, until n.
    while regions.len() < n {
        let mut best: Option<(usize, (Region, Region, Cut))> = None;
        for (i, r) in regions.iter().enumerate() {
            if best
                .as_ref()
                .is_some_and(|(j, _)| regions[*j].energy >= r.energy)
            {
                continue;
            }
            if let Some(s) = split(&sat, r, t.width, t.height) {
                best = Some((i, s));
            }
        }
        let Some((i, (a, b, c))) = best else { break };
        regions[i] = a;
        regions.insert(i + 1, b);
        cuts.push(c);
    }
    let mut lights = LightSet::with_capacity(regions.len());
    for r in &regions {
        let mut centroid = DVec3::ZERO;
        let mut power = DVec3::ZERO;
        let mut wsum = 0.0;
        for row in r.row0..r.row1 {
            for col in r.col0..r.col1 {
                let i = row * t.width + col;
                centroid += t.dir[i] * t.weight[i];
                power += t.power[i];
                wsum += t.weight[i];
            }
        }
        let dir = if wsum > 0.0 && centroid.length() > 1e-9 * wsum {
            centroid.normalize()
        } else {
            t.dir[((r.row0 + r.row1) / 2) * t.width + (r.col0 + r.col1) / 2]
        };
        lights.push(dir, power);
    }
    out.lights = lights;
    out.regions = regions;
    out.cuts = cuts;
    out
}

/// Lloyd relaxation on the sphere: weighted spherical k-means of the texel directions
/// (weight `luminance x solid angle`), seeded from [`median_cut`]'s lights, `iterations`
/// rounds of (assign each texel to its nearest light; move each light to its cell's
/// normalised energy centroid), stopping early when no assignment changes. Each light
/// then carries its final Voronoi cell's summed RGB power (f64), so the total is exact.
/// A light whose cell has no energy stays where it is with zero power.
///
/// Why it beats median cut: k-means minimises `sum weight |d - light|^2`, the
/// second-moment (spread) of each cell around its light, which is what the error of a
/// smooth response such as `max(0, n.l)` depends on to first order; median cut's
/// axis-aligned boxes only balance energy and leave long, thin cells. Cost:
/// O(iterations x texels x n) (brute-force nearest light).
pub fn lloyd(probe: &Probe, n: usize, iterations: usize) -> LightSet {
    let t = ProbeTables::new(probe);
    let seed = median_cut(probe, n);
    if seed.lights.is_empty() {
        return LightSet::default();
    }
    let mut dirs: Vec<DVec3> = (0..seed.lights.len())
        .map(|i| seed.lights.direction(i))
        .collect();
    let mut cells = nearest_light_cells(&t, &dirs);
    for _ in 0..iterations {
        let mut acc = vec![DVec3::ZERO; dirs.len()];
        for (i, &c) in cells.iter().enumerate() {
            if c != u32::MAX {
                acc[c as usize] += t.dir[i] * t.weight[i];
            }
        }
        for (d, a) in dirs.iter_mut().zip(&acc) {
            if let Some(nd) = a.try_normalize() {
                *d = nd;
            }
        }
        let next = nearest_light_cells(&t, &dirs);
        let changed = next != cells;
        cells = next;
        if !changed {
            break;
        }
    }
    lights_from_cells(&t, &dirs, &cells)
}
