//! Summed-area table (Crow 1984) of a row-major weight grid: the sum over any texel
//! rectangle in O(1), which is what makes [`super::median_cut()`]'s median search cheap.
//!
//! Design rule: the table is built once, in f64, by the recurrence
//! `S(r+1, c+1) = S(r, c+1) + (row r's prefix sum up to c)`; a rectangle sum is the
//! four-corner difference, clamped at 0 so cancellation can never give a negative energy.

/// Summed-area table of `width x height` weights, stored `(height+1) x (width+1)` with a
/// zero first row and column.
pub(super) struct SummedAreaTable {
    w: usize,
    s: Vec<f64>,
}

impl SummedAreaTable {
    /// Builds the table of row-major `weights` (`width x height`) in O(cells).
    pub(super) fn new(weights: &[f64], width: usize, height: usize) -> Self {
        let (w, h) = (width, height);
        let mut s = vec![0.0; (w + 1) * (h + 1)];
        for r in 0..h {
            let mut row_acc = 0.0;
            for c in 0..w {
                row_acc += weights[r * w + c];
                s[(r + 1) * (w + 1) + c + 1] = s[r * (w + 1) + c + 1] + row_acc;
            }
        }
        SummedAreaTable { w, s }
    }

    /// Sum of the weights of rows `r0..r1`, columns `c0..c1` (half-open), `>= 0`.
    pub(super) fn sum(&self, r0: usize, r1: usize, c0: usize, c1: usize) -> f64 {
        let at = |r: usize, c: usize| self.s[r * (self.w + 1) + c];
        (at(r1, c1) - at(r0, c1) - at(r1, c0) + at(r0, c0)).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangle_sums_match_brute_force() {
        let (w, h) = (7, 5);
        // Integers up to 1e3: every partial sum is exact in f64, so equality is exact.
        let weights: Vec<f64> = (0..w * h).map(|i| ((i * 37 + 11) % 1000) as f64).collect();
        let t = SummedAreaTable::new(&weights, w, h);
        for r0 in 0..=h {
            for r1 in r0..=h {
                for c0 in 0..=w {
                    for c1 in c0..=w {
                        let mut want = 0.0;
                        for r in r0..r1 {
                            for c in c0..c1 {
                                want += weights[r * w + c];
                            }
                        }
                        assert_eq!(t.sum(r0, r1, c0, c1), want, "{r0}..{r1} x {c0}..{c1}");
                    }
                }
            }
        }
    }
}
