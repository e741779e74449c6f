//! `golden check --shard I/N` and `golden bless --shard I/N`: the golden set spread over the
//! tasks of an array job, and the merges that make one verdict (check) or one manifest
//! (bless) of the shards' files.
//!
//! The entries are the selection (the names given, else every entry) in manifest order;
//! entry `k` of it belongs to shard `k % N` ([`crate::shard::Shard`]). Each shard's file
//! records the shard, the selection and the hash of the manifest it started from
//! ([`manifest_key`]); a merge refuses, with one line naming the file, a file of another
//! manifest or selection or split, a shard given twice, and names a shard that is missing.
//!
//! - **check**: a shard writes a JSON report ([`CheckReport`]: its outcomes and whether it
//!   passed); [`merge_check_reports`] joins them into the outcomes of the whole set, and
//!   the command exits as an unsharded check does (0 pass, 1 a failure, 2 unusable input).
//! - **bless**: a shard writes its own entries' images (distinct files per entry, so shards
//!   running at once never write the same file) and, instead of the manifest, its entries'
//!   records ([`BlessRecords`], TOML, the manifest's own encoding); [`merge_bless_records`]
//!   then writes each record into the manifest and the README table once. N shards and the
//!   merge leave the same golden/ as one `golden bless`.

use super::{bless_images, load_manifest, manifest_path, write_manifest, CheckOptions, Entry};
use super::{Manifest, Outcome};
use crate::error::{Error, Result};
use crate::hash::{self, StableHasher};
use crate::image_io;
use crate::shard::Shard;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// `format` of a check shard's report.
pub const CHECK_REPORT_FORMAT: &str = "brdfkit-golden-check-shard-v1";
/// `format` of a bless shard's records.
pub const BLESS_RECORDS_FORMAT: &str = "brdfkit-golden-bless-shard-v1";

/// The selection (`names`, else every entry, in manifest order) and the names of it that
/// `shard` takes (entry `k` of the selection to shard `k % N`).
pub fn shard_names(
    manifest: &Manifest,
    names: &[String],
    shard: Shard,
) -> (Vec<String>, Vec<String>) {
    let selection: Vec<String> = manifest
        .entries
        .iter()
        .filter(|e| names.is_empty() || names.contains(&e.name))
        .map(|e| e.name.clone())
        .collect();
    let mine = selection
        .iter()
        .enumerate()
        .filter(|(k, _)| shard.contains(*k))
        .map(|(_, n)| n.clone())
        .collect();
    (selection, mine)
}

/// The hash of `dir`'s manifest.toml as it is now ([`hash::tagged`] XXH3-64 of its bytes):
/// the shards of one run started from the same manifest.
pub fn manifest_key(dir: &Path) -> Result<String> {
    let p = manifest_path(dir);
    let bytes = std::fs::read(&p).map_err(|e| Error::io(&p, "cannot read", e))?;
    let mut h = StableHasher::new();
    h.write(&bytes);
    Ok(hash::tagged(h.finish()))
}

/// What every shard's file records, and a merge checks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardStamp {
    pub format: String,
    /// `I/N`, 0-based.
    pub shard: String,
    /// [`manifest_key`] when the shard started.
    pub manifest: String,
    /// The selection, in manifest order.
    pub selection: Vec<String>,
    /// The names of the selection this shard took.
    pub entries: Vec<String>,
}

/// A check shard's report (`golden check --shard I/N --json FILE`).
#[derive(Debug, Serialize, Deserialize)]
pub struct CheckReport {
    #[serde(flatten)]
    pub stamp: ShardStamp,
    /// The outcome of each of the shard's entries, in manifest order.
    pub outcomes: Vec<Outcome>,
    /// Entries whose fast-vs-reference bound (`--bounds`) failed.
    pub bounds_failed: Vec<String>,
    /// Every outcome passed and no bound failed.
    pub passed: bool,
}

