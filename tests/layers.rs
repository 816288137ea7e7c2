//! The layering of the library and of the solver built on it (ARCHITECTURE.md, "Layers"): in
//! each crate, each top-level module imports only the modules below it, so no two import each
//! other; inside every module, nested ones included, no files import each other in a circle.
//! Reads the sources' `crate::…` and `super::…` paths (comments and test modules left out), so a
//! new upward or circular import fails here.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Each crate's source folder (from the repository's root) and its modules, bottom to top.
/// `lib.rs` may name any of them; the solver sees the library only through its public API.
const CRATES: [(&str, &[&str]); 2] = [
    ("src", &["mesh", "io", "cpu", "dent", "fracture", "damage", "record", "gpu", "bend", "collider"]),
    ("solver/src", &["sim", "coupling", "scene", "render"]),
];

/// The crates' source folders with their layers.
fn crates() -> impl Iterator<Item = (PathBuf, &'static [&'static str])> {
    CRATES.into_iter().map(|(dir, layers)| (Path::new(env!("CARGO_MANIFEST_DIR")).join(dir), layers))
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The library code of a source file: without its `#[cfg(test)]` module (the file's tail, by
/// convention) and without comments (line, doc and block comments); strings kept.
fn code(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text.find("#[cfg(test)]").map_or(text, |k| &text[..k]);
    while !rest.is_empty() {
        if rest.starts_with("//") {
            rest = rest.find('\n').map_or("", |k| &rest[k..]);
        } else if rest.starts_with("/*") {
            rest = rest.find("*/").map_or("", |k| &rest[k + 2..]);
        } else {
            let c = rest.chars().next().unwrap();
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    out
}

fn ident(text: &str) -> &str {
    let end = text.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(text.len());
    &text[..end]
}

/// The first path segment after every `prefix` in `code`: `prefix::a::…` gives `a`, and
/// `prefix::{a::…, b}` gives `a` and `b`.
fn heads(code: &str, prefix: &str) -> Vec<String> {
    let mut out = Vec::new();
    let needle = format!("{prefix}::");
    for (k, _) in code.match_indices(&needle) {
        let before = code[..k].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        let after = &code[k + needle.len()..];
        if let Some(group) = after.strip_prefix('{') {
            let (mut depth, mut start) = (0usize, 0usize);
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        out.push(ident(group[start..].trim_start()).to_owned());
                        break;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        out.push(ident(group[start..].trim_start()).to_owned());
                        start = i + 1;
                    }
                    _ => {}
                }
            }
        } else {
            out.push(ident(after).to_owned());
        }
    }
    out.retain(|h| !h.is_empty());
    out
}

/// Top-level module of a file under src/ (`None` for lib.rs).
fn top(path: &Path, src: &Path) -> Option<String> {
    let rel = path.strip_prefix(src).unwrap();
    let mut parts = rel.components();
    let first = parts.next()?.as_os_str().to_string_lossy().into_owned();
    if rel.components().count() == 1 {
        return first.strip_suffix(".rs").filter(|s| *s != "lib").map(str::to_owned);
    }
    Some(first)
}

#[test]
fn modules_import_only_the_layers_below_them() {
    let mut upward = BTreeSet::new();
    for (src, layers) in crates() {
        let mut files = Vec::new();
        sources(&src, &mut files);
        let rank = |m: &str| layers.iter().position(|l| *l == m);
        for file in &files {
            let Some(module) = top(file, &src) else { continue };
            let mine = rank(&module).unwrap_or_else(|| panic!("{module} (from {}) is not in CRATES", file.display()));
            let text = code(&std::fs::read_to_string(file).unwrap());
            for head in heads(&text, "crate") {
                if let Some(theirs) = rank(&head)
                    && theirs > mine
                {
                    upward.insert(format!("{} imports {head} (above {module})", file.display()));
                }
            }
            // The library never names the solver (it cannot depend on it; this keeps docs and
            // comments from leaning on it either).
            assert!(
                !layers.contains(&"mesh") || !text.contains("dentbend_solver"),
                "{} names dentbend_solver",
                file.display()
            );
        }
    }
    assert!(upward.is_empty(), "upward imports:\n{}", upward.into_iter().collect::<Vec<_>>().join("\n"));
}

/// Which file of module `dir` defines each name its `mod.rs` re-exports (`pub use file::{…}`).
fn exports(mod_rs: &str) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for statement in mod_rs.split(';') {
        let statement = statement.trim();
        let Some(path) = statement.strip_prefix("pub use ").or_else(|| statement.strip_prefix("pub(crate) use "))
        else {
            continue;
        };
        let file = ident(path).to_owned();
        let items = path[file.len()..].trim_start_matches("::");
        let items = items.trim_start_matches('{').trim_end_matches('}');
        for item in items.split(',') {
            let name = item.trim().rsplit(" as ").next().unwrap_or("").trim();
            if !name.is_empty() {
                out.insert(ident(name).to_owned(), file.clone());
            }
        }
    }
    out
}

