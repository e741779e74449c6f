//! Every repository path the docs name exists: README.md, docs/*.md, golden/README.md and
//! the comments of src/, tests/, benches/, examples/ and .ci/ name files (`src/scene/
//! env_method.rs`, `tests/integration/golden.rs`, `assets/probes/city.exr`) that a reader
//! opens next; a file moved or renamed leaves such a name behind, and nothing else notices.
//!
//! A path is a word that starts with one of [`ROOTS`] (not inside a longer path or a URL)
//! and runs over `[A-Za-z0-9_./-]`; a word with a placeholder (`golden/<name>.exr`,
//! `golden/NAME.exr`, `tests/*.rs`) is checked up to the placeholder. Paths in another project's tree are named
//! with the project (`mitsuba3`'s, `pbrt-v4`'s) and skipped: see [`EXTERNAL`].
//! `seeded_missing_paths_are_reported` shows the checker reports what it must.

use std::path::{Path, PathBuf};

/// The repository's top-level folders a doc names paths under.
const ROOTS: [&str; 10] = [
    "src/",
    "tests/",
    "docs/",
    "assets/",
    "golden/",
    "examples/",
    "benches/",
    "scripts/",
    "fuzz/",
    ".ci/",
];

/// Words that, found shortly before a path on its line, say it is another project's.
const EXTERNAL: [&str; 6] = ["mitsuba", "pbrt", "vello", "tiny-skia", "glam", "upstream"];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn is_path_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '/' | '-')
}

/// The repository paths named in `text`: (1-based line, path).
fn named_paths(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let chars: Vec<(usize, char)> = line.char_indices().collect();
        for (k, &(at, c)) in chars.iter().enumerate() {
            if k > 0 && (is_path_char(chars[k - 1].1) || chars[k - 1].1 == ':') {
                continue;
            }
            if !is_path_char(c) {
                continue;
            }
            let rest = &line[at..];
            if !ROOTS.iter().any(|r| rest.starts_with(r)) {
                continue;
            }
            let before = line[..at].to_ascii_lowercase();
            let near = &before[before.len().saturating_sub(40)..];
            if EXTERNAL.iter().any(|w| near.contains(w)) {
                continue;
            }
            let word: String = rest.chars().take_while(|&c| is_path_char(c)).collect();
            let word = word.trim_end_matches('.');
            // A glob or placeholder after a partial name (`closed_form_*.rs`): its folder.
            let word = match rest[word.len()..].chars().next() {
                Some('*' | '<' | '{') => &word[..word.rfind('/').map_or(0, |i| i + 1)],
                _ => word,
            };
            // Up to a placeholder component in capitals (`golden/NAME.exr`, `KEY.json`).
            let mut kept = String::new();
            for part in word.split_inclusive('/') {
                let stem = part.trim_end_matches('/').split('.').next().unwrap_or("");
                if !stem.is_empty() && stem.chars().all(|c| c.is_ascii_uppercase() || c == '_') {
                    break;
                }
                kept.push_str(part);
            }
            out.push((i + 1, kept));
        }
    }
    out
}

/// The paths of `text` (named `name` in messages) missing under `root`.
fn missing(name: &str, text: &str, root: &Path) -> Vec<String> {
    named_paths(text)
        .into_iter()
        .filter(|(_, p)| !root.join(p).exists())
        .map(|(line, p)| format!("{name}:{line}: {p}"))
        .collect()
}