/// A bless shard's records (`golden bless --shard I/N --records FILE`): the manifest
/// records of its entries as bless wrote them.
#[derive(Debug, Serialize, Deserialize)]
pub struct BlessRecords {
    #[serde(flatten)]
    pub stamp: ShardStamp,
    #[serde(rename = "entry", default)]
    pub records: Vec<Entry>,
}

/// The stamp of shard `shard` of `names` in `dir`, and the names it takes.
pub fn stamp(dir: &Path, names: &[String], shard: Shard, format: &str) -> Result<ShardStamp> {
    let manifest = load_manifest(dir)?;
    for n in names {
        Entry::find(&manifest, &manifest_path(dir), n)?;
    }
    let (selection, entries) = shard_names(&manifest, names, shard);
    Ok(ShardStamp {
        format: format.to_string(),
        shard: shard.to_string(),
        manifest: manifest_key(dir)?,
        selection,
        entries,
    })
}

/// Writes `value` as pretty JSON to `path`, atomically.
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<()> {
    let text = serde_json::to_string_pretty(value).expect("serialisable");
    image_io::write_atomically(path, |tmp| {
        std::fs::write(tmp, &text).map_err(|e| Error::io(path, "cannot write", e))
    })
}

/// `golden bless --shard`: blesses the shard's entries (images only; none when the shard
/// takes no entry) and writes their records to `records`.
pub fn bless_shard(
    dir: &Path,
    names: &[String],
    shard: Shard,
    opts: &CheckOptions,
    records: &Path,
) -> Result<Vec<PathBuf>> {
    let stamp = stamp(dir, names, shard, BLESS_RECORDS_FORMAT)?;
    let (manifest, written) = if stamp.entries.is_empty() {
        (load_manifest(dir)?, Vec::new())
    } else {
        bless_images(dir, &stamp.entries, opts)?
    };
    let records_list = manifest
        .entries
        .iter()
        .filter(|e| stamp.entries.contains(&e.name))
        .cloned()
        .collect();
    let doc = BlessRecords {
        stamp,
        records: records_list,
    };
    let text = toml::to_string_pretty(&doc).expect("serialisable");
    image_io::write_atomically(records, |tmp| {
        std::fs::write(tmp, &text).map_err(|e| Error::io(records, "cannot write", e))
    })?;
    Ok(written)
}

/// Checks that `stamps` (each with the file it was read from) are the N shards of one run,
/// each once, of `format`: a file of another format, manifest, selection or split, or a
/// shard given twice, is an error naming it; a missing shard an error naming the shard.
pub fn check_stamps(format: &str, stamps: &[(&Path, &ShardStamp)]) -> Result<()> {
    let Some((first_path, first)) = stamps.first() else {
        return Err(Error::field("--merge", "no shard files given"));
    };
    let parse = |path: &Path, s: &ShardStamp| {
        Shard::parse(&s.shard)
            .map_err(|_| Error::format(path, format!("shard: {:?} is not I/N", s.shard)))
    };
    let count = parse(first_path, first)?.count;
    let mut seen: Vec<Option<&Path>> = vec![None; count];
    for (path, s) in stamps {
        if s.format != format {
            return Err(Error::format(
                *path,
                format!("format {:?}, expected {format:?}: not merged", s.format),
            ));
        }
        let shard = parse(path, s)?;
        let other = |what: &str| {
            Err(Error::format(
                *path,
                format!(
                    "a shard of another {what} than {}: not merged",
                    first_path.display()
                ),
            ))
        };
        if shard.count != count {
            return other("split (N)");
        }
        if s.manifest != first.manifest {
            return other("manifest");
        }
        if s.selection != first.selection {
            return other("selection of entries");
        }
        if let Some(earlier) = seen[shard.index] {
            return Err(Error::format(
                *path,
                format!(
                    "shard {shard} given twice (also {}): not merged",
                    earlier.display()
                ),
            ));
        }
        seen[shard.index] = Some(path);
    }
    let missing: Vec<String> = (0..count)
        .filter(|&i| seen[i].is_none())
        .map(|i| format!("{i}/{count}"))
        .collect();
    if !missing.is_empty() {
        return Err(Error::field(
            "--merge",
            format!(
                "shard {} missing ({} of {count} files given): rerun that shard, then merge all {count}",
                missing.join(", "),
                stamps.len()
            ),
        ));
    }
    Ok(())
}

