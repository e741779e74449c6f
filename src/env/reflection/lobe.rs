//! The integrand of the bake's sums (`build`'s radiance sum), prepared once per bake: for
//! Blinn-Phong and the isotropic D-BRDFs, the lobe's factor that depends on the half
//! vector's polar angle alone is a per-bake 1D table, so a (sample, texel) pair costs a few
//! multiply-adds, one square root, one division and a linear interpolation (`sums.rs`)
//! instead of a `pow` (glibc's
//! `__ieee754_pow_fma` was 57% of a Blinn-Phong bake's profile) or an octahedral lookup
//! (`DBrdf::eval_f64`'s `hemi_oct_encode` and four texels, 66% of a D-BRDF bake's).
//! Every other material keeps [`Material::eval_f64`] per pair.
//!
//! # The radial table and its bound
//! The variable is `x = 1 - cos(polar_h)` (`~ polar_h^2 / 2` near the normal), in which a
//! Blinn-Phong lobe is `g(x) = (n.h)^s = (1 - x)^s`, `|g''| <= s (s - 1)` (largest at
//! `x = 0`). The table spans `[0, x_cut]` ([`RadialTable::cut`], "Culling" below: 1 where
//! the lobe has no zero tail) in [`RADIAL_INTERVALS`] uniform intervals,
//! `delta = x_cut / 4096`, linear between nodes: the interpolation error is at most
//! `delta^2 / 8 max|g''| = delta^2 s (s - 1) / 8` of the lobe's peak. Since
//! `x_cut ~ ln(1 / CUT) / s` that is about `(13.8 / 4096)^2 / 8 = 1.4e-6` at any sharp
//! exponent, and 0 for `s = 1`. (Before, the variable was `u = sqrt(x)` over `[0, 1]`:
//! `delta^2 s / 4` = 7.5e-6 at `s = 500`; `x` needs one square root per pair fewer, and
//! its range follows the lobe.) Each table also *measures* its error at build
//! ([`RadialTable::bound`]): the largest difference between the interpolation and the
//! function at 3 points inside every interval and at the cut search's nodes beyond the
//! cut, relative to the peak.
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
//! The cut is found on 4096 uniform intervals in `u = sqrt(x)`: from the first of those
//! nodes after the last one at or above [`CUT`] (1e-6) of the peak, `x_cut = u_cut^2`, the
//! function is zero, and the table's last node (at `x_cut`) is zero, so the table is zero
//! from `x_cut` on ([`RadialTable::cut`]; the measured bound includes the cut, at most
//! `CUT` of the peak). A texel is the reflection of the view
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
//! drops those texels from the node's list (`Lobe::cull_cos`) and the sums change by
//! rounding only (the kept texels move between the four partial sums of `sums.rs`). The angle is 42 degrees at Blinn-Phong 200, 27 at 500 and 81 at 50. (The bound
//! before, `sin(alpha / 2) <= 2 sqrt(2) sin(polar_h / 2)` from `|l - r| = 2 |(v.h) h -
//! (v.n) n|`, was 62 and 38 degrees and culled nothing at Blinn-Phong 50; the tighter one
//! drops about a fifth of a node's texels, the same bits.)
//!
//! A per-pair error of `e` times the lobe's peak `F_max` changes a sample's radiance by at
//! most `e F_max E(n)` (`E` the residual's irradiance at the normal): for the default
//! Blinn-Phong 500 (`F_max = k_s (s + 8) / (8 pi)`, `k_s = 0.25`) that is `1.5e-5 E`,
//! below 0.01% of the Lambertian term's `k_d E / pi` alone.

use crate::brdf::{BlinnPhong, DBrdf};
use crate::lanes::{F64x4, Isa, F64_LANES};
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
    values: Box<[f64; RADIAL_INTERVALS + 1]>,
    /// The table spans `x` in `[0, cut]` and is zero from `x = cut` outwards (`cut = 1`:
    /// no zero tail).
    cut: f64,
    /// `RADIAL_INTERVALS / cut`: intervals per unit of `x`.
    inv_step: f64,
    /// Largest measured interpolation error inside an interval, relative to the largest
    /// node value.
    bound: f64,
    /// Largest deviation of the tabulated function from the one it averages (a D-BRDF's
    /// azimuths), relative to the largest node value; zero for Blinn-Phong.
    spread: f64,
}

impl RadialTable {
    /// Tabulates `g(x)` (`g` the function, `x = 1 - cos(polar_h)` in `[0, 1]`) over `[0,
    /// x_cut]`, with its measured bound (module doc). The cut is found on the grid of
    /// [`RADIAL_INTERVALS`] uniform intervals in `u = sqrt(x)`: the last of its nodes at or
    /// above [`CUT`] of their peak, the cut the next one.
    fn new(g: impl Fn(f64) -> f64, spread: f64) -> Self {
        let n = RADIAL_INTERVALS;
        let at_u = |i: usize| {
            let u = i as f64 / n as f64;
            g(u * u)
        };
        let coarse: Vec<f64> = (0..=n).map(at_u).collect();
        let peak = coarse.iter().copied().fold(0.0f64, f64::max);
        let last = coarse
            .iter()
            .rposition(|&x| x.abs() >= CUT * peak)
            .unwrap_or(0);
        let u_cut = ((last + 1) as f64 / n as f64).min(1.0);
        let cut = u_cut * u_cut;
        let mut values = Box::new([0.0f64; RADIAL_INTERVALS + 1]);
        for (i, v) in values.iter_mut().enumerate() {
            *v = g(cut * i as f64 / n as f64);
        }
        if u_cut < 1.0 {
            // Zero from the cut on: the node there is below CUT of the peak.
            values[n] = 0.0;
        }
        let mut table = RadialTable {
            values,
            cut,
            inv_step: n as f64 / cut,
            bound: 0.0,
            spread: 0.0,
        };
        let mut worst = 0.0f64;
        for i in 0..n {
            for q in [0.25, 0.5, 0.75] {
                let x = cut * (i as f64 + q) / n as f64;
                worst = worst.max((table.at(x) - g(x)).abs());
            }
        }
        // Beyond the cut the table is zero: the function there, at the grid in u.
        for c in &coarse[last + 1..] {
            worst = worst.max(c.abs());
        }
        let rel = |x: f64| if peak > 0.0 { x / peak } else { x };
        table.bound = rel(worst);
        table.spread = rel(spread);
        table
    }

