#!/usr/bin/env python3
"""ARCHITECTURE.md kept true: its generated parts, the crates' dependencies (from each Cargo.toml)
and the table of every source file with its concept (the first sentence of its doc: a Rust
file's leading `//!` lines, a Python module's docstring); and two hand-written parts checked
against the tree, "Where things go" (every path it names exists) and "Code shape" (no tuple
parameter in library code, no function or file over its length).

    python3 scripts/architecture.py --check   # fails when ARCHITECTURE.md is stale or untrue
                                              # (scripts/lint.sh, run by CI)
    python3 scripts/architecture.py --write   # regenerates it after files were added, moved or
                                              # their first doc lines changed

The check also fails when a crate depends on a workspace crate that is not in a lower layer
(LAYERS below, the picture in ARCHITECTURE.md), or when a source file has no doc to show.
Every problem is one line naming the file (and line) and the rule.
"""

import argparse
import ast
import pathlib
import re
import sys
import tomllib

ROOT = pathlib.Path(__file__).resolve().parents[1]
DOC = ROOT / "ARCHITECTURE.md"

# The crates' layers, bottom first: a crate depends only on crates in lower layers.
LAYERS = {
    "grasp-model": 0,
    "grasp-io": 1,
    "grasp-transfer": 2,
    "grasp-batch": 2,
    "grasp-bench": 3,
    "grasp-cli": 4,
    "grasp-py": 4,
    "grasp-tests": 4,
}

# Where each crate's sources are (the `tests` member's files are tests, not listed).
SOURCES = {
    "grasp-model": ["crates/grasp-model/src"],
    "grasp-io": ["crates/grasp-io/src"],
    "grasp-transfer": ["crates/grasp-transfer/src"],
    "grasp-batch": ["crates/grasp-batch/src"],
    "grasp-bench": ["crates/grasp-bench/src", "crates/grasp-bench/benches"],
    "grasp-cli": ["crates/grasp-cli/src"],
    "grasp-py": ["crates/grasp-py/src"],
    "python/grasp": ["python/grasp"],
}

# grasp-model's folders in layer order (root files first), so its table reads bottom-up.
MODEL_ORDER = ["", "geometry", "scene", "model", "program", "solver", "solve", "sensors", "analysis"]

BEGIN = "<!-- BEGIN GENERATED {}: python3 scripts/architecture.py --write -->"
END = "<!-- END GENERATED {} -->"

# Words after which a period does not end a sentence.
ABBREVIATIONS = ("e.g", "i.e", "eq", "eqs", "cf", "vs", "Fig", "approx", "etc")
LONGEST = 240


def manifests():
    """Every workspace member's name and its Cargo.toml, parsed."""
    out = {}
    for path in sorted(ROOT.glob("crates/*/Cargo.toml")) + [ROOT / "tests/Cargo.toml"]:
        data = tomllib.loads(path.read_text())
        out[data["package"]["name"]] = data
    return out


def dependencies(manifest):
    """(normal, dev-only) dependency names of a manifest, target-specific ones included."""
    normal = set(manifest.get("dependencies", {}))
    for target in manifest.get("target", {}).values():
        normal |= set(target.get("dependencies", {}))
    dev = set(manifest.get("dev-dependencies", {})) - normal
    return normal, dev


def dependency_table(members):
    rows = [
        "| crate | layer | workspace crates | other crates | tests and benches only |",
        "|---|---|---|---|---|",
    ]
    problems = []
    for name in sorted(members, key=lambda n: (LAYERS.get(n, 99), n)):
        if name not in LAYERS:
            problems.append(f"{name}: not in scripts/architecture.py's LAYERS")
            continue
        normal, dev = dependencies(members[name])
        inside = sorted(d for d in normal | dev if d in members)
        for d in inside:
            if LAYERS.get(d, 99) >= LAYERS[name]:
                problems.append(f"{name} depends on {d}, which is not in a lower layer")
        ticks = lambda names: ", ".join(f"`{n}`" for n in sorted(names)) or "-"
        rows.append(
            f"| `{name}` | {LAYERS[name]} | {ticks(d for d in normal if d in members)} | "
            f"{ticks(d for d in normal if d not in members)} | {ticks(dev)} |"
        )
    return "\n".join(rows), problems


