//! Work the renderer skips because the scene does not need it, and the bound on what each
//! skip can change in the image. Decided once per frame ([`crate::shade::FramePrep::new`]).
//!
//! Skips that change no bit are documented where they happen: per-tile normal-cone culling
//! ([`crate::kernel`]), empty tiles and AOVs nobody asked for ([`crate::shade`],
//! [`crate::render`]), probe preprocessing already cached ([`crate::env::lightset::prepare`]). The
//! two skips here trade a bounded error for work:
//!
//! # Negligible lights ([`drop_weak_lights`], [`needs_restore`])
//! The weakest directional lights (by the largest channel of their irradiance `E_k`, ties
//! by index) are set aside while, in every colour channel, their irradiance
//! `E_drop = sum_{dropped} E_k` stays at most `fraction x` the total. A pixel is
//! `L = sum_k f(l_k, v) cos(polar_k) E_k` (thesis Def. 10), so leaving out the set `D`
//! changes it by
//! `|dL| = |sum_{k in D} f cos E_k| <= E_drop x M`, with `M` the material's bound on
//! `|f cos|` ([`crate::brdf::Brdf::max_cosine_weighted`]: Lambert `albedo/pi`,
//! Blinn-Phong `kd/pi + ks (a+8)/(8 pi)`, Phong `kd/pi + ks (a+2)/(2 pi)`, D-BRDF
//! `c max(p) max(1, R_s)`, SH data sets `max|c| L/sqrt(4 pi)` by Cauchy-Schwarz).
//!
//! That bound is relative to the brightest value any pixel could take (`E_total M`), not
//! to the pixel: under a glossy lobe the dim dropped lights made visible highlights (3% of
//! glossy pixels at `fraction = 1e-3`), and on the dark side of a studio probe a
//! Lambert pixel changed by 5%. So the bound is made relative to each pixel. Only the
//! dropped lights above the pixel's horizon (`n.l_k > 0`) reach it, so
//! `|dL| <= M E_D(n)` with `E_D(n) = sum_{k in D, n.l_k > 0} E_k` (a horizon test per
//! dropped light, no BRDF). The pixel is first shaded with the kept lights (`L_kept`), and
//! where in some channel `M E_D(n) > fraction x |L_kept|` ([`LightDrop::restore_below`],
//! [`needs_restore`]) the dropped lights are shaded for that pixel too and added. Every
//! pixel then has `|dL| <= fraction x |L_kept|` in each channel, and `|L_kept| <= L` where
//! the terms are non-negative (every BRDF; SH fits can ring below zero, where the bound
//! holds relative to `L_kept`). A material with a narrow lobe has a large `M` next to its
//! typical `f cos`, so its pixels get the dropped lights back almost everywhere: for glossy
//! materials the skip turns itself off.
//! Models without a bound drop nothing; point lights are never dropped (their irradiance
//! depends on the distance).
//!
//! # SH bands beyond what a material needs ([`crate::sh::dataset::ShDataset::effective_bands`])
//! A data set declares a band energy threshold; shading uses the first `L` of its `B` bands,
//! `L` the smallest with the dropped bands' coefficient energy below the threshold of the
//! total. At a pixel with (filtered) view coefficients `c`, the dropped part of the
//! reconstruction for any light direction `w` is, by Cauchy-Schwarz and the SH addition
//! theorem `sum_m Y_lm(w)^2 = (2l+1)/(4 pi)`,
//! `|sum_{l>=L} sum_m c_lm Y_lm(w)| <= |c_{l>=L}| sqrt(sum_{l=L}^{B-1} (2l+1)/(4 pi))
//! = |c_{l>=L}| sqrt((B^2 - L^2)/(4 pi))` ([`band_tail_factor`]), so the pixel changes by at
//! most `sum_k E_k w_k x |c_{l>=L}| x band_tail_factor(B, L)` over the lights above the
//! horizon (`w_k = cos(polar_k)`, or 1 when the table includes the cosine).
//!
//! Both bounds hold in exact arithmetic; the two f32 renders being compared also round
//! their sums in different orders, which [`summation_allowance`] bounds.

use crate::light::Light;
use glam::Vec3;

/// Default fraction of the total directional irradiance that may be dropped (weakest
/// lights first): 1e-3, which is also the largest change it allows at any pixel relative
/// to that pixel's value (module doc). In practice it drops the dim tail of uniform and
/// stratified light sets (golden `fig3-6-uniform-city`: 1 of 64 lights) and nothing from
/// median-cut or importance sets, whose lights carry nearly equal irradiance; Lloyd's
/// relaxation moves irradiance between regions and can leave a few dim ones (golden
/// `fig3-8-lloyd-studio`: 2 of 64).
pub const DEFAULT_DROP_LIGHTS: f32 = 1e-3;

