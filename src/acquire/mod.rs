//! Acquisition: projecting a BRDF onto the SH basis per view texel (thesis 2.3.3-2.3.4,
//! 3.1.3-3.1.5), measuring how well the projection fits, and fitting D-BRDFs
//! ([`fit`], thesis 2.3.6).
//!
//! Design rule: an acquisition *measures what the device measures*. Under basis
//! illumination (thesis 2.3.3) the acquisition device records reflected radiance, which is
//! `f_r(wi, wo) cos(polar_i)` per unit incident radiance; so every data set built here
//! stores `f_r cos(polar_i)` and sets [`ShDataset::cosine_included`] to `true`. Two further
//! reasons for that choice: `f_r cos` goes to zero at the horizon, so its extension below the
//! horizon is continuous (less ringing than `f_r`, which jumps there), and it is exactly the
//! integrand the renderer needs (the renderer then skips its own cosine, see
//! [`crate::brdf::eval_cosine_weighted`]). Every error in this module is measured on that
//! same quantity.
//!
//! # Grids and quadrature
//! The view direction `wo` is sampled at the texel centres of an `nu x nv` hemispherical
//! grid ([`crate::conventions::hemi_texel_angles_f64`]). The light direction `wi` is
//! integrated with a product rule on the sphere: Gauss-Legendre in `z = cos(polar_i)`,
//! **split at the horizon** (`n_mu` nodes on (0, 1) and their mirror images on (-1, 0), so
//! a function with a kink at the horizon is still integrated exactly piecewise), times
//! `n_az` equally spaced azimuths (offset by half a step). The rule is exact for
//! `Y_k * g` when `g` is band-limited to the same bands and `n_mu >= bands`,
//! `n_az >= 2 bands - 1`.
//!
//! # Fitting a hemisphere with a full-sphere basis ([`Method`])
//! The SH are orthonormal over the sphere, the data lives on the upper hemisphere:
//! * [`Method::Zero`]: extend by zero below the horizon and project exactly over the sphere
//!   (`c_k = integral g Y_k dω`). Optimal in sphere L2, but half of the basis's effort goes
//!   into reproducing the zero half, which leaves ringing near the horizon.
//! * [`Method::Lsq`]: Tikhonov-regularised least squares on the upper hemisphere only:
//!   `(G + lambda I) c = b`, `G_kl = integral_{H} Y_k Y_l dω`, `b_k = integral_{H} g Y_k dω`.
//!   `G` is the hemisphere Gram matrix; its eigenvalues lie in (0, 1] and about half of them
//!   tend to zero (functions concentrated below the horizon), so it is ill-conditioned at
//!   high order: `lambda` (default [`DEFAULT_LAMBDA`], in the units of `G`, i.e. relative to
//!   the largest possible eigenvalue 1) bounds the amplitude those directions may take.
//!   Best hemisphere L2 for small `lambda`; what happens below the horizon is not
//!   controlled (and not rendered: the renderer zeroes `wi.z <= 0`).
//! * [`Method::Even`]: mirror the data below the horizon (`g(x, y, -z) = g(x, y, z)`) and
//!   project exactly. Only terms with `l + m` even survive; the extension is continuous, so
//!   it rings less than zero extension at the same order.
//!
//! # Errors ([`ErrorReport`])
//! Measured against the source over a dense midpoint grid of the upper hemisphere of `wi`
//! ([`ErrorGrid`], equal solid-angle cells) times the view texel centres of the data set.
//! View texels are weighted by their projected solid angle `cos(polar_o) dω_o`
//! ([`view_texel_weight`]): that is the share of a rendered sphere's screen area whose
//! normals fall into the texel, so the weighted measures are what an image shows. The
//! report gives the weighted relative L2 of `f_r cos` (all three colours), the weighted
//! ringing (each view texel's most negative reconstructed value relative to *that
//! texel's* reconstructed peak, averaged with the same weights), the unweighted worst
//! cases of earlier versions, and the share of samples below zero.
//!
//! ## Why the view weights (measured cause)
//! Unweighted, the sums were dominated by the grazing view rows. The Ashikhmin-Shirley
//! specular term `sqrt((n_u+1)(n_v+1))/(8 pi) (n.h)^e F / ((h.k) max(n.k1, n.k2))` grows
//! like `1 / cos^2(polar_o)` at the mirror direction of a grazing view (`h.k` and
//! `max(n.k1, n.k2)` both tend to `cos(polar_o)`, Schlick's `F` tends to 1 whatever `R_s`),
//! and the lobe is squeezed against the horizon of `wi`, where no low-order SH can follow
//! it. Magenta plastic as A-S (`n = 12`, `R_s = 0.04`), 16x8 view grid, least squares
//! (`examples/acquire_rows.rs`): the last polar row (84.4 deg, 3.8 % of the projected solid
//! angle) peaks at `f_r cos = 3.14` against 0.26 at normal view, holds 33 % of all
//! `sum |s|^2` and 96 % (order 5) / 98 % (order 8) of all `sum |a - s|^2`. Row relative L2
//! at order 5: rows 0-4 (5.6-50.6 deg) 0.001-0.020, row 5 0.085, row 6 0.37, row 7 0.81;
//! at order 8: rows 0-4 <= 0.005, row 7 0.68. The global min/peak (-31 % at order 5, -26 %
//! at order 8) is row 7's; rows 0-4 ring less than 1.8 % of their own peak. The projection
//! is not at fault: Lambert plus a normalised Blinn-Phong lobe of the same width
//! (`kd = 0.7/0.04/0.45`, `ks = 0.04`, exponent 12) gives 0.0066 (order 5) and 0.0023
//! (order 8), min/peak -0.65 %; the A-S code agrees with an independent f64 transcription of
//! the paper's formula to 3.6e-6 relative. Weighting alone does not rescue A-S plastic
//! (weighted rel L2 0.30, weighted ringing -6.2 % at order 5): its grazing spike is a
//! property of the model, not of measured plastic, so the library's plastic and fabric now
//! use a D-BRDF lobe instead ([`crate::materials`]).

