//! The layering of src/lib.rs's crate doc, checked on the source: every top-level module
//! imports only modules of the layers before its own, as the crate doc's "Layering" list
//! states them (read from src/lib.rs, so the doc and the check cannot drift apart), with no
//! import cycle between modules and none between files.
//!
//! All non-test code is read, and only it ([`source`]): the module tree from src/lib.rs
//! through its `mod` items, with `#[cfg(test)]` items (and the files only they declare) left
//! out, item by item. An import is any path through `crate::`, `super::`, `self::` or a child
//! module, resolved to the file that defines the name (through `use` re-exports). A file and
//! the modules it declares are one unit of composition: a module's file re-exporting or
//! calling its own child modules is not a cycle with them; two sibling files that import
//! each other are. `cargo test --release --test integration architecture:: -- --nocapture`
//! prints the module graph.

mod source;

use source::Crate;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// module -> (imported module -> files that import it).
type Graph = BTreeMap<String, BTreeMap<String, BTreeSet<String>>>;

/// The top-level module graph of `c` (lib.rs and main.rs left out: they declare the
/// modules).
fn module_graph(c: &Crate) -> Graph {
    let top = |f: usize| c.files[f].module.first().cloned();
    let mut g = Graph::new();
    for (from, edges) in c.file_edges() {
        let Some(a) = top(from) else { continue };
        let entry = g.entry(a.clone()).or_default();
        for to in edges.keys() {
            if let Some(b) = top(*to) {
                if b != a {
                    entry
                        .entry(b)
                        .or_default()
                        .insert(c.files[from].rel.clone());
                }
            }
        }
    }
    g
}

/// The file graph of `c` (by path under src/) without a file's edges into the modules it
/// declares (module doc), with the names each edge imports.
fn file_graph(c: &Crate) -> Graph {
    let mut g = Graph::new();
    for (from, edges) in c.file_edges() {
        let entry = g.entry(c.files[from].rel.clone()).or_default();
        let m = &c.files[from].module;
        for (to, names) in edges {
            let inner = &c.files[to].module;
            if inner.len() > m.len() && inner.starts_with(m) {
                continue;
            }
            entry
                .entry(c.files[to].rel.clone())
                .or_default()
                .extend(names);
        }
    }
    g
}

/// Every cycle's members (strongly connected components of more than one node, Tarjan).
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

/// The crate doc's layers, first to last: the backticked module names of each numbered line
/// of its "Layering" section, before the line's first `: `.
fn doc_layers(lib_rs: &str) -> Vec<Vec<String>> {
    let mut layers = Vec::new();
    let mut inside = false;
    for line in lib_rs.lines() {
        let Some(doc) = line.strip_prefix("//!") else {
            continue;
        };
        let doc = doc.trim();
        if doc.starts_with("## ") {
            inside = doc == "## Layering";
            continue;
        }
        if !inside {
            continue;
        }
        let Some((num, rest)) = doc.split_once(". ") else {
            continue;
        };
        if num.is_empty() || !num.chars().all(|c| c.is_ascii_digit()) {
            continue;
        }
        let names = rest.split(": ").next().unwrap();
        let layer: Vec<String> = names
            .split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect();
        layers.push(layer);
    }
    layers
}

/// Imports against the crate doc's order that stand until the code moves, each with why
/// (none stands).
const EXCEPTIONS: [(&str, &str, &str); 0] = [];

/// The imports of `g` that go to a module of the same or a later layer than the importer's,
/// the [`EXCEPTIONS`] left out; and the modules no layer names.
fn layering_violations(g: &Graph, layers: &[Vec<String>]) -> Vec<String> {
    let rank: BTreeMap<&str, usize> = layers
        .iter()
        .enumerate()
        .flat_map(|(i, l)| l.iter().map(move |m| (m.as_str(), i)))
        .collect();
    let mut v = Vec::new();
    for (module, edges) in g {
        let Some(&r) = rank.get(module.as_str()) else {
            v.push(format!("{module} is in no layer of the crate doc"));
            continue;
        };
        for (used, files) in edges {
            let Some(&u) = rank.get(used.as_str()) else {
                continue;
            };
            let excepted = EXCEPTIONS.iter().any(|(a, b, _)| a == module && b == used);
            if u >= r && !excepted {
                v.push(format!(
                    "{module} (layer {}) imports {used} (layer {}): {files:?}",
                    r + 1,
                    u + 1
                ));
            }
        }
    }
    v
}

fn src() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn lib_rs() -> String {
    std::fs::read_to_string(src().join("lib.rs")).unwrap()
}

#[test]
fn modules_follow_the_crate_docs_layers_with_no_import_cycle() {
    let c = Crate::read(&src());
    let g = module_graph(&c);
    for (m, edges) in &g {
        println!("{m} -> {:?}", edges.keys().collect::<Vec<_>>());
    }
    assert!(c.files.len() > 150, "read too few files: {}", c.files.len());
    assert!(g.len() > 20, "read too few modules: {:?}", g.keys());
    let layers = doc_layers(&lib_rs());
    assert!(layers.len() >= 8, "the crate doc's layers: {layers:?}");
    for (a, b, why) in EXCEPTIONS {
        assert!(
            g.get(a).is_some_and(|e| e.contains_key(b)),
            "the exception {a} -> {b} ({why}) is gone: remove it"
        );
    }
    let v = layering_violations(&g, &layers);
    assert!(
        v.is_empty(),
        "imports against the crate doc's layers: {v:#?}"
    );
    let c_mod = cycles(&g);
    assert!(c_mod.is_empty(), "import cycles between modules: {c_mod:?}");
    let f = file_graph(&c);
    let c_file = cycles(&f);
    let shown: Vec<String> = c_file
        .iter()
        .map(|comp| {
            let mut s = comp.join(" <-> ");
            for a in comp {
                for (b, names) in &f[a] {
                    if comp.contains(b) {
                        s += &format!("\n  {a} -> {b}: {names:?}");
                    }
                }
            }
            s
        })
        .collect();
    assert!(
        c_file.is_empty(),
        "import cycles between files:\n{}",
        shown.join("\n")
    );
}