    /// The interpolated value at `x = 1 - cos(polar_h)` (zero from the cut on, clamped to
    /// the last node below 0).
    #[inline]
    pub fn at(&self, x: f64) -> f64 {
        let n = RADIAL_INTERVALS;
        let t = (x * self.inv_step).clamp(0.0, n as f64);
        // Through i64: one conversion instruction (t is in [0, n]).
        let i = (t as i64 as usize).min(n - 1);
        let w = t - i as f64;
        let (a, b) = (self.values[i], self.values[i + 1]);
        a + w * (b - a)
    }

    /// [`RadialTable::at`] on the f64 lanes of `s`, lane for lane the same bits: `x` is
    /// clamped to the table's range by the lanes' `max` and `min` (the inputs are finite),
    /// the interval's index is `floor(t)` found without a float-to-integer conversion (`t +
    /// 2^52` rounds `t` in `[0, 4096]` to the nearest integer exactly, in the low bits of
    /// its mantissa, and one is taken off where that rounded up; Rust's saturating `as`
    /// costs a NaN and a range test per lane), and the two nodes are read per lane.
    #[inline(always)]
    pub fn at_lanes<S: Isa>(&self, s: S, x: S::D) -> S::D {
        const N: usize = RADIAL_INTERVALS;
        const _: () = assert!(N.is_power_of_two() && N < 1 << 31);
        let two52 = s.splat_f64(4_503_599_627_370_496.0);
        let t = (x * s.splat_f64(self.inv_step))
            .max(s.splat_f64(0.0))
            .min(s.splat_f64(N as f64));
        let rounded = t + two52;
        // `rounded - 1` (exact at this magnitude) where rounding went up; the last node's
        // interval for `t = N`.
        let floored = (rounded - two52).select_gt(t, rounded - s.splat_f64(1.0), rounded);
        let index = floored.min(s.splat_f64((N - 1) as f64) + two52);
        let w = t - (index - two52);
        let mut bits = [0.0f64; F64_LANES];
        index.store(&mut bits);
        let (mut a, mut b) = ([0.0f64; F64_LANES], [0.0f64; F64_LANES]);
        for k in 0..F64_LANES {
            // The low 32 bits of the mantissa hold the index (below 2^31); masked to the
            // table's length, so no bounds test is left.
            let i = (bits[k].to_bits() as u32 as usize) & (N - 1);
            (a[k], b[k]) = (self.values[i], self.values[i + 1]);
        }
        let (a, b) = (s.load_f64(&a), s.load_f64(&b));
        a + w * (b - a)
    }

    /// `(1 - cut)^2 (1 - 1e-9)`: a pair whose `cos^2(polar_h)` is below it is past the cut
    /// with a margin for rounding, so its table value is exactly zero (0 where the table has
    /// no zero tail: no pair is past it).
    pub fn zero_from_cos_squared(&self) -> f64 {
        if self.cut >= 1.0 {
            return 0.0;
        }
        let h = 1.0 - self.cut;
        h * h * (1.0 - 1e-9)
    }

    /// `x = 1 - cos(polar_h)` from which the table is zero (1 where it has no zero tail).
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
        // alpha = 2 polar_h at the cut, where cos(polar_h) = 1 - x:
        // cos(alpha) = 2 cos^2(polar_h) - 1, less a margin for the rounding of r.
        let cos_h = 1.0 - table.cut;
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
        let table = RadialTable::new(|x| (1.0 - x).max(0.0).powf(s), 0.0);
        LobeForm::BlinnPhong {
            // `k_d / pi` as `lambertian_term` rounds it, so that it cancels `minus` exactly.
            lambert: (m.kd / std::f32::consts::PI).as_dvec3() - minus,
            scale: m.ks.as_dvec3() * ((s + 8.0) / (8.0 * pi)),
            table,
        }
    }

    fn dbrdf(m: &DBrdf, rd: Vec3, minus: DVec3) -> Self {
        // p at polar angle acos(1 - x) and each azimuth, as the renderer looks it up.
        let samples = |x: f64| -> (f64, f64) {
            let cz = (1.0 - x).max(0.0);
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
            .map(|i| {
                let u = i as f64 / RADIAL_INTERVALS as f64;
                samples(u * u).1
            })
            .fold(0.0f64, f64::max);
        let table = RadialTable::new(|x| samples(x).0, spread);
        LobeForm::Dbrdf {
            // `r_d / pi` as `lambertian_term` rounds it, so that it cancels `minus` exactly.
            lambert: (rd * std::f32::consts::FRAC_1_PI).as_dvec3() - minus,
            c: m.c as f64,
            rs: m.rs.as_dvec3(),
            table,
        }
    }
}
