//! Merging shard CSVs (`brdfkit sweep --merge`): the rows of `--shard I/N` runs put back
//! together into exactly what one run writes, or an error naming the shard left out or
//! the row given twice.

use super::{finish_rows, read_csv, Row};
use crate::error::{Error, Result};
use std::path::PathBuf;

/// Merges shard CSVs into what one run writes: rows sorted by index, the Pareto column
/// recomputed over the union. A row index in two files is an error naming both files; a
/// gap in the row indices (a shard left out) is an error naming the missing rows.
pub fn merge(inputs: &[PathBuf]) -> Result<Vec<Row>> {
    let mut rows: Vec<(Row, usize)> = Vec::new();
    for (k, p) in inputs.iter().enumerate() {
        rows.extend(read_csv(p)?.into_iter().map(|r| (r, k)));
    }
    rows.sort_by_key(|(r, _)| r.config.index);
    for w in rows.windows(2) {
        if w[0].0.config.index == w[1].0.config.index {
            return Err(Error::format(
                &inputs[w[1].1],
                format!(
                    "row index {} is also in {} (the same row in two shards)",
                    w[1].0.config.index,
                    inputs[w[0].1].display()
                ),
            ));
        }
    }
    // Shard I of N holds the rows k with k % N == I, so a missing shard leaves a gap in the
    // indices (unless it held only the last rows of the grid, which a CSV cannot tell).
    if let Some((i, (r, _))) = rows
        .iter()
        .enumerate()
        .find(|(i, (r, _))| r.config.index != *i)
    {
        let shown: Vec<String> = inputs.iter().map(|p| p.display().to_string()).collect();
        return Err(Error::format(
            &inputs[0],
            format!(
                "rows {i} to {} are missing from the merge of {} (a shard left out?)",
                r.config.index - 1,
                shown.join(", ")
            ),
        ));
    }
    let mut rows: Vec<Row> = rows.into_iter().map(|(r, _)| r).collect();
    finish_rows(&mut rows);
    Ok(rows)
}
