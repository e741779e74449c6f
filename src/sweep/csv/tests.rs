//! Tests of the sweep CSV ([`super`]): exact text, header-keyed reading, and errors that
//! name the file, the line and the column. Expected text comes from the committed sweep
//! (assets/readme/sweep.csv) and from hand-written lines.

use super::*;

fn readme_csv() -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/readme/sweep.csv");
    std::fs::read_to_string(p).unwrap()
}

/// The first `n` lines of `text` with every line's fields reordered by `order`
/// (`order[k]` is the old position of new column `k`).
fn reorder(text: &str, n: usize, order: &[usize]) -> String {
    text.lines()
        .take(n)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            order.iter().map(|&k| f[k]).collect::<Vec<_>>().join(",") + "\n"
        })
        .collect()
}

fn parse_error(text: &str) -> String {
    match parse_csv(Path::new("shard-7.csv"), text.as_bytes()) {
        Ok(rows) => panic!("parsed {} rows of a bad CSV:\n{text}", rows.len()),
        Err(e) => e.to_string(),
    }
}

fn assert_mentions(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "{msg:?} does not mention {p:?}");
    }
}

fn lights_row() -> Row {
    Row {
        config: Config {
            index: 7,
            method: MethodAxis::Lights {
                sampler: SamplerKind::MedianCut,
                count: 64,
            },
            order: 5,
            lookup: Some(Lookup::Bilinear),
            precision: Precision::F64,
        },
        rel_rmse: 0.012345678901234,
        max_err: 1.5e-3,
        p99_rel: 0.031,
        flip_mean: 0.0291,
        default: true,
        prep_ms: 1.2345,
        frame_ms: 83.0,
        pareto: true,
    }
}

#[test]
fn csv_round_trip() {
    let row = lights_row();
    let text = csv_text(std::slice::from_ref(&row));
    let line = text.lines().nth(1).unwrap();
    assert_eq!(
        line,
        "7,lights,median-cut,64,-,-,-,-,-,-,5,bilinear,f64,0.012345678901234,0.031,0.0015,0.0291,1,1.234,83.000,1"
    );
    let back = parse_csv(Path::new("t.csv"), text.as_bytes()).unwrap();
    assert_eq!(back.len(), 1);
    assert_eq!(back[0].config, row.config);
    assert_eq!(back[0].csv_line(), line);
    assert_eq!(
        back[0].deterministic_part(),
        "7,lights,median-cut,64,-,-,-,-,-,-,5,bilinear,f64,0.012345678901234,0.031,0.0015,0.0291,1"
    );
    // A transfer row: its parameters, `-` for the sampler's.
    let transfer = Row {
        config: Config {
            index: 900,
            method: MethodAxis::Transfer {
                azimuth: 64,
                polar: 33,
                exact_lights: 16,
            },
            ..row.config
        },
        ..row.clone()
    };
    let text = csv_text(std::slice::from_ref(&transfer));
    let line = text.lines().nth(1).unwrap();
    assert_eq!(
        line,
        "900,transfer,-,-,64,33,16,-,-,-,5,bilinear,f64,0.012345678901234,0.031,0.0015,0.0291,1,1.234,83.000,1"
    );
    let back = parse_csv(Path::new("t.csv"), text.as_bytes()).unwrap();
    assert_eq!(back[0].config, transfer.config);
    assert_eq!(back[0].csv_line(), line);
    // A reflection row: its grid and exact lights.
    let reflection = Row {
        config: Config {
            index: 1100,
            method: MethodAxis::Reflection {
                grid: 64,
                exact_lights: 16,
            },
            ..row.config
        },
        ..row.clone()
    };
    let text = csv_text(std::slice::from_ref(&reflection));
    let line = text.lines().nth(1).unwrap();
    assert_eq!(
        line,
        "1100,reflection,-,-,-,-,16,-,-,64,5,bilinear,f64,0.012345678901234,0.031,0.0015,0.0291,1,1.234,83.000,1"
    );
    let back = parse_csv(Path::new("t.csv"), text.as_bytes()).unwrap();
    assert_eq!(back[0].config, reflection.config);
    // Small and large errors keep Rust's positional form (no exponent), as `{}` writes.
    let tiny = Row {
        rel_rmse: 1e-9,
        max_err: 1e21,
        config: Config {
            lookup: None,
            ..row.config
        },
        ..row
    };
    assert_eq!(
        tiny.csv_line(),
        "7,lights,median-cut,64,-,-,-,-,-,-,5,-,f64,0.000000001,0.031,1000000000000000000000,0.0291,1,1.234,83.000,1"
    );
    // No rows: the header alone.
    assert_eq!(csv_text(&[]), format!("{CSV_HEADER}\n"));
}

