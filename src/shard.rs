//! Shards: split a list of work items over the tasks of an array job.
//!
//! A shard is written `I/N`: shard `I` of `N`, **0-based** (`0 <= I < N`), so it takes a
//! scheduler's 0-based task id as it is. Item `k` (a sweep row's index, a turntable frame's
//! number) belongs to shard `k % N`. Every item belongs to exactly one shard, and a shard's
//! items are the same whatever machine runs it, so the shards' outputs merge into what one
//! run writes (`brdfkit sweep --merge`, `brdfkit render --turntable N --assemble`).
//!
//! A Slurm array job running a sweep as 4 shards and merging them:
//!
//! ```sh
//! #!/bin/sh
//! #SBATCH --array=0-3
//! #SBATCH --cpus-per-task=2
//! brdfkit sweep --shard "$SLURM_ARRAY_TASK_ID/4" -o "sweep-$SLURM_ARRAY_TASK_ID.csv"
//! ```
//!
//! then, after the array finishes (e.g. `sbatch --dependency=afterok:JOBID merge.sh`):
//!
//! ```sh
//! brdfkit sweep --merge sweep-0.csv sweep-1.csv sweep-2.csv sweep-3.csv -o sweep.csv --plot sweep.png
//! ```
//!
//! A still image the same way, by bands of rows ([`RowBands`]): `brdfkit render --shard
//! "$SLURM_ARRAY_TASK_ID/4" -o part_$SLURM_ARRAY_TASK_ID.exr` per task (band `b` of the
//! image to shard `b % N`), then `brdfkit render --merge part_*.exr -o full.exr`.
//!
//! A turntable the same way: `brdfkit render --turntable 120 --shard "$SLURM_ARRAY_TASK_ID/4"
//! -o spin.png` per task, then `brdfkit render --turntable 120 --assemble -o spin.png`.
//! (Give every shard the same shared reference cache, `--cache DIR`, or let the first task
//! fill it before the others start, so the reference is rendered once.)

use crate::error::{Error, Result};

/// Shard `index` of `count` (0-based): items `k` with `k % count == index`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// The one shard that holds every item.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `I/N` (0-based, `0 <= I < N`, `N >= 1`, decimal, surrounding spaces allowed).
    /// The error names `--shard`, the value and the rule.
    pub fn parse(s: &str) -> Result<Shard> {
        let bad = |why: &str| {
            Error::field(
                "--shard",
                format!("{s:?} {why} (expected I/N, 0-based: 0 <= I < N, e.g. 0/4 ... 3/4)"),
            )
        };
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| bad("is not of the form I/N"))?;
        let i: usize = i
            .trim()
            .parse()
            .map_err(|_| bad("has no whole number before the '/'"))?;
        let n: usize = n
            .trim()
            .parse()
            .map_err(|_| bad("has no whole number after the '/'"))?;
        if n == 0 {
            return Err(bad("has N = 0 shards"));
        }
        if i >= n {
            return Err(bad("has I >= N"));
        }
        Ok(Shard { index: i, count: n })
    }

    /// Whether item `k` belongs to this shard (`k % count == index`).
    pub fn contains(&self, k: usize) -> bool {
        k % self.count == self.index
    }

    /// Whether this is the single shard of everything (`0/1`).
    pub fn is_all(&self) -> bool {
        self.count == 1
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl std::str::FromStr for Shard {
    type Err = Error;
    fn from_str(s: &str) -> Result<Shard> {
        Shard::parse(s)
    }
}

/// The rows of a still image split into shards: bands of `rows` image rows, band `b` (rows
/// `b rows .. (b + 1) rows`, the last one shorter) to shard `b % N`. Interleaved bands keep
/// the shards' work even when the object fills only part of the frame. `rows` is a whole
/// number of the renderer's tiles (the renderer chooses it: `crate::render::shard_rows`), so
/// a shard shades whole tiles and its pixels are the unsharded render's bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowBands {
    pub shard: Shard,
    /// Image rows per band (at least 1).
    pub rows: u32,
}

impl RowBands {
    /// Whether image row `y` belongs to this shard.
    pub fn owns(&self, y: u32) -> bool {
        self.shard.contains((y / self.rows) as usize)
    }

    /// How many of the rows `0..height` belong to this shard.
    pub fn rows_owned(&self, height: u32) -> u32 {
        (0..height).filter(|&y| self.owns(y)).count() as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_zero_based() {
        assert_eq!(Shard::parse("0/1").unwrap(), Shard::ALL);
        assert_eq!(Shard::parse("2/3").unwrap(), Shard { index: 2, count: 3 });
        assert_eq!(
            Shard::parse(" 1 / 4 ").unwrap(),
            Shard { index: 1, count: 4 }
        );
        assert_eq!(Shard::parse("3/4").unwrap().to_string(), "3/4");
    }

    #[test]
    fn rejects_bad_specs() {
        for s in [
            "3/2", "2/2", "0/0", "x", "1", "/", "1/", "/2", "-1/2", "1/-2", "a/b", "1.5/2", "",
        ] {
            let e = Shard::parse(s).unwrap_err().to_string();
            assert!(e.starts_with("--shard: "), "{s:?}: {e}");
            assert!(!e.contains('\n'), "{s:?}: {e}");
        }
        assert!(Shard::parse("3/2")
            .unwrap_err()
            .to_string()
            .contains("I >= N"));
        assert!(Shard::parse("0/0")
            .unwrap_err()
            .to_string()
            .contains("N = 0"));
    }

    #[test]
    fn shards_partition_items() {
        for n in 1..6 {
            for k in 0..50 {
                let owners = (0..n)
                    .filter(|&i| Shard { index: i, count: n }.contains(k))
                    .count();
                assert_eq!(owners, 1, "item {k} of {n} shards");
            }
        }
    }

    #[test]
    fn row_bands_partition_rows() {
        for n in 1..5 {
            for rows in [1, 8, 32] {
                let total: u32 = (0..n)
                    .map(|i| {
                        RowBands {
                            shard: Shard { index: i, count: n },
                            rows,
                        }
                        .rows_owned(100)
                    })
                    .sum();
                assert_eq!(total, 100, "{n} shards of {rows}-row bands");
            }
        }
        let b = RowBands {
            shard: Shard { index: 1, count: 2 },
            rows: 8,
        };
        assert!(!b.owns(7) && b.owns(8) && b.owns(15) && !b.owns(16));
    }
}
