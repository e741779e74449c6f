//! Probes resampled: [`downsample_box`], a smaller probe of the same power (what Lloyd's
//! relaxation iterates on for a large probe); [`upsample_bilinear`], a larger one, for
//! measuring how each environment method's preparation grows with the probe
//! (`examples/upsample_probe.rs`, `benches/prepare.rs`): the shipped probes are 512 x 256,
//! the probes people download 1K-8K wide.

use super::Probe;

/// The texels of `probe` resampled bilinearly to `width x height` (row-major, row 0 at +y),
/// between texel centres as [`crate::conventions`] places them (`(col + 1/2) / width`):
/// azimuth wraps around, the polar coordinate is clamped to the first and last rows' centres.
/// Smooth, so a bright source spreads over more texels at a larger size while the total
/// power changes little (a few percent at most where a source is one texel).
pub fn upsample_bilinear(probe: &Probe, width: usize, height: usize) -> Vec<[f32; 3]> {
    let (pw, ph) = (probe.width(), probe.height());
    let mut out = Vec::with_capacity(width * height);
    for row in 0..height {
        let y = ((row as f64 + 0.5) / height as f64 * ph as f64 - 0.5).clamp(0.0, (ph - 1) as f64);
        let (r0, fy) = (y.floor() as usize, (y - y.floor()) as f32);
        let r1 = (r0 + 1).min(ph - 1);
        for col in 0..width {
            let x = ((col as f64 + 0.5) / width as f64 * pw as f64 - 0.5).rem_euclid(pw as f64);
            let (c0, fx) = (x.floor() as usize % pw, (x - x.floor()) as f32);
            let c1 = (c0 + 1) % pw;
            let mix =
                |a: [f32; 3], b: [f32; 3], f: f32| [0, 1, 2].map(|c| a[c] * (1.0 - f) + b[c] * f);
            let top = mix(probe.texel(r0, c0), probe.texel(r0, c1), fx);
            let bottom = mix(probe.texel(r1, c0), probe.texel(r1, c1), fx);
            out.push(mix(top, bottom, fy));
        }
    }
    out
}

/// `probe` downsampled by `f` (which divides its width and height): each coarse texel's
/// radiance is its block's power `sum L Omega` (f64, texels in row-major order) over the
/// coarse texel's solid angle, so the probe's power is kept per block (to f32 rounding of
/// the radiance). Same name and rotation.
pub fn downsample_box(probe: &Probe, f: usize) -> Probe {
    let (w, h) = (probe.width(), probe.height());
    assert!(
        f >= 1 && w % f == 0 && h % f == 0,
        "{f} must divide {w} x {h}"
    );
    let (cw, ch) = (w / f, h / f);
    let mut texels = Vec::with_capacity(cw * ch);
    for crow in 0..ch {
        let omega = crate::conventions::probe_texel_solid_angle(crow, cw, ch);
        for ccol in 0..cw {
            let mut p = [0.0f64; 3];
            for row in crow * f..(crow + 1) * f {
                let o = probe.solid_angle(row);
                for col in ccol * f..(ccol + 1) * f {
                    let t = probe.texel(row, col);
                    for c in 0..3 {
                        p[c] += t[c] as f64 * o;
                    }
                }
            }
            texels.push(p.map(|v| (v / omega) as f32));
        }
    }
    let opts = super::LoadOptions {
        rotation: probe.rotation(),
        max_texels: usize::MAX,
        ..super::LoadOptions::default()
    };
    Probe::from_texels(probe.name(), cw, ch, texels, &opts)
        .expect("finite, non-negative texels")
        .0
}
