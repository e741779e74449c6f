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
//! * [`Method::NonNegative`]: [`Method::Lsq`]'s objective, held to `f_r cos >= 0` on a
//!   dense set of upper-hemisphere directions by a penalty with a growing active set
//!   ([`nonneg`]). The library's SH representations use it: least squares dips below zero
//!   by a few percent of the peak even where it fits well, and under a probe with a sun
//!   (1e5 times its median) a few percent of the sun is more than the rest of the light,
//!   so those pixels render negative.
//! * [`Method::Positive`]: zero extension and exact projection, then band `l` scaled by
//!   the window [`positive_window`], `w_l = n! (n+1)! / ((n-l)! (n+l+1)!)` with `n = L - 1`.
//!   These are the Legendre coefficients (normalised to `w_0 = 1`) of the zonal kernel
//!   `K(t) ∝ ((1 + t) / 2)^n`, a polynomial of degree `n` that is `>= 0` on `[-1, 1]`. By
//!   the Funk-Hecke theorem the windowed reconstruction is the convolution `g * K`, and the
//!   projection's quadrature has positive weights, so the reconstruction is a positive sum
//!   of shifted copies of `K`: **it is never negative where the data is not** (up to f32
//!   rounding of the stored coefficients), whatever the source. The price is blur: the
//!   kernel's half maximum is at `2 acos(2^(-1 / 2n))` from its centre (36 degrees at 8
//!   bands, 47 at 5), so sharp lobes lose their peak; the `acquire` table gives that cost
//!   next to the other methods. The thesis (2.3.4) answers ringing only by fitting an
//!   analytic model; this is the SH answer for data that must stay SH (a GPU port's SH
//!   path, a renderer that writes an unsigned target).
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
//! use a D-BRDF lobe instead ([`crate::brdf::stand_ins`]).
//!
//! Layout: this file holds the options and [`acquire`] itself; [`quadrature`] the split
//! product quadrature and projection; [`measure`] the error grid, report and ringing flag;
//! [`fit`] the D-BRDF fit. The D-BRDF file format sits beside its type
//! ([`crate::brdf::dbrdf::file`]); the `SOURCE` argument of the commands is parsed by the
//! command line (`cli::source`); the library's source models are
//! [`crate::brdf::stand_ins`].

pub mod fit;
pub mod measure;
pub mod nonneg;
pub mod quadrature;

pub use measure::*;
pub use quadrature::*;

use crate::brdf::{eval_cosine_weighted, Brdf};
use crate::conventions::{hemi_texel_angles_f64, local_direction_f64};
use crate::progress::Progress;
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
    /// Zero extension, exact projection, then the non-negative window [`positive_window`]:
    /// never rings below zero, blurs (module doc).
    Positive,
    /// [`Method::Lsq`] held to `f_r cos >= 0` on a dense set of upper-hemisphere
    /// directions ([`nonneg`]): least squares' accuracy without its dips below zero.
    NonNegative { lambda: f64 },
}

impl Method {
    /// Short name as used on the command line (`zero`, `lsq`, `even`, `positive`, `nonneg`).
    pub fn name(&self) -> &'static str {
        match self {
            Method::Zero => "zero",
            Method::Lsq { .. } => "lsq",
            Method::Even => "even",
            Method::Positive => "positive",
            Method::NonNegative { .. } => "nonneg",
        }
    }
}

impl Method {
    /// The Tikhonov weight of a least-squares method, [`DEFAULT_LAMBDA`] for the others.
    pub fn lambda(&self) -> f64 {
        match self {
            Method::Lsq { lambda } | Method::NonNegative { lambda } => *lambda,
            Method::Zero | Method::Even | Method::Positive => DEFAULT_LAMBDA,
        }
    }
}

