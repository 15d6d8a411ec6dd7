"""Every command block of the README, the guide (docs/guide/*.md) and docs/benchmarks.md runs,
in order, as a reader pastes them one after another from the repository root.

Each ```sh, ```console and ```python block is one test. The blocks of one document (a chapter)
share one scratch copy of the checkout's `examples/` and `.gitignore` (never the checkout
itself), and run in the document's order: a block never runs before the blocks above it (a test
selected alone runs them first), so a block sees the files those wrote, and one that writes a
file an earlier one wrote must say so (`--force`, `overwrite=True`) as a reader would need to.
Once a block fails, the later blocks of its chapter fail without running, naming it.

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
- a reader's checkout stays clean: the scratch copy is a git repository with the checkout's
  `.gitignore`, and after each block every file it added lies in an ignored place (`out/`) and
  no file of the copy changed; otherwise the block fails, naming the file;
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
        path = self.path.relative_to(ROOT) if self.path.is_relative_to(ROOT) else self.path.name
        return f"{path}:{self.line}"


def blocks_of(path):
    """The command blocks of one document, in its order."""
    found = []
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


CHAPTERS = {path: blocks_of(path) for path in DOCUMENTS}
BLOCKS = [b for path in DOCUMENTS for b in CHAPTERS[path]]


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


def writes(block):
    """Each file a block says it writes, with whether it says to replace one already there
    (`--force`; Python: `overwrite=True`)."""
    if block.lang == "python":
        return [(name, "overwrite=True" in block.body) for name in re.findall(r"\"(out/[^\"]+)\"", block.body)]
    return [(name, "--force" in cmd.split()) for cmd in commands(block)[0] for name in written_files(cmd)]


def check_written(block, folder, names):
    for name in names:
        path = folder / name
        # A prefix (`--out out/handoff` of grasp.mujoco handoff) names the files it begins.
        found = [path] if path.exists() else list(path.parent.glob(path.name + ".*"))
        assert found, f"{block.id}: {name} was not written"
        for p in found:
            assert p.is_dir() or p.stat().st_size > 0, f"{block.id}: {p.name} is empty"


def git(folder, *args):
    # The checkout's own ignore rules only: no user-wide excludes file, no system config.
    proc = subprocess.run(["git", "-c", "core.excludesFile=/dev/null", *args], cwd=folder,
                          capture_output=True, text=True, env=dict(os.environ, GIT_CONFIG_NOSYSTEM="1"))
    assert proc.returncode == 0, f"git {' '.join(args)}: {proc.stderr}"
    return proc.stdout


def changes(folder):
    """What a reader's `git status` would show after the blocks: files added outside the
    ignored places (`??`), files of the copy changed or removed (`M`)."""
    added = git(folder, "ls-files", "-z", "--others", "--exclude-standard").split("\0")
    changed = git(folder, "ls-files", "-z", "--modified").split("\0")
    return [f"?? {name}" for name in added if name] + [f"M  {name}" for name in changed if name]


class Chapter:
    """One document's scratch copy and how far through its blocks it has run."""

    def __init__(self, blocks, base, grasp_bin):
        self.blocks, self.done, self.failed, self.skipped = blocks, 0, None, None
        self.folder = base / "checkout"
        self.folder.mkdir()
        shutil.copytree(ROOT / "examples", self.folder / "examples")
        shutil.copy(ROOT / ".gitignore", self.folder / ".gitignore")
        git(self.folder, "init", "--quiet")
        git(self.folder, "add", "--all")
        self.env = environment(grasp_bin, base / "bin")

    def run_through(self, block):
        """Runs the blocks above `block` not yet run, then `block` (a skipped one skips)."""
        k = self.blocks.index(block)
        assert self.done <= k, f"{block.id} ran already"
        while self.done <= k:
            current = self.blocks[self.done]
            if self.failed:
                pytest.fail(f"{block.id}: not run: {self.failed}, above it in its chapter, failed")
            if self.skipped:
                pytest.skip(f"{block.id}: not run: {self.skipped}, above it in its chapter, did not run")
            self.done += 1
            if current.marker == "skip":
                if current is block:
                    pytest.skip(f"{block.id}: {block.reason}")
                continue
            try:
                run_block(current, self.folder, self.env)
            except pytest.skip.Exception:
                self.skipped = current.id
                raise
            except BaseException:
                self.failed = current.id
                raise


