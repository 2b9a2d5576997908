//! ARCHITECTURE.md checked against the code: its layer tables (each module uses only the
//! modules its row names, every module has a row, each row names only modules above it) and
//! "no two files import each other".
//!
//! A file imports another where one of its paths (`crate::`, `super::`, `self::`, a child
//! module's name in a `mod.rs`, `ringlab::` and `ringlab_core::` from the binary), in a `use`
//! or in the code, names that file's module or an item in it. An item named through a
//! `mod.rs` that re-exports it (`pub use child::Item`) counts as an import of the file it comes
//! from, and such re-exports of a module's own children are not imports of theirs. Comments
//! and string literals are skipped. Std only: no parser crate, just tokens.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The three crates whose files are checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Krate {
    /// `ringlab-core` (crates/ringlab-core/src/lib.rs).
    Core,
    /// The app's library (src/lib.rs), which re-exports the core's modules.
    App,
    /// The `ringlab` binary (src/main.rs and src/cli/).
    Bin,
}

/// The core's modules the app's library re-exports under their own names.
const REEXPORTED: [&str; 7] =
    ["analysis", "config", "film", "physics", "plot", "recording", "report"];

#[derive(Clone, Debug, PartialEq, Eq)]
enum Tok {
    Ident(String),
    /// `::`
    Sep,
    Punct(char),
}

