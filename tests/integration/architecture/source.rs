//! Reading the crate's non-test code as the compiler sees it, for the architecture test: the
//! module tree from `src/lib.rs` down through its `mod` declarations (a `#[path]` honoured),
//! every file's tokens with comments, strings and `#[cfg(test)]` items left out, and every
//! `crate::`, `super::`, `self::` or child-module path in that code resolved to the file that
//! defines the item it names (following `use` re-exports).
//!
//! A `#[cfg(test)]` item is the attribute, the attributes after it and the item up to its
//! first `;` or its first balanced `{ ... }` at bracket depth 0 (a `use` item: up to its `;`),
//! so `#[cfg(test)] mod tests;` near the top of a file hides nothing after it.
//!
//! (Past 400 lines because it is one concept, the crate's code as the compiler's module tree
//! and name resolution see it: the lexer, the test-item filter, the module walk and the
//! path resolver are used only together, by this one test.)

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Tok {
    Ident(String),
    /// `::`
    Sep,
    Punct(char),
    /// A string, char or number literal (its text is not needed).
    Lit,
}

fn is_ident_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The tokens of `text`, comments and literals' contents left out.
pub fn tokens(text: &str) -> Vec<Tok> {
    let c: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        let ch = c[i];
        let next = c.get(i + 1).copied().unwrap_or('\0');
        if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && next == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && next == '*' {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if (ch == 'r' || ch == 'b') && (next == '"' || next == '#' || next == 'r') && {
            // A raw string r"..", r#".."#, br".." (not an identifier starting with r or b).
            let mut j = i + 1;
            if ch == 'b' && next == 'r' {
                j += 1;
            }
            while c.get(j) == Some(&'#') {
                j += 1;
            }
            c.get(j) == Some(&'"') && (ch == 'r' || next == 'r' || next == '"')
        } {
            let mut j = i + 1;
            if c[j] == 'r' {
                j += 1;
            }
            let mut hashes = 0;
            while c[j] == '#' {
                hashes += 1;
                j += 1;
            }
            j += 1; // the opening quote
            if hashes == 0 && ch == 'b' && c[i + 1] == '"' {
                // b"..": an ordinary byte string, with escapes.
                i = skip_string(&c, i + 1);
                out.push(Tok::Lit);
                continue;
            }
            loop {
                if c[j] == '"' && (0..hashes).all(|k| c.get(j + 1 + k) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            i = j;
            out.push(Tok::Lit);
        } else if ch == '"' {
            i = skip_string(&c, i);
            out.push(Tok::Lit);
        } else if ch == '\'' {
            // A char literal ('a', '\n', '\u{..}') or a lifetime ('a, 'static).
            if next == '\\' {
                let mut j = i + 2;
                while c[j] != '\'' {
                    j += 1;
                }
                i = j + 1;
                out.push(Tok::Lit);
            } else if c.get(i + 2) == Some(&'\'') {
                i += 3;
                out.push(Tok::Lit);
            } else {
                i += 1;
                while i < c.len() && is_ident_char(c[i]) {
                    i += 1;
                }
            }
        } else if ch == ':' && next == ':' {
            out.push(Tok::Sep);
            i += 2;
        } else if ch.is_ascii_digit() {
            while i < c.len() && (is_ident_char(c[i]) || c[i] == '.') {
                // `1..n`: a range is not part of the number.
                if c[i] == '.' && c.get(i + 1) == Some(&'.') {
                    break;
                }
                i += 1;
            }
            out.push(Tok::Lit);
        } else if is_ident_char(ch) {
            let start = i;
            while i < c.len() && is_ident_char(c[i]) {
                i += 1;
            }
            out.push(Tok::Ident(c[start..i].iter().collect()));
        } else {
            out.push(Tok::Punct(ch));
            i += 1;
        }
    }
    out
}

/// The index after the string literal whose opening quote is at `i`.
fn skip_string(c: &[char], i: usize) -> usize {
    let mut j = i + 1;
    while c[j] != '"' {
        if c[j] == '\\' {
            j += 1;
        }
        j += 1;
    }
    j + 1
}

fn ident(t: Option<&Tok>) -> Option<&str> {
    match t {
        Some(Tok::Ident(s)) => Some(s),
        _ => None,
    }
}

/// The index after the bracket group opened at `i` (`(`, `[` or `{`).
fn skip_group(t: &[Tok], i: usize) -> usize {
    let mut depth = 0i32;
    let mut j = i;
    while j < t.len() {
        match t[j] {
            Tok::Punct('(' | '[' | '{') => depth += 1,
            Tok::Punct(')' | ']' | '}') => {
                depth -= 1;
                if depth == 0 {
                    return j + 1;
                }
            }
            _ => {}
        }
        j += 1;
    }
    t.len()
}

/// Whether an attribute `#[cfg(test)]` starts at `i`.
fn is_cfg_test(t: &[Tok], i: usize) -> bool {
    let want = [
        Tok::Punct('#'),
        Tok::Punct('['),
        Tok::Ident("cfg".into()),
        Tok::Punct('('),
        Tok::Ident("test".into()),
        Tok::Punct(')'),
        Tok::Punct(']'),
    ];
    t.len() >= i + want.len() && t[i..i + want.len()] == want
}

/// `t` without its `#[cfg(test)]` items (module doc).
pub fn without_test_items(t: &[Tok]) -> Vec<Tok> {
    let mut out = Vec::with_capacity(t.len());
    let mut i = 0;
    while i < t.len() {
        if !is_cfg_test(t, i) {
            out.push(t[i].clone());
            i += 1;
            continue;
        }
        i += 7;
        // Further attributes of the same item.
        while t.get(i) == Some(&Tok::Punct('#')) && t.get(i + 1) == Some(&Tok::Punct('[')) {
            i = skip_group(t, i + 1);
        }
        let is_use = t[i..]
            .iter()
            .take_while(|k| !matches!(k, Tok::Punct(';' | '{')))
            .any(|k| *k == Tok::Ident("use".into()));
        let mut depth = 0i32;
        while i < t.len() {
            match t[i] {
                Tok::Punct('(' | '[') => depth += 1,
                Tok::Punct(')' | ']') => depth -= 1,
                Tok::Punct(';') if depth == 0 => {
                    i += 1;
                    break;
                }
                Tok::Punct('{') if depth == 0 && !is_use => {
                    i = skip_group(t, i);
                    break;
                }
                _ => {}
            }
            i += 1;
        }
    }
    out
}

/// One source file of the crate: its path under src/, its module path (`["shade", "tile"]`)
/// and its non-test tokens.
pub struct SourceFile {
    pub rel: String,
    pub module: Vec<String>,
    pub code: Vec<Tok>,
}

/// Every non-test source file of the crate under `src` (from lib.rs through `mod` items),
/// and every module (file or inline) -> the index of the file that holds it.
pub struct Crate {
    pub files: Vec<SourceFile>,
    pub modules: BTreeMap<Vec<String>, usize>,
    /// Per file, the crate paths written in its non-test code.
    pub paths: Vec<Vec<WrittenPath>>,
}

impl Crate {
    pub fn read(src: &Path) -> Crate {
        Crate::read_with(src, &BTreeMap::new())
    }

    /// [`Crate::read`] with the text of some files (by path under src/) replaced: how the
    /// seeded faults are planted without writing to the tree.
    pub fn read_with(src: &Path, replaced: &BTreeMap<String, String>) -> Crate {
        let mut c = Crate {
            files: Vec::new(),
            modules: BTreeMap::new(),
            paths: Vec::new(),
        };
        c.add_file(src, &src.join("lib.rs"), Vec::new(), true, replaced);
        c.paths = (0..c.files.len()).map(|f| c.paths_of(f)).collect();
        c
    }

    /// Reads file `path` as module `module`; `owns_dir`: its child modules' files sit beside
    /// it (lib.rs, mod.rs) rather than in a folder of its name.
    fn add_file(
        &mut self,
        src: &Path,
        path: &Path,
        module: Vec<String>,
        owns_dir: bool,
        replaced: &BTreeMap<String, String>,
    ) {
        let rel = path
            .strip_prefix(src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let text = match replaced.get(&rel) {
            Some(t) => t.clone(),
            None => {
                std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            }
        };
        let code = without_test_items(&tokens(&text));
        let index = self.files.len();
        let dir: PathBuf = if owns_dir {
            path.parent().unwrap().to_path_buf()
        } else {
            path.with_extension("")
        };
        self.modules.insert(module.clone(), index);
        // `mod NAME;` and inline `mod NAME { .. }` items, with the inline modules' nesting.
        let mut children = Vec::new();
        let mut inline: Vec<(Vec<String>, usize)> = Vec::new();
        let mut depth = 0usize;
        let mut path_attr: Option<String> = None;
        for (i, tok) in code.iter().enumerate() {
            match tok {
                Tok::Punct('{') => depth += 1,
                Tok::Punct('}') => {
                    depth -= 1;
                    if inline.last().is_some_and(|(_, d)| *d == depth) {
                        inline.pop();
                    }
                }
                Tok::Ident(k)
                    if k == "path"
                        && i >= 1
                        && code[i - 1] == Tok::Punct('[')
                        && code.get(i + 1) == Some(&Tok::Punct('=')) =>
                {
                    // The literal's text is gone: read it again from the source.
                    path_attr = Some(path_attribute(&text));
                }
                Tok::Ident(k) if k == "mod" => {
                    let Some(name) = ident(code.get(i + 1)) else {
                        continue;
                    };
                    let mut m = inline
                        .last()
                        .map(|(m, _)| m.clone())
                        .unwrap_or(module.clone());
                    m.push(name.to_string());
                    match code.get(i + 2) {
                        Some(Tok::Punct(';')) => {
                            let file = match path_attr.take() {
                                Some(p) => path.parent().unwrap().join(p),
                                None if dir.join(format!("{name}.rs")).exists() => {
                                    dir.join(format!("{name}.rs"))
                                }
                                None => dir.join(name).join("mod.rs"),
                            };
                            children.push((file, m));
                        }
                        Some(Tok::Punct('{')) => {
                            self.modules.insert(m.clone(), index);
                            inline.push((m, depth));
                        }
                        _ => {}
                    }
                }
                _ => {}
            }
        }
        self.files.push(SourceFile { rel, module, code });
        for (file, m) in children {
            let owns = file.file_name().is_some_and(|n| n == "mod.rs");
            self.add_file(src, &file, m, owns, replaced);
        }
    }

    /// The file (index) that defines what `path` names, seen from module `from`: the
    /// longest prefix that is a module, then any `use` of the next name in that module
    /// followed (`hops` at most). `None` outside the crate.
    fn resolve(&self, from: &[String], path: &[String], hops: usize) -> Option<usize> {
        let mut m: Vec<String> = match path.first().map(String::as_str) {
            Some("crate") => Vec::new(),
            Some("self") => from.to_vec(),
            Some("super") => from[..from.len().saturating_sub(1)].to_vec(),
            _ => return None,
        };
        let mut rest = &path[1..];
        while rest.first().is_some_and(|s| s == "super") {
            m.pop();
            rest = &rest[1..];
        }
        while let Some(seg) = rest.first() {
            let mut child = m.clone();
            child.push(seg.clone());
            if self.modules.contains_key(&child) {
                m = child;
                rest = &rest[1..];
            } else {
                break;
            }
        }
        let file = *self.modules.get(&m)?;
        if let (Some(name), true) = (rest.first(), hops > 0) {
            for (bound, target) in self.uses_in(file, &m) {
                if bound == *name {
                    if let Some(f) = self.resolve(&m, &target, hops - 1) {
                        return Some(f);
                    }
                }
            }
        }
        Some(file)
    }

    /// The names `use` items of file `file` bind in module `m` and the paths they bind,
    /// made absolute or `self`/`super`-relative (module doc).
    fn uses_in(&self, file: usize, m: &[String]) -> Vec<(String, Vec<String>)> {
        self.paths[file]
            .iter()
            .filter(|p| p.in_use && p.module == m)
            .map(|p| (p.bound.clone(), p.path.clone()))
            .collect()
    }

    /// Every crate path written in file `file`'s non-test code.
    fn paths_of(&self, file: usize) -> Vec<WrittenPath> {
        let f = &self.files[file];
        let t = &f.code;
        let mut out = Vec::new();
        let mut inline: Vec<(Vec<String>, usize)> = Vec::new();
        let mut depth = 0usize;
        let mut in_use = false;
        let mut i = 0;
        while i < t.len() {
            let module = inline
                .last()
                .map(|(m, _)| m.clone())
                .unwrap_or(f.module.clone());
            match &t[i] {
                Tok::Punct('{') => depth += 1,
                Tok::Punct('}') => {
                    depth -= 1;
                    if inline.last().is_some_and(|(_, d)| *d == depth) {
                        inline.pop();
                    }
                }
                Tok::Punct(';') => in_use = false,
                Tok::Ident(k) if k == "use" => in_use = true,
                Tok::Ident(k) if k == "mod" && t.get(i + 2) == Some(&Tok::Punct('{')) => {
                    let mut m = module.clone();
                    m.push(ident(t.get(i + 1)).unwrap().to_string());
                    inline.push((m, depth));
                    depth += 1;
                    i += 3;
                    continue;
                }
                _ => {}
            }
            let starts = i == 0 || t[i - 1] != Tok::Sep;
            let rooted = match &t[i] {
                Tok::Ident(s) if starts && t.get(i + 1) == Some(&Tok::Sep) => {
                    if s == "crate" || s == "self" || s == "super" {
                        Some(Vec::new())
                    } else {
                        let mut child = module.clone();
                        child.push(s.clone());
                        self.modules
                            .contains_key(&child)
                            .then(|| vec!["self".to_string()])
                    }
                }
                // `use {a::X, b::Y};` at the top of a use item: paths relative to the module.
                Tok::Punct('{') if in_use && t.get(i - 1) == Some(&Tok::Ident("use".into())) => {
                    Some(vec!["self".to_string()])
                }
                _ => None,
            };
            if let Some(prefix) = rooted {
                let (end, trees) = use_tree(t, i, prefix);
                for (path, bound) in trees {
                    out.push(WrittenPath {
                        module: module.clone(),
                        path,
                        bound,
                        in_use,
                    });
                }
                i = end;
                continue;
            }
            i += 1;
        }
        out
    }

    /// File -> (file it imports from -> the names imported), edges within a file left out.
    pub fn file_edges(&self) -> BTreeMap<usize, BTreeMap<usize, BTreeSet<String>>> {
        let mut g: BTreeMap<usize, BTreeMap<usize, BTreeSet<String>>> = BTreeMap::new();
        for file in 0..self.files.len() {
            let entry = g.entry(file).or_default();
            for p in &self.paths[file] {
                if let Some(to) = self.resolve(&p.module, &p.path, 8) {
                    if to != file {
                        let name = p.path.last().cloned().unwrap_or_default();
                        entry.entry(to).or_default().insert(name);
                    }
                }
            }
        }
        g
    }
}

/// The `"..."` of the first `#[path = "..."]` of `text`.
fn path_attribute(text: &str) -> String {
    let at = text.find("#[path").expect("a path attribute");
    let rest = &text[at..];
    let open = rest.find('"').unwrap() + 1;
    let close = open + rest[open..].find('"').unwrap();
    rest[open..close].to_string()
}

/// A path written in a file: the module it is written in, the path (from `crate`, `self`
/// or `super`), and, in a `use` item, the name it binds.
pub struct WrittenPath {
    pub module: Vec<String>,
    pub path: Vec<String>,
    pub bound: String,
    pub in_use: bool,
}

/// The paths of the path or use tree starting at `i` (an identifier or `{`), each with the
/// name it binds, after `prefix`; and the index after the tree.
fn use_tree(t: &[Tok], mut i: usize, prefix: Vec<String>) -> (usize, Vec<(Vec<String>, String)>) {
    let mut path = prefix;
    let mut out = Vec::new();
    loop {
        match t.get(i) {
            Some(Tok::Ident(s)) => {
                path.push(s.clone());
                i += 1;
                if t.get(i) == Some(&Tok::Sep) {
                    i += 1;
                    continue;
                }
                let mut bound = s.clone();
                if ident(t.get(i)) == Some("as") {
                    bound = ident(t.get(i + 1)).unwrap_or("_").to_string();
                    i += 2;
                }
                if bound == "self" {
                    path.pop();
                    bound = path.last().cloned().unwrap_or_default();
                }
                out.push((path, bound));
                return (i, out);
            }
            Some(Tok::Punct('{')) => {
                i += 1;
                while t.get(i).is_some_and(|k| *k != Tok::Punct('}')) {
                    if t[i] == Tok::Punct(',') {
                        i += 1;
                        continue;
                    }
                    let (end, inner) = use_tree(t, i, path.clone());
                    out.extend(inner);
                    i = end.max(i + 1);
                }
                return (i + 1, out);
            }
            Some(Tok::Punct('*')) => {
                // A glob: what it brings in is the module's.
                out.push((path.clone(), String::new()));
                return (i + 1, out);
            }
            _ => {
                if !path.is_empty() {
                    out.push((path.clone(), path.last().cloned().unwrap_or_default()));
                }
                return (i, out);
            }
        }
    }
}
