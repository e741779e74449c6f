//! Output paths are checked before the work starts: a wrong extension or an unwritable
//! directory gives exit 2 and one `brdfkit: error:` line naming the path, within a fraction
//! of a second of CPU time (the commands below are sized to take over a second of CPU if
//! they ran), and leaves no file behind. The bound is on CPU time, not wall time: a busy
//! machine delays a refused run but does not make it compute.

use std::path::{Path, PathBuf};
use std::time::Duration;

/// Bound on a refused run's CPU time (user + system, `common::Run::cpu`): start-up and
/// the checks take 7-30 ms (measured on a 2-core machine); each refused command below would
/// compute for over a second of CPU (render 4096x4096, acquire 10 bands, the default sweep)
/// before writing. `seeded_faults_fail_the_judge` measures the render.
const FAST: Duration = Duration::from_millis(150);

use crate::common;
use common::Run;

fn list(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = walk(dir);
    v.sort();
    v
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut v = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            v.extend(walk(&p));
        }
        v.push(p);
    }
    v
}

/// `brdfkit args` in `dir`, killed after 60 s.
fn brdfkit(dir: &Path, args: &[&str]) -> Run {
    common::brdfkit(dir).timeout(60).run(args)
}

/// What a refused output must look like; `Err` says what is wrong. Pure, so the seeded
/// faults below can show each clause fails.
fn judge(r: &Run, before: &[PathBuf], after: &[PathBuf], needles: &[&str]) -> Result<(), String> {
    if r.code != Some(2) {
        return Err(format!("exit {:?}, not 2 (stderr: {})", r.code, r.stderr));
    }
    if r.cpu > FAST {
        return Err(format!("took {:?} of CPU (bound {FAST:?})", r.cpu));
    }
    let lines: Vec<&str> = r.stderr.lines().collect();
    if lines.len() != 1 || !lines[0].starts_with("brdfkit: error: ") {
        return Err(format!("not one `brdfkit: error:` line: {lines:?}"));
    }
    for n in needles {
        if !lines[0].contains(n) {
            return Err(format!("{:?} does not mention {n:?}", lines[0]));
        }
    }
    if before != after {
        return Err(format!("files left behind: {before:?} -> {after:?}"));
    }
    Ok(())
}

fn refused(dir: &Path, args: &[&str], needles: &[&str]) -> Duration {
    let before = list(dir);
    let r = brdfkit(dir, args);
    let after = list(dir);
    if let Err(e) = judge(&r, &before, &after, needles) {
        panic!("{args:?}: {e}");
    }
    r.cpu
}

/// A small EXR image and a light probe (2:1) for `compare` and `lights` to read.
fn inputs(dir: &Path) {
    for (name, w, h) in [("a.exr", "8", "6"), ("probe.exr", "16", "8")] {
        let r = brdfkit(
            dir,
            &[
                "render", "--width", w, "--height", h, "--mesh", "sphere", "-o", name,
            ],
        );
        assert_eq!(r.code, Some(0), "{}", r.stderr);
    }
    std::fs::write(dir.join("file.txt"), "a regular file, not a directory").unwrap();
}

#[test]
fn wrong_extensions_are_refused_before_the_work() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    inputs(dir);
    let big = ["--width", "4096", "--height", "4096"];
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        (
            [&["render"][..], &big, &["-o", "x.jpg"]].concat(),
            vec!["x.jpg", "--output", ".png or .exr"],
        ),
        (
            [&["render"][..], &big, &["--turntable", "4", "-o", "t.exr"]].concat(),
            vec!["t.exr", "--output", "--turntable writes PNG", ".png"],
        ),
        (
            vec![
                "acquire",
                "lambert:albedo=0.5",
                "--bands",
                "10",
                "-o",
                "x.png",
            ],
            vec!["x.png", "--output", ".exr"],
        ),
        (
            vec!["fit-dbrdf", "lambert:albedo=0.5", "-o", "y.png"],
            vec!["y.png", "--output", ".exr"],
        ),
        (
            vec!["compare", "a.exr", "a.exr", "--diff", "d.jpg"],
            vec!["d.jpg", "--diff", ".png"],
        ),
        (
            vec!["lights", "probe.exr", "-o", "l.txt"],
            vec!["l.txt", "--output", ".json or .csv"],
        ),
        (
            vec!["lights", "probe.exr", "--overlay", "o.jpg"],
            vec!["o.jpg", "--overlay", ".png"],
        ),
        (
            vec!["sweep", "-o", "s.png"],
            vec!["s.png", "--output", ".csv"],
        ),
        (
            vec!["sweep", "-o", "s.csv", "--plot", "p.csv"],
            vec!["p.csv", "--plot", ".png"],
        ),
    ];
    for (args, needles) in &cases {
        let t = refused(dir, args, needles);
        eprintln!("{args:?}: refused in {t:?} of CPU");
    }
    // Case-insensitive: an upper-case extension is accepted and written.
    let r = brdfkit(
        dir,
        &["render", "--width", "4", "--height", "3", "-o", "UP.PNG"],
    );
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(dir.join("UP.PNG").is_file());
}

