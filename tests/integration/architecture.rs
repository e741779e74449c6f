//! The module layering of src/lib.rs's crate doc, checked on the source: no import cycle
//! between the crate's top-level modules, and no leaf module (conventions, the BRDF
//! models, the SH data sets, the material set) importing a module above it.
//!
//! An import is any `crate::NAME` path (or `crate::{NAME, ...}` group) in a module's
//! non-test code: `//` comment lines (doc links included), files named `tests.rs` or
//! `tests_*.rs`, and everything after a file's `#[cfg(test)]` are left out, since tests
//! may reach across layers. `cargo test --release --test integration architecture:: -- --nocapture` prints the graph.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

type Graph = BTreeMap<String, BTreeMap<String, BTreeSet<String>>>;

/// module -> (imported module -> files that import it).
fn import_graph(src: &Path) -> Graph {
    let mut g: Graph = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
                continue;
            }
            let rel = p
                .strip_prefix(src)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            if !rel.ends_with(".rs") || name == "tests.rs" || name.starts_with("tests_") {
                continue;
            }
            let top = rel
                .split('/')
                .next()
                .unwrap()
                .trim_end_matches(".rs")
                .to_string();
            if top == "lib" || top == "main" {
                continue;
            }
            let text = std::fs::read_to_string(&p).unwrap();
            let code = text.split("#[cfg(test)]").next().unwrap();
            let entry = g.entry(top.clone()).or_default();
            for line in code.lines().filter(|l| !l.trim_start().starts_with("//")) {
                for used in crate_paths(line) {
                    if used != top {
                        entry.entry(used).or_default().insert(rel.clone());
                    }
                }
            }
        }
    }
    g
}

/// The top-level module names a line reaches through `crate::`.
fn crate_paths(line: &str) -> Vec<String> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        if let Some(group) = after.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let name = ident(item.trim());
                if !name.is_empty() {
                    out.push(name);
                }
            }
        } else {
            let name = ident(after);
            if !name.is_empty() {
                out.push(name);
            }
        }
        rest = after;
    }
    out
}

/// Every cycle's members (strongly connected components of more than one module, Tarjan).
fn cycles(g: &Graph) -> Vec<Vec<String>> {
    struct State<'a> {
        g: &'a Graph,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on: BTreeSet<&'a str>,
        next: usize,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        s.index.insert(v, s.next);
        s.low.insert(v, s.next);
        s.next += 1;
        s.stack.push(v);
        s.on.insert(v);
        if let Some(edges) = s.g.get(v) {
            for w in edges.keys() {
                let w = w.as_str();
                if !s.index.contains_key(w) {
                    visit(s, w);
                    let lw = s.low[w];
                    let lv = s.low.get_mut(v).unwrap();
                    *lv = (*lv).min(lw);
                } else if s.on.contains(w) {
                    let iw = s.index[w];
                    let lv = s.low.get_mut(v).unwrap();
                    *lv = (*lv).min(iw);
                }
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = s.stack.pop().unwrap();
                s.on.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                s.out.push(comp);
            }
        }
    }
    let mut s = State {
        g,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in g.keys() {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.out
}

/// What each leaf module may import (the layering of the crate doc, bottom up).
const LEAVES: [(&str, &[&str]); 5] = [
    ("conventions", &[]),
    ("error", &["image_io"]),
    ("brdf", &["conventions", "error", "image_io"]),
    ("sh", &["brdf", "conventions", "error", "image_io"]),
    // conventions: the cone bounds (material::cone_bound) read a D-BRDF table's angles.
    ("material", &["brdf", "conventions", "sh"]),
];

fn layering_violations(g: &Graph) -> Vec<String> {
    let mut v = Vec::new();
    for (module, allowed) in LEAVES {
        for (used, files) in g.get(module).into_iter().flatten() {
            if !allowed.contains(&used.as_str()) {
                v.push(format!("{module} imports {used} ({files:?})"));
            }
        }
    }
    v
}

fn src() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

#[test]
fn modules_form_no_import_cycle_and_leaves_stay_leaves() {
    let g = import_graph(&src());
    for (m, edges) in &g {
        println!("{m} -> {:?}", edges.keys().collect::<Vec<_>>());
    }
    assert!(g.len() > 15, "read too few modules: {:?}", g.keys());
    let c = cycles(&g);
    assert!(c.is_empty(), "import cycles between modules: {c:?}");
    let v = layering_violations(&g);
    assert!(v.is_empty(), "leaf modules importing upward: {v:#?}");
}

#[test]
fn seeded_cycles_and_upward_imports_are_caught() {
    // A brdf -> kernel hook (the cycle this layering removed) and a three-module ring.
    let mut g = import_graph(&src());
    let files = BTreeSet::from(["seeded".to_string()]);
    g.entry("brdf".into())
        .or_default()
        .insert("kernel".into(), files.clone());
    let c = cycles(&g);
    assert!(
        c.iter()
            .any(|comp| comp.contains(&"brdf".into()) && comp.contains(&"kernel".into())),
        "{c:?}"
    );
    assert!(!layering_violations(&g).is_empty());

    let mut ring = Graph::new();
    for (a, b) in [("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")] {
        ring.entry(a.into())
            .or_default()
            .insert(b.into(), files.clone());
    }
    assert_eq!(cycles(&ring), vec![vec!["a", "b", "c"]]);
    assert_eq!(
        crate_paths("use crate::{brdf::Brdf, sh::X}; crate::kernel::f()"),
        ["brdf", "sh", "kernel"]
    );
}
