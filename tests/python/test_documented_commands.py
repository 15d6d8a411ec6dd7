"""Every command block of the README, the guide (docs/guide/*.md) and docs/benchmarks.md runs.

Each ```sh, ```console and ```python block is one test, run in a fresh scratch folder holding a
copy of `examples/` (never in the checkout), as a reader would paste it from the repository root:

- `cargo run --release -- ARGS` and `grasp ARGS` run the built CLI ($GRASP_BIN, as the other
  tests); `python` is this interpreter, which has the package installed (scripts/test.sh runs
  `pip install .` before the Python tests); a `pip install ...` line checks instead that what it
  installs imports (`grasp`; with `[mujoco]` also `mujoco` and `rerun`);
- a ```sh block runs as one bash script with `set -euo pipefail` (so every command's exit status is
  checked), a ```console block runs its `$ ` lines and the lines shown under them are its expected
  output (`...` stands for any text), a ```python block runs as a script;
- every file a command says it writes (`--json`, `--npz`, `--csv`, `--mcap`, `--rrd`, `--plot`,
  `--out`, `--report`, `--save-rollout`; `"out/..."` in Python) must exist afterwards and not be empty,
  except after a command documented to end in an outcome (`... || test $? = 2`: it writes nothing);
- an HTML comment on the line before a block marks it: `<!-- doc-test: skip: REASON -->` (it
  cannot run here: a desktop viewer, a cluster; the reason shows in the test report) or
  `<!-- doc-test: long -->` (over about 20 s; it runs all the same). One command of the README's
  first block is left out with its reason (LEFT_OUT below): the test command itself.
"""

import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys
import time

import pytest

from conftest import ROOT, checker

DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md")), ROOT / "docs" / "benchmarks.md"]
MARKER = re.compile(r"<!--\s*doc-test:\s*(skip|long)\s*(?::\s*(.*?))?\s*-->")
OUTPUT_FLAGS = {"--json", "--npz", "--csv", "--mcap", "--rrd", "--plot", "--out", "--report", "--save-rollout"}
# Commands of a block that are not run, and why (each is printed in the test's output).
LEFT_OUT = {
    "bash scripts/test.sh": "the test command itself (it runs this test)",
}


class Block:
    def __init__(self, path, line, lang, body, marker, reason):
        self.path, self.line, self.lang, self.body = path, line, lang, body
        self.marker, self.reason = marker, reason

    @property
    def id(self):
        return f"{self.path.relative_to(ROOT)}:{self.line}"


def blocks():
    found = []
    for path in DOCUMENTS:
        lines = path.read_text().split("\n")
        i = 0
        while i < len(lines):
            m = re.fullmatch(r"```(sh|console|python)\s*", lines[i])
            if not m:
                i += 1
                continue
            start = i
            i += 1
            body = []
            while lines[i] != "```":
                body.append(lines[i])
                i += 1
            before = next((lines[k] for k in range(start - 1, -1, -1) if lines[k].strip()), "")
            mark = MARKER.fullmatch(before.strip())
            found.append(Block(path, start + 1, m.group(1), "\n".join(body) + "\n",
                               mark.group(1) if mark else None, mark.group(2) if mark else None))
            i += 1
    return found


BLOCKS = blocks()


def test_the_documents_have_command_blocks():
    # The runner finds the blocks it is meant to run: the README's two commands among them.
    langs = {b.lang for b in BLOCKS}
    assert {"sh", "console", "python"} <= langs, langs
    readme = [b for b in BLOCKS if b.path.name == "README.md" and b.path.parent == ROOT]
    assert any("bash scripts/test.sh" in b.body and "cargo run --release -- transfer" in b.body for b in readme)
    assert all(b.reason for b in BLOCKS if b.marker == "skip"), "a skipped block gives its reason"


def commands(block):
    """The commands of a shell block, continuation lines joined, and for a console block the
    expected output lines under them."""
    text = block.body.replace("\\\n", " ")
    cmds, expected = [], []
    for line in text.split("\n"):
        if block.lang == "console":
            if line.startswith("$ "):
                cmds.append(line[2:].strip())
            elif line.strip():
                expected.append(line.strip())
        elif line.strip() and not line.lstrip().startswith("#"):
            cmds.append(line.strip())
    return cmds, expected