fn read_text(path: &Path) -> Result<String> {
    Ok(image_io::read_regular_text(path, 64 << 20, "shard file")?)
}

/// `golden check --merge REPORT...`: the reports checked ([`check_stamps`]) and their
/// outcomes in selection order, with the names of failed bounds and the verdict.
pub fn merge_check_reports(paths: &[PathBuf]) -> Result<(Vec<Outcome>, Vec<String>, bool)> {
    let reports = paths
        .iter()
        .map(|p| {
            let text = read_text(p)?;
            serde_json::from_str::<CheckReport>(&text)
                .map_err(|e| Error::format(p, format!("not a golden check shard report: {e}")))
        })
        .collect::<Result<Vec<_>>>()?;
    let stamps: Vec<_> = paths
        .iter()
        .map(PathBuf::as_path)
        .zip(reports.iter().map(|r| &r.stamp))
        .collect();
    check_stamps(CHECK_REPORT_FORMAT, &stamps)?;
    for (p, r) in paths.iter().zip(&reports) {
        let names: Vec<&String> = r.outcomes.iter().map(|o| &o.name).collect();
        if names != r.stamp.entries.iter().collect::<Vec<_>>() {
            return Err(Error::format(
                p,
                "its outcomes are not its entries (an interrupted or edited report): rerun that shard",
            ));
        }
    }
    let selection = reports[0].stamp.selection.clone();
    let mut outcomes = Vec::new();
    let mut bounds_failed = Vec::new();
    let mut passed = true;
    let mut all: Vec<Outcome> = Vec::new();
    for r in reports {
        passed &= r.passed;
        bounds_failed.extend(r.bounds_failed);
        all.extend(r.outcomes);
    }
    for name in &selection {
        if let Some(i) = all.iter().position(|o| &o.name == name) {
            outcomes.push(all.swap_remove(i));
        }
    }
    passed &= outcomes.iter().all(|o| o.passed) && bounds_failed.is_empty();
    Ok((outcomes, bounds_failed, passed))
}

/// `golden bless --merge RECORDS...`: the records checked ([`check_stamps`], and against
/// `dir`'s manifest, which must be the one the shards started from), written into the
/// manifest and the README table. Returns the entries' names.
pub fn merge_bless_records(dir: &Path, paths: &[PathBuf]) -> Result<Vec<String>> {
    let docs = paths
        .iter()
        .map(|p| {
            let text = read_text(p)?;
            toml::from_str::<BlessRecords>(&text)
                .map_err(|e| Error::format(p, format!("not golden bless shard records: {e}")))
        })
        .collect::<Result<Vec<_>>>()?;
    let stamps: Vec<_> = paths
        .iter()
        .map(PathBuf::as_path)
        .zip(docs.iter().map(|d| &d.stamp))
        .collect();
    check_stamps(BLESS_RECORDS_FORMAT, &stamps)?;
    let key = manifest_key(dir)?;
    if docs[0].stamp.manifest != key {
        return Err(Error::format(
            &paths[0],
            format!(
                "started from another {} (edited since the shards ran?): rerun the shards",
                manifest_path(dir).display()
            ),
        ));
    }
    let mut manifest = load_manifest(dir)?;
    let mut merged = Vec::new();
    for (p, d) in paths.iter().zip(docs) {
        let names: Vec<&String> = d.records.iter().map(|e| &e.name).collect();
        if names != d.stamp.entries.iter().collect::<Vec<_>>() {
            return Err(Error::format(
                p,
                "its records are not its entries: rerun that shard",
            ));
        }
        for rec in d.records {
            let slot = manifest
                .entries
                .iter_mut()
                .find(|e| e.name == rec.name)
                .expect("the manifest hash matched, so the entry is there");
            merged.push(rec.name.clone());
            *slot = rec;
        }
    }
    write_manifest(dir, &manifest)?;
    Ok(merged)
}
