//! The Pareto front of a sweep: which rows no other row beats in both frame time and error.
//!
//! Design rule: the front is a pure function of the rows' written values (`frame_ms` as the
//! CSV rounds it, `rel_rmse`), so `--merge` recomputes exactly the front a single run
//! writes, ties included.

use super::Row;

/// The Pareto front of points `(time, error)`, both smaller-is-better: `front[i]` is true
/// when no other point is at least as good in both and strictly better in one. Equal
/// points are all on the front. NaN points are never on it and dominate nothing.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(t, e)| {
            !t.is_nan()
                && !e.is_nan()
                && !points
                    .iter()
                    .any(|&(t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .collect()
}

/// Sorts rows by index and sets their `pareto` flags over (frame_ms, rel_rmse).
pub fn finish_rows(rows: &mut [Row]) {
    rows.sort_by_key(|r| r.config.index);
    let pts: Vec<(f64, f64)> = rows.iter().map(|r| (r.frame_ms, r.rel_rmse)).collect();
    for (r, p) in rows.iter_mut().zip(pareto_front(&pts)) {
        r.pareto = p;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_basic() {
        // (time, error)
        let pts = [
            (1.0, 10.0), // front: fastest
            (2.0, 5.0),  // front
            (3.0, 5.0),  // dominated by (2, 5)
            (4.0, 1.0),  // front: most accurate
            (5.0, 2.0),  // dominated by (4, 1)
            (2.0, 5.0),  // equal to a front point: also on it
            (f64::NAN, 0.1),
        ];
        assert_eq!(
            pareto_front(&pts),
            vec![true, true, false, true, false, true, false]
        );
        assert!(pareto_front(&[]).is_empty());
        assert_eq!(pareto_front(&[(1.0, 1.0)]), vec![true]);
    }

    #[test]
    fn pareto_front_is_not_dominated_and_dominates_the_rest() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64::seed_from_u64(5);
        let pts: Vec<(f64, f64)> = (0..300)
            .map(|_| (rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0)))
            .collect();
        let front = pareto_front(&pts);
        for (i, &(t, e)) in pts.iter().enumerate() {
            let dominated = pts
                .iter()
                .any(|&(t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e));
            assert_eq!(front[i], !dominated);
        }
        assert!(front.iter().any(|&f| f));
    }
}
