//! Polynomial approximations of the transcendental functions of the kernels (the view
//! angles of the SH coefficient lookup, [`view_angles`] and the packed paths), each with
//! its maximum error against `std` stated here and tested below on a dense grid. Fast path
//! only: the scalar oracle and the f64 path use `std` (no approximation there).
//!
//! - [`acos_01`]: `acos(x)` for `x` in `[0, 1]` (clamped), Abramowitz & Stegun 4.4.46,
//!   `sqrt(1-x) (a0 + a1 x + .. + a7 x^7)`, truncation error <= 2e-8 rad; evaluated in f32,
//!   max error against `f64::acos` [`ACOS_MAX_ERROR`] = 4e-7 rad.
//! - [`azimuth`]: `atan2(y, x)` wrapped into `[0, 2 pi)`, as
//!   [`crate::conventions::local_angles`] returns it; atan on `[0, 1]` reduced to
//!   `[0, tan(pi/8)]` by `atan(a) = pi/4 + atan((a-1)/(a+1))` and the Cephes `atanf`
//!   polynomial; max error against `f64::atan2` [`AZIMUTH_MAX_ERROR`] = 1e-6 rad (for
//!   azimuths near 2 pi most of it is the f32 rounding of `2 pi - r`).
//!
//! On a 32 x 32 coefficient table 1e-6 rad moves a texture coordinate by 6e-7, a change of
//! the bilinear weights ~1000x below [`super::KERNEL_TOLERANCE`]. (The D-BRDF's half-vector
//! lookup needs no angle: [`crate::brdf::dbrdf`], octahedral coordinates.)

use crate::lanes::{F32x8, Isa};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};

/// Largest difference from `f64::acos` of [`acos_01`] over `[0, 1]`, radians.
pub const ACOS_MAX_ERROR: f64 = 4e-7;
/// Largest difference from `f64::atan2` (wrapped into `[0, 2 pi)`) of [`azimuth`], radians.
pub const AZIMUTH_MAX_ERROR: f64 = 1e-6;

/// `acos(x)` per lane for `x` in `[0, 1]` (inputs outside are clamped), radians.
#[inline(always)]
pub fn acos_01<S: Isa>(s: S, x: S::V) -> S::V {
    let x = x.max(s.zero()).min(s.splat(1.0));
    // The published coefficients, digit for digit; f32 rounds each to its nearest value.
    #[allow(clippy::excessive_precision)]
    const A: [f32; 8] = [
        1.570_796_305,
        -0.214_598_801_6,
        0.088_978_987_4,
        -0.050_174_304_6,
        0.030_891_881_0,
        -0.017_088_125_6,
        0.006_670_090_1,
        -0.001_262_491_1,
    ];
    let mut p = s.splat(A[7]);
    for k in (0..7).rev() {
        p = p.mul_add(x, s.splat(A[k]));
    }
    (s.splat(1.0) - x).sqrt() * p
}

/// `atan2(y, x)` per lane wrapped into `[0, 2 pi)` (0 at `x = y = 0`), radians.
#[inline(always)]
// The polynomial's coefficients as published; f32 rounds each to its nearest value.
#[allow(clippy::excessive_precision)]
pub fn azimuth<S: Isa>(s: S, y: S::V, x: S::V) -> S::V {
    let (ax, ay) = (x.abs(), y.abs());
    let zero = s.zero();
    let one = s.splat(1.0);
    let hi = ax.max(ay);
    let lo = ax.min(ay);
    // a = lo / hi in [0, 1]; 0 when both are 0.
    let a = hi.select_gt(zero, lo.div(hi.max(s.splat(f32::MIN_POSITIVE))), zero);
    // Reduce a > tan(pi/8) to (a - 1) / (a + 1) in (-0.414, 0].
    let big = a.select_gt(s.splat(0.414_213_56), one, zero);
    let r = big.select_gt(zero, (a - one).div(a + one), a);
    let off = big.select_gt(zero, s.splat(FRAC_PI_4), zero);
    let z = r * r;
    let p = s
        .splat(8.053_744_5e-2)
        .mul_add(z, s.splat(-1.387_768_6e-1))
        .mul_add(z, s.splat(1.997_771_1e-1))
        .mul_add(z, s.splat(-3.333_294_9e-1));
    let t = (p * z).mul_add(r, r) + off;
    // Octant, quadrant and sign.
    let t = ay.select_gt(ax, s.splat(FRAC_PI_2) - t, t);
    let t = zero.select_gt(x, s.splat(PI) - t, t);
    let t = zero.select_gt(y, s.splat(TAU) - t, t);
    // As `wrap_azimuth`: a value that rounds up to 2 pi is 0.
    s.splat(TAU).select_gt(t, t, zero)
}