def rust_doc(text):
    """The leading `//!` paragraph of a Rust file, as one line."""
    lines = []
    for line in text.splitlines():
        if not line.startswith("//!"):
            break
        words = line[3:].strip()
        if not words and lines:
            break
        if words and not words.startswith("#"):
            lines.append(words)
        elif words.startswith("#"):
            lines.append(words.lstrip("# ").rstrip() + ".")
    return " ".join(lines)


def python_doc(text):
    doc = ast.get_docstring(ast.parse(text)) or ""
    return " ".join(doc.split("\n\n")[0].split())


def first_sentence(paragraph):
    """The paragraph's first sentence, links reduced to their text, at most LONGEST characters."""
    text = re.sub(r"\[(`[^`\]]+`)\](\([^)]*\))?", r"\1", paragraph)
    text = re.sub(r"\[([^\]]+)\]\(([^)]*)\)", r"\1", text)
    for m in re.finditer(r"\.(\s+)(?=[A-Z])", text):
        before = text[: m.start()]
        if not before.endswith(ABBREVIATIONS):
            text = before + "."
            break
    if len(text) > LONGEST:
        text = text[: text.rfind(" ", 0, LONGEST)] + " ..."
    elif text.endswith(":"):
        text = text[:-1] + "."
    return text.replace("|", "\\|")


def source_files(folder):
    base = ROOT / folder
    suffix = ".py" if folder.startswith("python") else ".rs"
    return sorted(p for p in base.rglob(f"*{suffix}") if p.is_file())


def order_key(crate, relative):
    """A folder's files before its subfolders; grasp-model's folders in layer order."""
    *folders, name = relative.parts
    key = [(1, f) for f in folders] + [(0, name)]
    if crate == "grasp-model":
        top = folders[0] if folders else ""
        rank = MODEL_ORDER.index(top) if top in MODEL_ORDER else len(MODEL_ORDER)
        key = [(rank,)] + key
    return key


def file_table(crate, folders):
    rows = ["| file | concept |", "|---|---|"]
    problems = []
    entries = []
    for folder in folders:
        for path in source_files(folder):
            relative = path.relative_to(ROOT / folder)
            shown = relative if len(folders) == 1 else pathlib.Path(folder).name / relative
            text = path.read_text()
            doc = python_doc(text) if path.suffix == ".py" else rust_doc(text)
            if not doc:
                problems.append(f"{path.relative_to(ROOT)}: no doc to show (a `//!` line first)")
            entries.append((order_key(crate, shown), shown, first_sentence(doc)))
    for _, shown, concept in sorted(entries):
        rows.append(f"| `{shown.as_posix()}` | {concept} |")
    return "\n".join(rows), problems


def file_tables():
    parts, problems = [], []
    for crate, folders in SOURCES.items():
        table, found = file_table(crate, folders)
        problems += found
        where = ", ".join(f"`{f}/`" for f in folders)
        parts.append(f"### {crate} ({where})\n\n{table}")
    return "\n\n".join(parts), problems


def replace_block(doc, name, body):
    begin, end = BEGIN.format(name), END.format(name)
    if begin not in doc or end not in doc:
        raise SystemExit(f"ARCHITECTURE.md lacks the markers of the generated {name}: {begin}")
    head, rest = doc.split(begin, 1)
    _, tail = rest.split(end, 1)
    return f"{head}{begin}\n\n{body}\n\n{end}{tail}"


# ---- "Where things go": every path the section names exists ----

WHERE = "Where things go"
# A path starting with one of these is from the repository root; any other is from the `src/`
# folder its subsection's heading names (ARCHITECTURE.md says so at the section's top).
ROOT_FOLDERS = ("crates/", "tests/", "docs/", "python/", "scripts/")
# A span in backticks is a path when it is one (no spaces) and ends with `/` or one of these.
PATH_SPAN = re.compile(r"[\w.-]+(/[\w.-]+)*/?")
PATH_ENDINGS = (".rs", ".py", ".pyi", ".md", ".json", ".toml", ".sh")
PLANNED = " (planned)"


