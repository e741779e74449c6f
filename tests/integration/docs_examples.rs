//! Every TOML example in README.md and docs/*.md is a scene file the program accepts.
//!
//! Each ```` ```toml ```` block is parsed with [`SceneFile::parse`] (syntax, field names, types)
//! and then loaded with [`Scene::resolve`] against the directory of the Markdown file, so its
//! values are in range and the files it names (meshes, probes) exist where the example says.
//! `Scene::resolve` computes an `[env]`'s light set with no cache (tests/integration/no_hidden_state.rs),
//! so the test never reads or writes the user's cache.
//!
//! A block preceded by the line `<!-- docs_examples: parse-only -->` is only parsed: it
//! names a file the reader makes first (e.g. the output of `brdfkit acquire`).
//!
//! `checker_reports_each_seeded_fault` feeds the checker Markdown with known-bad blocks and
//! asserts that each is reported with its line.

use brdfkit::scene::{Scene, SceneFile};
use std::path::{Path, PathBuf};

const PARSE_ONLY: &str = "<!-- docs_examples: parse-only -->";

/// A fenced TOML block: 1-based line of its opening fence, its text, whether only parsed.
struct Block {
    line: usize,
    text: String,
    parse_only: bool,
}

/// The ```` ```toml ```` blocks of a Markdown text.
fn toml_blocks(markdown: &str) -> Vec<Block> {
    let mut blocks = Vec::new();
    let mut open: Option<Block> = None;
    let mut previous = "";
    for (i, line) in markdown.lines().enumerate() {
        let fence = line.trim_start();
        match open.take() {
            Some(b) if fence.starts_with("```") => blocks.push(b),
            Some(mut b) => {
                b.text.push_str(line);
                b.text.push('\n');
                open = Some(b);
            }
            None if fence.starts_with("```toml") => {
                open = Some(Block {
                    line: i + 1,
                    text: String::new(),
                    parse_only: previous.trim() == PARSE_ONLY,
                });
            }
            None => {}
        }
        if !line.trim().is_empty() {
            previous = line;
        }
    }
    assert!(open.is_none(), "unterminated ```toml block");
    blocks
}

/// Parses and loads one block; relative paths resolve against `base`.
fn check_block(block: &Block, base: &Path) -> Result<(), String> {
    let file = SceneFile::parse(&block.text)?;
    if block.parse_only {
        return Ok(());
    }
    Scene::resolve(&file, base).map_err(|e| e.to_string())?;
    Ok(())
}

/// Checks every block of `markdown`; returns the number of blocks and one message per
/// failing block, `NAME:LINE: error`. LINE is the Markdown line of a syntax or field error
/// ([`SceneFile::parse`] says `line K` of the block), else the block's opening fence.
fn check_markdown(name: &str, markdown: &str, base: &Path) -> (usize, Vec<String>) {
    let blocks = toml_blocks(markdown);
    let failures = blocks
        .iter()
        .filter_map(|b| {
            let e = check_block(b, base).err()?;
            let in_block = e.strip_prefix("line ").and_then(|rest| {
                let (k, msg) = rest.split_once(": ")?;
                Some((k.parse::<usize>().ok()?, msg))
            });
            Some(match in_block {
                Some((k, msg)) => format!("{name}:{}: {msg}", b.line + k),
                None => format!("{name}:{}: {e}", b.line),
            })
        })
        .collect();
    (blocks.len(), failures)
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// README.md and every docs/*.md, in name order.
fn markdown_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(repo().join("docs"))
        .expect("docs/ exists")
        .map(|e| e.expect("readable docs/ entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    files.sort();
    files.insert(0, repo().join("README.md"));
    files
}

#[test]
fn every_toml_example_in_the_docs_is_an_accepted_scene() {
    let mut failures = Vec::new();
    let mut counts = Vec::new();
    for path in markdown_files() {
        let name = path.strip_prefix(repo()).unwrap().display().to_string();
        let text = std::fs::read_to_string(&path).expect("readable Markdown");
        let (n, f) = check_markdown(&name, &text, path.parent().unwrap());
        println!("{name}: {n} TOML blocks, {} failing", f.len());
        counts.push((name, n));
        failures.extend(f);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The files that document the format must have examples for this test to check.
    for required in ["README.md", "docs/scene-format.md"] {
        let n = counts
            .iter()
            .find(|(name, _)| name == required)
            .map(|c| c.1);
        assert!(
            n.is_some_and(|n| n >= 2),
            "{required}: expected at least 2 TOML blocks, found {n:?}"
        );
    }
}

#[test]
fn checker_reports_each_seeded_fault() {
    let base = repo();
    let markdown = "\
# Seeded faults

```toml
[render]
width = 64
```

The README's old inline example, not TOML (a table header and keys on one line):

```toml
[env] file = \"assets/probes/city.exr\", sampler = \"lloyd\", count = 128
```

```toml
[render]
widht = 64
```

```toml
[render]
width = 0
```

```toml
[env]
file = \"assets/probes/no-such-probe.exr\"
```

```toml
[material]
kind = \"library\"
name = \"no-such-material\"
```

<!-- docs_examples: parse-only -->
```toml
[material]
kind = \"sh-file\"
path = \"made-by-the-reader.exr\"
```

<!-- docs_examples: parse-only -->
```toml
[material]
kind = \"sh-file\"
pth = \"typo-caught-even-when-parse-only.exr\"
```
";
    let (n, failures) = check_markdown("faults.md", markdown, &base);
    assert_eq!(n, 8, "blocks found");
    let lines: Vec<&str> = failures
        .iter()
        .map(|f| f.split(": ").next().unwrap())
        .collect();
    assert_eq!(
        lines,
        [
            "faults.md:11",
            "faults.md:16",
            "faults.md:19",
            "faults.md:24",
            "faults.md:29",
            // The `pth` line itself, not its table's header (an unknown field of
            // `[material]` is looked up by its key: crate::error::toml_message).
            "faults.md:46"
        ],
        "failures: {failures:#?}"
    );
    for (failure, words) in failures.iter().zip([
        "invalid table header",
        "widht",
        "render.width",
        "no-such-probe.exr",
        "no-such-material",
        "pth",
    ]) {
        assert!(failure.contains(words), "{failure:?} should name {words:?}");
    }
}