/// Every directory module under `dir`: a folder with a `mod.rs`, or one beside a `<name>.rs`
/// that declares its files; as its path from `src` and its module file.
fn module_dirs(dir: &Path, src: &Path, out: &mut Vec<(PathBuf, PathBuf)>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            let beside = path.with_extension("rs");
            let module_file = [path.join("mod.rs"), beside].into_iter().find(|f| f.exists());
            if let Some(module_file) = module_file {
                out.push((path.strip_prefix(src).unwrap().to_path_buf(), module_file));
            }
            module_dirs(&path, src, out);
        }
    }
}

#[test]
fn files_inside_a_module_import_each_other_in_no_cycle() {
    let (mut found, mut beside): (Vec<String>, bool) = (Vec::new(), false);
    for (src, layers) in crates() {
        let mut modules = Vec::new();
        module_dirs(&src, &src, &mut modules);
        assert!(modules.len() > layers.len(), "nested modules are checked too");
        beside |= modules.iter().any(|(_, file)| !file.ends_with("mod.rs"));
        found.extend(module_cycles(&src, &modules));
    }
    assert!(beside, "modules beside their file are checked too");
    assert!(found.is_empty(), "files that import each other in a circle:\n{}", found.join("\n"));
}

/// The circles of files importing each other inside each of `modules` (from [`module_dirs`]).
fn module_cycles(src: &Path, modules: &[(PathBuf, PathBuf)]) -> Vec<String> {
    let mut found: Vec<String> = Vec::new();
    for (module, module_file) in modules {
        let dir = src.join(module);
        let names = exports(&code(&std::fs::read_to_string(module_file).unwrap()));
        let path = module.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect::<Vec<_>>();
        let absolute = format!("crate::{}", path.join("::"));
        let mut files = Vec::new();
        sources(&dir, &mut files);
        // Direct files of the module only (a nested directory module is one node).
        let stem = |p: &Path| -> Option<String> {
            let rel = p.strip_prefix(&dir).ok()?;
            let first = rel.components().next()?.as_os_str().to_string_lossy().into_owned();
            Some(first.trim_end_matches(".rs").to_owned()).filter(|s| s != "mod")
        };
        let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for file in &files {
            let Some(from) = stem(file) else { continue };
            let direct = file.parent() == Some(dir.as_path());
            let text = code(&std::fs::read_to_string(file).unwrap());
            let mut targets: Vec<String> = if direct { heads(&text, "super") } else { Vec::new() };
            targets.extend(heads(&text, &absolute));
            for target in targets {
                let to = names.get(&target).cloned().unwrap_or(target);
                if to != from && (dir.join(format!("{to}.rs")).exists() || dir.join(&to).is_dir()) {
                    edges.entry(from.clone()).or_default().insert(to);
                }
            }
        }
        found.extend(cycles(&edges).into_iter().map(|group| format!("{}: {group:?}", module.display())));
    }
    found
}

/// The strongly connected groups of two or more nodes (Tarjan's algorithm).
fn cycles(edges: &BTreeMap<String, BTreeSet<String>>) -> Vec<BTreeSet<String>> {
    struct State<'a> {
        edges: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        out: Vec<BTreeSet<String>>,
    }
    fn visit<'a>(node: &'a str, s: &mut State<'a>) {
        let n = s.index.len();
        s.index.insert(node, n);
        s.low.insert(node, n);
        s.stack.push(node);
        for next in s.edges.get(node).into_iter().flatten() {
            if !s.index.contains_key(next.as_str()) {
                visit(next, s);
                let l = s.low[next.as_str()].min(s.low[node]);
                s.low.insert(node, l);
            } else if s.stack.contains(&next.as_str()) {
                let l = s.index[next.as_str()].min(s.low[node]);
                s.low.insert(node, l);
            }
        }
        if s.low[node] == s.index[node] {
            let mut group = BTreeSet::new();
            while let Some(top) = s.stack.pop() {
                group.insert(top.to_owned());
                if top == node {
                    break;
                }
            }
            if group.len() > 1 {
                s.out.push(group);
            }
        }
    }
    let mut s = State { edges, index: BTreeMap::new(), low: BTreeMap::new(), stack: Vec::new(), out: Vec::new() };
    let nodes: BTreeSet<&str> =
        edges.iter().flat_map(|(k, v)| std::iter::once(k.as_str()).chain(v.iter().map(String::as_str))).collect();
    for node in nodes {
        if !s.index.contains_key(node) {
            visit(node, &mut s);
        }
    }
    s.out
}

#[test]
fn the_checker_sees_grouped_and_nested_imports() {
    let text = code(
        "use crate::{dent::Impact, gpu::{GpuContext, GpuError}};\n// crate::render::x\nlet a = crate::sim::World::new();",
    );
    assert_eq!(heads(&text, "crate"), ["dent", "gpu", "sim"]);
    let mut edges = BTreeMap::new();
    edges.insert("a".to_owned(), BTreeSet::from(["b".to_owned()]));
    edges.insert("b".to_owned(), BTreeSet::from(["a".to_owned()]));
    edges.insert("c".to_owned(), BTreeSet::from(["a".to_owned()]));
    let groups = cycles(&edges);
    assert_eq!(groups, [BTreeSet::from(["a".to_owned(), "b".to_owned()])]);
}