def hand_section(doc, title):
    """The text of `## {title}` up to the next `## ` heading, and its offset in `doc`; None
    when there is no such section."""
    m = re.search(rf"^## {re.escape(title)}\n", doc, re.M)
    if not m:
        return None
    end = re.search(r"^## ", doc[m.end():], re.M)
    return doc[m.start(): m.end() + end.start() if end else len(doc)], m.start()


def named_paths(text):
    """Every path `text` names in backticks: (offset, path, planned)."""
    out = []
    for m in re.finditer(r"`([^`\n]*)`", text):
        span = m.group(1)
        if PATH_SPAN.fullmatch(span) and (span.endswith("/") or span.endswith(PATH_ENDINGS)):
            out.append((m.start(), span, text.startswith(PLANNED, m.end())))
    return out


def where_problems(doc):
    """Every path "Where things go" names exists (a folder as a folder); a path marked
    (planned) does not exist yet, and its folder does."""
    found = hand_section(doc, WHERE)
    if found is None:
        return [f'ARCHITECTURE.md has no "## {WHERE}" section']
    section, at = found
    problems = []
    # Subsections: the intro (paths from the root only), then one per kind of extension.
    starts = [0] + [m.start() for m in re.finditer(r"^### ", section, re.M)] + [len(section)]
    for begin, end in zip(starts, starts[1:]):
        part = section[begin:end]
        heading = part.splitlines()[0] if part.startswith("### ") else ""
        base = next((p for _, p, _ in named_paths(heading) if p.endswith("/src/")), None)
        paths = named_paths(part)
        line = lambda offset: doc.count("\n", 0, at + begin + offset) + 1
        if heading and not paths:
            problems.append(f"ARCHITECTURE.md:{line(0)}: {heading[4:]!r} names no file")
        for offset, path, planned in paths:
            why = path_problem(path, planned, base)
            if why:
                problems.append(f'ARCHITECTURE.md:{line(offset)}: "{WHERE}" names `{path}`: {why}')
    return problems


def path_problem(path, planned, base):
    """What is wrong with a path "Where things go" names (`base`: the `src/` folder of its
    heading, or None); None when nothing is."""
    if path.startswith(ROOT_FOLDERS):
        target = ROOT / path
    elif base:
        target = ROOT / base / path
    else:
        return "it is neither from the repository root nor under a heading naming its crate's src/"
    shown = target.relative_to(ROOT).as_posix() + ("/" if path.endswith("/") else "")
    exists = target.is_dir() if path.endswith("/") else target.is_file()
    if planned and exists:
        return f"it is marked (planned) but {shown} exists: drop the mark, say what it holds"
    if planned and not target.parent.is_dir():
        folder = target.parent.relative_to(ROOT).as_posix()
        return f"it is planned in {folder}/, which does not exist"
    if not planned and not exists:
        return f"{shown} does not exist: name the file as it is now"
    return None


# ---- "Code shape": tuple parameters, long functions, long files (tests excluded) ----

# grasp-cli is the one binary; every other crate under crates/ is a library.
BINARY_CRATES = ("grasp-cli",)
LIBRARY_FUNCTION_LINES = 80
BINARY_FUNCTION_LINES = 100
LIBRARY_FILE_LINES = 800
SHAPE = 'ARCHITECTURE.md, "Code shape"'


def code_only(text):
    """`text` with its comments and its string and character literals blanked (every character
    but a line break becomes a space), so that whatever is left (braces, parentheses, `fn`,
    `#[cfg(test)]`) is code. Offsets and lines are those of `text`."""
    out = list(text)
    i = 0
    while i < len(text):
        end = literal_end(text, i)
        if end > i:
            for k in range(i, end):
                if out[k] != "\n":
                    out[k] = " "
            i = end
        else:
            i += 1
    return "".join(out)


def literal_end(t, i):
    """The end of the comment or literal starting at `i`; `i` itself when none starts there."""
    two = t[i:i + 2]
    if two == "//":
        end = t.find("\n", i)
        return len(t) if end < 0 else end
    if two == "/*":
        return block_comment_end(t, i)
    if t[i] == '"':
        return quoted_end(t, i + 1)
    if t[i] == "'":
        return char_end(t, i)
    if t[i] in "rbc" and not (i > 0 and is_ident(t[i - 1])):
        # Prefixed literals: r"..", r#".."#, b"..", br"..", c"..", cr"..", b'.'.
        k = i + 1 if t[i] in "bc" and t[i + 1:i + 2] == "r" else i
        if t[k] == "r":
            return raw_end(t, i, k + 1)
        if t[i + 1:i + 2] == '"':
            return quoted_end(t, i + 2)
        if t[i] == "b" and t[i + 1:i + 2] == "'":
            end = char_end(t, i + 1)
            return end if end > i + 1 else i
    return i