def environment(grasp_bin, bindir):
    env = dict(os.environ)
    bindir.mkdir()
    # `grasp` and `python` as a reader's shell would find them: the built CLI, this interpreter (its
    # folder first on the PATH: a venv's python must be called by its own path to find its packages).
    (bindir / "grasp").symlink_to(os.path.abspath(grasp_bin))
    env["PATH"] = f"{bindir}{os.pathsep}{pathlib.Path(sys.executable).parent}{os.pathsep}{env['PATH']}"
    return env


def run_block(block, folder, env):
    """Runs one block in the chapter's scratch copy and checks what it printed and wrote."""
    if "grasp.mujoco" in block.body or "[mujoco]" in block.body:
        # The optional extra: installed by scripts/install-checkers.sh, where its absence fails.
        checker("mujoco", "the MuJoCo blocks need the optional extra: pip install '.[mujoco]'")
        checker("rerun", "the MuJoCo blocks need the optional extra: pip install '.[mujoco]'")
    started = time.monotonic()
    if block.lang == "python":
        proc = subprocess.run([sys.executable, "-c", block.body], cwd=folder, env=env,
                              capture_output=True, text=True)
        assert proc.returncode == 0, f"{block.id}: exit {proc.returncode}\n{proc.stderr}"
        check_written(block, folder, re.findall(r"\"(out/[^\"]+)\"", block.body))
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
        proc = subprocess.run(["bash", "-c", script], cwd=folder, env=env, capture_output=True, text=True)
        assert proc.returncode == 0, f"{block.id}: exit {proc.returncode}\n{script}\n{proc.stdout}\n{proc.stderr}"
        out = proc.stdout + proc.stderr
        for line in expected:
            for piece in (p.strip() for p in line.split("...")):
                assert piece in out, f"{block.id}: the output has no `{piece}`:\n{out}"
        for cmd in run:
            if not re.search(r"\|\| test \$\? = \d+$", cmd):
                check_written(block, folder, written_files(cmd))
    dirty = changes(folder)
    assert not dirty, (f"{block.id} leaves the reader's checkout unclean (`git status`: ?? a file it wrote "
                       f"outside the ignored places such as out/, M a file of the checkout it changed or removed):\n"
                       + "\n".join(dirty) + f"\n{block.body}")
    print(f"{block.id}: {block.lang} block ran in {time.monotonic() - started:.1f} s"
          + (" (marked long)" if block.marker == "long" else ""))


def test_a_file_two_chapters_write_is_replaced_knowingly():
    # A reader runs the README, then the guide's chapters in whatever order, in one checkout:
    # a file that more than one chapter writes is written with `--force` (Python:
    # `overwrite=True`) by each chapter but the README, or the chapter the reader runs second
    # stops at the refusal to overwrite it (the guide's solve of cube_a and MuJoCo's pinch did).
    writers = {}
    for block in BLOCKS:
        for name, forced in writes(block):
            writers.setdefault(name, []).append((block, forced))
    unforced = [f"{block.id} writes {name} without --force (also written by "
                + ", ".join(b.id for b, _ in found if b.path != block.path) + ")"
                for name, found in writers.items() if len({b.path for b, _ in found}) > 1
                for block, forced in found if not forced and block.path != ROOT / "README.md"]
    assert not unforced, "\n".join(unforced)


@pytest.fixture(scope="module")
def chapters(tmp_path_factory, grasp_bin):
    """The chapters' scratch copies, each made when its first block runs."""
    made = {}

    def chapter(path):
        if path not in made:
            made[path] = Chapter(CHAPTERS[path], tmp_path_factory.mktemp(path.stem), grasp_bin)
        return made[path]

    return chapter


