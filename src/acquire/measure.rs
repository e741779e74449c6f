//! How well an acquired data set fits its source: the dense error grid over the hemisphere,
//! the error report (relative L2, negative lobes) and the ringing flag (thesis 2.3.4).

use super::*;

/// Dense evaluation grid over the upper hemisphere of `wi`: `n_mu` midpoints in
/// `cos(polar_i)` on (0, 1) times `n_az` midpoints in azimuth, all cells of equal solid
/// angle `2 pi / (n_mu n_az)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorGrid {
    pub n_mu: usize,
    pub n_az: usize,
}

impl Default for ErrorGrid {
    /// 40 x 80 directions (3200, cells of about 2 square degrees).
    fn default() -> Self {
        ErrorGrid { n_mu: 40, n_az: 80 }
    }
}

impl ErrorGrid {
    /// The grid's directions (local frame).
    pub fn directions(&self) -> Vec<DVec3> {
        let mut v = Vec::with_capacity(self.n_mu * self.n_az);
        for m in 0..self.n_mu {
            let z = (m as f64 + 0.5) / self.n_mu as f64;
            for a in 0..self.n_az {
                let az = (a as f64 + 0.5) / self.n_az as f64 * std::f64::consts::TAU;
                v.push(local_direction_f64(z.acos(), az));
            }
        }
        v
    }
}

/// Share of the projected solid angle of the upper hemisphere of `wo` covered by view texel
/// `(i, j)` of an `nu x nv` grid: `w = (sin^2(polar_1) - sin^2(polar_0)) / nu`, the exact
/// `integral cos(polar_o) dω_o / pi` over the texel (polar edges `polar_0 = j pi / (2 nv)`,
/// `polar_1 = (j + 1) pi / (2 nv)`). The weights of a grid sum to 1. This is the share of
/// the screen area of a sphere (or of any convex object) seen from afar whose normals fall
/// into the texel: what a rendered image integrates (module doc, "Errors").
pub fn view_texel_weight(j: usize, nu: usize, nv: usize) -> f64 {
    let edge = |k: usize| {
        (k as f64 / nv as f64 * std::f64::consts::FRAC_PI_2)
            .sin()
            .powi(2)
    };
    (edge(j + 1) - edge(j)) / nu as f64
}

/// How well an approximation reproduces a source (module doc). All ratios are plain
/// numbers (not percent). `w_t` is [`view_texel_weight`], `d` runs over the [`ErrorGrid`]
/// light directions (equal solid angle), `s`, `a` are the source's and the approximation's
/// `f_r cos(polar_i)` (RGB).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorReport {
    /// Projected-solid-angle weighted relative L2:
    /// `sqrt(sum_t w_t sum_d |a - s|^2 / sum_t w_t sum_d |s|^2)`. The error of a rendered
    /// image under light from every direction: a grazing view texel counts for the share
    /// of screen area it covers, not as much as a texel facing the viewer.
    pub rel_l2: f64,
    /// The same without view weights, `sqrt(sum |a - s|^2 / sum |s|^2)` over all samples
    /// (the measure of earlier versions). Dominated by the grazing view rows wherever the
    /// source has a grazing spike (Ashikhmin-Shirley, module doc).
    pub rel_l2_unweighted: f64,
    /// Ringing: `sum_t w_t min(0, lo_t / hi_t)`, where `lo_t` is the most negative and
    /// `hi_t` the largest value (any colour, any light direction) of the approximation *at
    /// view texel t*. The negative light next to a highlight relative to that highlight,
    /// in the pixel where both show, averaged over the screen area of a sphere. A texel
    /// whose approximation is nowhere positive but somewhere negative counts as `-1`.
    /// Relative to the reconstruction's peak, not the source's: a band-limited fit of a
    /// sharp lobe has a far lower peak than the source, and what shows in an image is the
    /// dark ring next to the highlight that is actually rendered.
    pub min_over_peak: f64,
    /// Worst case, unweighted: the most negative approximated value over all samples
    /// divided by the approximation's peak over all samples (the measure of earlier
    /// versions); 0 when nothing is negative.
    pub worst_min_over_peak: f64,
    /// Worst single view texel: `min_t min(0, lo_t / hi_t)`.
    pub worst_texel_min_over_peak: f64,
    /// Share of samples (direction x view texel, unweighted) where any colour of the
    /// approximation is below `-1e-6` times the global peak, in [0, 1].
    pub share_below_zero: f64,
}