/// The light set after dropping negligible lights, and what was dropped.
#[derive(Clone, Debug, PartialEq)]
pub struct LightDrop {
    /// The lights shaded at every pixel, in their original order.
    pub kept: Vec<Light>,
    /// The lights set aside, in their original order: shaded only at the pixels where
    /// leaving them out could change more than `fraction` of the value ([`needs_restore`]).
    pub removed: Vec<Light>,
    /// The material's bound `M` on `|f cos|` divided by the fraction (0 when nothing is
    /// dropped): [`LightDrop::restore_below`] is `E_D(n)` times this.
    pub restore_scale: Vec3,
    /// Number of directional lights dropped.
    pub dropped: usize,
    /// Sum of the dropped lights' irradiance at normal incidence (RGB, W/m^2).
    pub dropped_irradiance: Vec3,
    /// Sum of all directional lights' irradiance (RGB, W/m^2).
    pub total_irradiance: Vec3,
}

/// Sets aside the weakest directional lights of `lights` while, in every channel, their
/// summed irradiance stays at most `fraction x` the total (module doc), for a material with
/// `|f cos| <= max_f_cos` (which [`LightDrop::restore_below`] uses). `fraction <= 0`
/// (or NaN) drops nothing. Deterministic: order by the largest channel, ties by index; the
/// kept and removed lights keep their original order. Never fails.
pub fn drop_weak_lights(lights: &[Light], fraction: f32, max_f_cos: Vec3) -> LightDrop {
    let irr = |l: &Light| match *l {
        Light::Directional { irradiance, .. } => Some(irradiance),
        Light::Point { .. } => None,
    };
    let total = lights.iter().filter_map(irr).fold(Vec3::ZERO, |a, e| a + e);
    let mut out = LightDrop {
        kept: lights.to_vec(),
        removed: Vec::new(),
        restore_scale: Vec3::ZERO,
        dropped: 0,
        dropped_irradiance: Vec3::ZERO,
        total_irradiance: total,
    };
    if fraction.is_nan() || fraction <= 0.0 {
        return out;
    }
    let limit = total * fraction;
    let mut order: Vec<(usize, Vec3)> = lights
        .iter()
        .enumerate()
        .filter_map(|(i, l)| irr(l).map(|e| (i, e)))
        .collect();
    order.sort_by(|a, b| {
        a.1.max_element()
            .total_cmp(&b.1.max_element())
            .then(a.0.cmp(&b.0))
    });
    let mut drop = vec![false; lights.len()];
    let mut sum = Vec3::ZERO;
    for (i, e) in order {
        let next = sum + e;
        if next.cmpgt(limit).any() {
            break;
        }
        sum = next;
        drop[i] = true;
        out.dropped += 1;
    }
    out.dropped_irradiance = sum;
    let pick = |want: bool| -> Vec<Light> {
        lights
            .iter()
            .zip(&drop)
            .filter(|(_, d)| **d == want)
            .map(|(l, _)| *l)
            .collect()
    };
    out.kept = pick(false);
    out.removed = pick(true);
    out.restore_scale = max_f_cos / fraction;
    out
}

impl LightDrop {
    /// Per channel, the kept radiance below which a pixel with unit normal `n` gets the
    /// removed lights back: `M E_D(n) / fraction`, `E_D(n)` the removed lights' irradiance
    /// summed over those above the horizon of `n` (module doc). Zero when nothing was
    /// removed.
    pub fn restore_below(&self, n: Vec3) -> Vec3 {
        let mut e = Vec3::ZERO;
        for l in &self.removed {
            if let Light::Directional {
                to_light,
                irradiance,
            } = *l
            {
                if n.dot(to_light) > 0.0 {
                    e += irradiance;
                }
            }
        }
        e * self.restore_scale
    }
}

/// The largest change (RGB, radiance) dropping lights of summed irradiance
/// `dropped_irradiance` can make to any pixel of a material with `|f cos| <= max_f_cos`:
/// their product (module doc).
pub fn light_drop_bound(dropped_irradiance: Vec3, max_f_cos: Vec3) -> Vec3 {
    dropped_irradiance * max_f_cos
}