def is_ident(ch):
    return ch.isalnum() or ch == "_"


def block_comment_end(t, i):
    """The end of the block comment at `i` (block comments nest)."""
    depth, k = 0, i
    while k < len(t):
        if t.startswith("/*", k):
            depth, k = depth + 1, k + 2
        elif t.startswith("*/", k):
            depth, k = depth - 1, k + 2
            if depth == 0:
                return k
        else:
            k += 1
    return len(t)


def quoted_end(t, k):
    """The end of a string whose text starts at `k` (after its opening quote)."""
    while k < len(t):
        if t[k] == "\\":
            k += 2
        elif t[k] == '"':
            return k + 1
        else:
            k += 1
    return len(t)


def raw_end(t, i, k):
    """The end of a raw string starting at `i` whose hashes start at `k`; `i` when there is no
    quote after them (a raw identifier, `r#type`, or a plain one)."""
    hashes = len(t[k:]) - len(t[k:].lstrip("#"))
    if t[k + hashes:k + hashes + 1] != '"':
        return i
    close = t.find('"' + "#" * hashes, k + hashes + 1)
    return len(t) if close < 0 else close + 1 + hashes


def char_end(t, i):
    """The end of the character literal at `i` (`'x'`, `'\\''`, `'\\u{..}'`); `i` for a
    lifetime or a label (`'a`, `'outer:`)."""
    if t[i + 1:i + 2] == "\\":
        end = t.find("'", i + 3)
        return len(t) if end < 0 else end + 1
    if t[i + 2:i + 3] == "'" and t[i + 1:i + 2] not in ("", "\n"):
        return i + 3
    return i


def closing(code, i):
    """The offset of the bracket closing the one at `i` (`(`, `[`, `{` or `<`; in angle
    brackets the `>` of `->` closes nothing); len(code) when it is not closed."""
    opening = code[i]
    shut = {"(": ")", "[": "]", "{": "}", "<": ">"}[opening]
    depth = 0
    for k in range(i, len(code)):
        ch = code[k]
        if ch == opening:
            depth += 1
        elif ch == shut and not (shut == ">" and code[k - 1] == "-"):
            depth -= 1
            if depth == 0:
                return k
    return len(code)


def top_level(text, what):
    """Offsets in `text` of the characters in `what` outside any bracket (`->` is no bracket)."""
    out, depth = [], 0
    for k, ch in enumerate(text):
        if ch in "([{<" and not (ch == "<" and text[k + 1:k + 2] == "="):
            depth += 1
        elif ch in ")]}>" and not (ch == ">" and text[k - 1:k] in ("-", "=")):
            depth = max(depth - 1, 0)
        elif depth == 0 and ch in what:
            out.append(k)
    return out


def item_end(code, i):
    """The end of the item starting at `i`: after its `;` or its braced body, whichever comes
    first outside parentheses and square brackets; and whether it had a body."""
    depth, k = 0, i
    while k < len(code):
        ch = code[k]
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        elif depth == 0 and ch == ";":
            return k + 1, False
        elif depth == 0 and ch == "{":
            return closing(code, k) + 1, True
        k += 1
    return len(code), False


CFG_TEST = re.compile(r"#\s*\[\s*cfg\s*\(\s*test\s*\)\s*\]")
ATTRIBUTE = re.compile(r"\s*#\s*\[")


def test_items(code):
    """The `#[cfg(test)]` items of `code`: their (start, end) offsets, and the names of the
    modules declared without a body (`#[cfg(test)] mod tests;`: a file of tests)."""
    ranges, modules = [], []
    for m in CFG_TEST.finditer(code):
        k = m.end()
        while (a := ATTRIBUTE.match(code, k)) is not None:
            k = closing(code, a.end() - 1) + 1
        end, body = item_end(code, k)
        ranges.append((m.start(), end))
        declared = re.fullmatch(r"\s*(pub(\([\w\s:]+\))?\s+)?mod\s+(\w+)\s*;", code[k:end])
        if declared and not body:
            modules.append(declared.group(3))
    return ranges, modules


