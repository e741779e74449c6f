//! The integrand of the bake's sums (`build`'s radiance sum), prepared once per bake: for
//! Blinn-Phong and the isotropic D-BRDFs, the lobe's factor that depends on the half
//! vector's polar angle alone is a per-bake 1D table, so a (sample, texel) pair costs two
//! dot products, two square roots and a linear interpolation instead of a `pow` (glibc's
//! `__ieee754_pow_fma` was 57% of a Blinn-Phong bake's profile) or an octahedral lookup
//! (`DBrdf::eval_f64`'s `hemi_oct_encode` and four texels, 66% of a D-BRDF bake's).
//! Every other material keeps [`Material::eval_f64`] per pair.
//!
//! # The radial table and its bound
//! The variable is `u = sqrt(1 - cos(polar_h))` (`~ polar_h / sqrt(2)` near the normal),
//! in which a Blinn-Phong lobe `(n.h)^s = (1 - u^2)^s ~ exp(-s u^2)` is a Gaussian of
//! width `1/sqrt(2 s)` whose second derivative is largest at `u = 0`, `|g''| <= 2 s`.
//! [`RADIAL_INTERVALS`] uniform intervals over `u` in `[0, 1]`, `delta = 1/4096`, linear
//! between nodes: the interpolation error is at most `delta^2 / 8 max|g''| = delta^2 s / 4`
//! of the lobe's peak (7.5e-6 at `s = 500`, 1.5e-4 at `s = 10^4`). Each table also
//! *measures* its error at build ([`RadialTable::bound`]): the largest difference between
//! the interpolation and the function at 3 points inside every interval, relative to the
//! largest node value.
//!
//! For a D-BRDF the function is `p(h)` of [`DBrdf`] as the renderer evaluates it (the
//! derived octahedral table's bilinear lookup, `DBrdf::p_f64_blend`), averaged over
//! [`AZIMUTHS`] azimuths of `h` at each polar angle. For an isotropic file table the
//! octahedral lookup still varies a little with azimuth (its bilinear interpolation on a
//! square grid of a radial function); that spread, the largest `|p(polar, phi) - mean|`
//! over the azimuths and nodes relative to the peak, is [`RadialTable::spread`] and is the
//! rest of the approximation. The bake's own error (`measure_error`: exact
//! [`Material::eval_f64`] sums over the full probe) and the rendered error against the
//! converged reference include both.
//!
//! # Culling
//! Node values below [`CUT`] (1e-6) of the peak, from the last one above it outwards, are
//! zero, so the table is zero from `u_cut` on ([`RadialTable::cut`]; the measured bound
//! includes the cut, at most `CUT` of the peak). A texel is the reflection of the view
//! about the half vector, `l(h) = 2 (v.h) h - v`, and the reflected direction the same
//! map at the normal, `r = l(n)`. The map is 2-Lipschitz on the sphere: for a tangent
//! `dh` (unit `e`, normal to `h`), `dl = 2 (v.dh) h + 2 (v.h) dh`, two orthogonal parts,
//! so `|dl|^2 = 4 |dh|^2 ((v.e)^2 + (v.h)^2) <= 4 |dh|^2` (`e`, `h` orthonormal, `v`
//! unit). The great-circle arc from `n` to `h` (length `polar_h`) maps to a path from `r`
//! to `l` no longer than `2 polar_h`, so `alpha <= 2 polar_h` (`alpha` the angle from `l`
//! to `r`), for every view, and with equality for a half vector in the plane of incidence
//! (the bound is tight). A texel farther from `r` than twice `polar_h`'s cut therefore has
//! a zero lobe at *every* sample of the node, and where the integrand has no Lambertian
//! term (the shipped bake: it is held over normals) its pairs add exact zeros: the bake
//! drops those texels from the node's list (`Lobe::cull_cos`) and the sums keep their
//! bits. The angle is 42 degrees at Blinn-Phong 200, 27 at 500 and 81 at 50. (The bound
//! before, `sin(alpha / 2) <= 2 sqrt(2) sin(polar_h / 2)` from `|l - r| = 2 |(v.h) h -
//! (v.n) n|`, was 62 and 38 degrees and culled nothing at Blinn-Phong 50; the tighter one
//! drops about a fifth of a node's texels, the same bits.)
//!
//! A per-pair error of `e` times the lobe's peak `F_max` changes a sample's radiance by at
//! most `e F_max E(n)` (`E` the residual's irradiance at the normal): for the default
//! Blinn-Phong 500 (`F_max = k_s (s + 8) / (8 pi)`, `k_s = 0.25`) that is `1.5e-5 E`,
//! below 0.01% of the Lambertian term's `k_d E / pi` alone.