#[test]
fn test_code_is_skipped_item_by_item() {
    // A test module declared near the top hides nothing after it; test items are left out
    // whatever their shape.
    let text = concat!(
        "#[cfg(test)]\nmod tests;\n",
        "#[cfg(test)]\n#[allow(unused)]\nuse crate::kernel::A;\n",
        "#[cfg(test)]\nfn t() { let x = crate::kernel::B; }\n",
        "#[cfg(test)]\nconst C: [u8; 2] = [0; 2];\n",
        "pub fn after() -> u32 { crate::shade::D }\n",
        "// crate::kernel::InAComment\n",
        "const S: &str = \"crate::kernel::InAString\";\n",
        "#[cfg(test)]\nmod inline { use crate::kernel::E; }\n",
        "use crate::{sh::F, material::{G, H as I}};\n",
    );
    let code = source::without_test_items(&source::tokens(text));
    let written: Vec<String> = code
        .iter()
        .map(|t| match t {
            source::Tok::Ident(s) => s.clone(),
            source::Tok::Sep => "::".into(),
            source::Tok::Punct(c) => c.to_string(),
            source::Tok::Lit => "lit".into(),
        })
        .collect();
    let joined = written.join(" ");
    assert!(!joined.contains("kernel"), "{joined}");
    assert!(joined.contains("crate :: shade :: D"), "{joined}");
    assert!(joined.contains("H as I"), "{joined}");
}

#[test]
fn seeded_layering_violations_and_cycles_are_caught() {
    // An upward import (brdf -> kernel: the hook the layering removed) planted at the end of
    // src/brdf/mod.rs, below its `#[cfg(test)] mod tests_analytic;` near the top: caught.
    let brdf = std::fs::read_to_string(src().join("brdf/mod.rs")).unwrap();
    let top = brdf
        .find("#[cfg(test)]")
        .expect("brdf/mod.rs has a test module");
    let trait_at = brdf
        .find("pub trait Brdf")
        .expect("brdf/mod.rs has the trait");
    assert!(
        top < trait_at,
        "the test module is declared near the top of brdf/mod.rs, before the trait"
    );
    let seeded = format!("{brdf}\npub use crate::kernel::KERNEL_TOLERANCE as SEEDED;\n");
    let replaced = BTreeMap::from([("brdf/mod.rs".to_string(), seeded)]);
    let c = Crate::read_with(&src(), &replaced);
    let g = module_graph(&c);
    let layers = doc_layers(&lib_rs());
    let v = layering_violations(&g, &layers);
    assert!(
        v.iter()
            .any(|l| l.starts_with("brdf (layer") && l.contains("imports kernel")),
        "{v:#?}"
    );
    let c_mod = cycles(&g);
    assert!(
        c_mod
            .iter()
            .any(|comp| comp.contains(&"brdf".into()) && comp.contains(&"kernel".into())),
        "{c_mod:?}"
    );

    // A file-level cycle between two sibling files (shade/counts.rs <-> shade/view.rs), through
    // the parent's re-export: caught.
    let view = std::fs::read_to_string(src().join("shade/view.rs")).unwrap();
    let seeded = format!("{view}\n#[allow(unused)]\nuse super::ShadeCounts as SEEDED;\n");
    let mut replaced = BTreeMap::from([("shade/view.rs".to_string(), seeded)]);
    let counts = std::fs::read_to_string(src().join("shade/counts.rs")).unwrap();
    replaced.insert(
        "shade/counts.rs".into(),
        format!("{counts}\n#[allow(unused)]\nuse crate::shade::local_view as SEEDED;\n"),
    );
    let c = Crate::read_with(&src(), &replaced);
    let cf = cycles(&file_graph(&c));
    assert!(
        cf.contains(&vec!["shade/counts.rs".into(), "shade/view.rs".into()]),
        "{cf:?}"
    );

    // Tarjan on a ring with a tail.
    let files = BTreeSet::from(["seeded".to_string()]);
    let mut ring = Graph::new();
    for (a, b) in [("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")] {
        ring.entry(a.into())
            .or_default()
            .insert(b.into(), files.clone());
    }
    assert_eq!(cycles(&ring), vec![vec!["a", "b", "c"]]);
}

#[test]
fn the_crate_docs_layers_name_every_module_once() {
    let layers = doc_layers(&lib_rs());
    let named: Vec<&String> = layers.iter().flatten().collect();
    let unique: BTreeSet<&String> = named.iter().copied().collect();
    assert_eq!(
        named.len(),
        unique.len(),
        "a module named twice: {layers:?}"
    );
    let c = Crate::read(&src());
    let modules: BTreeSet<&String> = c.files.iter().filter_map(|f| f.module.first()).collect();
    assert_eq!(
        unique, modules,
        "the crate doc's layers and the crate's modules differ"
    );
}
