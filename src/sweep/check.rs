//! Checking a stored sweep CSV against what this build produces ([`deterministic_mismatches`],
//! `brdfkit sweep --check CSV`): the committed `assets/readme/sweep.csv` must not go stale.
//!
//! Design rule: only the deterministic columns are compared (`index` .. `default`, see the
//! module doc of [`crate::sweep`]), exactly: as the CSV writes them (Rust's shortest
//! round-trip form, [`Row::deterministic_part`]), so equal text is equal bits. The measured
//! columns (`prep_ms`, `frame_ms`, `pareto`) are never compared. A check re-renders any
//! subset of rows (a shard), so it can stay short: each fresh row is looked up by `index`.

use super::Row;

/// A fresh row whose deterministic columns differ from the stored row of its `index`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mismatch {
    pub index: usize,
    /// The stored row's deterministic columns; `None` when the CSV has no such row.
    pub stored: Option<String>,
    /// This build's.
    pub fresh: String,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let i = self.index;
        match &self.stored {
            None => write!(
                f,
                "row {i}: not in the stored CSV; this build {}",
                self.fresh
            ),
            Some(s) => write!(
                f,
                "row {i}: stored     {s}\nrow {i}: this build {}",
                self.fresh
            ),
        }
    }
}

/// The fresh rows whose deterministic columns differ from the stored row of the same
/// `index` (or that have no stored row), in the order of `fresh`; empty when all match.
/// Stored rows without a fresh counterpart (other shards) are not looked at.
pub fn deterministic_mismatches(stored: &[Row], fresh: &[Row]) -> Vec<Mismatch> {
    fresh
        .iter()
        .filter_map(|f| {
            let index = f.config.index;
            let fresh = f.deterministic_part();
            let stored = stored
                .iter()
                .find(|s| s.config.index == index)
                .map(Row::deterministic_part);
            (stored.as_ref() != Some(&fresh)).then_some(Mismatch {
                index,
                stored,
                fresh,
            })
        })
        .collect()
}