use crate::brdf::{BlinnPhong, DBrdf};
use crate::material::Material;
use glam::{DVec3, Vec3};

/// Intervals of the radial table over `u = sqrt(1 - cos(polar_h))` in `[0, 1]` (module doc).
pub const RADIAL_INTERVALS: usize = 4096;

/// Node values below this fraction of a radial table's peak, from the last one above it
/// outwards, are zero (module doc, "Culling").
pub const CUT: f64 = 1e-6;

/// Azimuths of `h` a D-BRDF's radial table averages the octahedral lookup over.
pub const AZIMUTHS: usize = 64;

/// A function of `u = sqrt(1 - cos(polar_h))` on [`RADIAL_INTERVALS`] uniform intervals,
/// linear between nodes (module doc).
#[derive(Clone, Debug)]
pub struct RadialTable {
    values: Vec<f64>,
    /// The table is zero from `u = cut` outwards.
    cut: f64,
    /// Largest measured interpolation error inside an interval, relative to the largest
    /// node value.
    bound: f64,
    /// Largest deviation of the tabulated function from the one it averages (a D-BRDF's
    /// azimuths), relative to the largest node value; zero for Blinn-Phong.
    spread: f64,
}

impl RadialTable {
    /// Tabulates `g(u)` (`g` the function, `u` in `[0, 1]`), with its measured bound.
    fn new(g: impl Fn(f64) -> f64, spread: f64) -> Self {
        let n = RADIAL_INTERVALS;
        let mut values: Vec<f64> = (0..=n).map(|i| g(i as f64 / n as f64)).collect();
        let peak = values.iter().copied().fold(0.0f64, f64::max);
        // The tail below CUT of the peak, from the last node above it: zero.
        let last = values
            .iter()
            .rposition(|&x| x.abs() >= CUT * peak)
            .unwrap_or(0);
        for x in &mut values[last + 1..] {
            *x = 0.0;
        }
        let mut table = RadialTable {
            values,
            cut: ((last + 1) as f64 / n as f64).min(1.0),
            bound: 0.0,
            spread: 0.0,
        };
        let mut worst = 0.0f64;
        for i in 0..n {
            for q in [0.25, 0.5, 0.75] {
                let u = (i as f64 + q) / n as f64;
                worst = worst.max((table.at(u) - g(u)).abs());
            }
        }
        let rel = |x: f64| if peak > 0.0 { x / peak } else { x };
        table.bound = rel(worst);
        table.spread = rel(spread);
        table
    }

    /// The interpolated value at `u` (clamped to `[0, 1]`).
    #[inline]
    pub fn at(&self, u: f64) -> f64 {
        let n = RADIAL_INTERVALS;
        let t = u.clamp(0.0, 1.0) * n as f64;
        let i = (t as usize).min(n - 1);
        let w = t - i as f64;
        let (a, b) = (self.values[i], self.values[i + 1]);
        a + w * (b - a)
    }

    /// `u` from which the table is zero.
    pub fn cut(&self) -> f64 {
        self.cut
    }

    /// The measured interpolation error (module doc), relative to the peak.
    pub fn bound(&self) -> f64 {
        self.bound
    }

    /// The azimuthal spread the table averages away (module doc), relative to the peak.
    pub fn spread(&self) -> f64 {
        self.spread
    }
}

/// The integrand `f - minus` of one bake (module doc): the material, the term `minus` taken
/// out of it (its Lambertian term, held over normals, or zero) and the tabulated form
/// where the model allows one.
pub(super) struct Lobe<'a> {
    pub material: &'a Material,
    pub minus: DVec3,
    pub form: LobeForm,
}

/// How a [`Lobe`] is evaluated per pair (module doc).
pub(super) enum LobeForm {
    /// Blinn-Phong: `(k_d / pi - minus) + k_s (s + 8) / (8 pi) g(u)`, `g` the table of
    /// `(n.h)^s`.
    BlinnPhong {
        lambert: DVec3,
        scale: DVec3,
        table: RadialTable,
    },
    /// An isotropic D-BRDF, alone or on a Lambert base (`r_d / pi`):
    /// `(r_d / pi - minus) + c p(u) F(k.h) / (a + b - a b)`.
    Dbrdf {
        lambert: DVec3,
        c: f64,
        rs: DVec3,
        table: RadialTable,
    },
    /// Every other model: [`Material::eval_f64`] minus `minus` per pair.
    Exact,
}