/// Whether a pixel whose kept lights give `kept_radiance` must have the dropped lights
/// shaded too: some channel's `|L_kept|` below `restore_below`
/// ([`LightDrop::restore_below`]; never where that is 0).
#[inline]
pub fn needs_restore(kept_radiance: Vec3, restore_below: Vec3) -> bool {
    kept_radiance.abs().cmplt(restore_below).any()
}

/// `sqrt(sum_{l=kept}^{bands-1} (2l+1)/(4 pi)) = sqrt((bands^2 - kept^2)/(4 pi))`: by the SH
/// addition theorem, the largest Euclidean norm the basis values of the dropped bands reach
/// at any direction (module doc). 0 when nothing is dropped.
pub fn band_tail_factor(bands: usize, kept: usize) -> f64 {
    let (b, k) = (bands as f64, kept.min(bands) as f64);
    ((b * b - k * k) / (4.0 * std::f64::consts::PI)).sqrt()
}

/// Bound on the difference between an f32 sum of `n` terms and the exact sum, when the
/// absolute values of the terms sum to at most `abs_sum`: `(n - 1) u abs_sum` with
/// `u = 2^-24` (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., 4.2, any
/// summation order), doubled here to cover one product rounding per term. Two renders that
/// sum the same terms in different orders differ by at most twice this.
pub fn summation_allowance(n: usize, abs_sum: f32) -> f32 {
    2.0 * n.saturating_sub(1) as f32 * f32::EPSILON * 0.5 * abs_sum
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(e: f32) -> Light {
        Light::Directional {
            to_light: Vec3::Y,
            irradiance: Vec3::splat(e),
        }
    }

    #[test]
    fn drops_the_weakest_within_the_fraction_and_keeps_order() {
        let lights = [dir(5.0), dir(0.1), dir(3.0), dir(0.2), dir(0.05)];
        // total 8.35; 5 % = 0.4175: 0.05 + 0.1 + 0.2 = 0.35 fits, + 3.0 does not.
        let m = Vec3::new(0.1, 0.2, 0.3);
        let d = drop_weak_lights(&lights, 0.05, m);
        assert_eq!(d.dropped, 3);
        assert_eq!(d.kept, vec![dir(5.0), dir(3.0)]);
        assert_eq!(d.removed, vec![dir(0.1), dir(0.2), dir(0.05)]);
        assert!((d.dropped_irradiance.x - 0.35).abs() < 1e-6);
        // Restore below M E_D(n) / fraction: all three removed lights are above the
        // horizon of +y (0.35 x (0.1, 0.2, 0.3) / 0.05), none of -y's.
        let below = d.restore_below(Vec3::Y);
        let want = Vec3::new(0.7, 1.4, 2.1);
        assert!((below - want).abs().max_element() < 1e-5, "{below}");
        assert_eq!(d.restore_below(-Vec3::Y), Vec3::ZERO);
        assert!(needs_restore(Vec3::new(1.0, 1.0, 3.0), below));
        // |L_kept| is compared: an SH fit ringing to -0.5 is below 0.7.
        assert!(needs_restore(Vec3::new(-0.5, 1.5, 3.0), below));
        assert!(!needs_restore(Vec3::new(-0.8, 1.5, 3.0), below));
        assert!(!needs_restore(Vec3::new(0.8, 1.5, 2.2), below));
        assert!(!needs_restore(Vec3::ZERO, Vec3::ZERO));
        assert_eq!(drop_weak_lights(&lights, 0.0, m).kept, lights.to_vec());
        let none = drop_weak_lights(&lights, 0.0, m);
        assert_eq!(none.restore_below(Vec3::Y), Vec3::ZERO);
        assert_eq!(drop_weak_lights(&lights, f32::NAN, m).dropped, 0);
        // A light whose weakest channel is small but another channel large is not weak.
        let coloured = Light::Directional {
            to_light: Vec3::Y,
            irradiance: Vec3::new(0.0, 0.0, 4.0),
        };
        let d = drop_weak_lights(&[dir(1.0), coloured], 0.5, m);
        assert_eq!(d.dropped, 0, "dropping either exceeds half of some channel");
    }

    #[test]
    fn band_tail_factor_is_the_addition_theorem_sum() {
        let direct: f64 =
            (3..8).map(|l| (2 * l + 1) as f64).sum::<f64>() / (4.0 * std::f64::consts::PI);
        assert!((band_tail_factor(8, 3) - direct.sqrt()).abs() < 1e-12);
        assert_eq!(band_tail_factor(5, 5), 0.0);
    }
}