def child_module(path, name):
    """Where the module `name` declared in `path` lives: its file, or its folder."""
    folder = path.parent if path.name in ("lib.rs", "main.rs", "mod.rs") else path.with_suffix("")
    return [folder / f"{name}.rs", folder / name]


def is_tuple(text):
    """True when `text` (a pattern or a type) is a tuple: parentheses around a top-level comma,
    behind any references (`&(A, B)`, `&'a mut (A,)`). A parenthesised type,
    `&(dyn Fn(usize) + Sync)`, is not one, nor the unit `()`."""
    bare = re.sub(r"^(\s*(&|'\w+|mut\b|ref\b|\*\s*const\b|\*\s*mut\b))*\s*", "", text)
    if not bare.startswith("("):
        return False
    return bool(top_level(bare[1:closing(bare, 0)], ","))


def tuple_parameter(parameter):
    """Why `parameter` (one, as written between the commas of a signature) is a tuple parameter:
    its pattern or its type is a tuple; None when it is not one."""
    parameter = re.sub(r"#\s*\[[^\]]*\]", "", parameter).strip()
    colons = [k for k in top_level(parameter, ":")
              if parameter[k - 1:k] != ":" and parameter[k + 1:k + 2] != ":"]
    if not colons:
        return None  # `self`, `&mut self`
    pattern, kind = parameter[:colons[0]], parameter[colons[0] + 1:]
    if is_tuple(pattern):
        return "its pattern is a tuple"
    if is_tuple(kind):
        return "its type is a tuple"
    return None


FN = re.compile(r"\bfn\s+([A-Za-z_]\w*)")


def functions(code):
    """Every function of `code`: (offset of `fn`, name, parameters as written, offset of the
    end of its body or None for a declaration without one)."""
    out = []
    for m in FN.finditer(code):
        k = m.end()
        while k < len(code) and code[k].isspace():
            k += 1
        if code[k:k + 1] == "<":
            k = closing(code, k) + 1
            while k < len(code) and code[k].isspace():
                k += 1
        if code[k:k + 1] != "(":
            continue
        shut = closing(code, k)
        inner = code[k + 1:shut]
        cuts = [-1] + top_level(inner, ",") + [len(inner)]
        parameters = [inner[a + 1:b] for a, b in zip(cuts, cuts[1:]) if inner[a + 1:b].strip()]
        end, body = item_end(code, shut + 1)
        out.append((m.start(), m.group(1), parameters, end - 1 if body else None))
    return out


def shape_problems_of(shown, code, binary):
    """The code-shape offences of one file, its `code` blanked by `code_only` (`shown` is its
    path in messages)."""
    ranges = test_items(code)[0]
    inside = lambda offset: any(a <= offset < b for a, b in ranges)
    line = lambda offset: code.count("\n", 0, offset) + 1
    problems = []
    for start, name, parameters, end in functions(code):
        if inside(start):
            continue
        for p in parameters if not binary else []:
            why = tuple_parameter(p)
            if why:
                problems.append(f"{shown}:{line(start)}: fn {name}: tuple parameter "
                                f"`{' '.join(p.split())}` ({why}); give a named struct with "
                                f"documented fields ({SHAPE})")
        limit = BINARY_FUNCTION_LINES if binary else LIBRARY_FUNCTION_LINES
        if end is not None and line(end) - line(start) + 1 > limit:
            kind = "a grasp-cli" if binary else "a library"
            problems.append(f"{shown}:{line(start)}: fn {name} is {line(end) - line(start) + 1} "
                            f"lines; {kind} function has at most {limit} ({SHAPE})")
    if not binary:
        tests = set()
        for a, b in ranges:
            tests.update(range(line(a), line(max(a, b - 1)) + 1))
        lines = len(code.splitlines()) - len(tests)
        if lines > LIBRARY_FILE_LINES:
            problems.append(f"{shown}: {lines} lines outside its tests; a library file has at "
                            f"most {LIBRARY_FILE_LINES} ({SHAPE})")
    return problems


