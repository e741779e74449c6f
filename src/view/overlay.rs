//! The status line drawn over the displayed frame (never into a screenshot): text in the
//! 8 x 8 public-domain glyphs of the `font8x8` crate, white on a darkened band.

use font8x8::legacy::BASIC_LEGACY;

/// Glyph cell edge (pixels) before scaling.
pub const GLYPH: usize = 8;

/// Draws `lines` from the top-left of a `width` x `height` 0x00RRGGBB buffer at `scale`
/// pixels per glyph pixel, each line on a band darkened to 1/4 of the image under it.
/// Characters outside ASCII draw as `?`; text past the right edge is cut.
pub fn draw_lines(buf: &mut [u32], width: usize, height: usize, lines: &[String], scale: usize) {
    let cell = GLYPH * scale;
    let band = cell + 2 * scale;
    for (row, text) in lines.iter().enumerate() {
        let y0 = row * band;
        if y0 + band > height {
            break;
        }
        let chars = text.chars().count();
        let band_w = ((chars * cell) + 4 * scale).min(width);
        for y in y0..y0 + band {
            for px in &mut buf[y * width..y * width + band_w] {
                *px = (*px >> 2) & 0x003f_3f3f;
            }
        }
        for (i, ch) in text.chars().enumerate() {
            let x0 = 2 * scale + i * cell;
            if x0 + cell > width {
                break;
            }
            let c = if ch.is_ascii() {
                ch as usize
            } else {
                b'?' as usize
            };
            let glyph = BASIC_LEGACY[c];
            for (gy, bits) in glyph.iter().enumerate() {
                for gx in 0..GLYPH {
                    if bits >> gx & 1 == 0 {
                        continue;
                    }
                    for sy in 0..scale {
                        let y = y0 + scale + gy * scale + sy;
                        let start = y * width + x0 + gx * scale;
                        buf[start..start + scale].fill(0x00ff_ffff);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_lights_pixels_inside_its_band_and_leaves_the_rest() {
        let (w, h) = (64, 40);
        let mut buf = vec![0x0080_8080u32; w * h];
        draw_lines(&mut buf, w, h, &["H".into()], 1);
        // 'H' has a full-height left stem at glyph column 0 or 1 of rows 0..7.
        let lit = (0..w * h).filter(|&i| buf[i] == 0x00ff_ffff).count();
        assert!(lit > 10 && lit < 40, "{lit}");
        // Outside the band (rows >= 10): untouched.
        assert!(buf[10 * w..].iter().all(|&p| p == 0x0080_8080));
        // Inside the band, unlit pixels are darkened to 1/4.
        assert_eq!(buf[0], 0x0020_2020);
    }
}
