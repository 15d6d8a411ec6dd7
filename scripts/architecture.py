#!/usr/bin/env python3
"""ARCHITECTURE.md's generated parts: the crates' dependencies (from each Cargo.toml) and the
table of every source file with its concept (the first sentence of its doc: a Rust file's
leading `//!` lines, a Python module's docstring).

    python3 scripts/architecture.py --check   # fails when ARCHITECTURE.md is stale (scripts/test.sh)
    python3 scripts/architecture.py --write   # regenerates it after files were added, moved or
                                              # their first doc lines changed

The check also fails when a crate depends on a workspace crate that is not in a lower layer
(LAYERS below, the picture in ARCHITECTURE.md), or when a source file has no doc to show.
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
MODEL_ORDER = ["", "geometry", "scene", "model", "program", "solver", "solve", "analysis"]

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
