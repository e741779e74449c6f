//! Rotation of SH coefficients about the local z axis (the normal).
//!
//! Design rule: the one place that turns coefficients between two shading frames that share
//! the normal ([`crate::conventions::ShadingFrame::turned`]). Under the real basis of
//! [`super::basis`] (no Condon-Shortley phase), a turn about z mixes only the pair
//! `(Y_lm, Y_l,-m)`, `m > 0`, whose azimuthal factors are `cos(m a)` and `sin(m a)`: with
//! `a' = a - angle` the azimuth in the turned frame, `cos(m a') = cos(m a) cos(m angle) +
//! sin(m a) sin(m angle)` and `sin(m a') = sin(m a) cos(m angle) - cos(m a) sin(m angle)`,
//! so a function with coefficients `c'` in the turned frame has, in the original frame,
//! `c_m = c'_m cos(m angle) - c'_-m sin(m angle)` and
//! `c_-m = c'_m sin(m angle) + c'_-m cos(m angle)`. `cos(m angle)` and `sin(m angle)` come
//! from the unit pair by the angle-sum recurrence, with no trigonometric call.

use super::basis::sh_index;

/// Coefficients `c` (`terms = bands^2` per colour, `[R.., G.., B..]` or a single colour:
/// `c.len()` a multiple of `bands^2`) of a function given in a frame turned by `angle`
/// about z, rewritten in place as the same function's coefficients in the unturned frame;
/// `(cos, sin)` is the unit pair of `angle`. Exact up to f32 rounding (tested against the
/// basis evaluated at turned directions).
pub fn rotate_about_z(c: &mut [f32], bands: usize, cos: f32, sin: f32) {
    let terms = bands * bands;
    debug_assert!(terms > 0 && c.len().is_multiple_of(terms));
    for colour in c.chunks_exact_mut(terms) {
        let (mut cm, mut sm) = (1.0f32, 0.0f32);
        for m in 1..bands {
            (cm, sm) = (cm * cos - sm * sin, sm * cos + cm * sin);
            for l in m..bands {
                let (kp, kn) = (sh_index(l, m as i32), sh_index(l, -(m as i32)));
                let (p, n) = (colour[kp], colour[kn]);
                colour[kp] = p * cm - n * sm;
                colour[kn] = p * sm + n * cm;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conventions::{local_direction, ShadingFrame};
    use crate::sh::basis::eval_sh_f32;
    use glam::Vec3;

    #[test]
    fn turned_coefficients_evaluate_to_the_same_function() {
        let bands = 6;
        let terms = bands * bands;
        let c_turned: Vec<f32> = (0..terms)
            .map(|k| ((k * 37 % 11) as f32 - 5.0) * 0.1)
            .collect();
        let angle = 0.83f32;
        let mut c = c_turned.clone();
        rotate_about_z(&mut c, bands, angle.cos(), angle.sin());
        let base = ShadingFrame::from_normal(Vec3::new(0.3, 0.8, -0.5).normalize());
        let turned = base.turned(angle.cos(), angle.sin());
        let mut y = vec![0.0f32; terms];
        let mut y_t = vec![0.0f32; terms];
        for i in 0..40 {
            let d = base.to_world(local_direction(0.07 * i as f32, 0.31 * i as f32));
            eval_sh_f32(base.to_local(d), &mut y);
            eval_sh_f32(turned.to_local(d), &mut y_t);
            let f: f32 = c.iter().zip(&y).map(|(a, b)| a * b).sum();
            let f_t: f32 = c_turned.iter().zip(&y_t).map(|(a, b)| a * b).sum();
            assert!((f - f_t).abs() < 2e-5, "direction {i}: {f} against {f_t}");
        }
    }
}
