//! [`Distribution2D`]: a discrete 2-D distribution over the cells of a `width x height`
//! grid (thesis Algorithm 1's marginal-row / conditional-column CDFs; pbrt-v4's
//! `PiecewiseConstant2D` restricted to picking cells), with its probability and its
//! inverse.
//!
//! Design rule: sampling, probability and inverse are three views of the same two CDF
//! tables. [`Distribution2D::sample`] maps `[0,1)^2` onto cells, [`Distribution2D::invert`]
//! returns the exact half-open rectangle of `[0,1)^2` that `sample` maps onto a cell, and
//! [`Distribution2D::probability`] is that rectangle's area, so the three agree to the
//! last bit of the CDFs whatever rounding the CDFs carry. Cells of zero weight have an
//! empty rectangle and are never sampled.

use std::ops::Range;

/// Discrete distribution over the cells `(row, col)` of a row-major grid, proportional to
/// non-negative weights: first a row from the marginal CDF of row sums, then a column
/// from that row's conditional CDF (thesis Algorithm 1).
#[derive(Clone, Debug)]
pub struct Distribution2D {
    width: usize,
    height: usize,
    /// Inclusive, normalised cumulative row sums; exactly 1 from the last non-zero row on.
    row_cdf: Vec<f64>,
    /// Per row, inclusive normalised cumulative weights; last entry of a non-zero row 1
    /// (a zero row stays all zero).
    col_cdf: Vec<f64>,
}

impl Distribution2D {
    /// Builds the CDFs of row-major `weights` (`width x height`, each `>= 0`) in O(cells).
    /// Returns `None` when the weights sum to zero (nothing to sample). Panics if
    /// `weights.len() != width * height`.
    pub fn new(weights: &[f64], width: usize, height: usize) -> Option<Self> {
        let (w, h) = (width, height);
        assert_eq!(weights.len(), w * h, "weights must be width x height");
        let mut col_cdf = vec![0.0; w * h];
        let mut row_sums = vec![0.0; h];
        for row in 0..h {
            let mut acc = 0.0;
            for col in 0..w {
                acc += weights[row * w + col];
                col_cdf[row * w + col] = acc;
            }
            row_sums[row] = acc;
            if acc > 0.0 {
                for c in &mut col_cdf[row * w..(row + 1) * w] {
                    *c /= acc;
                }
                col_cdf[(row + 1) * w - 1] = 1.0;
            }
        }
        let total: f64 = row_sums.iter().sum();
        if total <= 0.0 {
            return None;
        }
        let mut acc = 0.0;
        let mut row_cdf: Vec<f64> = row_sums
            .iter()
            .map(|s| {
                acc += s;
                acc / total
            })
            .collect();
        // Exactly 1 from the last non-zero row on, so u < 1 never runs past it.
        let last = row_sums.iter().rposition(|&s| s > 0.0).unwrap_or(h - 1);
        for c in &mut row_cdf[last..] {
            *c = 1.0;
        }
        Some(Distribution2D {
            width,
            height,
            row_cdf,
            col_cdf,
        })
    }

    /// Grid width (columns).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Grid height (rows).
    pub fn height(&self) -> usize {
        self.height
    }

    /// The cell `(row, col)` that `(xi_1, xi_2)` in `[0,1)^2` selects: the first row whose
    /// CDF exceeds `xi_1`, then the first column of that row whose CDF exceeds `xi_2`
    /// (binary search; zero-weight cells are never selected).
    pub fn sample(&self, xi1: f64, xi2: f64) -> (usize, usize) {
        let (w, h) = (self.width, self.height);
        let row = self.row_cdf.partition_point(|&c| c <= xi1).min(h - 1);
        let cdf = &self.col_cdf[row * w..(row + 1) * w];
        let col = cdf.partition_point(|&c| c <= xi2).min(w - 1);
        (row, col)
    }

    /// The inverse of [`Self::sample`]: `[xi_1 range, xi_2 range]`, the half-open
    /// rectangle of `[0,1)^2` that `sample` maps onto cell `(row, col)` (every point of it,
    /// and no point outside it); `None` for a cell that is never sampled (zero weight, or
    /// a weight below the rounding of its row's CDF).
    /// The rectangles of all cells tile `[0,1)^2`.
    pub fn invert(&self, row: usize, col: usize) -> Option<[Range<f64>; 2]> {
        let w = self.width;
        let below = |cdf: &[f64], i: usize| if i == 0 { 0.0 } else { cdf[i - 1] };
        let rows = below(&self.row_cdf, row)..self.row_cdf[row];
        let cdf = &self.col_cdf[row * w..(row + 1) * w];
        let cols = below(cdf, col)..cdf[col];
        (!rows.is_empty() && !cols.is_empty()).then_some([rows, cols])
    }