/// The tokens of Rust source, without comments, literals and lifetimes.
fn tokens(src: &str) -> Vec<Tok> {
    let c: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    let ident_char = |ch: char| ch.is_alphanumeric() || ch == '_';
    while i < c.len() {
        let ch = c[i];
        let next = c.get(i + 1).copied();
        if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && next == Some('/') {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && next == Some('*') {
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
        } else if ch == 'r' && (next == Some('#') || next == Some('"')) && raw_string_at(&c, i) {
            i = skip_raw_string(&c, i + 1);
        } else if ch == 'b' && next == Some('r') && raw_string_at(&c, i + 1) {
            i = skip_raw_string(&c, i + 2);
        } else if ch == '"' || (ch == 'b' && next == Some('"')) {
            i += if ch == 'b' { 2 } else { 1 };
            while i < c.len() && c[i] != '"' {
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
        } else if ch == '\'' || (ch == 'b' && next == Some('\'')) {
            let start = if ch == 'b' { i + 1 } else { i };
            // A char literal ('x', '\n', '\u{..}') or a lifetime ('a).
            if c.get(start + 1) == Some(&'\\') {
                i = start + 3;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if c.get(start + 2) == Some(&'\'') {
                i = start + 3;
            } else {
                i = start + 1;
                while i < c.len() && ident_char(c[i]) {
                    i += 1;
                }
            }
        } else if ch.is_ascii_digit() {
            while i < c.len()
                && (ident_char(c[i])
                    || c[i] == '.' && c.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
            {
                i += 1;
            }
        } else if ident_char(ch) {
            let start = i;
            while i < c.len() && ident_char(c[i]) {
                i += 1;
            }
            let word: String = c[start..i].iter().collect();
            out.push(Tok::Ident(word.trim_start_matches("r#").to_string()));
        } else if ch == ':' && next == Some(':') {
            out.push(Tok::Sep);
            i += 2;
        } else {
            out.push(Tok::Punct(ch));
            i += 1;
        }
    }
    out
}

/// Whether a raw string (`r"`, `r#"`) starts at `i` (the `r`).
fn raw_string_at(c: &[char], i: usize) -> bool {
    let mut j = i + 1;
    while c.get(j) == Some(&'#') {
        j += 1;
    }
    c.get(j) == Some(&'"') && (i == 0 || !(c[i - 1].is_alphanumeric() || c[i - 1] == '_'))
}

/// Past the raw string whose hashes start at `i`.
fn skip_raw_string(c: &[char], mut i: usize) -> usize {
    let mut hashes = 0;
    while c.get(i) == Some(&'#') {
        hashes += 1;
        i += 1;
    }
    i += 1;
    while i < c.len() {
        if c[i] == '"' && (1..=hashes).all(|k| c.get(i + k) == Some(&'#')) {
            return i + 1 + hashes;
        }
        i += 1;
    }
    i
}

/// A path as written: its segments (`*` for a glob) and the name it is known by here.
#[derive(Clone, Debug)]
struct Written {
    segs: Vec<String>,
    alias: Option<String>,
    /// Inside a `pub use`.
    reexport: bool,
    /// The inline modules (`mod tests { .. }`) it is written in.
    inline: Vec<String>,
}

/// The paths of a use tree starting at `tokens[i]` after `prefix`; returns them and the index
/// past the tree.
fn use_tree(
    t: &[Tok],
    mut i: usize,
    prefix: Vec<String>,
    out: &mut Vec<(Vec<String>, Option<String>)>,
) -> usize {
    let mut segs = prefix;
    loop {
        match t.get(i) {
            Some(Tok::Ident(w)) => {
                segs.push(w.clone());
                i += 1;
            }
            Some(Tok::Punct('*')) => {
                segs.push("*".into());
                out.push((segs, None));
                return i + 1;
            }
            Some(Tok::Punct('{')) => {
                i += 1;
                while i < t.len() && t[i] != Tok::Punct('}') {
                    if t[i] == Tok::Punct(',') {
                        i += 1;
                        continue;
                    }
                    i = use_tree(t, i, segs.clone(), out);
                }
                return i + 1;
            }
            _ => return i,
        }
        match (t.get(i), t.get(i + 1)) {
            (Some(Tok::Sep), Some(Tok::Punct('<'))) => break,
            (Some(Tok::Sep), _) => i += 1,
            (Some(Tok::Ident(a)), Some(Tok::Ident(alias))) if a == "as" => {
                // `self` inside a group names the group's prefix.
                if segs.last().is_some_and(|s| s == "self") {
                    segs.pop();
                }
                out.push((segs, Some(alias.clone())));
                return i + 2;
            }
            _ => break,
        }
    }
    if segs.last().is_some_and(|s| s == "self") {
        segs.pop();
    }
    out.push((segs, None));
    i
}

/// One source file: its crate, module path, children declared (`mod x;`) and paths written.
#[derive(Debug)]
struct File {
    krate: Krate,
    path: PathBuf,
    module: Vec<String>,
    children: BTreeSet<String>,
    written: Vec<Written>,
    /// Items it defines itself (`fn`, `struct`, ... at its top level or anywhere: a name is
    /// enough to tell a re-export from a definition).
    defines: BTreeSet<String>,
}

const PATH_STARTS: [&str; 5] = ["crate", "super", "self", "ringlab", "ringlab_core"];

fn parse_file(krate: Krate, path: &Path, module: Vec<String>) -> File {
    let src = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let t = tokens(&src);
    let mut children = BTreeSet::new();
    let mut defines = BTreeSet::new();
    // Declared children first: a bare path starting with one is a path into it.
    let mut depth = 0usize;
    for (k, tok) in t.iter().enumerate() {
        match tok {
            Tok::Punct('{') => depth += 1,
            Tok::Punct('}') => depth = depth.saturating_sub(1),
            Tok::Ident(w) if w == "mod" => {
                if let (Some(Tok::Ident(name)), Some(Tok::Punct(';'))) =
                    (t.get(k + 1), t.get(k + 2))
                    && depth == 0
                {
                    children.insert(name.clone());
                }
            }
            Tok::Ident(w)
                if matches!(
                    w.as_str(),
                    "fn" | "struct"
                        | "enum"
                        | "const"
                        | "static"
                        | "type"
                        | "trait"
                        | "union"
                        | "macro_rules"
                ) =>
            {
                if let Some(Tok::Ident(name)) = t.get(k + 1) {
                    defines.insert(name.clone());
                }
                if w == "macro_rules"
                    && let Some(Tok::Ident(name)) = t.get(k + 2)
                {
                    defines.insert(name.clone());
                }
            }
            _ => {}
        }
    }
    let mut written = Vec::new();
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < t.len() {
        match &t[i] {
            Tok::Punct('{') => {
                depth += 1;
                i += 1;
                continue;
            }
            Tok::Punct('}') => {
                depth = depth.saturating_sub(1);
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
                i += 1;
                continue;
            }
            Tok::Ident(w) if w == "mod" => {
                if let (Some(Tok::Ident(name)), Some(Tok::Punct('{'))) =
                    (t.get(i + 1), t.get(i + 2))
                {
                    inline.push((name.clone(), depth));
                    depth += 1;
                    i += 3;
                    continue;
                }
            }
            _ => {}
        }
        let after_sep = i > 0 && t[i - 1] == Tok::Sep;
        let is_use = matches!(&t[i], Tok::Ident(w) if w == "use");
        let reexport = is_use
            && i > 0
            && (matches!(&t[i - 1], Tok::Ident(p) if p == "pub")
                || (t[i - 1] == Tok::Punct(')')
                    && t.get(i.wrapping_sub(4)) == Some(&Tok::Ident("pub".into()))));
        let start = if is_use { i + 1 } else { i };
        let starts_path = match (t.get(start), t.get(start + 1)) {
            (Some(Tok::Ident(w)), Some(Tok::Sep)) => {
                !after_sep
                    && (PATH_STARTS.contains(&w.as_str())
                        || (inline.is_empty() && children.contains(w)))
            }
            (Some(Tok::Ident(w)), _) if is_use => inline.is_empty() && children.contains(w),
            (Some(Tok::Punct('{')), _) if is_use => true,
            _ => false,
        };
        if !starts_path {
            i += 1;
            continue;
        }
        let mut paths = Vec::new();
        let next = use_tree(&t, start, Vec::new(), &mut paths);
        for (segs, alias) in paths {
            let first = segs.first().map(String::as_str).unwrap_or("");
            if PATH_STARTS.contains(&first) || (inline.is_empty() && children.contains(first)) {
                written.push(Written {
                    segs,
                    alias,
                    reexport,
                    inline: inline.iter().map(|(n, _)| n.clone()).collect(),
                });
            }
        }
        i = next.max(i + 1);
    }
    File { krate, path: path.to_path_buf(), module, children, written, defines }
}

/// Every file of a crate, from its root by the `mod x;` declarations.
fn crate_files(krate: Krate, root: &Path, out: &mut Vec<File>) {
    fn walk(krate: Krate, path: &Path, module: Vec<String>, out: &mut Vec<File>) {
        let file = parse_file(krate, path, module.clone());
        let name = path.file_name().unwrap().to_str().unwrap();
        let dir = if matches!(name, "mod.rs" | "lib.rs" | "main.rs") {
            path.parent().unwrap().to_path_buf()
        } else {
            path.with_extension("")
        };
        let children = file.children.clone();
        out.push(file);
        for child in children {
            let flat = dir.join(format!("{child}.rs"));
            let nested = dir.join(&child).join("mod.rs");
            let p = if flat.exists() { flat } else { nested };
            assert!(p.exists(), "{}: mod {child}; has no file", path.display());
            let mut m = module.clone();
            m.push(child);
            walk(krate, &p, m, out);
        }
    }
    walk(krate, root, Vec::new(), out);
}

struct Tree {
    files: Vec<File>,
    by_module: BTreeMap<(Krate, Vec<String>), usize>,
}

impl Tree {
    fn load(root: &Path) -> Tree {
        let mut files = Vec::new();
        crate_files(Krate::Core, &root.join("crates/ringlab-core/src/lib.rs"), &mut files);
        crate_files(Krate::App, &root.join("src/lib.rs"), &mut files);
        crate_files(Krate::Bin, &root.join("src/main.rs"), &mut files);
        let by_module =
            files.iter().enumerate().map(|(i, f)| ((f.krate, f.module.clone()), i)).collect();
        Tree { files, by_module }
    }

    /// A written path as (crate, absolute segments), or None where it leaves the three crates.
    fn absolute(&self, f: &File, w: &Written) -> Option<(Krate, Vec<String>)> {
        let mut here: Vec<String> = f.module.iter().chain(&w.inline).cloned().collect();
        let mut segs = w.segs.as_slice();
        let mut krate = f.krate;
        match segs.first().map(String::as_str) {
            Some("crate") => {
                here.clear();
                segs = &segs[1..];
            }
            Some("ringlab") if f.krate == Krate::Bin => {
                krate = Krate::App;
                here.clear();
                segs = &segs[1..];
            }
            Some("ringlab_core") => {
                krate = Krate::Core;
                here.clear();
                segs = &segs[1..];
            }
            Some("self") => segs = &segs[1..],
            Some("super") => {
                while segs.first().is_some_and(|s| s == "super") {
                    here.pop()?;
                    segs = &segs[1..];
                }
            }
            Some(_) => {} // a child module of this one
            None => return None,
        }
        here.extend(segs.iter().cloned());
        if krate == Krate::App && here.first().is_some_and(|m| REEXPORTED.contains(&m.as_str())) {
            krate = Krate::Core;
        }
        Some((krate, here))
    }

    /// The file an absolute path leads to, through re-exports.
    fn target(&self, krate: Krate, segs: &[String], hops: usize) -> Option<usize> {
        let mut n = segs.len();
        let found = loop {
            if let Some(&i) = self.by_module.get(&(krate, segs[..n].to_vec())) {
                break i;
            }
            if n == 0 {
                return None;
            }
            n -= 1;
        };
        let file = &self.files[found];
        let Some(item) = segs.get(n) else { return Some(found) };
        if hops > 8 || file.defines.contains(item) || item == "*" {
            return Some(found);
        }
        // An item re-exported by this module: the file it comes from.
        for w in file.written.iter().filter(|w| w.reexport && w.inline.is_empty()) {
            let named = w.alias.as_deref().or(w.segs.last().map(String::as_str));
            let glob = w.segs.last().is_some_and(|s| s == "*");
            if named != Some(item.as_str()) && !glob {
                continue;
            }
            let Some((k, mut abs)) = self.absolute(file, w) else { continue };
            if glob {
                abs.pop();
                abs.push(item.clone());
            }
            if let Some(t) = self.target(k, &abs, hops + 1)
                && (!glob || self.files[t].defines.contains(item) || t != found)
            {
                return Some(t);
            }
        }
        Some(found)
    }

    /// Each file's imports of other files (indices), with one path that makes each.
    fn edges(&self) -> Vec<BTreeMap<usize, String>> {
        self.files
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let mut out = BTreeMap::new();
                for w in &f.written {
                    let Some((k, abs)) = self.absolute(f, w) else { continue };
                    // A module's re-exports of its own children are its face, not imports.
                    if w.reexport
                        && k == f.krate
                        && abs.starts_with(&f.module)
                        && abs.len() > f.module.len() + 1
                    {
                        continue;
                    }
                    if let Some(t) = self.target(k, &abs, 0)
                        && t != i
                    {
                        out.entry(t).or_insert_with(|| w.segs.join("::"));
                    }
                }
                out
            })
            .collect()
    }

    fn name(&self, i: usize) -> String {
        self.files[i].path.display().to_string()
    }
}

/// A layer table of ARCHITECTURE.md: its modules, lowest first, and what each row says it uses.
struct Layers {
    core: Vec<(String, BTreeSet<String>)>,
    app: Vec<(String, BTreeSet<String>)>,
}

fn layers(doc: &str) -> Layers {
    let section = doc.split("\n## Layers").nth(1).expect("ARCHITECTURE.md has ## Layers");
    let section = section.split("\n## ").next().unwrap();
    let mut core: Vec<(String, Vec<String>)> = Vec::new();
    let mut app: Vec<(String, Vec<String>)> = Vec::new();
    let mut table = None;
    for line in section.lines() {
        if line.starts_with("**Core**") {
            table = Some(0);
        } else if line.starts_with("**App**") {
            table = Some(1);
        }
        let Some(rest) = line.strip_prefix("| `") else { continue };
        let module = rest.split('`').next().unwrap().to_string();
        let cells: Vec<&str> = line.split('|').map(str::trim).filter(|c| !c.is_empty()).collect();
        let uses = cells.last().unwrap().split(',').map(|u| u.trim().to_string()).collect();
        match table {
            Some(0) => core.push((module, uses)),
            Some(_) => app.push((module, uses)),
            None => panic!("a layer row before **Core** or **App**: {line}"),
        }
    }
    let core_names: Vec<String> = core.iter().map(|(m, _)| m.clone()).collect();
    let all: Vec<String> = core_names.iter().chain(app.iter().map(|(m, _)| m)).cloned().collect();
    let expand = |uses: &[String]| -> BTreeSet<String> {
        let mut out = BTreeSet::new();
        for u in uses {
            match u.as_str() {
                "core" => out.extend(core_names.iter().cloned()),
                "everything" => out.extend(all.iter().cloned()),
                u if all.iter().any(|m| m == u) => {
                    out.insert(u.to_string());
                }
                _ => {} // an outside crate (nalgebra, egui, ...)
            }
        }
        out
    };
    Layers {
        core: core.iter().map(|(m, u)| (m.clone(), expand(u))).collect(),
        app: app.iter().map(|(m, u)| (m.clone(), expand(u))).collect(),
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The layer (top module) of a file, or None for a crate's root file.
fn layer(f: &File) -> Option<&str> {
    f.module.first().map(String::as_str)
}

#[test]
fn the_layer_tables_name_every_module_and_only_modules_above_each() {
    let tree = Tree::load(&root());
    let doc = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let l = layers(&doc);
    let mut problems = Vec::new();
    for (krate, table) in [(Krate::Core, &l.core), (Krate::App, &l.app)] {
        let in_code: BTreeSet<&str> = tree
            .files
            .iter()
            .filter(|f| f.krate == krate || (krate == Krate::App && f.krate == Krate::Bin))
            .filter_map(layer)
            .collect();
        let in_doc: BTreeSet<&str> = table.iter().map(|(m, _)| m.as_str()).collect();
        for m in in_code.difference(&in_doc) {
            problems.push(format!("module `{m}` has no row in ARCHITECTURE.md's layer tables"));
        }
        for m in in_doc.difference(&in_code) {
            problems.push(format!("ARCHITECTURE.md's layer row `{m}` is no module of the code"));
        }
        for (k, (m, uses)) in table.iter().enumerate() {
            let above: BTreeSet<&str> = table[..k].iter().map(|(m, _)| m.as_str()).collect();
            for u in uses {
                let core_row = l.core.iter().any(|(c, _)| c == u);
                let fine = above.contains(u.as_str()) || (krate == Krate::App && core_row);
                if !fine && u != m {
                    problems
                        .push(format!("ARCHITECTURE.md: `{m}` uses `{u}`, which is not above it"));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn no_module_imports_one_its_layer_row_does_not_name() {
    let tree = Tree::load(&root());
    let doc = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let l = layers(&doc);
    let uses: BTreeMap<&str, &BTreeSet<String>> =
        l.core.iter().chain(&l.app).map(|(m, u)| (m.as_str(), u)).collect();
    let mut problems = Vec::new();
    for (i, targets) in tree.edges().iter().enumerate() {
        let Some(from) = layer(&tree.files[i]) else { continue };
        for (&t, how) in targets {
            let Some(to) = layer(&tree.files[t]) else { continue };
            if from != to && !uses.get(from).is_some_and(|u| u.contains(to)) {
                problems.push(format!(
                    "{} (`{from}`) imports {} (`{to}`, as {how}): ARCHITECTURE.md's `{from}` row does not use `{to}`",
                    tree.name(i),
                    tree.name(t)
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// Pairs of files that still import each other, each to be broken (a trait or a leaf module):
/// the check fails on any other pair, and on a pair here that no longer does.
const KNOWN_CYCLES: [(&str, &str); 0] = [];

/// Whether `a` is the `mod.rs` (or crate root) of the module `b` is a file of: a folder's
/// `mod.rs` holds what its files share and hands work to them, so the two may use each other.
fn parent_and_child(a: &File, b: &File) -> bool {
    let parent_file =
        a.path.file_name().is_some_and(|n| n == "mod.rs" || n == "lib.rs" || n == "main.rs");
    parent_file
        && a.krate == b.krate
        && b.module.len() == a.module.len() + 1
        && b.module.starts_with(&a.module)
}

#[test]
fn no_two_files_import_each_other() {
    let tree = Tree::load(&root());
    let edges = tree.edges();
    let relative = |i: usize| {
        let p = &tree.files[i].path;
        p.strip_prefix(root()).unwrap_or(p).to_string_lossy().into_owned()
    };
    let mut problems = Vec::new();
    let mut known_seen = BTreeSet::new();
    for (a, targets) in edges.iter().enumerate() {
        for (&b, how) in targets {
            let Some(back) = edges[b].get(&a) else { continue };
            let (fa, fb) = (&tree.files[a], &tree.files[b]);
            if a > b || parent_and_child(fa, fb) || parent_and_child(fb, fa) {
                continue;
            }
            let pair = (relative(a), relative(b));
            if let Some(k) = KNOWN_CYCLES
                .iter()
                .position(|(x, y)| (pair.0 == *x && pair.1 == *y) || (pair.0 == *y && pair.1 == *x))
            {
                known_seen.insert(k);
                continue;
            }
            problems.push(format!("{} and {} import each other ({how}; {back})", pair.0, pair.1));
        }
    }
    for (k, (x, y)) in KNOWN_CYCLES.iter().enumerate() {
        if !known_seen.contains(&k) {
            problems.push(format!(
                "{x} and {y} no longer import each other: take them off KNOWN_CYCLES"
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The checker sees the imports: an empty graph would pass the checks above.
#[test]
fn the_checker_sees_the_imports_it_checks() {
    let tree = Tree::load(&root());
    let edges = tree.edges();
    let count: usize = edges.iter().map(BTreeMap::len).sum();
    assert!(tree.files.len() > 100 && count > 300, "{} files, {count} imports", tree.files.len());
    let find = |p: &str| tree.files.iter().position(|f| f.path.ends_with(p)).unwrap();
    // Through a re-export (`crate::export::Frames`) to the file that defines it.
    assert!(edges[find("src/ui/frames.rs")].contains_key(&find("src/export/frames.rs")));
    // A path in code, not in a `use`.
    assert!(edges[find("src/cli/diagnose.rs")].contains_key(&find("src/cli/diagnose_batch.rs")));
}

/// The checker itself, on sources written for it.
#[test]
fn the_checker_reads_paths_as_rust_does() {
    let t = tokens(
        "use a::{b, c::d as e}; // x::y\n let s = \"crate::z\"; r#\"q::r\"#; 'a' '\\n' &'b str",
    );
    let idents: Vec<String> = t
        .iter()
        .filter_map(|t| if let Tok::Ident(w) = t { Some(w.clone()) } else { None })
        .collect();
    assert_eq!(idents, ["use", "a", "b", "c", "d", "as", "e", "let", "s", "str"]);
    let mut out = Vec::new();
    use_tree(&tokens("super::frames::{self, Aim, x::*};"), 0, Vec::new(), &mut out);
    let paths: Vec<String> = out.iter().map(|(s, _)| s.join("::")).collect();
    assert_eq!(paths, ["super::frames", "super::frames::Aim", "super::frames::x::*"]);
}
