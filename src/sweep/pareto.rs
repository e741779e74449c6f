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

/// The relative RMSE bound of [`fastest_within`] at which the environment methods'
/// defaults are picked ([`crate::scene::env_method`]): 1%.
pub const ERROR_BOUND: f64 = 0.01;

/// The fastest row with `rel_rmse <= bound` (ties in `frame_ms`: the smaller error, then
/// the smaller index), `None` when no row meets the bound. Such a row is always on the
/// Pareto front: a row dominating it would be at least as fast and at least as accurate,
/// so it would meet the bound too and be the one chosen. This is the row a material
/// class's default method is picked from (`bound` = [`ERROR_BOUND`], with `brdfkit sweep
/// --max-p99` also bounding the 99th percentile: [`crate::scene::env_method`]).
pub fn fastest_within(rows: &[Row], bound: f64) -> Option<&Row> {
    rows.iter()
        .filter(|r| r.rel_rmse <= bound && !r.frame_ms.is_nan())
        .min_by(|a, b| {
            a.frame_ms
                .total_cmp(&b.frame_ms)
                .then(a.rel_rmse.total_cmp(&b.rel_rmse))
                .then(a.config.index.cmp(&b.config.index))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(points: &[(f64, f64)]) -> Vec<Row> {
        use crate::sweep::{Config, MethodAxis};
        points
            .iter()
            .enumerate()
            .map(|(index, &(frame_ms, rel_rmse))| Row {
                config: Config {
                    index,
                    method: MethodAxis::Lights {
                        sampler: crate::env::schema::SamplerKind::Lloyd,
                        count: 1,
                    },
                    order: 0,
                    lookup: None,
                    precision: crate::scene::Precision::F32,
                },
                rel_rmse,
                max_err: 0.0,
                p99_rel: 0.0,
                flip_mean: 0.0,
                default: false,
                prep_ms: 0.0,
                frame_ms,
                pareto: false,
            })
            .collect()
    }

    #[test]
    fn fastest_within_the_bound() {
        // (time, error)
        let mut r = rows(&[
            (1.0, 0.5),   // fastest, too inaccurate
            (3.0, 0.009), // meets the bound
            (2.0, 0.011), // just over it
            (3.0, 0.004), // as fast as row 1, more accurate: the one
            (9.0, 0.001),
            (3.0, 0.004), // equal to row 3: the lower index wins
        ]);
        finish_rows(&mut r);
        let f = fastest_within(&r, ERROR_BOUND).unwrap();
        assert_eq!(f.config.index, 3);
        assert!(f.pareto);
        assert_eq!(fastest_within(&r, 1e-4), None);
        assert_eq!(fastest_within(&r, 1.0).unwrap().config.index, 0);
    }

    #[test]
    fn fastest_within_is_the_brute_force_choice_and_on_the_front() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64::seed_from_u64(9);
        for _ in 0..50 {
            let pts: Vec<(f64, f64)> = (0..60)
                .map(|_| {
                    // Coarse values, so ties in time and error happen.
                    (
                        rng.gen_range(1..20) as f64,
                        rng.gen_range(1..40) as f64 * 1e-3,
                    )
                })
                .collect();
            let mut r = rows(&pts);
            finish_rows(&mut r);
            let got = fastest_within(&r, ERROR_BOUND).map(|r| r.config.index);
            // Brute force: the smallest time among rows within the bound, then the
            // smallest error among those, then the smallest index.
            let ok: Vec<&Row> = r.iter().filter(|r| r.rel_rmse <= 0.01).collect();
            let want = ok
                .iter()
                .map(|r| r.frame_ms)
                .reduce(f64::min)
                .and_then(|t| {
                    let at_t: Vec<&&Row> = ok.iter().filter(|r| r.frame_ms == t).collect();
                    let e = at_t.iter().map(|r| r.rel_rmse).reduce(f64::min).unwrap();
                    at_t.iter()
                        .filter(|r| r.rel_rmse == e)
                        .map(|r| r.config.index)
                        .min()
                });
            assert_eq!(got, want);
            if let Some(i) = got {
                assert!(r[i].pareto, "row {i} is not on the front");
            }
        }
    }

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