#[test]
fn unwritable_directories_are_refused_before_the_work() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    inputs(dir);
    // A path under a regular file: creating anything there fails (ENOTDIR), even as root.
    let cases: Vec<Vec<&str>> = vec![
        vec![
            "render",
            "--width",
            "4096",
            "--height",
            "4096",
            "-o",
            "file.txt/out.png",
        ],
        vec![
            "render",
            "--width",
            "4096",
            "--height",
            "4096",
            "-o",
            "file.txt/out.exr",
        ],
        vec![
            "render",
            "--width",
            "2048",
            "--height",
            "2048",
            "--turntable",
            "8",
            "-o",
            "file.txt/spin.png",
        ],
        vec![
            "acquire",
            "lambert:albedo=0.5",
            "--bands",
            "10",
            "-o",
            "file.txt/x.exr",
        ],
        vec!["fit-dbrdf", "lambert:albedo=0.5", "-o", "file.txt/y.exr"],
        // (compare --diff is not here: an unwritable diff is a warning, the verdict stands;
        // tests/integration/compare.rs.)
        vec!["lights", "probe.exr", "-o", "file.txt/l.json"],
        vec!["lights", "probe.exr", "--overlay", "file.txt/o.png"],
        vec!["sweep", "-o", "file.txt/s.csv"],
        vec!["sweep", "-o", "s.csv", "--plot", "file.txt/p.png"],
        // A directory that does not exist.
        vec![
            "render",
            "--width",
            "4096",
            "--height",
            "4096",
            "-o",
            "no/such/out.png",
        ],
    ];
    for args in &cases {
        let out = *args.last().unwrap();
        let t = refused(dir, args, &[out, "cannot create a file in"]);
        eprintln!("{args:?}: refused in {t:?} of CPU");
    }
    // An existing directory given as the output name.
    std::fs::create_dir(dir.join("d.png")).unwrap();
    refused(
        dir,
        &["render", "-o", "d.png"],
        &["d.png", "is a directory"],
    );
}

#[test]
fn seeded_faults_fail_the_judge() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let needles = ["x.png"];
    let error = |stderr: &str, code: i32, ms: u64| Run {
        code: Some(code),
        stdout: String::new(),
        stderr: stderr.to_string(),
        elapsed: Duration::from_millis(ms),
        cpu: Duration::from_millis(ms),
    };
    let line = "brdfkit: error: x.png: --output: wrong output format\n";
    let none: Vec<PathBuf> = vec![];
    judge(&error(line, 2, 10), &none, &none, &needles).unwrap();
    // Each fault alone fails.
    assert!(judge(&error(line, 0, 10), &none, &none, &needles).is_err());
    assert!(judge(&error(line, 2, 3700), &none, &none, &needles).is_err());
    assert!(judge(
        &error("brdfkit: error: bad\n", 2, 10),
        &none,
        &none,
        &needles
    )
    .is_err());
    let two = format!("{line}{line}");
    assert!(judge(&error(&two, 2, 10), &none, &none, &needles).is_err());
    assert!(judge(
        &error(line, 2, 10),
        &none,
        &[PathBuf::from("x.png")],
        &needles
    )
    .is_err());
    // A real run that does the work instead of refusing: exit 0, a file written.
    let before = list(dir);
    let r = brdfkit(
        dir,
        &["render", "--width", "4", "--height", "3", "-o", "x.png"],
    );
    let after = list(dir);
    assert!(judge(&r, &before, &after, &needles).is_err());
    // The CPU bound tells a refusal from the work: the render the refusals above skip (the
    // default scene at 4096x4096) costs more than the bound.
    let r = brdfkit(
        dir,
        &[
            "render", "--width", "4096", "--height", "4096", "-o", "work.png",
        ],
    );
    assert!(r.success(), "{}", r.stderr);
    eprintln!("render 4096x4096: {:?} of CPU", r.cpu);
    assert!(r.cpu > FAST, "the work took only {:?} of CPU", r.cpu);
    std::fs::remove_file(dir.join("work.png")).unwrap();
    // A late refusal: the output is fine, the input is found bad only after the output
    // check; the message does not name the output.
    std::fs::write(dir.join("junk.exr"), "not an EXR").unwrap();
    let before = list(dir);
    let r = brdfkit(dir, &["compare", "junk.exr", "junk.exr", "--diff", "x.png"]);
    let after = list(dir);
    assert!(judge(&r, &before, &after, &needles).is_err());
}