@pytest.mark.parametrize("block", BLOCKS, ids=[b.id for b in BLOCKS])
def test_documented_block_runs(block, chapters):
    chapters(block.path).run_through(block)


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


def synthetic_chapter(tmp_path, grasp_bin, *bodies):
    """A chapter of ```sh blocks with these bodies, and its scratch copy."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    doc = tmp_path / "chapter.md"
    doc.write_text("".join(f"Step {k}:\n\n```sh\n{body}\n```\n\n" for k, body in enumerate(bodies)))
    blocks = blocks_of(doc)
    return Chapter(blocks, tmp_path, grasp_bin), blocks


def test_a_block_sees_the_files_the_blocks_above_it_wrote(tmp_path, grasp_bin):
    # A reader pastes a chapter's blocks one after another in one checkout: the second block
    # reads what the first wrote, and a block run alone runs the blocks above it first.
    chapter, (_, second) = synthetic_chapter(tmp_path, grasp_bin, "grasp solve examples/cube_a.json --json out/a.json",
                                             "python -c 'import json; json.load(open(\"out/a.json\"))'")
    chapter.run_through(second)


def test_a_block_rewriting_an_earlier_blocks_file_without_force_fails(tmp_path, grasp_bin):
    # Guide blocks rewrote a file an earlier block of their chapter had written, without
    # `--force`: the CLI refuses, as a reader running them in order saw, while a test running
    # each block in a fresh copy passed.
    solve = "grasp solve examples/cube_a.json --json out/a.json"
    chapter, (_, second) = synthetic_chapter(tmp_path, grasp_bin, solve, solve)
    with pytest.raises(AssertionError, match=r"chapter.md:\d+: exit 1"):
        chapter.run_through(second)
    forced, (_, again) = synthetic_chapter(tmp_path / "forced", grasp_bin, solve, solve + " --force")
    forced.run_through(again)


def test_a_block_after_a_failed_one_does_not_run(tmp_path, grasp_bin):
    chapter, (first, second) = synthetic_chapter(tmp_path, grasp_bin, "false", "mkdir -p out && touch out/ran")
    with pytest.raises(AssertionError, match="exit 1"):
        chapter.run_through(first)
    with pytest.raises(pytest.fail.Exception, match=r"chapter.md:\d+: not run: chapter.md:\d+, above it"):
        chapter.run_through(second)
    assert not (chapter.folder / "out" / "ran").exists()


@pytest.mark.parametrize("body, dirt", [
    ("grasp solve examples/cube_a.json --json cube_a.json", "?? cube_a.json"),
    ("mkdir -p notes && echo x > notes/plan.txt", "?? notes/plan.txt"),
    ("echo ' ' >> examples/cube_a.json", "M  examples/cube_a.json"),
])
def test_a_block_that_leaves_the_checkout_unclean_fails(tmp_path, grasp_bin, body, dirt):
    # The guide wrote untracked files in the repository's root (plan.schedule.json, hertz_256.json):
    # a block's files go where the checkout's .gitignore ignores them (out/), and a block that
    # writes elsewhere, or changes a file of the checkout, fails naming the file and the block.
    chapter, (block,) = synthetic_chapter(tmp_path, grasp_bin, body)
    with pytest.raises(AssertionError, match=re.escape(f"chapter.md:3 leaves the reader's checkout unclean")) as failure:
        chapter.run_through(block)
    assert dirt in str(failure.value)


def test_a_block_writing_under_out_leaves_the_checkout_clean(tmp_path, grasp_bin):
    chapter, (block,) = synthetic_chapter(tmp_path, grasp_bin, "grasp solve examples/cube_a.json --json out/cube_a.json")
    chapter.run_through(block)
    assert (chapter.folder / "out" / "cube_a.json").stat().st_size > 0
