//! Negative texels: their mass is moved into nearby positive texels, so the probe keeps its
//! local signed integral.
//!
//! Lossy DWAB compression rings around bright sources with both overshoot and undershoot
//! (the shipped probes are stored already cleaned by this code, assets/probes/README.md;
//! tests/data/probes/sky-dwab.exr keeps one original for the tests). Clamping the undershoot to zero keeps the overshoot and adds
//! energy (+0.1% to +6.3% of a whole image on six real probes); the signed integral is the
//! better estimate of the true light. So each channel of each negative texel is treated as a
//! negative mass `m = v x omega` (radiance in the file's units times the texel's exact solid
//! angle, [`crate::conventions::probe_texel_solid_angle`], sr) and taken out of the positive
//! texels around it:
//!
//! * Neighbourhood: the square window of texel radius `r = 1, 2, 4, ...` around the texel
//!   (columns wrap around the horizon, rows stop at the poles), widened until its positive
//!   mass `S` (same channel, `sum v_j omega_j` over texels with `v_j > 0`) is at least `-m`,
//!   up to the whole probe: nearest first.
//! * Weighting: each positive texel of that window gives a share of `-m` proportional to its
//!   own mass, i.e. every positive texel of the window is scaled by `1 - (-m) / S` (in f64,
//!   rounded once to f32), and the negative texel becomes 0. No texel ends negative, and the
//!   window's signed mass is unchanged (to f32 rounding of the scaled texels).
//! * Order: texels row-major, channels R, G, B; each step sees the texels the earlier steps
//!   left, so the result is deterministic and independent of any thread count.
//! * A channel whose whole-probe signed integral is negative cannot be cleaned that way:
//!   its negative texels are set to 0 and that mass is counted as
//!   [`LoadReport::negative_power_unplaced`] (never seen in a real probe).

use super::LoadReport;
use crate::conventions::probe_texel_solid_angle;

/// Moves the mass of every negative channel into nearby positive texels of the same
/// channel (module doc) and records in `report` the texels touched and the power moved.
/// `texels` is row-major, `width x height`, every channel finite.
pub(super) fn move_negative_mass(
    texels: &mut [[f32; 3]],
    width: usize,
    height: usize,
    report: &mut LoadReport,
) {
    let omega: Vec<f64> = (0..height)
        .map(|r| probe_texel_solid_angle(r, width, height))
        .collect();
    let mass = |t: &[[f32; 3]], i: usize, c: usize| t[i][c] as f64 * omega[i / width];
    for c in 0..3 {
        report.signed_power[c] = (0..texels.len()).map(|i| mass(texels, i, c)).sum();
    }
    // Largest radius needed for the window to hold every texel.
    let r_all = height.max(width / 2 + 1);
    for i in 0..texels.len() {
        if !texels[i].iter().any(|&v| v < 0.0) {
            continue;
        }
        report.negative_texels += 1;
        let (row, col) = (i / width, i % width);
        for c in 0..3 {
            if texels[i][c] >= 0.0 {
                continue;
            }
            let need = -mass(texels, i, c);
            texels[i][c] = 0.0;
            report.negative_power_moved[c] += need;
            let mut r = 1usize;
            loop {
                let window = Window::new(row, col, r, width, height);
                let have: f64 = window
                    .iter()
                    .filter(|&j| texels[j][c] > 0.0)
                    .map(|j| mass(texels, j, c))
                    .sum();
                if have >= need {
                    let keep = 1.0 - need / have;
                    for j in window.iter() {
                        if texels[j][c] > 0.0 {
                            texels[j][c] = ((texels[j][c] as f64) * keep).max(0.0) as f32;
                        }
                    }
                    break;
                }
                if r >= r_all {
                    // Not enough positive mass in the whole probe: everything left goes.
                    for j in window.iter() {
                        texels[j][c] = 0.0;
                    }
                    report.negative_power_moved[c] -= need - have;
                    report.negative_power_unplaced[c] += need - have;
                    break;
                }
                r *= 2;
            }
        }
    }
}

/// The square window of texel radius `r` around `(row, col)`: columns wrap (each column at
/// most once), rows are clamped to the probe.
struct Window {
    rows: std::ops::RangeInclusive<usize>,
    cols: Vec<usize>,
    width: usize,
}

impl Window {
    fn new(row: usize, col: usize, r: usize, width: usize, height: usize) -> Window {
        let rows = row.saturating_sub(r)..=(row + r).min(height - 1);
        let cols = if 2 * r + 1 >= width {
            (0..width).collect()
        } else {
            (0..=2 * r).map(|k| (col + width + k - r) % width).collect()
        };
        Window { rows, cols, width }
    }

    fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.rows
            .clone()
            .flat_map(move |row| self.cols.iter().map(move |&col| row * self.width + col))
    }
}