def shape_problems():
    """The code-shape offences of every crate's `src/` (tests excluded: `#[cfg(test)]` items,
    `*_tests.rs` files, the files a `#[cfg(test)] mod` declares)."""
    problems = []
    for src in sorted(ROOT.glob("crates/*/src")):
        binary = src.parent.name in BINARY_CRATES
        files = {p: code_only(p.read_text()) for p in sorted(src.rglob("*.rs"))}
        tests = {p for p in files if p.name == "tests.rs" or p.name.endswith("_tests.rs")}
        for path, code in files.items():
            for name in test_items(code)[1]:
                tests.update(child_module(path, name))
        for path, code in files.items():
            if path not in tests and not tests.intersection(path.parents):
                problems += shape_problems_of(path.relative_to(ROOT).as_posix(), code, binary)
    return problems + shape_self_check()


# A sample the shape check must read exactly: offences in code; none in tests, comments or
# literals; a parenthesised trait-object type and a slice of pairs are no tuples; a function of
# exactly 80 lines is allowed, one of 81 is not.
SAMPLE = r'''
/* a block comment /* nested */ with a brace { and fn hidden((a, b): (u8, u8)) */
fn pattern((a, b): (usize, f64)) {}
fn reference<'a, F: Fn(usize) -> f64>(f: F, pair: &'a mut (usize, f64),
                                      done: &(dyn Fn(usize, f64) + Sync)) {}
fn many(x: HashMap<usize, f64>, y: [u8; 2], s: &str, pairs: &[(u8, u8)]) -> Result<[u8; 2], ()> {
    let text = "a brace { and fn fake((a, b): (u8, u8)) in a string \" still {";
    let raw = br#"another { "quoted" one"#;
    let chars = ['{', '"', '\'', '\u{7b}', b'}'];
    let life: &'static str = "}";
    // a line comment {
    'outer: loop { break 'outer; }
}
trait Declared { fn declared(&self, mut pair: (u8, u8)); }
#[cfg(test)]
fn test_helper((a, b): (u8, u8)) {}
''' + "fn exactly_80() {\n" + "    let _ = 1;\n" * 78 + "}\n" \
    + "fn long() {\n" + "    let _ = 1;\n" * 79 + "}\n" + r'''
#[cfg(test)]
#[allow(unused)]
mod tests {
    fn in_test((a, b): (u8, u8)) { "}"; }
}
'''
SAMPLE_OFFENCES = [
    "sample.rs:3: fn pattern: tuple parameter `(a, b): (usize, f64)` (its pattern is a tuple)",
    "sample.rs:4: fn reference: tuple parameter `pair: &'a mut (usize, f64)` (its type is a tuple)",
    "sample.rs:14: fn declared: tuple parameter `mut pair: (u8, u8)` (its type is a tuple)",
    "sample.rs:97: fn long is 81 lines; a library function has at most 80",
]


def shape_self_check():
    """The check run on SAMPLE, so that a checker that misreads Rust fails too."""
    found = [p.split("; give")[0].split(f" ({SHAPE})")[0]
             for p in shape_problems_of("sample.rs", code_only(SAMPLE), False)]
    if found == SAMPLE_OFFENCES:
        return []
    return [f"the code-shape check misreads its sample: found {found}, expected {SAMPLE_OFFENCES}"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true", help="fail if ARCHITECTURE.md is stale (default)")
    mode.add_argument("--write", action="store_true", help="regenerate ARCHITECTURE.md")
    args = parser.parse_args()
    deps, problems = dependency_table(manifests())
    files, found = file_tables()
    problems += found
    old = DOC.read_text()
    problems += where_problems(old)
    problems += shape_problems()
    new = replace_block(replace_block(old, "dependencies", deps), "files", files)
    if args.write:
        DOC.write_text(new)
    elif new != old:
        import difflib

        diff = difflib.unified_diff(old.splitlines(), new.splitlines(), "ARCHITECTURE.md", "generated", lineterm="", n=0)
        print("\n".join(list(diff)[:60]))
        problems.append("ARCHITECTURE.md is stale: run `python3 scripts/architecture.py --write`")
    for p in problems:
        print(f"architecture: {p}", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