def shell_line(cmd):
    """A documented command as this test runs it (see the module's docstring)."""
    if cmd.startswith("pip install"):
        modules = ["grasp"] + (["mujoco", "rerun"] if "[mujoco]" in cmd else [])
        return f"python -c 'import {', '.join(modules)}'"
    return re.sub(r"^cargo run --release --(?= )", "grasp", cmd)


def written_files(cmd):
    try:
        words = shlex.split(cmd)
    except ValueError:
        return []
    return [words[k + 1] for k, w in enumerate(words[:-1]) if w in OUTPUT_FLAGS]


def check_written(folder, names):
    for name in names:
        path = folder / name
        # A prefix (`--out out/handoff` of grasp.mujoco handoff) names the files it begins.
        found = [path] if path.exists() else list(path.parent.glob(path.name + ".*"))
        assert found, f"{name} was not written"
        for p in found:
            assert p.is_dir() or p.stat().st_size > 0, f"{p.name} is empty"


@pytest.fixture
def scratch(tmp_path):
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    return tmp_path


def environment(grasp_bin, folder):
    env = dict(os.environ)
    bindir = folder / ".bin"
    bindir.mkdir()
    # `grasp` and `python` as a reader's shell would find them: the built CLI, this interpreter (its
    # folder first on the PATH: a venv's python must be called by its own path to find its packages).
    (bindir / "grasp").symlink_to(os.path.abspath(grasp_bin))
    env["PATH"] = f"{bindir}{os.pathsep}{pathlib.Path(sys.executable).parent}{os.pathsep}{env['PATH']}"
    return env


@pytest.mark.parametrize("block", BLOCKS, ids=[b.id for b in BLOCKS])
def test_documented_block_runs(block, scratch, grasp_bin):
    if block.marker == "skip":
        pytest.skip(f"{block.id}: {block.reason}")
    if "grasp.mujoco" in block.body or "[mujoco]" in block.body:
        # The optional extra: installed by scripts/install-checkers.sh, where its absence fails.
        checker("mujoco", "the MuJoCo blocks need the optional extra: pip install '.[mujoco]'")
        checker("rerun", "the MuJoCo blocks need the optional extra: pip install '.[mujoco]'")
    env = environment(grasp_bin, scratch)
    started = time.monotonic()
    if block.lang == "python":
        proc = subprocess.run([sys.executable, "-c", block.body], cwd=scratch, env=env,
                              capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
        check_written(scratch, re.findall(r"\"(out/[^\"]+)\"", block.body))
    else:
        cmds, expected = commands(block)
        run = []
        for cmd in cmds:
            if cmd in LEFT_OUT:
                print(f"{block.id}: not run here: `{cmd}`: {LEFT_OUT[cmd]}")
                continue
            run.append(cmd)
        assert run, f"{block.id} has no command to run"
        script = "set -euo pipefail\n" + "\n".join(shell_line(c) for c in run) + "\n"
        proc = subprocess.run(["bash", "-c", script], cwd=scratch, env=env, capture_output=True, text=True)
        assert proc.returncode == 0, f"exit {proc.returncode}\n{script}\n{proc.stdout}\n{proc.stderr}"
        out = proc.stdout + proc.stderr
        for line in expected:
            for piece in (p.strip() for p in line.split("...")):
                assert piece in out, f"{block.id}: the output has no `{piece}`:\n{out}"
        for cmd in run:
            if not re.search(r"\|\| test \$\? = \d+$", cmd):
                check_written(scratch, written_files(cmd))
    print(f"{block.id}: {block.lang} block ran in {time.monotonic() - started:.1f} s"
          + (" (marked long)" if block.marker == "long" else ""))


def slug(heading):
    """GitHub's anchor of a Markdown heading: lower case, punctuation dropped, spaces as hyphens."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def anchors(path):
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)
    return {slug(m.group(1)) for m in re.finditer(r"^#+ (.*)$", text, re.M)}


def test_the_documents_links_resolve():
    # Every relative link of the README, the guide and the benchmarks names a file of the
    # checkout, and every #anchor a heading of its file (links into the old long README broke
    # when its sections moved into the guide).
    broken = []
    for path in DOCUMENTS:
        text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"[a-z]+:", target):
                continue
            file, _, anchor = target.partition("#")
            dest = (path.parent / file).resolve() if file else path
            if not dest.exists():
                broken.append(f"{path.relative_to(ROOT)}: {target}: no such file")
            elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                broken.append(f"{path.relative_to(ROOT)}: {target}: no such heading")
    assert not broken, "\n".join(broken)