/// A method's parameters must be given on its rows and `-` on every other method's.
#[test]
fn method_parameters_belong_to_their_method() {
    let line = |fields: &str| format!("{CSV_HEADER}\n{fields},0.5,0.6,0.1,0.01,0,1.000,2.000,0\n");
    // Good rows, for reference.
    for ok in [
        "0,lights,lloyd,128,-,-,-,-,-,-,8,bilinear,f32",
        "1,transfer,-,-,128,65,16,-,-,-,8,bilinear,f32",
        "2,transfer,-,-,32,17,0,-,-,-,0,-,f32",
        "3,lightcuts,-,-,-,-,-,0.01,1000,-,0,-,f32",
        "4,reflection,-,-,-,-,64,-,-,64,0,-,f32",
    ] {
        parse_csv(Path::new("ok.csv"), line(ok).as_bytes()).unwrap();
    }
    for (fields, says) in [
        (
            "0,lights,-,128,-,-,-,-,-,-,8,bilinear,f32",
            "column sampler: a lights row needs a sampler",
        ),
        (
            "0,lights,lloyd,-,-,-,-,-,-,-,8,bilinear,f32",
            "column lights: a lights row needs a lights",
        ),
        (
            "0,lights,lloyd,128,64,-,-,-,-,-,8,bilinear,f32",
            "column transfer_azimuth: a lights row has no transfer_azimuth",
        ),
        (
            "1,transfer,lloyd,-,128,65,16,-,-,-,8,bilinear,f32",
            "column sampler: a transfer row has no sampler",
        ),
        (
            "1,transfer,-,-,128,-,16,-,-,-,8,bilinear,f32",
            "column transfer_polar: a transfer row needs a transfer_polar",
        ),
        (
            "1,transfer,-,-,128,65,16,0.01,-,-,8,bilinear,f32",
            "column cut_error: a transfer row has no cut_error",
        ),
        (
            "0,lights,lloyd,128,-,-,-,-,64,-,8,bilinear,f32",
            "column cut_max: a lights row has no cut_max",
        ),
        (
            "0,lightcuts,-,-,-,-,-,-,64,-,0,-,f32",
            "column cut_error: a lightcuts row needs a cut_error",
        ),
        (
            "0,lightcuts,lloyd,-,-,-,-,0.01,64,-,0,-,f32",
            "column sampler: a lightcuts row has no sampler",
        ),
        (
            "4,reflection,-,-,-,-,64,-,-,-,0,-,f32",
            "column reflection_grid: a reflection row needs a reflection_grid",
        ),
        (
            "4,reflection,-,-,128,-,64,-,-,64,0,-,f32",
            "column transfer_azimuth: a reflection row has no transfer_azimuth",
        ),
        (
            "3,lightcuts,-,-,-,-,-,0.01,1000,64,0,-,f32",
            "column reflection_grid: a lightcuts row has no reflection_grid",
        ),
        (
            "1,transfer,-,-,12x,65,16,-,-,-,8,bilinear,f32",
            "is not a number or -",
        ),
    ] {
        assert_mentions(
            &parse_error(&line(fields)),
            &["shard-7.csv", "line 2:", says],
        );
    }
}

/// A CSV written before the method axis (its header, one of its rows) is refused with a
/// message saying what it is and what to do, not read as lights rows (the module doc of
/// [`crate::sweep`] says why).
#[test]
fn a_csv_from_before_the_method_axis_is_refused_saying_so() {
    let old = "index,sampler,lights,order,lookup,precision,rel_rmse,max_err,flip_mean,default,prep_ms,frame_ms,pareto\n\
               831,lloyd,128,8,bilinear,f32,0.012713361556001786,0.0358,0.006,1,265.000,3.900,1\n";
    assert_mentions(
        &parse_error(old),
        &[
            "shard-7.csv",
            "line 1",
            "from before the method axis",
            "no method column",
            "regenerate it",
        ],
    );
}

/// A CSV written before the reflection method (no `reflection_grid` column) is refused,
/// saying what it is and what to do.
#[test]
fn a_csv_from_before_the_reflection_method_is_refused_saying_so() {
    let old = format!("{}\n", CSV_HEADER.replace(",reflection_grid", ""));
    assert_mentions(
        &parse_error(&old),
        &[
            "shard-7.csv",
            "line 1",
            "before the reflection method",
            "regenerate it",
        ],
    );
}

#[test]
fn the_header_is_the_record_schema() {
    assert_eq!(COLUMNS.join(","), CSV_HEADER);
    // serde's own header (the field names of `Record`, in declaration order).
    let mut w = ::csv::Writer::from_writer(Vec::new());
    w.serialize(Record::from(
        &parse_csv(Path::new("r.csv"), readme_csv().as_bytes()).unwrap()[0],
    ))
    .unwrap();
    let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
    assert_eq!(text.lines().next(), Some(CSV_HEADER));
    assert_eq!(
        CSV_HEADER.split(',').nth(DETERMINISTIC_COLUMNS - 1),
        Some("default")
    );
}