/// Compares `approx` with `src` on `f_r cos(polar_i)` (each through
/// [`eval_cosine_weighted`]) over `grid` x the view texel centres of an `nu x nv` grid
/// ([`ErrorReport`] gives the formulas). Parallel over view texels; per-texel sums are
/// added in texel order (deterministic). Never fails; a source that is zero everywhere
/// gives `rel_l2 = 0` if the approximation is zero too, infinity otherwise.
pub fn hemisphere_error(
    src: &dyn Brdf,
    approx: &dyn Brdf,
    nu: usize,
    nv: usize,
    grid: ErrorGrid,
) -> ErrorReport {
    hemisphere_error_with_progress(src, approx, nu, nv, grid, &Progress::hidden())
}

/// [`hemisphere_error`], counting one step on `progress` per finished view texel (`nu x nv`
/// in all; the caller sets the length). Counting does not change the report.
pub fn hemisphere_error_with_progress(
    src: &dyn Brdf,
    approx: &dyn Brdf,
    nu: usize,
    nv: usize,
    grid: ErrorGrid,
    progress: &Progress,
) -> ErrorReport {
    let dirs = grid.directions();
    let texels: Vec<(usize, usize)> = (0..nv).flat_map(|j| (0..nu).map(move |i| (i, j))).collect();
    // Per texel: (sum err^2, sum src^2, max approx, smallest colour of each approximation).
    let parts: Vec<(f64, f64, f64, Vec<f64>)> = texels
        .par_iter()
        .map(|&(i, j)| {
            let (p, a) = hemi_texel_angles_f64(i, j, nu, nv);
            let wo = local_direction_f64(p, a).as_vec3();
            let (mut e2, mut s2, mut hi) = (0.0, 0.0, 0.0f64);
            let mut mins = Vec::with_capacity(dirs.len());
            for d in &dirs {
                let wi = d.as_vec3();
                let s = eval_cosine_weighted(src, wi, wo).as_dvec3();
                let x = eval_cosine_weighted(approx, wi, wo).as_dvec3();
                e2 += (x - s).length_squared();
                s2 += s.length_squared();
                hi = hi.max(x.max_element());
                mins.push(x.min_element());
            }
            progress.inc(1);
            (e2, s2, hi, mins)
        })
        .collect();
    let (mut e2, mut s2, mut hi) = (0.0, 0.0, 0.0f64);
    let (mut e2w, mut s2w, mut ring, mut worst_texel) = (0.0, 0.0, 0.0, 0.0f64);
    for (p, &(_, j)) in parts.iter().zip(&texels) {
        let w = view_texel_weight(j, nu, nv);
        e2 += p.0;
        s2 += p.1;
        e2w += w * p.0;
        s2w += w * p.1;
        hi = hi.max(p.2);
        let lo_t = p.3.iter().fold(0.0f64, |a, &b| a.min(b));
        let r = if lo_t >= 0.0 {
            0.0
        } else if p.2 > 0.0 {
            (lo_t / p.2).max(-1.0)
        } else {
            -1.0
        };
        ring += w * r;
        worst_texel = worst_texel.min(r);
    }
    let lo = parts
        .iter()
        .flat_map(|p| p.3.iter())
        .fold(0.0f64, |a, &b| a.min(b));
    let below = parts
        .iter()
        .flat_map(|p| p.3.iter())
        .filter(|&&m| m < -1e-6 * hi)
        .count();
    let total = (texels.len() * dirs.len()).max(1);
    let ratio = crate::metrics::relative_l2;
    ErrorReport {
        rel_l2: ratio(e2w, s2w),
        rel_l2_unweighted: ratio(e2, s2),
        min_over_peak: ring,
        worst_min_over_peak: if hi > 0.0 { (lo / hi).min(0.0) } else { 0.0 },
        worst_texel_min_over_peak: worst_texel,
        share_below_zero: below as f64 / total as f64,
    }
}

/// True when the report's weighted ringing [`ErrorReport::min_over_peak`] passes
/// [`RINGING_THRESHOLD`] (below -5 %): the material should be rendered from its D-BRDF fit
/// instead (thesis 2.3.4).
pub fn ringing_flagged(r: &ErrorReport) -> bool {
    r.min_over_peak < RINGING_THRESHOLD
}