pub mod dbrdf_file;
pub mod fit;
pub mod source;

use crate::brdf::{eval_cosine_weighted, Brdf};
use crate::conventions::{hemi_texel_angles_f64, local_direction_f64};
use crate::sh::quadrature::gauss_legendre;
use crate::sh::{eval_sh_f64, num_terms, ShDataError, ShDataset, MAX_BANDS};
use glam::DVec3;
use rayon::prelude::*;

/// Default Tikhonov weight of [`Method::Lsq`] (relative to the unit eigenvalue scale of the
/// hemisphere Gram matrix). Small enough that a band-limited source is recovered to about
/// `sqrt(lambda)/2` relative error, large enough to keep order 10 solvable in f64.
pub const DEFAULT_LAMBDA: f64 = 1e-6;

/// Ringing threshold of [`ringing_flagged`]: a reconstruction whose most negative value is,
/// averaged over the screen area ([`ErrorReport::min_over_peak`]), below `-5 %` of the same
/// view texel's peak is visibly wrong (dark or coloured bands where the
/// material should be lit) and should use its D-BRDF fit instead (thesis 2.3.4: "To resolve
/// the ringing artifacts, we can fit the acquired data to an analytical model").
pub const RINGING_THRESHOLD: f64 = -0.05;

/// How the upper-hemisphere data is fitted with the full-sphere SH basis (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Zero extension below the horizon, exact projection over the sphere.
    Zero,
    /// Tikhonov-regularised least squares on the upper hemisphere with weight `lambda`.
    Lsq { lambda: f64 },
    /// Even (mirror) extension below the horizon, exact projection over the sphere.
    Even,
}

