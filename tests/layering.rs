//! The layering of every crate of the workspace, checked on its source (`crates/*/src`): a file
//! imports only from its own layer or the layers below it (per crate a table of layers, bottom
//! first; two layers on the same level are independent: neither imports the other), and no two
//! files import each other. A name imported through the crate's face (`lib.rs`, which
//! re-exports) counts as imported from the file that defines it. Every file is reached: it is
//! in a layer of its crate's table and declared by a `mod` of its parent. And each face is
//! sealed: `lib.rs` makes no file's module public (bar the deliberate faces the table names),
//! and a module it writes inline (`pub mod limits { pub use ...; }`) only re-exports.
//!
//! An import is any path that names a module of the crate: a `use` item (groups expanded,
//! `crate::`, `super::`, `self::` or a child module's name) or a `crate::`/`super::`/`self::`
//! path in the code; comments, doc links and string literals are not imports.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// One layer of a crate: its level (0 lowest) and the top modules it holds (a folder or a root
/// file, without `.rs`; `*`: every root file not named by another layer).
type Layer = (usize, &'static [&'static str]);

/// A crate's layering.
struct Layering {
    /// The crate's folder under `crates/`.
    name: &'static str,
    /// Its layers, bottom first.
    layers: &'static [Layer],
    /// The modules `lib.rs` may declare `pub mod` from their own file: deliberate faces whose
    /// every item is meant to be named through the module (option names).
    public_modules: &'static [&'static str],
    /// At least this many files are read (a wrong folder fails loudly).
    min_files: usize,
}

/// Every crate of the workspace. grasp-model: seven folders over the root files; grasp-transfer:
/// the driver's files at the root, then the sinks and the planner, independent of each other;
/// grasp-cli: the root files, then the pictures, then the subcommands; the other crates are
/// flat (one layer: only pairs of files importing each other are found).
const CRATES: [Layering; 7] = [
    Layering {
        name: "grasp-model",
        layers: &[
            (0, &["*"]),
            (1, &["geometry"]),
            (2, &["scene"]),
            (3, &["model"]),
            (4, &["program"]),
            (5, &["solver"]),
            (6, &["solve"]),
            (7, &["sensors", "analysis"]),
        ],
        public_modules: &["option_names"],
        min_files: 50,
    },
    Layering {
        name: "grasp-io",
        layers: &[(0, &["*"])],
        public_modules: &[],
        min_files: 10,
    },
    Layering {
        name: "grasp-transfer",
        layers: &[(0, &["*"]), (1, &["sinks"]), (1, &["plan"])],
        public_modules: &[],
        min_files: 30,
    },
    Layering {
        name: "grasp-batch",
        layers: &[(0, &["*"])],
        public_modules: &["option_names"],
        min_files: 10,
    },
    Layering {
        name: "grasp-bench",
        layers: &[(0, &["*"])],
        public_modules: &[],
        min_files: 8,
    },
    Layering {
        name: "grasp-cli",
        layers: &[(0, &["*"]), (1, &["pictures"]), (2, &["commands"])],
        public_modules: &[],
        min_files: 25,
    },
    Layering {
        name: "grasp-py",
        layers: &[(0, &["*"])],
        public_modules: &[],
        min_files: 15,
    },
];

/// A module's path from the crate root (`[]` is `lib.rs` or `main.rs`).
type ModulePath = Vec<String>;

/// A crate's source: each file by its module path, with its path under `src/` and its text.
type Sources = BTreeMap<ModulePath, (String, String)>;