impl<'a> Lobe<'a> {
    /// The integrand of `material` less `minus` (module doc).
    pub fn new(material: &'a Material, minus: DVec3) -> Self {
        let form = match material {
            Material::BlinnPhong(m) => LobeForm::blinn_phong(m, minus),
            Material::DBrdf(m) if m.is_isotropic_table() => LobeForm::dbrdf(m, Vec3::ZERO, minus),
            Material::LambertDbrdf(m) if m.lobe.is_isotropic_table() => {
                LobeForm::dbrdf(&m.lobe, m.rd, minus)
            }
            Material::Lambert(_)
            | Material::Phong(_)
            | Material::AshikhminShirley(_)
            | Material::DBrdf(_)
            | Material::LambertDbrdf(_)
            | Material::Merl(_)
            | Material::Rgl(_)
            | Material::Sh(_) => LobeForm::Exact,
        };
        Lobe {
            material,
            minus,
            form,
        }
    }

    /// The cosine of the angle from the reflected direction `r` beyond which every pair of a
    /// sample about `r` has a zero integrand (module doc, "Culling"), or `None` where the
    /// integrand has no zero tail (no table, a Lambertian term left in it, a lobe whose cut
    /// is at or past 90 degrees of the half vector).
    pub fn cull_cos(&self) -> Option<f64> {
        let (lambert, table) = match &self.form {
            LobeForm::BlinnPhong { lambert, table, .. }
            | LobeForm::Dbrdf { lambert, table, .. } => (*lambert, table),
            LobeForm::Exact => return None,
        };
        if lambert != DVec3::ZERO || table.cut >= 1.0 {
            return None;
        }
        // alpha = 2 polar_h at the cut, where cos(polar_h) = 1 - u^2:
        // cos(alpha) = 2 cos^2(polar_h) - 1, less a margin for the rounding of r.
        let cos_h = 1.0 - table.cut * table.cut;
        if cos_h <= 0.0 {
            return None;
        }
        Some(2.0 * cos_h * cos_h - 1.0 - 1e-9)
    }

    /// The radial table, where there is one (read by the tests: its bounds).
    #[cfg(test)]
    pub fn table(&self) -> Option<&RadialTable> {
        match &self.form {
            LobeForm::BlinnPhong { table, .. } | LobeForm::Dbrdf { table, .. } => Some(table),
            LobeForm::Exact => None,
        }
    }
}

impl LobeForm {
    fn blinn_phong(m: &BlinnPhong, minus: DVec3) -> Self {
        let s = m.exponent as f64;
        let pi = std::f64::consts::PI;
        let table = RadialTable::new(|u| (1.0 - u * u).max(0.0).powf(s), 0.0);
        LobeForm::BlinnPhong {
            // `k_d / pi` as `lambertian_term` rounds it, so that it cancels `minus` exactly.
            lambert: (m.kd / std::f32::consts::PI).as_dvec3() - minus,
            scale: m.ks.as_dvec3() * ((s + 8.0) / (8.0 * pi)),
            table,
        }
    }

    fn dbrdf(m: &DBrdf, rd: Vec3, minus: DVec3) -> Self {
        // p at polar angle acos(1 - u^2) and each azimuth, as the renderer looks it up.
        let samples = |u: f64| -> (f64, f64) {
            let cz = (1.0 - u * u).max(0.0);
            let sz = (1.0 - cz * cz).max(0.0).sqrt();
            let (mut sum, mut lo, mut hi) = (0.0, f64::INFINITY, f64::NEG_INFINITY);
            for k in 0..AZIMUTHS {
                let phi = std::f64::consts::TAU * (k as f64 + 0.5) / AZIMUTHS as f64;
                let h = DVec3::new(sz * phi.cos(), sz * phi.sin(), cz);
                let p = m.p_f64_blend(h.as_vec3());
                sum += p;
                lo = lo.min(p);
                hi = hi.max(p);
            }
            let mean = sum / AZIMUTHS as f64;
            (mean, (hi - mean).max(mean - lo))
        };
        let spread = (0..=RADIAL_INTERVALS)
            .map(|i| samples(i as f64 / RADIAL_INTERVALS as f64).1)
            .fold(0.0f64, f64::max);
        let table = RadialTable::new(|u| samples(u).0, spread);
        LobeForm::Dbrdf {
            // `r_d / pi` as `lambertian_term` rounds it, so that it cancels `minus` exactly.
            lambert: (rd * std::f32::consts::FRAC_1_PI).as_dvec3() - minus,
            c: m.c as f64,
            rs: m.rs.as_dvec3(),
            table,
        }
    }
}