impl Method {
    /// Short name as used on the command line (`zero`, `lsq`, `even`).
    pub fn name(&self) -> &'static str {
        match self {
            Method::Zero => "zero",
            Method::Lsq { .. } => "lsq",
            Method::Even => "even",
        }
    }

    /// Parses `zero`, `lsq` (with [`DEFAULT_LAMBDA`]) or `even`; `None` otherwise.
    pub fn parse(s: &str) -> Option<Method> {
        match s {
            "zero" => Some(Method::Zero),
            "lsq" => Some(Method::Lsq {
                lambda: DEFAULT_LAMBDA,
            }),
            "even" => Some(Method::Even),
            _ => None,
        }
    }
}

/// What to acquire.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AcquireOptions {
    /// Number of SH bands L (terms L^2), 1..=[`MAX_BANDS`] (1 to 10 are the useful range).
    pub bands: usize,
    /// View grid: azimuth texels.
    pub nu: usize,
    /// View grid: polar texels.
    pub nv: usize,
    /// How the hemisphere is fitted.
    pub method: Method,
    /// Gauss-Legendre nodes in `cos(polar_i)` per half sphere; `0` picks
    /// `max(bands, 48)`. Azimuth nodes are twice this.
    pub n_mu: usize,
}

impl AcquireOptions {
    /// `bands` bands on an `nu x nv` view grid with `method` and the default quadrature.
    pub fn new(bands: usize, nu: usize, nv: usize, method: Method) -> Self {
        AcquireOptions {
            bands,
            nu,
            nv,
            method,
            n_mu: 0,
        }
    }

    fn n_mu(&self) -> usize {
        if self.n_mu == 0 {
            self.bands.max(48)
        } else {
            self.n_mu.max(self.bands)
        }
    }
}

/// Why an acquisition could not be made.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum AcquireError {
    #[error("bands: {0} is out of range (1 to {MAX_BANDS})")]
    Bands(usize),
    #[error("grid: {nu}x{nv} is empty or larger than 1024x1024")]
    Grid { nu: usize, nv: usize },
    #[error("lambda: {0} must be a finite number > 0")]
    Lambda(f64),
    #[error("least squares: the regularised hemisphere Gram matrix is not positive definite (increase lambda)")]
    Singular,
    #[error("source returned a non-finite value (view texel {i}, {j})")]
    NonFinite { i: usize, j: usize },
    #[error("data set: {0}")]
    Data(#[from] ShDataError),
}

/// The acquired quantity `f_r(wi, wo) cos(polar_i)` of any BRDF (f64 RGB), zero when
/// `wi.z <= 0` or `wo.z <= 0`.
#[inline]
pub fn acquired_value(src: &dyn Brdf, wi: DVec3, wo: DVec3) -> DVec3 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return DVec3::ZERO;
    }
    eval_cosine_weighted(src, wi.as_vec3(), wo.as_vec3()).as_dvec3()
}

/// Product quadrature on the sphere split at the horizon (module doc), with the SH basis
/// tabulated at its nodes. The first `upper` nodes are above the horizon; node `upper + p`
/// is the mirror image of node `p`.
pub struct SphereQuadrature {
    bands: usize,
    dirs: Vec<DVec3>,
    weights: Vec<f64>,
    upper: usize,
    y: Vec<f64>,
}

impl SphereQuadrature {
    /// `n_mu` Gauss-Legendre nodes in `z` per half sphere, `n_az` azimuths, basis of `bands`
    /// bands. Panics if any count is zero.
    pub fn new(bands: usize, n_mu: usize, n_az: usize) -> Self {
        assert!(bands > 0 && n_mu > 0 && n_az > 0, "empty quadrature");
        let (x, w) = gauss_legendre(n_mu);
        let mut dirs = Vec::with_capacity(2 * n_mu * n_az);
        let mut weights = Vec::with_capacity(2 * n_mu * n_az);
        let daz = std::f64::consts::TAU / n_az as f64;
        for sign in [1.0, -1.0] {
            for (xm, wm) in x.iter().zip(&w) {
                // Map [-1, 1] onto (0, 1): z = (x + 1)/2, dz = dx/2.
                let z = 0.5 * (xm + 1.0) * sign;
                let polar = z.clamp(-1.0, 1.0).acos();
                for a in 0..n_az {
                    let az = (a as f64 + 0.5) * daz;
                    dirs.push(local_direction_f64(polar, az));
                    weights.push(0.5 * wm * daz);
                }
            }
        }
        let t = num_terms(bands);
        let mut y = vec![0.0; dirs.len() * t];
        for (p, d) in dirs.iter().enumerate() {
            eval_sh_f64(*d, &mut y[p * t..(p + 1) * t]);
        }
        SphereQuadrature {
            bands,
            upper: n_mu * n_az,
            dirs,
            weights,
            y,
        }
    }

