//! `brdfkit sweep`: run time against error over a grid of configurations ([`crate::sweep`]).

use super::SweepArgs;
use crate::error::{Error, Result};
use crate::progress::Progress;
use crate::scene::{Precision, SceneFile};
use crate::sh::dataset::Lookup;
use crate::shard::Shard;
use crate::sweep::{self, Grid};
use std::path::{Path, PathBuf};

fn parse_lookups(v: &[String]) -> Result<Vec<Option<Lookup>>> {
    v.iter()
        .map(|s| match sweep::parse_lookup(s.trim()) {
            Some(Some(l)) => Ok(Some(l)),
            _ => Err(Error::field(
                "--lookups",
                format!("{s:?} is not a lookup (nearest, bilinear)"),
            )),
        })
        .collect()
}

fn parse_precisions(v: &[String]) -> Result<Vec<Precision>> {
    v.iter()
        .map(|s| match s.trim() {
            "f32" => Ok(Precision::F32),
            "f64" => Ok(Precision::F64),
            other => Err(Error::field(
                "--precisions",
                format!("{other:?} is not a precision (f32, f64)"),
            )),
        })
        .collect()
}

/// Parses `--transfer-grids` values `AZIMUTHxPOLAR`.
fn parse_transfer_grids(v: &[String]) -> Result<Vec<(usize, usize)>> {
    v.iter()
        .map(|s| {
            s.trim()
                .split_once('x')
                .and_then(|(a, p)| Some((a.parse().ok()?, p.parse().ok()?)))
                .ok_or_else(|| {
                    Error::field(
                        "--transfer-grids",
                        format!("{s:?} is not AZIMUTHxPOLAR (e.g. 64x33)"),
                    )
                })
        })
        .collect()
}

fn plot_title(rows: &[sweep::Row], what: &str) -> String {
    format!(
        "brdfkit sweep{what}: frame time against error ({} configurations)",
        rows.len()
    )
}

/// Prints the fastest row within 1% relative RMSE ([`sweep::fastest_within`]).
/// Prints the fastest row at `rel_rmse <= ERROR_BOUND` (and `p99_rel <= max_p99` when
/// given), with its errors.
fn report_fastest(rows: &[sweep::Row], what: &str, max_p99: Option<f64>) {
    let bound = sweep::ERROR_BOUND;
    let admitted: Vec<sweep::Row> = rows
        .iter()
        .filter(|r| max_p99.is_none_or(|q| r.p99_rel <= q))
        .cloned()
        .collect();
    let rule = match max_p99 {
        Some(q) => format!("rel_rmse <= {bound} and p99_rel <= {q}"),
        None => format!("rel_rmse <= {bound}"),
    };
    match sweep::fastest_within(&admitted, bound) {
        Some(r) => println!(
            "fastest at {rule}{what}: {} (row {}: {:.3} ms, rel_rmse {:.5}, p99_rel {:.4}, prep {:.0} ms)",
            sweep::describe(&r.config),
            r.config.index,
            r.frame_ms,
            r.rel_rmse,
            r.p99_rel,
            r.prep_ms
        ),
        None => {
            let best = rows.iter().min_by(|a, b| a.rel_rmse.total_cmp(&b.rel_rmse));
            println!(
                "fastest at {rule}{what}: none; the most accurate row is {}",
                best.map_or("-".into(), |r| format!(
                    "{} (row {}: {:.3} ms, rel_rmse {:.5}, p99_rel {:.4})",
                    sweep::describe(&r.config),
                    r.config.index,
                    r.frame_ms,
                    r.rel_rmse,
                    r.p99_rel
                ))
            );
        }
    }
}

