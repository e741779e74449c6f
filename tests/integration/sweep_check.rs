//! `brdfkit sweep --check CSV`: a stored sweep CSV whose deterministic columns (index ..
//! default) no longer match this build is reported row by row with exit 1; measured columns
//! never count. Small: 10 rows of the default scene at 32x24 (8 lights rows, 2 transfer rows
//! on a 32x17 table), the reference rendered once into a temporary cache and shared by every
//! run.
//! (.ci/sweep-check runs the same check on assets/readme/sweep.csv at its own size.)

use std::path::Path;
use std::process::Command;

const GRID: &[&str] = &[
    "--samplers",
    "lloyd,median-cut",
    "--counts",
    "16,128",
    "--orders",
    "8",
    "--transfer-grids",
    "32x17",
    "--exact-lights",
    "16",
    "--width",
    "32",
    "--height",
    "24",
];

struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

fn sweep(dir: &Path, extra: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_brdfkit"))
        .arg("sweep")
        .args(GRID)
        .args(["--frames", "1", "--cache"])
        .arg(dir.join("cache"))
        .args(extra)
        .current_dir(dir)
        .output()
        .unwrap();
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// `csv` with the field `column` (0-based) of the data line of row `index` replaced.
fn edit(csv: &str, index: usize, column: usize, value: &str) -> String {
    csv.lines()
        .map(|line| {
            let mut f: Vec<&str> = line.split(',').collect();
            if f[0] == index.to_string() {
                f[column] = value;
            }
            f.join(",") + "\n"
        })
        .collect()
}

#[test]
fn check_passes_on_a_fresh_csv_and_names_each_edited_deterministic_value() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let made = sweep(dir, &["-o", "stored.csv"]);
    assert_eq!(made.code, Some(0), "{}", made.stderr);
    let stored = std::fs::read_to_string(dir.join("stored.csv")).unwrap();
    assert_eq!(stored.lines().count(), 11, "header and 10 rows:\n{stored}");
    assert!(
        stored
            .lines()
            .nth(9)
            .unwrap()
            .starts_with("8,transfer,-,-,32,17,16,"),
        "{stored}"
    );

    // The CSV this build wrote: every row matches.
    let ok = sweep(dir, &["--check", "stored.csv"]);
    assert_eq!(ok.code, Some(0), "{}{}", ok.stdout, ok.stderr);
    assert!(ok.stdout.is_empty(), "{}", ok.stdout);
    assert!(
        ok.stderr.contains("10 of 10 rows (shard 0/1) match"),
        "{}",
        ok.stderr
    );

    // Measured columns (prep_ms 18, frame_ms 19, pareto 20) are not compared.
    let timed = edit(
        &edit(&edit(&stored, 2, 18, "999.000"), 2, 19, "0.001"),
        2,
        20,
        "0",
    );
    std::fs::write(dir.join("timed.csv"), timed).unwrap();
    let r = sweep(dir, &["--check", "timed.csv"]);
    assert_eq!(r.code, Some(0), "{}{}", r.stdout, r.stderr);

    // Seeded faults: one deterministic value edited (rel_rmse of row 5 by one ulp; flip_mean (column 16) of row 8, a transfer row), each found and named; a shard checks
    // only its rows.
    // One ulp up, written shortest (as the checker prints what it read): editing the last
    // decimal digit instead can give a string that reads back as a value printed otherwise
    // (0.14243876935926675 -> ...679, printed 0.1424387693592668).
    let rel: f64 = stored
        .lines()
        .nth(6)
        .unwrap()
        .split(',')
        .nth(13)
        .unwrap()
        .parse()
        .unwrap();
    let bumped = f64::from_bits(rel.to_bits() + 1).to_string();
    let edited = edit(&edit(&stored, 5, 13, &bumped), 8, 16, "0.5");
    std::fs::write(dir.join("edited.csv"), edited).unwrap();
    let r = sweep(dir, &["--check", "edited.csv"]);
    assert_eq!(r.code, Some(1), "{}{}", r.stdout, r.stderr);
    assert!(r.stdout.contains("row 5: stored     5,"), "{}", r.stdout);
    assert!(r.stdout.contains(&bumped), "{}", r.stdout);
    assert!(
        r.stdout.contains("row 8: stored     8,transfer,"),
        "{}",
        r.stdout
    );
    assert_eq!(
        r.stdout.lines().count(),
        4,
        "two rows, two lines each:\n{}",
        r.stdout
    );
    assert!(
        r.stderr
            .contains("8 of 10 rows (shard 0/1) match; 2 differ"),
        "{}",
        r.stderr
    );
    let shard = sweep(dir, &["--check", "edited.csv", "--shard", "1/2"]);
    assert_eq!(shard.code, Some(1), "{}", shard.stderr);
    assert!(shard.stdout.contains("row 5:") && !shard.stdout.contains("row 8:"));
    let shard = sweep(dir, &["--check", "edited.csv", "--shard", "2/4"]);
    assert_eq!(
        shard.code,
        Some(0),
        "rows 2 and 6 are untouched: {}",
        shard.stdout
    );

    // A row the CSV lacks is a difference too (a CSV from a smaller grid).
    let missing: String = stored
        .lines()
        .filter(|l| !l.starts_with("7,"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.join("missing.csv"), missing).unwrap();
    let r = sweep(dir, &["--check", "missing.csv"]);
    assert_eq!(r.code, Some(1));
    assert!(
        r.stdout.contains("row 7: not in the stored CSV"),
        "{}",
        r.stdout
    );
}