/// Every `.rs` file under `dir` (`rel`: its path under `src/`) by its module path.
fn read_sources(dir: &Path, rel: &str, prefix: &[String], out: &mut Sources) {
    for entry in std::fs::read_dir(dir).expect("a readable source folder") {
        let path = entry.expect("a folder entry").path();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        let here = format!("{rel}{file}");
        let mut module = prefix.to_vec();
        if path.is_dir() {
            module.push(name);
            read_sources(&path, &format!("{here}/"), &module, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let root = prefix.is_empty() && (name == "lib" || name == "main");
            if name != "mod" && !root {
                module.push(name);
            }
            let text = std::fs::read_to_string(&path).expect("a readable file");
            out.insert(module, (here, text));
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

/// True when `module` is a folder (some file of the crate sits inside it).
fn is_folder(modules: &BTreeSet<ModulePath>, module: &[String]) -> bool {
    modules
        .iter()
        .any(|m| m.len() > module.len() && m.starts_with(module))
}

/// The layer of a module, an index into `layers` (`None`: the crate root, or a file no layer
/// holds).
fn layer(layers: &[Layer], modules: &BTreeSet<ModulePath>, module: &ModulePath) -> Option<usize> {
    let first = module.first()?;
    let named = layers
        .iter()
        .position(|(_, names)| names.contains(&first.as_str()));
    let root_file = !is_folder(modules, &module[..1]);
    named.or_else(|| {
        let rest = layers.iter().position(|(_, names)| names.contains(&"*"));
        rest.filter(|_| root_file)
    })
}

/// The names the crate root re-exports (`pub use a::b::Name`, or an inline `pub mod name { pub
/// use a::b::*; }`) with the file that defines them.
fn face(modules: &BTreeSet<ModulePath>, root: &str) -> BTreeMap<String, ModulePath> {
    let mut out = BTreeMap::new();
    for (here, path) in named_paths(&Vec::new(), &code_only(root)) {
        let key = here.first().or(path.last()).cloned();
        if let (Some(key), Some(target)) = (key, resolve(modules, &here, &path)) {
            out.insert(key, target);
        }
    }
    out
}

/// The breaches of a sealed face in the crate root's code (`root`: its file name): a file's
/// module made public (unless `allowed`), an inline public module that does more than
/// re-export.
fn unsealed(code: &str, allowed: &[&str], root: &str) -> Vec<String> {
    let t = tokens(code);
    let (mut out, mut depth) = (Vec::new(), 0);
    for i in 0..t.len() {
        match t[i].as_str() {
            "{" => depth += 1,
            "}" => depth -= 1,
            "pub" if depth == 0 && t.get(i + 1).is_some_and(|s| s == "mod") => {
                let name = t.get(i + 2).map_or("", String::as_str);
                match t.get(i + 3).map(String::as_str) {
                    Some(";") if !allowed.contains(&name) => out.push(format!(
                        "{root} makes a file's module public: `pub mod {name};` (re-export its \
                         names instead)"
                    )),
                    Some("{") if !only_reexports(&t, i + 4) => {
                        out.push(format!("{root}: `pub mod {name}` does more than re-export"))
                    }
                    _ => {}
                }
            }
            _ => {}
        }
    }
    out
}

/// True when the items from `t[i]` to the `}` closing their module are all `use` items (with
/// attributes and any visibility).
fn only_reexports(t: &[String], mut i: usize) -> bool {
    let skip_group = |i: &mut usize, open: &str, close: &str| {
        let mut depth = 0;
        while *i < t.len() {
            depth += usize::from(t[*i] == open);
            if t[*i] == close {
                depth -= 1;
                if depth == 0 {
                    break;
                }
            }
            *i += 1;
        }
    };
    loop {
        match t.get(i).map(String::as_str) {
            None | Some("}") => return true,
            Some("#") => {
                i += 1;
                skip_group(&mut i, "[", "]");
            }
            Some("pub") if t.get(i + 1).is_some_and(|s| s == "(") => {
                i += 1;
                skip_group(&mut i, "(", ")");
            }
            Some("pub") => {}
            Some("use") => {
                while t.get(i).is_some_and(|s| s != ";") {
                    if t[i] == "{" {
                        skip_group(&mut i, "{", "}");
                    }
                    i += 1;
                }
            }
            Some(_) => return false,
        }
        i += 1;
    }
}

/// The files no `mod` of their parent declares (never compiled, so never checked).
fn undeclared(sources: &Sources) -> Vec<String> {
    let mut out = Vec::new();
    for (module, (path, _)) in sources.iter().filter(|(m, _)| !m.is_empty()) {
        let (parent, name) = module.split_at(module.len() - 1);
        let declared = sources.get(parent).is_some_and(|(_, text)| {
            let t = tokens(&code_only(text));
            t.windows(3)
                .any(|w| w[0] == "mod" && w[1] == name[0] && w[2] == ";")
        });
        if !declared {
            out.push(format!("{path} is declared by no `mod` of its parent"));
        }
    }
    out
}

/// Every breach of `layering` in `sources`, one line each: imports upward or beside, files
/// importing each other, files in no layer or declared nowhere, an unsealed face. A name
/// imported through the crate root counts as imported from the file that defines it.
fn problems(layering: &Layering, sources: &Sources) -> Vec<String> {
    let modules: BTreeSet<ModulePath> = sources.keys().cloned().collect();
    let name = |m: &ModulePath| sources.get(m).map_or_else(|| m.join("/"), |s| s.0.clone());
    let (root, root_text) = sources
        .get(&Vec::new())
        .map_or(("lib.rs", ""), |(p, t)| (p.as_str(), t.as_str()));
    let face = face(&modules, root_text);
    let layers = layering.layers;
    let layer_of = |m: &ModulePath| layer(layers, &modules, m);
    let mut out = unsealed(&code_only(root_text), layering.public_modules, root);
    out.extend(undeclared(sources));
    let mut edges = BTreeSet::new();
    for (file, (path, text)) in sources.iter().filter(|(m, _)| !m.is_empty()) {
        if layer_of(file).is_none() {
            out.push(format!("{path} is in no layer of its crate's table"));
        }
        for (here, named) in named_paths(file, &code_only(text)) {
            let Some(mut target) = resolve(&modules, &here, &named) else {
                continue;
            };
            if target.is_empty() {
                match named.get(1).and_then(|n| face.get(n)) {
                    Some(defined) => target = defined.clone(),
                    None => continue,
                }
            }
            if &target == file {
                continue;
            }
            if let (Some(a), Some(b)) = (layer_of(file), layer_of(&target)) {
                let how = match layers[b].0.cmp(&layers[a].0) {
                    std::cmp::Ordering::Greater => Some("upward"),
                    std::cmp::Ordering::Equal if a != b => Some("beside its layer"),
                    _ => None,
                };
                if let Some(how) = how {
                    out.push(format!(
                        "{path} imports {how} from {} (`{}`)",
                        name(&target),
                        named.join("::")
                    ));
                }
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
fn every_crate_is_layered_and_sealed() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("../crates");
    let mut found = Vec::new();
    for layering in &CRATES {
        let mut sources = Sources::new();
        read_sources(
            &crates.join(layering.name).join("src"),
            "",
            &[],
            &mut sources,
        );
        assert!(
            sources.len() >= layering.min_files,
            "{}: read {} files",
            layering.name,
            sources.len()
        );
        found.extend(
            problems(layering, &sources)
                .into_iter()
                .map(|p| format!("{}: {p}", layering.name)),
        );
    }
    assert!(found.is_empty(), "layering problems:\n{}", found.join("\n"));
}

#[test]
fn the_table_has_every_crate() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("../crates");
    let on_disk: BTreeSet<String> = std::fs::read_dir(crates)
        .expect("the crates folder")
        .map(|e| {
            e.expect("a folder entry")
                .file_name()
                .to_string_lossy()
                .into()
        })
        .collect();
    let listed: BTreeSet<String> = CRATES.iter().map(|c| c.name.to_string()).collect();
    assert_eq!(on_disk, listed);
}

/// Sources from (path under `src/`, text) pairs.
fn sources(files: &[(&str, &str)]) -> Sources {
    files
        .iter()
        .map(|(path, text)| {
            let module: ModulePath = path
                .trim_end_matches(".rs")
                .split('/')
                .filter(|s| !s.is_empty() && *s != "mod" && *s != "lib")
                .map(String::from)
                .collect();
            (module, (path.to_string(), text.to_string()))
        })
        .collect()
}

/// The check itself fails where it should: an upward import (as `use`, in a group, as a path in
/// the code, through a name `lib.rs` re-exports), a root file importing a folder, and two files
/// importing each other; comments, strings and a test module's `use super::*` are no imports.
#[test]
fn the_check_finds_each_kind_of_breach() {
    let files = sources(&[
        (
            "lib.rs",
            "mod model; mod scene; mod error; pub use model::m::Thing;",
        ),
        ("error.rs", "fn f() -> crate::model::m::M { todo!() }"),
        ("scene/mod.rs", "pub mod s;"),
        (
            "scene/s.rs",
            "use crate::Thing;\nuse crate::{error::E, model::n::N};\n// use crate::solve::x;\n\
             const T: &str = \"crate::solve::x\";",
        ),
        ("model/mod.rs", "pub mod m; pub mod n;"),
        (
            "model/m.rs",
            "use super::n::N;\n#[cfg(test)]\nmod tests {\n    use super::*;\n}",
        ),
        ("model/n.rs", "pub fn f() { crate::model::m::g(); }"),
    ]);
    assert_eq!(
        problems(&CRATES[0], &files),
        [
            "error.rs imports upward from model/m.rs (`crate::model::m::M`)",
            "model/m.rs and model/n.rs import each other",
            "scene/s.rs imports upward from model/m.rs (`crate::Thing`)",
            "scene/s.rs imports upward from model/n.rs (`crate::model::n::N`)",
        ]
    );
}

/// The face and the reach: a file's module made public, an inline public module defining an
/// item, a file no `mod` declares, a folder in no layer, and an import between two layers of
/// the same level are found; an allowed public module and an inline module of re-exports
/// (with its docs and attributes) pass.
#[test]
fn the_check_finds_an_unsealed_face_and_unreached_files() {
    let files = sources(&[
        (
            "lib.rs",
            "pub mod sinks; mod plan; mod stray; mod step; pub mod option_names;\n\
             /// Limits.\npub mod limits {\n    #[doc(inline)]\n    pub use crate::step::{A, B};\n\
             }\npub mod helpers { pub fn f() {} }\npub(crate) mod extra;",
        ),
        ("option_names.rs", ""),
        ("extra.rs", ""),
        ("step.rs", "pub struct A; pub struct B;"),
        ("sinks/mod.rs", "mod csv;"),
        ("sinks/csv.rs", "use crate::plan::P;"),
        ("sinks/npz.rs", ""),
        ("plan/mod.rs", "pub struct P;"),
        ("stray/mod.rs", "mod inner;"),
        ("stray/inner.rs", ""),
    ]);
    let layering = Layering {
        name: "grasp-transfer",
        layers: &[(0, &["*"]), (1, &["sinks"]), (1, &["plan"])],
        public_modules: &["option_names"],
        min_files: 0,
    };
    assert_eq!(
        problems(&layering, &files),
        [
            "lib.rs makes a file's module public: `pub mod sinks;` (re-export its names instead)",
            "lib.rs: `pub mod helpers` does more than re-export",
            "sinks/csv.rs imports beside its layer from plan/mod.rs (`crate::plan::P`)",
            "sinks/npz.rs is declared by no `mod` of its parent",
            "stray/inner.rs is in no layer of its crate's table",
            "stray/mod.rs is in no layer of its crate's table",
        ]
    );
}
