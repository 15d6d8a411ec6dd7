//! The crate's layering, checked on its source: a file imports only from its own folder or the
//! folders below it (`geometry < scene < model < program < solver < solve < analysis`, with the
//! root files `error.rs`, `option_names.rs` and `number_text.rs` below them all), and no two
//! files import each other. A name imported through the crate's face (`lib.rs`, which
//! re-exports) counts as imported from the file that defines it.
//!
//! An import is any path that names a module of the crate: a `use` item (groups expanded,
//! `crate::`, `super::`, `self::` or a child module's name) or a `crate::`/`super::`/`self::`
//! path in the code; comments, doc links and string literals are not imports.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The folders, bottom first.
const FOLDERS: [&str; 7] = [
    "geometry", "scene", "model", "program", "solver", "solve", "analysis",
];

/// The files at the root below every folder.
const ROOT_FILES: [&str; 3] = ["error", "option_names", "number_text"];

/// A module's path from the crate root (`[]` is `lib.rs`).
type ModulePath = Vec<String>;

/// Every `.rs` file under `dir` by its module path, with its text.
fn read_sources(dir: &Path, prefix: &[String], out: &mut BTreeMap<ModulePath, String>) {
    for entry in std::fs::read_dir(dir).expect("a readable source folder") {
        let path = entry.expect("a folder entry").path();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let mut module = prefix.to_vec();
        if path.is_dir() {
            module.push(name);
            read_sources(&path, &module, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            if name != "mod" && name != "lib" {
                module.push(name);
            }
            out.insert(
                module,
                std::fs::read_to_string(&path).expect("a readable file"),
            );
        }
    }
}

/// `src` with comments, string and character literals blanked (line breaks kept).
fn code_only(src: &str) -> String {
    let c: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    let blank = |out: &mut String, s: &[char]| {
        out.extend(s.iter().map(|&ch| if ch == '\n' { '\n' } else { ' ' }))
    };
    while i < c.len() {
        let end = literal_end(&c, i);
        if end > i {
            blank(&mut out, &c[i..end]);
            i = end;
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

/// The end of the comment or literal starting at `i` (`i` itself when none starts there).
fn literal_end(c: &[char], i: usize) -> usize {
    let at = |k: usize| c.get(k).copied().unwrap_or('\0');
    match (at(i), at(i + 1)) {
        ('/', '/') => (i..c.len()).find(|&k| c[k] == '\n').unwrap_or(c.len()),
        ('/', '*') => {
            let (mut k, mut depth) = (i + 2, 1);
            while k < c.len() && depth > 0 {
                match (at(k), at(k + 1)) {
                    ('/', '*') => (depth, k) = (depth + 1, k + 2),
                    ('*', '/') => (depth, k) = (depth - 1, k + 2),
                    _ => k += 1,
                }
            }
            k
        }
        ('"', _) => quoted_end(c, i + 1),
        ('r', '"') | ('r', '#') if i == 0 || !is_ident(at(i - 1)) => raw_end(c, i + 1),
        ('\'', '\\') => (i + 3..c.len())
            .find(|&k| c[k] == '\'')
            .map_or(c.len(), |k| k + 1),
        ('\'', _) if at(i + 2) == '\'' => i + 3,
        _ => i,
    }
}

/// The end of a string whose text starts at `i` (after its opening quote).
fn quoted_end(c: &[char], mut i: usize) -> usize {
    while i < c.len() {
        match c[i] {
            '\\' => i += 2,
            '"' => return i + 1,
            _ => i += 1,
        }
    }
    c.len()
}

/// The end of a raw string `r#"..."#` whose hashes start at `i` (no quote: not a raw string).
fn raw_end(c: &[char], i: usize) -> usize {
    let hashes = c[i..].iter().take_while(|&&ch| ch == '#').count();
    if c.get(i + hashes) != Some(&'"') {
        return i - 1;
    }
    let close: Vec<char> = std::iter::once('"')
        .chain(std::iter::repeat_n('#', hashes))
        .collect();
    (i + hashes + 1..c.len())
        .find(|&k| c[k..].starts_with(&close))
        .map_or(c.len(), |k| k + close.len())
}

fn is_ident(ch: char) -> bool {
    ch.is_alphanumeric() || ch == '_'
}

/// The tokens of code: identifiers, `::`, and single punctuation characters.
fn tokens(code: &str) -> Vec<String> {
    let c: Vec<char> = code.chars().collect();
    let (mut out, mut i) = (Vec::new(), 0);
    while i < c.len() {
        if is_ident(c[i]) {
            let start = i;
            while i < c.len() && is_ident(c[i]) {
                i += 1;
            }
            out.push(c[start..i].iter().collect());
        } else if c[i] == ':' && c.get(i + 1) == Some(&':') {
            out.push("::".into());
            i += 2;
        } else {
            if !c[i].is_whitespace() {
                out.push(c[i].to_string());
            }
            i += 1;
        }
    }
    out
}

/// The paths of a `use` tree starting at `t[*i]`, each with its prefix, up to its end (`;`,
/// `,` or `}` of the enclosing group).
fn use_tree(t: &[String], i: &mut usize, prefix: &[String], out: &mut Vec<Vec<String>>) {
    let mut path = prefix.to_vec();
    while *i < t.len() {
        let tok = t[*i].as_str();
        match tok {
            "::" => *i += 1,
            "{" => {
                *i += 1;
                while *i < t.len() && t[*i] != "}" {
                    use_tree(t, i, &path, out);
                    if t.get(*i).is_some_and(|s| s == ",") {
                        *i += 1;
                    }
                }
                *i += 1;
                return;
            }
            ";" | "," | "}" => break,
            "as" => *i += 2,
            "*" => *i += 1,
            _ => {
                path.push(tok.to_string());
                *i += 1;
            }
        }
    }
    out.push(path);
}

/// The module paths a file names (before resolution), each with the module it is named in
/// (the file's own, or an inline module of it such as `mod tests { .. }`).
fn named_paths(file: &ModulePath, code: &str) -> Vec<(ModulePath, Vec<String>)> {
    let t = tokens(code);
    let (mut out, mut inline, mut depth) = (Vec::new(), Vec::<(String, usize)>::new(), 0);
    let mut i = 0;
    while i < t.len() {
        let here: ModulePath = file
            .iter()
            .cloned()
            .chain(inline.iter().map(|m| m.0.clone()))
            .collect();
        match t[i].as_str() {
            "mod" if t.get(i + 2).is_some_and(|s| s == "{") => {
                inline.push((t[i + 1].clone(), depth + 1));
                depth += 1;
                i += 3;
                continue;
            }
            "{" => depth += 1,
            "}" => {
                if inline.last().is_some_and(|m| m.1 == depth) {
                    inline.pop();
                }
                depth -= 1;
            }
            "use" => {
                i += 1;
                let mut paths = Vec::new();
                use_tree(&t, &mut i, &[], &mut paths);
                out.extend(paths.into_iter().map(|p| (here.clone(), p)));
                continue;
            }
            "crate" | "super" | "self" if t.get(i + 1).is_some_and(|s| s == "::") => {
                let mut path = vec![t[i].clone()];
                while t.get(i + 1).is_some_and(|s| s == "::")
                    && t.get(i + 2)
                        .is_some_and(|s| is_ident(s.chars().next().unwrap()))
                {
                    path.push(t[i + 2].clone());
                    i += 2;
                }
                out.push((here.clone(), path));
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// The file a path named in module `here` refers to: the longest module of the crate it
/// starts with (`None`: not the crate's, e.g. `std::` or `faer::`).
fn resolve(
    modules: &BTreeSet<ModulePath>,
    here: &ModulePath,
    path: &[String],
) -> Option<ModulePath> {
    let mut base: ModulePath = here.clone();
    let mut rest = path;
    match path.first().map(String::as_str) {
        Some("crate") => (base, rest) = (Vec::new(), &path[1..]),
        Some("self") => rest = &path[1..],
        Some("super") => {
            while rest.first().is_some_and(|s| s == "super") {
                base.pop();
                rest = &rest[1..];
            }
        }
        Some(first) => {
            let mut child = here.clone();
            child.push(first.to_string());
            if !modules.contains(&child) {
                return None;
            }
        }
        None => return None,
    }
    for seg in rest {
        let mut next = base.clone();
        next.push(seg.clone());
        if !modules.contains(&next) {
            break;
        }
        base = next;
    }
    while !base.is_empty() && !modules.contains(&base) {
        base.pop();
    }
    Some(base)
}

/// The layer of a module: 0 for the root files, 1 to 7 for the folders (`None`: `lib.rs`).
fn layer(module: &ModulePath) -> Option<usize> {
    let first = module.first()?;
    if ROOT_FILES.contains(&first.as_str()) {
        return Some(0);
    }
    FOLDERS.iter().position(|f| f == first).map(|p| p + 1)
}

fn file_name(module: &ModulePath, modules: &BTreeSet<ModulePath>) -> String {
    let has_children = modules
        .iter()
        .any(|m| m.len() > module.len() && m.starts_with(module));
    match (module.is_empty(), has_children) {
        (true, _) => "lib.rs".into(),
        (false, true) => format!("{}/mod.rs", module.join("/")),
        (false, false) => format!("{}.rs", module.join("/")),
    }
}

/// The names `lib.rs` re-exports (`pub use a::b::Name`, or an inline `pub mod name { pub use
/// a::b::*; }`) with the file that defines them.
fn face(modules: &BTreeSet<ModulePath>, lib: &str) -> BTreeMap<String, ModulePath> {
    let mut out = BTreeMap::new();
    for (here, path) in named_paths(&Vec::new(), &code_only(lib)) {
        let key = here.first().or(path.last()).cloned();
        if let (Some(key), Some(target)) = (key, resolve(modules, &here, &path)) {
            out.insert(key, target);
        }
    }
    out
}

/// Every breach of the layering in `sources` (module path -> text), one line each. A name
/// imported through `lib.rs` counts as imported from the file that defines it.
fn problems(sources: &BTreeMap<ModulePath, String>) -> Vec<String> {
    let modules: BTreeSet<ModulePath> = sources.keys().cloned().collect();
    let name = |m: &ModulePath| file_name(m, &modules);
    let face = face(
        &modules,
        sources.get(&Vec::new()).map_or("", String::as_str),
    );
    let mut edges = BTreeSet::new();
    let mut out = Vec::new();
    for (file, text) in sources.iter().filter(|(m, _)| !m.is_empty()) {
        for (here, path) in named_paths(file, &code_only(text)) {
            let Some(mut target) = resolve(&modules, &here, &path) else {
                continue;
            };
            if target.is_empty() {
                match path.get(1).and_then(|n| face.get(n)) {
                    Some(defined) => target = defined.clone(),
                    None => continue,
                }
            }
            if &target == file {
                continue;
            }
            match (layer(file), layer(&target)) {
                (Some(a), Some(b)) if b > a => out.push(format!(
                    "{} imports upward from {} (`{}`)",
                    name(file),
                    name(&target),
                    path.join("::")
                )),
                _ => {}
            }
            edges.insert((file.clone(), target));
        }
    }
    for (a, b) in &edges {
        if a < b && edges.contains(&(b.clone(), a.clone())) {
            out.push(format!("{} and {} import each other", name(a), name(b)));
        }
    }
    out.sort();
    out.dedup();
    out
}

#[test]
fn no_file_imports_upward_or_circularly() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut sources = BTreeMap::new();
    read_sources(&src, &[], &mut sources);
    assert!(sources.len() > 50, "read {} files", sources.len());
    let found = problems(&sources);
    assert!(found.is_empty(), "layering problems:\n{}", found.join("\n"));
}

fn module(path: &str) -> ModulePath {
    path.split('/')
        .filter(|s| !s.is_empty())
        .map(String::from)
        .collect()
}

/// The check itself fails where it should: an upward import (as `use`, in a group, as a path in
/// the code, through a name `lib.rs` re-exports), a root file importing a folder, and two files
/// importing each other; comments, strings and a test module's `use super::*` are no imports.
#[test]
fn the_check_finds_each_kind_of_breach() {
    let sources: BTreeMap<ModulePath, String> = [
        (
            "",
            "mod model; mod scene; mod error; pub use model::m::Thing;",
        ),
        ("error", "fn f() -> crate::model::m::M { todo!() }"),
        ("scene", "pub mod s;"),
        (
            "scene/s",
            "use crate::Thing;\nuse crate::{error::E, model::n::N};\n// use crate::solve::x;\n\
             const T: &str = \"crate::solve::x\";",
        ),
        ("model", "pub mod m; pub mod n;"),
        (
            "model/m",
            "use super::n::N;\n#[cfg(test)]\nmod tests {\n    use super::*;\n}",
        ),
        ("model/n", "pub fn f() { crate::model::m::g(); }"),
    ]
    .into_iter()
    .map(|(m, s)| (module(m), s.to_string()))
    .collect();
    assert_eq!(
        problems(&sources),
        [
            "error.rs imports upward from model/m.rs (`crate::model::m::M`)",
            "model/m.rs and model/n.rs import each other",
            "scene/s.rs imports upward from model/m.rs (`crate::Thing`)",
            "scene/s.rs imports upward from model/n.rs (`crate::model::n::N`)",
        ]
    );
}