/// The band weights of [`Method::Positive`] for `bands` bands (module doc): `w_0 = 1`,
/// `w_(l+1) = w_l (n - l) / (n + l + 2)` with `n = bands - 1`, the Legendre coefficients of
/// `((1 + t) / 2)^n` over those of its constant term. Each weight lies in (0, 1] and they
/// decrease with `l`; one band gives `[1]`.
pub fn positive_window(bands: usize) -> Vec<f64> {
    let n = bands.saturating_sub(1) as f64;
    let mut w = Vec::with_capacity(bands);
    let mut v = 1.0f64;
    for l in 0..bands {
        w.push(v);
        let l = l as f64;
        v *= (n - l) / (n + l + 2.0);
    }
    w
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

/// The band `l` of SH index `k = l^2 + l + m` (`floor(sqrt(k))`, exact in integers).
fn band_of(k: usize) -> usize {
    let mut l = (k as f64).sqrt() as usize;
    while l * l > k {
        l -= 1;
    }
    while (l + 1) * (l + 1) <= k {
        l += 1;
    }
    l
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

/// Acquires `src` as an SH data set (module doc). The data set stores `f_r cos(polar_i)`
/// (`includes_cosine = true`), uses bilinear coefficient lookup, and its provenance names
/// the source, method and quadrature. Parallel over view texels (rayon); each texel is
/// computed by one task, so the result does not depend on the thread count.
///
/// Fails on bands outside 1..=[`MAX_BANDS`], an empty or oversized grid, a non-positive
/// `lambda`, a singular least-squares system, or a non-finite source value.
pub fn acquire(src: &dyn Brdf, opts: &AcquireOptions) -> Result<ShDataset, AcquireError> {
    acquire_with_progress(src, opts, &Progress::hidden())
}

/// [`acquire`], counting one step on `progress` per finished view texel (`nu x nv` in
/// all; the caller sets the length). Counting does not change the data set.
pub fn acquire_with_progress(
    src: &dyn Brdf,
    opts: &AcquireOptions,
    progress: &Progress,
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
    let (regularised, factor) = match method {
        Method::Lsq { lambda } | Method::NonNegative { lambda } => {
            if !(lambda.is_finite() && lambda > 0.0) {
                return Err(AcquireError::Lambda(lambda));
            }
            let mut g = quad.upper_gram();
            for k in 0..t {
                g[k * t + k] += lambda;
            }
            let l = cholesky(&g, t).ok_or(AcquireError::Singular)?;
            (g, Some(l))
        }
        Method::Zero | Method::Even | Method::Positive => (Vec::new(), None),
    };
    let constraints =
        matches!(method, Method::NonNegative { .. }).then(|| nonneg::Constraints::new(t));
    let window = positive_window(bands);
    let texels: Vec<(usize, usize)> = (0..nv).flat_map(|j| (0..nu).map(move |i| (i, j))).collect();
    let blocks: Vec<Result<Vec<f32>, AcquireError>> = texels
        .par_iter()
        .map(|&(i, j)| {
            let (p, a) = hemi_texel_angles_f64(i, j, nu, nv);
            let wo = local_direction_f64(p, a);
            let c = match method {
                Method::Zero => quad.project(|wi| acquired_value(src, wi, wo)),
                Method::Positive => {
                    let mut c = quad.project(|wi| acquired_value(src, wi, wo));
                    for (k, v) in c.iter_mut().enumerate() {
                        *v *= window[band_of(k)];
                    }
                    c
                }
                Method::Even => {
                    quad.project(|wi| acquired_value(src, DVec3::new(wi.x, wi.y, wi.z.abs()), wo))
                }
                Method::Lsq { .. } | Method::NonNegative { .. } => {
                    let b = quad.project_upper(|wi| acquired_value(src, wi, wo));
                    let l = factor.as_ref().expect("factor computed for lsq");
                    let mut out = vec![DVec3::ZERO; t];
                    for ch in 0..3 {
                        let mut x: Vec<f64> = b.iter().map(|v| v[ch]).collect();
                        match &constraints {
                            Some(cons) => {
                                x = cons
                                    .solve(&regularised, l, &x)
                                    .ok_or(AcquireError::Singular)?;
                            }
                            None => cholesky_solve(l, t, &mut x),
                        }
                        for k in 0..t {
                            out[k][ch] = x[k];
                        }
                    }
                    out
                }
            };
            progress.inc(1);
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
        Method::Lsq { lambda } | Method::NonNegative { lambda } => format!(", lambda {lambda:e}"),
        Method::Zero | Method::Even | Method::Positive => String::new(),
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
    ds.isotropic = src.is_isotropic();
    Ok(ds)
}