/// The committed sweep assets/readme/sweep.csv (1024 rows: 880 lights, 144 transfer) reads
/// and writes back to the same bytes.
#[test]
fn readme_sweep_reads_and_writes_back_byte_identical() {
    let text = readme_csv();
    let rows = parse_csv(Path::new("sweep.csv"), text.as_bytes()).unwrap();
    assert_eq!(rows.len(), 1024);
    let transfer = rows
        .iter()
        .filter(|r| r.config.method.kind() == MethodKind::Transfer)
        .count();
    assert_eq!(transfer, 144);
    assert_eq!(csv_text(&rows), text);
}

#[test]
fn reordered_columns_read_the_same() {
    let text = readme_csv();
    let rows = parse_csv(
        Path::new("a.csv"),
        reorder(&text, 40, &(0..21).collect::<Vec<_>>()).as_bytes(),
    )
    .unwrap();
    assert_eq!(rows.len(), 39);
    let reversed: Vec<usize> = (0..21).rev().collect();
    let moved = reorder(&text, 40, &reversed);
    assert!(moved.starts_with("pareto,frame_ms,"));
    let back = parse_csv(Path::new("b.csv"), moved.as_bytes()).unwrap();
    assert_eq!(back, rows);
    // Written back in the fixed column order.
    assert_eq!(
        csv_text(&back),
        reorder(&text, 40, &(0..21).collect::<Vec<_>>())
    );
}

#[test]
fn bad_columns_and_values_name_the_file_the_line_and_the_column() {
    let text = readme_csv();
    let all: Vec<usize> = (0..21).collect();
    let without = |k: usize| -> Vec<usize> { all.iter().copied().filter(|&i| i != k).collect() };
    // A missing column (pareto dropped from every line).
    assert_mentions(
        &parse_error(&reorder(&text, 3, &without(20))),
        &[
            "shard-7.csv",
            "line 1",
            "not a sweep CSV",
            "no column \"pareto\"",
        ],
    );
    // An unknown column, and a repeated one.
    let renamed = reorder(&text, 3, &all).replacen("max_err", "max_error", 1);
    assert_mentions(
        &parse_error(&renamed),
        &["shard-7.csv", "line 1", "unknown column \"max_error\""],
    );
    let mut twice = all.clone();
    twice.push(15);
    assert_mentions(
        &parse_error(&reorder(&text, 3, &twice)),
        &["shard-7.csv", "line 1", "\"max_err\" appears twice"],
    );
    assert_mentions(&parse_error(""), &["shard-7.csv", "line 1", "empty file"]);
    // A CSV from before the p99_rel column is named as such.
    // (Which had no reflection_grid column either.)
    let no_p99: Vec<usize> = all.iter().copied().filter(|&i| i != 9 && i != 14).collect();
    let no_p99 = reorder(&text, 3, &no_p99);
    assert_mentions(
        &parse_error(&no_p99),
        &[
            "shard-7.csv",
            "line 1",
            "before the p99_rel column",
            "regenerate",
        ],
    );
    // Bad values, in a CSV with its columns reversed: the column is named by header.
    let reversed: Vec<usize> = (0..21).rev().collect();
    let moved = reorder(&text, 4, &reversed);
    let mut lines: Vec<String> = moved.lines().map(str::to_string).collect();
    let set = |lines: &[String], line: usize, column: &str, value: &str| -> String {
        let k = lines[0].split(',').position(|h| h == column).unwrap();
        let mut out = lines.to_vec();
        let mut f: Vec<&str> = lines[line - 1].split(',').collect();
        f[k] = value;
        out[line - 1] = f.join(",");
        out.join("\n") + "\n"
    };
    for (line, column, value, says) in [
        (3, "rel_rmse", "zero", "is not a number"),
        (2, "index", "-1", "is not a whole number"),
        (4, "lights", "1.5", "is not a number or -"),
        (3, "method", "delta", "is not a method this build sweeps"),
        (2, "pareto", "2", "is not 0 or 1"),
        (3, "default", "yes", "is not 0 or 1"),
        (2, "sampler", "octahedral", "unknown sampler"),
        (3, "lookup", "trilinear", "unknown lookup"),
        (4, "precision", "f16", "unknown precision"),
    ] {
        let msg = parse_error(&set(&lines, line, column, value));
        assert_mentions(
            &msg,
            &[
                "shard-7.csv",
                &format!("line {line}:"),
                &format!("column {column}:"),
                value,
                says,
            ],
        );
    }
    // A line with a field missing.
    lines[2] = lines[2].rsplit_once(',').unwrap().0.to_string();
    assert_mentions(
        &parse_error(&(lines.join("\n") + "\n")),
        &["shard-7.csv", "line 3:", "20 fields, expected 21"],
    );
}
