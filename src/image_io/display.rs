//! The one display encoding of linear values: exposure, tone map, sRGB transfer curve,
//! 8 bits. Every 8-bit image the crate writes from linear data goes through it: PNG
//! output ([`super::write_png`]), golden previews and triptychs, `brdfkit compare`'s FLIP
//! inputs and report images, and probe overlays ([`crate::cli::lights_overlay`]).
//!
//! Design rule: one documented order, `x * 2^exposure` (stops), then `max(x, 0)` and the
//! tone map ([`Tonemap`]), then the sRGB transfer curve (IEC 61966-2-1, [`srgb_encode`]),
//! then rounding to the nearest of 256 levels ([`to_u8`]). [`display_u8`] is the whole
//! chain; [`encode_u8`] the chain after exposure.

use serde::Deserialize;

/// Tone maps applied to exposed linear values before the sRGB curve.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize, serde::Serialize, clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Tonemap {
    /// `min(x, 1)` per channel: exact for values in [0, 1], clips highlights.
    Clamp,
    /// Reinhard 2002, per channel: `x / (1 + x)`.
    Reinhard,
    /// Narkowicz 2015 fit of the ACES filmic curve, per channel:
    /// `x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`, clamped to [0, 1].
    #[default]
    Aces,
}

impl Tonemap {
    /// The tone-mapped value of an exposed linear value `x`, in [0, 1]: negative values
    /// map to 0 (NaN stays NaN, and [`to_u8`] maps it to 0).
    #[inline]
    pub fn apply(self, x: f32) -> f32 {
        let x = x.max(0.0);
        match self {
            Tonemap::Clamp => x.min(1.0),
            Tonemap::Reinhard => x / (1.0 + x),
            Tonemap::Aces => {
                ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
            }
        }
    }
}

/// The sRGB transfer curve (linear [0, 1] to encoded [0, 1]).
#[inline]
pub fn srgb_encode(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Encoded [0, 1] to 8 bits, rounded to nearest (`round`, halves away from zero; values
/// outside [0, 1] clamp first); NaN maps to 0.
#[inline]
pub fn to_u8(x: f32) -> u8 {
    if x.is_nan() {
        0
    } else {
        (x.clamp(0.0, 1.0) * 255.0).round() as u8
    }
}

/// Display encoding of one linear value already scaled by the exposure: tone map, sRGB,
/// 8 bits.
#[inline]
pub fn encode_u8(exposed: f32, tonemap: Tonemap) -> u8 {
    to_u8(srgb_encode(tonemap.apply(exposed)))
}

/// Display encoding of one linear value: exposure (`x * 2^exposure`, stops), tone map,
/// sRGB, 8 bits.
#[inline]
pub fn display_u8(x: f32, exposure: f32, tonemap: Tonemap) -> u8 {
    encode_u8(x * exposure.exp2(), tonemap)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_form_levels() {
        // sRGB(0.5) = 1.055 * 0.5^(1/2.4) - 0.055 = 0.73536 -> 187.52 -> 188.
        assert_eq!(encode_u8(1.0, Tonemap::Reinhard), 188);
        // sRGB(0.25) = 0.53710 -> 136.96 -> 137; two stops up clips to white.
        assert_eq!(display_u8(0.25, 0.0, Tonemap::Clamp), 137);
        assert_eq!(display_u8(0.25, 2.0, Tonemap::Clamp), 255);
        assert_eq!(display_u8(0.0, 0.0, Tonemap::Aces), 0);
        assert_eq!(display_u8(f32::NAN, 0.0, Tonemap::Aces), 0);
        // Linear segment: 12.92 * 0.001 * 255 = 3.29 -> 3.
        assert_eq!(encode_u8(0.001, Tonemap::Clamp), 3);
    }

    #[test]
    fn negative_values_are_black_under_every_tone_map() {
        // Reinhard's x / (1 + x) of x = -2 is +2: without the clamp to 0 a negative value
        // below -1 would show white (the former overlay encoder did this).
        assert_eq!((-2.0f32 / (1.0 - 2.0)).min(1.0), 1.0);
        for tm in [Tonemap::Clamp, Tonemap::Reinhard, Tonemap::Aces] {
            for x in [-0.5, -2.0, -1e30] {
                assert_eq!(encode_u8(x, tm), 0, "{tm:?} {x}");
            }
        }
    }

    #[test]
    fn rounding_is_to_nearest() {
        // The one f32 in [0, 1] where `(y * 255 + 0.5) as u8` (the former overlay
        // encoder's rounding) and round-to-nearest disagree (found by trying all
        // 1,065,353,217 of them): y * 255 = 0.49999997, below one half.
        let y = 0.001_960_784_2f32;
        assert_eq!(y * 255.0, 0.499_999_97);
        assert_eq!((y * 255.0 + 0.5) as u8, 1);
        assert_eq!(to_u8(y), 0);
        assert_eq!(to_u8(0.5 / 255.0 + 1e-6), 1);
        assert_eq!(to_u8(254.5 / 255.0), 255);
    }
}