    /// Probability that [`Self::sample`] of a uniform point of `[0,1)^2` returns cell
    /// `(row, col)`: the area of its [`Self::invert`] rectangle, `0` for a zero-weight cell.
    /// Equals `weight / total` up to the rounding of the CDFs (about 1e-16 relative).
    pub fn probability(&self, row: usize, col: usize) -> f64 {
        self.invert(row, col)
            .map_or(0.0, |[r, c]| (r.end - r.start) * (c.end - c.start))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64;

    /// Weights with zero cells, a zero row, a zero first and last row, and a wide range.
    fn weights(w: usize, h: usize, seed: u64) -> Vec<f64> {
        let mut rng = Pcg64::seed_from_u64(seed);
        (0..w * h)
            .map(|i| {
                let (row, col) = (i / w, i % w);
                if row == 0 || row == h - 1 || row == 2 || (row + col) % 5 == 0 {
                    0.0
                } else {
                    (1e-3 + rng.gen::<f64>().powi(4)) * 1e3
                }
            })
            .collect()
    }

    /// The largest f64 below `x` (`x > 0`).
    fn just_below(x: f64) -> f64 {
        f64::from_bits(x.to_bits() - 1)
    }

    /// Round trip of an inverse: for every cell, `sample` of the rectangle's lower corner,
    /// its midpoint and its last point below the upper corner returns the cell, the
    /// rectangle's area is the cell's `weight / total` (computed here from the weights,
    /// not from the CDFs) to 1e-12, zero cells have no rectangle, and the areas sum to 1.
    /// Returns the number of failures.
    fn round_trip_failures(
        d: &Distribution2D,
        weights: &[f64],
        invert: impl Fn(usize, usize) -> Option<[Range<f64>; 2]>,
    ) -> usize {
        let total: f64 = weights.iter().sum();
        let mut failures = 0;
        let mut area_sum = 0.0;
        for row in 0..d.height() {
            for col in 0..d.width() {
                let want_p = weights[row * d.width() + col] / total;
                match invert(row, col) {
                    None => failures += usize::from(want_p != 0.0),
                    Some([r, c]) => {
                        let area = (r.end - r.start) * (c.end - c.start);
                        area_sum += area;
                        failures += usize::from((area - want_p).abs() > 1e-12);
                        for (x, y) in [
                            (r.start, c.start),
                            ((r.start + r.end) / 2.0, (c.start + c.end) / 2.0),
                            (just_below(r.end), just_below(c.end)),
                        ] {
                            failures += usize::from(d.sample(x, y) != (row, col));
                        }
                    }
                }
            }
        }
        failures + usize::from((area_sum - 1.0).abs() > 1e-12)
    }

    #[test]
    fn invert_round_trips_and_probability_is_weight_over_total() {
        for (w, h, seed) in [(17, 9, 1), (1, 6, 2), (6, 1, 3), (64, 32, 4)] {
            let wt = if w == 1 || h == 1 {
                (0..w * h).map(|i| (i % 3) as f64).collect()
            } else {
                weights(w, h, seed)
            };
            let d = Distribution2D::new(&wt, w, h).unwrap();
            assert_eq!(round_trip_failures(&d, &wt, |r, c| d.invert(r, c)), 0);
            let total: f64 = wt.iter().sum();
            for row in 0..h {
                for col in 0..w {
                    let want = wt[row * w + col] / total;
                    assert!((d.probability(row, col) - want).abs() <= 1e-12);
                }
            }
            // Random points fall inside the rectangle of the cell they sample.
            let mut rng = Pcg64::seed_from_u64(seed);
            for _ in 0..10_000 {
                let (x, y): (f64, f64) = (rng.gen(), rng.gen());
                let (row, col) = d.sample(x, y);
                let [r, c] = d.invert(row, col).expect("sampled cells have weight");
                assert!(r.contains(&x) && c.contains(&y), "{x} {y} -> {row} {col}");
            }
        }
    }

    #[test]
    fn round_trip_check_catches_a_wrong_inverse() {
        // Seeded faults: the neighbouring column's rectangle, and a rectangle widened by
        // one ulp at the top; the check must report both.
        let (w, h) = (17, 9);
        let wt = weights(w, h, 1);
        let d = Distribution2D::new(&wt, w, h).unwrap();
        let shifted = |r: usize, c: usize| d.invert(r, (c + 1) % w);
        assert!(round_trip_failures(&d, &wt, shifted) > 0);
        let widened = |r: usize, c: usize| {
            d.invert(r, c)
                .map(|[a, b]| [a.start..f64::from_bits(a.end.to_bits() + 1), b])
        };
        assert!(round_trip_failures(&d, &wt, widened) > 0);
    }

    #[test]
    fn zero_weights_give_no_distribution() {
        assert!(Distribution2D::new(&[0.0; 6], 3, 2).is_none());
    }
}
