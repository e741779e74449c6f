//! The pass rule of a comparison, bound by bound: what `brdfkit compare` prints on its
//! FAIL line and in `--json`, and what `golden check --device gpu` applies.
//!
//! Design rule: one list of bounds ([`Metrics::bounds`]) is the verdict; [`Metrics::passes`]
//! is "every bound holds", so the report, the JSON and the exit status cannot disagree.
//! A non-finite pixel fails first, and the FLIP bounds are then not evaluated (FLIP of a
//! NaN's display bytes measures nothing).

use super::{Metrics, Thresholds};

/// One bound of the pass rule and how the comparison stands against it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Bound {
    /// Stable name for scripts: `non_finite`, `flip_mean`, `flip_at_percentile`, the
    /// radiometric `mean_error`, `rel_rmse`, `rel_error_at_percentile`,
    /// `coverage_mismatch` (where set), and `alpha_` and the FLIP names for the alpha
    /// channel.
    pub measure: &'static str,
    /// How the report names it: "non-finite pixels", "FLIP mean", "FLIP p99", "alpha FLIP
    /// mean", ...
    pub label: String,
    /// The measured value (a count for `non_finite`, a share of the measured pixels for
    /// `coverage_mismatch`, a relative error for the radiometric bounds, FLIP in [0, 1]
    /// otherwise); `None` when not evaluated.
    pub value: Option<f64>,
    /// Largest passing value.
    pub limit: f64,
    /// `Some(true)` holds, `Some(false)` fails, `None` not evaluated (a FLIP bound while a
    /// pixel is not finite).
    pub passed: Option<bool>,
}

impl Bound {
    /// `label value > limit`, as the FAIL line names a failed bound.
    pub fn failure_text(&self) -> String {
        let value = self.value.map_or("n/a".to_string(), |v| v.to_string());
        format!("{} {value} > {}", self.label, self.limit)
    }
}

/// An f32 as the f64 of its shortest decimal form (0.01f32 -> 0.01, not 0.0099999997...),
/// so the JSON and the FAIL line show the number the user wrote or the report printed.
/// NaN and infinities stay themselves.
pub fn decimal(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(f64::NAN)
}

/// The percentile label: `p99` for 0.99, `p99.9` for 0.999.
pub fn percentile_label(p: f32) -> String {
    format!("p{}", decimal(p * 100.0))
}

impl Metrics {
    /// Every bound of the pass rule against `th`, in report order: no non-finite pixel,
    /// FLIP mean, FLIP at the percentile, the radiometric bounds `th` sets; then the FLIP
    /// bounds for the alpha channel when it is compared.
    pub fn bounds(&self, th: &Thresholds) -> Vec<Bound> {
        let mut radiometric = Vec::new();
        let finite = self.non_finite == 0;
        let r = &self.radiometric;
        let rb = &th.radiometric;
        for (measure, label, value, limit) in [
            (
                "mean_error",
                "mean error".to_string(),
                r.mean_error,
                rb.mean_error,
            ),
            (
                "rel_rmse",
                "relative RMSE".to_string(),
                r.rel_rmse,
                rb.rel_rmse,
            ),
            (
                "rel_error_at_percentile",
                format!("relative error {}", percentile_label(th.percentile)),
                r.rel_error_at_percentile,
                rb.rel_error_at_percentile,
            ),
            (
                "coverage_mismatch",
                "coverage mismatch".to_string(),
                self.coverage_mismatch_share(),
                rb.coverage_mismatch,
            ),
        ] {
            if let Some(limit) = limit {
                radiometric.push(Bound {
                    measure,
                    label,
                    value: finite.then_some(value),
                    limit: decimal(limit),
                    passed: finite.then_some(value <= decimal(limit)),
                });
            }
        }
        let mut out = Vec::new();
        let mut push =
            |prefix: &str, measure: [&'static str; 3], non_finite: usize, mean: f32, at: f32| {
                let finite = non_finite == 0;
                out.push(Bound {
                    measure: measure[0],
                    label: format!("{prefix}non-finite pixels"),
                    value: Some(non_finite as f64),
                    limit: 0.0,
                    passed: Some(finite),
                });
                for (m, label, value, limit) in [
                    (measure[1], "FLIP mean".to_string(), mean, th.flip_mean),
                    (
                        measure[2],
                        format!("FLIP {}", percentile_label(th.percentile)),
                        at,
                        th.flip_at_percentile,
                    ),
                ] {
                    out.push(Bound {
                        measure: m,
                        label: format!("{prefix}{label}"),
                        value: finite.then(|| decimal(value)),
                        limit: decimal(limit),
                        passed: finite.then_some(value <= limit),
                    });
                }
            };
        push(
            "",
            ["non_finite", "flip_mean", "flip_at_percentile"],
            self.non_finite,
            self.flip_mean,
            self.flip_at_percentile,
        );
        if let Some(a) = &self.alpha {
            push(
                "alpha ",
                [
                    "alpha_non_finite",
                    "alpha_flip_mean",
                    "alpha_flip_at_percentile",
                ],
                a.non_finite,
                a.flip_mean,
                a.flip_at_percentile,
            );
        }
        // After the colour's three bounds, before the alpha channel's.
        out.splice(3..3, radiometric);
        out
    }

    /// The bounds of [`Metrics::bounds`] that fail (not-evaluated ones are not listed:
    /// the non-finite bound that kept them from evaluation fails).
    pub fn failures(&self, th: &Thresholds) -> Vec<Bound> {
        self.bounds(th)
            .into_iter()
            .filter(|b| b.passed == Some(false))
            .collect()
    }

    /// Whether the comparison passes: every bound of [`Metrics::bounds`] holds.
    pub fn passes(&self, th: &Thresholds) -> bool {
        self.bounds(th).iter().all(|b| b.passed == Some(true))
    }
}