    /// `c_k = sum_p w_p g(d_p) Y_k(d_p)` over the whole sphere, RGB; `g` sees every node.
    pub fn project(&self, g: impl Fn(DVec3) -> DVec3) -> Vec<DVec3> {
        let t = num_terms(self.bands);
        let mut c = vec![DVec3::ZERO; t];
        for (p, d) in self.dirs.iter().enumerate() {
            let v = g(*d) * self.weights[p];
            if v == DVec3::ZERO {
                continue;
            }
            for (ck, yk) in c.iter_mut().zip(&self.y[p * t..(p + 1) * t]) {
                *ck += v * *yk;
            }
        }
        c
    }

    /// `b_k = sum_{p upper} w_p g(d_p) Y_k(d_p)` over the upper hemisphere only.
    fn project_upper(&self, g: impl Fn(DVec3) -> DVec3) -> Vec<DVec3> {
        let t = num_terms(self.bands);
        let mut c = vec![DVec3::ZERO; t];
        for p in 0..self.upper {
            let v = g(self.dirs[p]) * self.weights[p];
            for (ck, yk) in c.iter_mut().zip(&self.y[p * t..(p + 1) * t]) {
                *ck += v * *yk;
            }
        }
        c
    }

    /// Hemisphere Gram matrix `G_kl = sum_{p upper} w_p Y_k Y_l` (row-major `T x T`).
    fn upper_gram(&self) -> Vec<f64> {
        let t = num_terms(self.bands);
        let mut g = vec![0.0; t * t];
        for p in 0..self.upper {
            let y = &self.y[p * t..(p + 1) * t];
            let w = self.weights[p];
            for k in 0..t {
                let wk = w * y[k];
                for l in 0..t {
                    g[k * t + l] += wk * y[l];
                }
            }
        }
        g
    }
}

/// Projects a function of the direction over the **full sphere** onto `bands` bands with
/// the split product rule of the module doc (`n_mu` nodes per half, `2 n_mu` azimuths;
/// `n_mu` is raised to `bands` if smaller). Exact (to rounding) when `g` is band-limited to
/// `bands` bands. This is the projection of [`Method::Zero`] and [`Method::Even`] once the
/// extension below the horizon is applied.
pub fn project_sphere_function(
    g: &(dyn Fn(DVec3) -> DVec3 + Sync),
    bands: usize,
    n_mu: usize,
) -> Vec<DVec3> {
    let n_mu = n_mu.max(bands);
    SphereQuadrature::new(bands, n_mu, 2 * n_mu).project(g)
}