/// `brdfkit sweep`; `Ok(false)` when `--check` finds rows that differ (exit 1).
pub fn run(a: SweepArgs) -> Result<bool> {
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("sweep.csv"));
    if let Some(q) = a.max_p99 {
        if !(q > 0.0 && q.is_finite()) {
            return Err(Error::field(
                "--max-p99",
                format!("{q} is out of range (a fraction > 0)"),
            ));
        }
    }
    // Read first: a bad --check file fails before the reference is rendered.
    let stored = match &a.check {
        Some(p) => Some(sweep::read_csv(p)?),
        None => {
            crate::image_io::check_output(&output, &["csv"], "--output")?;
            None
        }
    };
    if let Some(p) = &a.plot {
        crate::image_io::check_output(p, &["png"], "--plot")?;
    }
    // Names the class in the plot's title and the printed choice (with --merge too).
    let what = format!(
        "{}{}",
        a.class
            .map(|c| format!(", class {}", c.name()))
            .unwrap_or_default(),
        a.probe
            .as_ref()
            .map(|p| format!(", probe {p}"))
            .unwrap_or_default()
    );
    if !a.merge.is_empty() {
        let rows = sweep::merge(&a.merge)?;
        sweep::write_csv(&output, &rows)?;
        eprintln!(
            "wrote {} ({} rows from {} files)",
            output.display(),
            rows.len(),
            a.merge.len()
        );
        if let Some(p) = &a.plot {
            sweep::plot::write_plot(p, &rows, &plot_title(&rows, &what))?;
            eprintln!("wrote {}", p.display());
        }
        report_fastest(&rows, &what, a.max_p99);
        return Ok(true);
    }
    let shard = match &a.shard {
        Some(s) => Shard::parse(s)?,
        None => Shard::ALL,
    };
    let mut grid = a
        .class
        .map_or_else(Grid::default, sweep::MaterialClass::grid);
    if !a.methods.is_empty() {
        grid.methods = a.methods.clone();
    }
    if !a.transfer_grids.is_empty() {
        grid.transfer_grids = parse_transfer_grids(&a.transfer_grids)?;
    }
    if !a.cut_errors.is_empty() {
        grid.cut_errors = a.cut_errors.clone();
    }
    if !a.cut_maxes.is_empty() {
        grid.cut_maxes = a.cut_maxes.clone();
    }
    if !a.exact_lights.is_empty() {
        grid.exact_lights = a.exact_lights.clone();
    }
    if !a.reflection_grids.is_empty() {
        grid.reflection_grids = a.reflection_grids.clone();
    }
    if !a.samplers.is_empty() {
        grid.samplers = a.samplers.clone();
    }
    if !a.counts.is_empty() {
        grid.counts = a.counts.clone();
    }
    if !a.orders.is_empty() {
        grid.orders = a.orders.clone();
    }
    if !a.lookups.is_empty() {
        grid.lookups = parse_lookups(&a.lookups)?;
    }
    if !a.precisions.is_empty() {
        grid.precisions = parse_precisions(&a.precisions)?;
    }
    if a.frames == 0 || a.frames > 100 {
        return Err(Error::field(
            "--frames",
            format!("{} is out of range (1 to 100)", a.frames),
        ));
    }
    let (mut file, base) = match (&a.scene, a.class) {
        (Some(p), _) => (
            SceneFile::load(p)?,
            p.parent().map(Path::to_path_buf).unwrap_or_default(),
        ),
        (None, Some(c)) => (c.scene_file()?, PathBuf::from(".")),
        (None, None) => (sweep::default_scene_file()?, PathBuf::from(".")),
    };

    if let Some(probe) = &a.probe {
        let env = file
            .env
            .as_mut()
            .ok_or_else(|| Error::field("--probe", "the swept scene has no [env] to relight"))?;
        env.file = sweep::probe_path(probe)?;
    }
    if let Some(w) = a.width {
        file.render.width = w;
    }
    if let Some(h) = a.height {
        file.render.height = h;
    }
    if let Some(t) = a.threads {
        file.render.threads = t;
    }
    let cache = if a.no_cache {
        None
    } else {
        Some(
            a.cache
                .clone()
                .unwrap_or_else(|| PathBuf::from("target").join("brdfkit-cache")),
        )
    };
    let start = std::time::Instant::now();
    // A check compares no times: one frame per row.
    let frames = if stored.is_some() { 1 } else { a.frames };
    let sw = sweep::Sweep::prepare(file, &base, grid, cache.as_deref(), frames, |f, tiles| {
        eprintln!(
            "rendering the reference (full probe, f64; minutes for large probes){}",
            f.map(|f| format!(" into {}", f.display()))
                .unwrap_or_else(|| " (--no-cache: not stored)".into())
        );
        Progress::bar(tiles, "reference", "tiles")
    })?;
    for note in &sw.notes {
        eprintln!("note: {note}");
    }
    if let Some(why) = &sw.reference_rejected {
        eprintln!("warning: cached reference ignored and rewritten: {why}");
    }
    if let (false, Some(f)) = (sw.reference_rendered, &sw.reference_file) {
        eprintln!("reference: {} (cached)", f.display());
    }
    let configs = sw.configs(shard);
    eprintln!(
        "sweep: {} of {} configurations (shard {shard})",
        configs.len(),
        sw.grid.len()
    );
    let pb = Progress::bar(configs.len() as u64, "sweep", "rows");
    let rows = sw.run(&configs, |r| {
        pb.set_message(format!(
            "sweep {} o{}",
            r.config.method.label(),
            r.config.order
        ));
        pb.inc(1);
    });
    pb.finish();
    let mut rows = rows?;
    if let (Some(stored), Some(path)) = (&stored, &a.check) {
        let mismatches = sweep::deterministic_mismatches(stored, &rows);
        for line in &mismatches {
            println!("{line}");
        }
        let differing = mismatches.len();
        eprintln!(
            "check {}: {} of {} rows (shard {shard}) {}",
            path.display(),
            rows.len() - differing,
            rows.len(),
            if differing == 0 {
                "match this build in the deterministic columns".to_string()
            } else {
                format!("match; {differing} differ (regenerate it: see `brdfkit sweep --help`)")
            }
        );
        return Ok(differing == 0);
    }
    sweep::finish_rows(&mut rows);
    sweep::write_csv(&output, &rows)?;
    eprintln!(
        "wrote {} ({} rows, {:.1} s)",
        output.display(),
        rows.len(),
        start.elapsed().as_secs_f64()
    );
    if let Some(r) = rows.iter().find(|r| r.default) {
        eprintln!(
            "default configuration: {} ({})",
            r.csv_line(),
            if r.pareto {
                "on the Pareto front"
            } else {
                "dominated"
            }
        );
    }
    if shard.is_all() {
        report_fastest(&rows, &what, a.max_p99);
    }
    if let Some(p) = &a.plot {
        if shard.is_all() {
            sweep::plot::write_plot(p, &rows, &plot_title(&rows, &what))?;
            eprintln!("wrote {}", p.display());
        } else {
            eprintln!("--plot: skipped for a shard (plot the merged CSV: --merge ... --plot)");
        }
    }
    Ok(true)
}