/// `(polar, azimuth)` of a local view direction `wo` with `wo.z >= 0` (as
/// [`crate::shade::local_view`] lifts it), as [`crate::conventions::local_angles`] returns
/// them, through [`acos_01`] and [`azimuth`] on lane 0: one pixel's coefficient-table
/// lookup costs one vector evaluation instead of `std`'s scalar `acos` and `atan2` (11% of a
/// point-lit SH frame). Errors as stated for the two functions; `wo.z < 0` clamps the polar
/// angle to `pi/2`; at the pole (`x = y = 0`) the azimuth is 0, where `std`'s `atan2` gives 0
/// or pi by the sign of a zero `x` (the oracle may then blend the pole row's texels at
/// another `u`: a set of pixels of measure zero).
#[inline(always)]
pub fn view_angles<S: Isa>(s: S, wo: glam::Vec3) -> (f32, f32) {
    let polar = acos_01(s, s.splat(wo.z)).lane(0);
    let az = azimuth(s, s.splat(wo.y), s.splat(wo.x)).lane(0);
    (polar, az)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::{Dispatch, Kernel, LANES};

    struct Eval(Vec<f32>, Vec<f32>);
    impl Kernel for Eval {
        type Out = (Vec<f32>, Vec<f32>);
        #[inline(always)]
        fn run<S: Isa>(self, s: S) -> Self::Out {
            let (mut ac, mut az) = (vec![0.0; self.0.len()], vec![0.0; self.0.len()]);
            for o in (0..self.0.len()).step_by(LANES) {
                let (x, y) = (s.load(&self.0[o..]), s.load(&self.1[o..]));
                acos_01(s, x).store(&mut ac[o..]);
                azimuth(s, y, x).store(&mut az[o..]);
            }
            (ac, az)
        }
    }

    fn wrapped(y: f32, x: f32) -> f64 {
        let a = (y as f64).atan2(x as f64);
        if a < 0.0 {
            a + std::f64::consts::TAU
        } else {
            a
        }
    }

    #[test]
    fn acos_and_azimuth_stay_within_their_stated_errors() {
        for d in [Dispatch::portable(), Dispatch::detect()] {
            // acos on [0, 1] (with 1 and 0 exactly); azimuth around the circle, several
            // radii, the axes and the origin.
            let n = 1 << 16;
            let mut xs: Vec<f32> = (0..=n).map(|i| i as f32 / n as f32).collect();
            let mut ys: Vec<f32> = vec![0.0; xs.len()];
            let m = xs.len();
            for i in 0..m {
                let ang = i as f64 / m as f64 * std::f64::consts::TAU;
                let r = [1.0, 1e-3, 0.7][i % 3];
                xs.push((r * ang.cos()) as f32);
                ys.push((r * ang.sin()) as f32);
            }
            for (x, y) in [
                (0.0, 0.0),
                (1.0, 0.0),
                (0.0, 1.0),
                (-1.0, 0.0),
                (0.0, -1.0),
                (1.0, -0.0),
            ] {
                xs.push(x);
                ys.push(y);
            }
            while !xs.len().is_multiple_of(LANES) {
                xs.push(0.5);
                ys.push(0.5);
            }
            let (ac, az) = d.run(Eval(xs.clone(), ys.clone()));
            let mut worst = (0.0f64, 0.0f64);
            for i in 0..xs.len() {
                if i <= n {
                    let e = (ac[i] as f64 - (xs[i] as f64).acos()).abs();
                    worst.0 = worst.0.max(e);
                }
                let want = wrapped(ys[i], xs[i]);
                let mut e = (az[i] as f64 - want).abs();
                // 0 and 2 pi are the same azimuth.
                e = e.min((e - std::f64::consts::TAU).abs());
                worst.1 = worst.1.max(e);
                assert!(
                    (0.0..TAU).contains(&az[i]),
                    "azimuth {} out of range",
                    az[i]
                );
            }
            eprintln!(
                "{}: acos {:.2e}, azimuth {:.2e}",
                d.name(),
                worst.0,
                worst.1
            );
            assert!(worst.0 <= ACOS_MAX_ERROR, "acos error {:e}", worst.0);
            assert!(worst.1 <= AZIMUTH_MAX_ERROR, "azimuth error {:e}", worst.1);
        }
    }
}

#[cfg(test)]
mod view_angle_tests {
    use super::*;
    use crate::conventions::local_angles;
    use crate::lanes::{Dispatch, Kernel};

    struct Views(Vec<glam::Vec3>);
    impl Kernel for Views {
        type Out = Vec<(f32, f32)>;
        #[inline(always)]
        fn run<S: Isa>(self, s: S) -> Self::Out {
            self.0.iter().map(|&w| view_angles(s, w)).collect()
        }
    }

    #[test]
    fn view_angles_match_local_angles_within_the_stated_errors() {
        // Unit directions over the upper hemisphere, including the pole and the horizon.
        let mut ws = vec![
            glam::Vec3::Z,
            glam::Vec3::X,
            glam::Vec3::new(0.0, -1.0, 0.0),
        ];
        for i in 0..4096 {
            let polar = (i % 64) as f32 / 63.0 * std::f32::consts::FRAC_PI_2;
            let az = (i / 64) as f32 / 64.0 * std::f32::consts::TAU;
            ws.push(crate::conventions::local_direction(polar, az));
        }
        for d in [Dispatch::portable(), Dispatch::detect()] {
            let got = d.run(Views(ws.clone()));
            for (w, (p, a)) in ws.iter().zip(got) {
                let (pe, ae) = local_angles(*w);
                assert!(
                    ((p - pe) as f64).abs() <= ACOS_MAX_ERROR + 2e-7,
                    "{w} polar {p} {pe}"
                );
                // At the pole std's atan2 says 0 or pi by the sign of a zero x; the
                // approximation says 0 (documented on `view_angles`).
                if w.x == 0.0 && w.y == 0.0 {
                    assert_eq!(a, 0.0);
                    continue;
                }
                // Azimuths compare on the circle (2 pi - tiny and 0 are neighbours).
                let da = (a - ae).abs();
                let da = da.min(std::f32::consts::TAU - da) as f64;
                assert!(da <= AZIMUTH_MAX_ERROR + 2e-7, "{w} azimuth {a} {ae}");
            }
        }
    }
}