/// Cholesky factor (lower, row-major) of a symmetric positive definite `n x n` matrix.
/// `None` if a pivot is not positive.
pub(crate) fn cholesky(a: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            if i == j {
                if !(s > 0.0) {
                    return None;
                }
                l[i * n + i] = s.sqrt();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    Some(l)
}

/// Solves `L L^T x = b` in place for a Cholesky factor from [`cholesky`].
pub(crate) fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

/// Acquires `src` as an SH data set (module doc). The data set stores `f_r cos(polar_i)`
/// (`includes_cosine = true`), uses bilinear coefficient lookup, and its provenance names
/// the source, method and quadrature. Parallel over view texels (rayon); each texel is
/// computed by one task, so the result does not depend on the thread count.
///
/// Fails on bands outside 1..=[`MAX_BANDS`], an empty or oversized grid, a non-positive
/// `lambda`, a singular least-squares system, or a non-finite source value.
pub fn acquire(src: &dyn Brdf, opts: &AcquireOptions) -> Result<ShDataset, AcquireError> {
    acquire_with_progress(src, opts, &|| {})
}

/// [`acquire`], calling `tick` once per finished view texel (for a progress bar).
pub fn acquire_with_progress(
    src: &dyn Brdf,
    opts: &AcquireOptions,
    tick: &(dyn Fn() + Sync),
) -> Result<ShDataset, AcquireError> {
    let AcquireOptions {
        bands,
        nu,
        nv,
        method,
        ..
    } = *opts;
    if bands == 0 || bands > MAX_BANDS {
        return Err(AcquireError::Bands(bands));
    }
    if nu == 0 || nv == 0 || nu > 1024 || nv > 1024 {
        return Err(AcquireError::Grid { nu, nv });
    }
    let n_mu = opts.n_mu();
    let quad = SphereQuadrature::new(bands, n_mu, 2 * n_mu);
    let t = num_terms(bands);
    let factor = match method {
        Method::Lsq { lambda } => {
            if !(lambda.is_finite() && lambda > 0.0) {
                return Err(AcquireError::Lambda(lambda));
            }
            let mut g = quad.upper_gram();
            for k in 0..t {
                g[k * t + k] += lambda;
            }
            Some(cholesky(&g, t).ok_or(AcquireError::Singular)?)
        }
        _ => None,
    };
    let texels: Vec<(usize, usize)> = (0..nv).flat_map(|j| (0..nu).map(move |i| (i, j))).collect();
    let blocks: Vec<Result<Vec<f32>, AcquireError>> = texels
        .par_iter()
        .map(|&(i, j)| {
            let (p, a) = hemi_texel_angles_f64(i, j, nu, nv);
            let wo = local_direction_f64(p, a);
            let c = match method {
                Method::Zero => quad.project(|wi| acquired_value(src, wi, wo)),
                Method::Even => {
                    quad.project(|wi| acquired_value(src, DVec3::new(wi.x, wi.y, wi.z.abs()), wo))
                }
                Method::Lsq { .. } => {
                    let b = quad.project_upper(|wi| acquired_value(src, wi, wo));
                    let l = factor.as_ref().expect("factor computed for lsq");
                    let mut out = vec![DVec3::ZERO; t];
                    for ch in 0..3 {
                        let mut x: Vec<f64> = b.iter().map(|v| v[ch]).collect();
                        cholesky_solve(l, t, &mut x);
                        for k in 0..t {
                            out[k][ch] = x[k];
                        }
                    }
                    out
                }
            };
            tick();
            let mut block = vec![0.0f32; 3 * t];
            for ch in 0..3 {
                for k in 0..t {
                    let v = c[k][ch] as f32;
                    if !v.is_finite() {
                        return Err(AcquireError::NonFinite { i, j });
                    }
                    block[ch * t + k] = v;
                }
            }
            Ok(block)
        })
        .collect();
    let mut coeffs = Vec::with_capacity(nu * nv * 3 * t);
    for b in blocks {
        coeffs.extend(b?);
    }
    let lambda = match method {
        Method::Lsq { lambda } => format!(", lambda {lambda:e}"),
        _ => String::new(),
    };
    let provenance = format!(
        "brdfkit acquire: source {}, {bands} bands, method {}{lambda}, view grid {nu}x{nv}, \
         quadrature {n_mu}x{} per half sphere; values are f_r cos(polar_i)",
        src.name(),
        method.name(),
        2 * n_mu
    );
    let mut ds = ShDataset::new(nu, nv, bands, true, provenance, coeffs)?;
    ds.coeff_lookup = crate::sh::Lookup::Bilinear;
    Ok(ds)
}

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
    let ratio = |e2: f64, s2: f64| {
        if s2 > 0.0 {
            (e2 / s2).sqrt()
        } else if e2 > 0.0 {
            f64::INFINITY
        } else {
            0.0
        }
    };
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