/// Only the comment lines of a source file (`//`, `#`), so that paths built in code (a
/// temporary `golden/` copy, a test's output name) are not taken for references.
fn comments(text: &str, hash: bool) -> String {
    text.lines()
        .map(|l| {
            let t = l.trim_start();
            let keep = t.starts_with("//") || (hash && t.starts_with('#'));
            if keep {
                l
            } else {
                ""
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn files_under(dir: &Path, ext: &str, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = rd.map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            files_under(&p, ext, out);
        } else if p.extension().is_some_and(|e| e == ext) {
            out.push(p);
        }
    }
}

#[test]
fn every_repository_path_named_in_the_docs_exists() {
    let root = repo();
    let mut docs = vec![root.join("README.md"), root.join("golden/README.md")];
    files_under(&root.join("docs"), "md", &mut docs);
    let mut sources = Vec::new();
    for dir in ["src", "tests", "benches", "examples"] {
        files_under(&root.join(dir), "rs", &mut sources);
    }
    let mut scripts: Vec<PathBuf> = std::fs::read_dir(root.join(".ci"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    scripts.sort();
    let mut bad = Vec::new();
    let mut checked = 0;
    let rel = |p: &Path| p.strip_prefix(&root).unwrap().display().to_string();
    for p in &docs {
        let text = std::fs::read_to_string(p).unwrap();
        checked += named_paths(&text).len();
        bad.extend(missing(&rel(p), &text, &root));
    }
    for (files, hash) in [(&sources, false), (&scripts, true)] {
        for p in files {
            let text = comments(&std::fs::read_to_string(p).unwrap(), hash);
            checked += named_paths(&text).len();
            bad.extend(missing(&rel(p), &text, &root));
        }
    }
    eprintln!("{checked} path names checked");
    assert!(
        checked > 50,
        "only {checked} path names found: is the scanner broken?"
    );
    assert!(
        bad.is_empty(),
        "paths named that do not exist:\n{}",
        bad.join("\n")
    );
}

#[test]
fn seeded_missing_paths_are_reported() {
    let root = repo();
    let text = "See `src/lib.rs` and src/no/such.rs.\n\
                The old `tests/golden-gone.rs`, then golden/<name>.exr, golden/NAME.exr, tests/*.rs;\n\
                src/nowhere/x_*.rs is a glob; tests/integration/closed_form_*.rs matches some;\n\
                https://example.org/src/missing.rs is a URL, mitsuba3's `src/bsdfs/x.cpp` another's.\n";
    let got = missing("seed.md", text, &root);
    assert_eq!(
        got,
        [
            "seed.md:1: src/no/such.rs",
            "seed.md:2: tests/golden-gone.rs",
            "seed.md:3: src/nowhere/",
        ]
    );
    // Only comments of a source file are read.
    let code = "let p = \"golden/not-here.exr\";\n// but src/not-here.rs is named\n";
    assert_eq!(
        missing("x.rs", &comments(code, false), &root),
        ["x.rs:2: src/not-here.rs"]
    );
}

/// The places in `text` that cite a tracker's number (the word, an optional `s`, `#` or
/// space, then digits): (1-based line, the line). The work an issue asked for is described
/// in words; its number means nothing to a reader of the code.
fn issue_citations(text: &str) -> Vec<(usize, String)> {
    let word = concat!("iss", "ue");
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let lower = line.to_ascii_lowercase();
        let cited = lower.match_indices(word).any(|(at, _)| {
            let rest = lower[at + word.len()..].trim_start_matches('s');
            let rest = rest.trim_start_matches([' ', '#', '-', '_']);
            rest.starts_with(|c: char| c.is_ascii_digit())
        });
        if cited {
            out.push((i + 1, line.trim().to_string()));
        }
    }
    out
}

#[test]
fn no_code_doc_or_test_cites_an_issue_number() {
    let root = repo();
    let mut files = vec![root.join("README.md"), root.join("Cargo.toml")];
    for (dir, ext) in [
        ("docs", "md"),
        ("golden", "md"),
        ("golden", "toml"),
        ("assets", "md"),
        ("src", "rs"),
        ("src", "wgsl"),
        ("tests", "rs"),
        ("tests", "md"),
        ("benches", "rs"),
        ("examples", "rs"),
        ("scripts", "py"),
        ("fuzz", "rs"),
        ("fuzz", "md"),
    ] {
        files_under(&root.join(dir), ext, &mut files);
    }
    for e in std::fs::read_dir(root.join(".ci")).unwrap() {
        files.push(e.unwrap().path());
    }
    let mut bad = Vec::new();
    for p in &files {
        let Ok(text) = std::fs::read_to_string(p) else {
            continue;
        };
        for (line, l) in issue_citations(&text) {
            bad.push(format!(
                "{}:{line}: {l}",
                p.strip_prefix(&root).unwrap().display()
            ));
        }
    }
    assert!(
        files.len() > 100,
        "only {} files scanned: is the walk broken?",
        files.len()
    );
    assert!(bad.is_empty(), "issue numbers cited:\n{}", bad.join("\n"));
}

#[test]
fn seeded_issue_citations_are_reported() {
    let text = concat!(
        "a fix (iss",
        "ue 14, item 5)\n",
        "no number: the issue of speed\n",
        "Iss",
        "ues 14 and 15\n",
        "see iss",
        "ue #3\n",
    );
    let lines: Vec<usize> = issue_citations(text).into_iter().map(|(l, _)| l).collect();
    assert_eq!(lines, [1, 3, 4]);
}

#[test]
fn numbers_the_readme_states_are_the_codes() {
    // The README's counts and defaults, each rebuilt from the code: a default changed in
    // the code and not in the README fails here, naming the sentence to change.
    use brdfkit::env::schema::{
        EnvSpec, DEFAULT_CUT_ERROR, DEFAULT_EXACT_LIGHTS, DEFAULT_TRANSFER_AZIMUTH,
        DEFAULT_TRANSFER_POLAR,
    };
    let root = repo();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let entries = brdfkit::golden::load_manifest(&root.join("golden"))
        .unwrap()
        .entries
        .len();
    // The default sweep's rows: the default grid fitted to the default scene's material,
    // as `brdfkit sweep` fits it (methods the material cannot take are left out).
    let configurations = {
        use brdfkit::sweep::grid::Grid;
        let file = brdfkit::sweep::default_scene::default_scene_file().unwrap();
        let scene = brdfkit::scene::Scene::resolve(&file, &root).unwrap();
        let bands = scene.material.as_sh().map(|ds| ds.bands());
        let mut grid = Grid::default();
        grid.fit_material(bands, |m| {
            brdfkit::sweep::run::not_swept(m, &scene.material)
        })
        .unwrap();
        grid.len()
    };
    let spec: EnvSpec = toml::from_str("file = \"probe.exr\"").unwrap();
    let claims = [
        format!(
            "a {DEFAULT_TRANSFER_AZIMUTH} x {DEFAULT_TRANSFER_POLAR} transfer table + the \
             {DEFAULT_EXACT_LIGHTS} brightest texels"
        ),
        format!("light cuts at `cut_error = {DEFAULT_CUT_ERROR}`"),
        format!("re-render the {entries} golden entries"),
        format!("run time against error, {configurations} configurations"),
        format!("({} {:?} lights by default)", spec.count, spec.sampler),
    ];
    let missing: Vec<&String> = claims
        .iter()
        .filter(|c| !readme.contains(c.as_str()))
        .collect();
    assert!(missing.is_empty(), "README.md no longer says: {missing:#?}");
}

#[test]
fn bench_flags_reach_criterion() {
    // `cargo bench -- --warm-up-time 1` (docs/benchmarks.md) hands the flags to every bench
    // harness it runs: a libtest harness of the lib or bin target would reject them
    // ("Unrecognized option"), so those have `bench = false`, and every bench target is
    // criterion's (`harness = false`). CI does not build or run the benches: this reads the
    // manifest instead.
    let manifest: toml::Value =
        toml::from_str(&std::fs::read_to_string(repo().join("Cargo.toml")).unwrap()).unwrap();
    assert_eq!(
        manifest["lib"]["bench"].as_bool(),
        Some(false),
        "[lib] bench"
    );
    let bins = manifest["bin"].as_array().unwrap();
    assert!(!bins.is_empty());
    for b in bins {
        assert_eq!(b["bench"].as_bool(), Some(false), "[[bin]] {}", b["name"]);
    }
    let benches = manifest["bench"].as_array().unwrap();
    assert!(benches.len() >= 4, "{} bench targets", benches.len());
    for b in benches {
        assert_eq!(
            b["harness"].as_bool(),
            Some(false),
            "[[bench]] {}",
            b["name"]
        );
    }
}
