"""The figures the docs quote (file sizes, counts, solver numbers, run times), each with one
source: the command that produces it and how it is computed, and where the docs quote it.

Each `Figure` names its document and a pattern that finds the quoted value there (exactly once;
a space in a pattern matches any run of white space, so a line break may fall anywhere), the
run that produces it (`RUNS`: a command in a scratch folder, timed, its peak memory taken) and
how the value is computed from that run, formatted at the precision the docs quote.
Deterministic figures (sizes of deterministic outputs, counts, solver numbers) are checked by
tests/python/test_quoted_figures.py; timings and memory peaks are not deterministic: this
script re-measures them on this machine and rewrites the date and load average quoted beside
them. The `<!-- doc-test: long -->` markers in `LONG_MARKERS` follow the measured time of their
block's command (marked when over `LONG_S`).

    python3 scripts/make-figures.py             # lists every figure: quoted and fresh value
    python3 scripts/make-figures.py --write     # rewrites the stale ones in place
    python3 scripts/make-figures.py --test-log LOG   # the README's test count, from the closing
                                                # line of a log of `bash scripts/test.sh`

The README's test count is refreshed only from a log of the whole test command (every Rust
test binary built and run, the API docs' examples and the Python tests, whose skips depend on
the machine): it is not checked by the test, which would have to run them all.
Needs the grasp CLI (GRASP_BIN, else $CARGO_TARGET_DIR/release/grasp) and, for the MuJoCo
figures, the Python package with MuJoCo (`pip install '.[mujoco]'`).
"""

import argparse
import dataclasses
import datetime
import json
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time
from typing import Callable

ROOT = pathlib.Path(__file__).resolve().parents[1]
LONG_S = 20.0
LONG_MARKER = "<!-- doc-test: long -->"


def grasp_bin():
    """The CLI: $GRASP_BIN, else the release build of $CARGO_TARGET_DIR (or target/)."""
    path = os.environ.get("GRASP_BIN")
    if path:
        return path
    return os.path.join(os.environ.get("CARGO_TARGET_DIR", str(ROOT / "target")), "release", "grasp")


@dataclasses.dataclass
class Run:
    """A finished command: its folder, output, wall time and peak memory."""

    folder: pathlib.Path
    stdout: str
    wall_s: float
    peak_bytes: int
    load: float
    date: str

    def size(self, name):
        """A written file's size in bytes."""
        return (self.folder / name).stat().st_size

    def output(self, pattern):
        """The first group of `pattern` in the command's output (fails if absent)."""
        m = re.search(pattern, self.stdout)
        if not m:
            raise RuntimeError(f"{pattern!r} not in the output:\n{self.stdout}")
        return m.group(1)

    def conditions(self):
        """The wording beside a timing: the date and the machine's load when the run started."""
        return f"{self.date}, load average {self.load:.1f}"


def execute(argv, folder, env=None):
    """Runs `argv` from the repository root (examples/ relative), in `folder`'s terms for its
    outputs; returns a `Run` with the wall time and the child's peak resident memory."""
    load = os.getloadavg()[0]
    date = datetime.date.today().strftime("%-d %B %Y")
    out = open(folder / "stdout", "w+")
    start = time.perf_counter()
    proc = subprocess.Popen(argv, cwd=ROOT, stdout=out, stderr=subprocess.STDOUT, text=True,
                            env=dict(os.environ, **(env or {})))
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    out.seek(0)
    text = out.read()
    out.close()
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(map(str, argv))} exited {proc.returncode}:\n{text}")
    return Run(folder, text, wall, usage.ru_maxrss * 1024, load, date)


def run_fine_patch(folder):
    """docs/guide/outputs.md: the plate hand-off with 128 x 128 receivers, all three files."""
    return execute([grasp_bin(), "transfer", "examples/plate_transfer_fine.json",
                    "--schedule", "examples/plate_transfer.schedule.json",
                    "--mcap", folder / "plate_fine.mcap", "--rrd", folder / "plate_fine.rrd",
                    "--csv", folder / "plate_fine.csv"], folder)


def run_mujoco_handoff(folder):
    """docs/guide/mujoco.md: the scripted MuJoCo hand-off replayed into an MCAP and a recording."""
    return execute([sys.executable, "-m", "grasp.mujoco", "handoff", "examples/mujoco/handoff.xml",
                    "--object", "cylinder", "--controller", "examples/mujoco/handoff_controller.py:control",
                    "--steps", "1600", "--every", "10", "--materials", "examples/mujoco/handoff.materials.json",
                    "--out", folder / "handoff", "--mcap", folder / "handoff.mcap",
                    "--rrd", folder / "handoff.rrd"], folder)


def run_error_estimate(folder):
    """docs/guide/solving.md: the Hertz example solved with its discretisation error estimate."""
    return execute([grasp_bin(), "solve", "examples/hertz_sphere_on_flat.json", "--error-estimate"], folder)


def refined_hertz(folder, n):
    """The bundled Hertz scene refined to n x n elements, as docs/guide/outputs.md makes it."""
    text = (ROOT / "examples" / "hertz_sphere_on_flat.json").read_text()
    path = folder / f"h{n}.json"
    path.write_text(text.replace('"grid": [21, 21]', f'"grid": [{n}, {n}]'))
    return path


def run_hertz_1024_outputs(folder):
    """docs/guide/outputs.md: a 1024 x 1024 patch solved, written as JSON and as .npz."""
    return execute([grasp_bin(), "solve", refined_hertz(folder, 1024), "--json", folder / "o.json",
                    "--npz", folder / "o.npz"], folder)


def run_hertz_512_json(folder):
    """docs/guide/scenes.md: a 512 x 512 patch solved, its solution streamed into a JSON file."""
    return execute([grasp_bin(), "solve", refined_hertz(folder, 512), "--json", folder / "o.json"], folder)


PLAN = ["plan", "examples/plate_handoff_coulomb.json", "--releasing", "f1,f2", "--receiving", "f3,f4",
        "--template", "examples/plate_handoff_coulomb.schedule.json"]


def plan_and_margins(folder, extra):
    """A plan of the Coulomb plate hand-off, then `grasp transfer --margins` of its schedule
    (that run's output appended)."""
    plan = execute([grasp_bin(), *PLAN, *extra, "--out", folder / "plan.schedule.json",
                    "--report", folder / "plan.json"], folder)
    margins = execute([grasp_bin(), "transfer", "examples/plate_handoff_coulomb.json",
                       "--schedule", folder / "plan.schedule.json", "--margins"], folder)
    plan.stdout += "\n--- margins ---\n" + margins.stdout
    return plan


def run_plan_min_margin(folder):
    """docs/guide/planning.md: the plan that keeps a disturbance margin of 1 N."""
    return plan_and_margins(folder, ["--max-rate", "1.5", "--steps", "12", "--min-margin", "1", "--max-runs", "12"])


def run_plan_12_steps(folder):
    """docs/guide/planning.md: the same plan on 12 steps without the margin threshold."""
    return plan_and_margins(folder, ["--max-rate", "1.5", "--steps", "12"])


def run_plan_linear(folder):
    """docs/guide/planning.md: the plan against the thesis's linear template."""
    return execute([grasp_bin(), "plan", "examples/plate_handoff_coulomb.json", "--releasing", "f1,f2",
                    "--receiving", "f3,f4", "--template", "examples/plate_handoff_coulomb_linear.schedule.json",
                    "--max-rate", "0.8", "--out", folder / "plan.schedule.json", "--report", folder / "plan.json"],
                   folder)


RUNS = {
    "fine_patch": run_fine_patch,
    "mujoco_handoff": run_mujoco_handoff,
    "error_estimate": run_error_estimate,
    "plan_min_margin": run_plan_min_margin,
    "plan_12_steps": run_plan_12_steps,
    "plan_linear": run_plan_linear,
    "hertz_1024_outputs": run_hertz_1024_outputs,
    "hertz_512_json": run_hertz_512_json,
}


class Runs:
    """Each run at most once, in its own folder under a scratch folder."""

    def __init__(self, scratch):
        self.scratch = pathlib.Path(scratch)
        self.done = {}

    def get(self, name):
        if name not in self.done:
            folder = self.scratch / name
            folder.mkdir(parents=True, exist_ok=True)
            self.done[name] = RUNS[name](folder)
        return self.done[name]


@dataclasses.dataclass
class Figure:
    """One quoted figure: where it is quoted and how it is computed."""

    name: str
    doc: str  # the document, relative to the repository root
    pattern: str  # finds the quoted value (its one group) exactly once; a space matches any white space
    run: str  # the run in RUNS that produces it
    value: Callable[[Run], str]  # the fresh value, formatted as the docs quote it
    deterministic: bool = True  # False: a timing, a memory peak or their conditions (not tested)

    def regex(self):
        return re.compile(self.pattern.replace(" ", r"\s+"))


@dataclasses.dataclass
class Quote:
    """Where a figure is quoted: its span in the document's text and its line."""

    text: str
    start: int
    end: int
    line: int


def find(figure, text):
    """The figure's quote in `text`; fails naming the document when it is not there exactly once."""
    found = list(figure.regex().finditer(text))
    if len(found) != 1:
        raise LookupError(f"{figure.doc}: figure {figure.name}: {figure.pattern!r} found {len(found)} times, "
                          "not once: fix the document or the pattern in scripts/make-figures.py")
    m = found[0]
    return Quote(m.group(1), m.start(1), m.end(1), text.count("\n", 0, m.start(1)) + 1)


# The fine-patch example's receivers: f3, f4 on 128 x 128 elements, and its 200 steps.
FINE_ELEMENT_STEPS = 2 * 128 * 128 * 200
FINE_ELEMENTS = 2 * 128 * 128


def mcap_bytes_per_element_step(r):
    return r.size("plate_fine.mcap") / FINE_ELEMENT_STEPS


def mb(name, digits):
    """A file's size in MB (10^6 bytes) at `digits` decimals."""
    return lambda r: f"{r.size(name) / 1e6:.{digits}f}"


def output(pattern):
    """The first group of `pattern` in the run's output, as printed."""
    return lambda r: r.output(pattern)


def number(pattern, digits):
    """The first group of `pattern` in the run's output, a number rounded to `digits` decimals."""
    return lambda r: f"{float(r.output(pattern)):.{digits}f}"


def model_and_solve_s(r):
    """`grasp solve`'s model and solve times (its `time:` line), in seconds at one decimal."""
    m = re.search(r"time: model ([\d.]+) (m?s), solve ([\d.]+) (m?s)", r.stdout)
    scale = {"s": 1.0, "ms": 1e-3}
    return f"{float(m.group(1)) * scale[m.group(2)] + float(m.group(3)) * scale[m.group(4)]:.1f}"


# `grasp transfer --margins`: "least safe step: 4 (t = 1.800 s), smallest disturbance margin 0.9012 N ..."
LEAST_SAFE = r"least safe step: \d+ \(t = ([\d.]+) s\), smallest disturbance margin ([\d.]+) N"


def least_safe(group, digits):
    """The least safe step's time (group 1) or margin (group 2) of `grasp transfer --margins`."""
    return lambda r: f"{float(re.search(LEAST_SAFE, r.stdout).group(group)):.{digits}f}"

FIGURES = [
    # docs/guide/outputs.md, the fine-patch recordings
    Figure("fine-patch MCAP size", "docs/guide/outputs.md", r"writes a ([\d.]+) MB MCAP", "fine_patch",
           mb("plate_fine.mcap", 1)),
    Figure("fine-patch recording size", "docs/guide/outputs.md", r"and a ([\d.]+) MB `\.rrd`", "fine_patch",
           mb("plate_fine.rrd", 1)),
    Figure("fine-patch MCAP bytes per element and step", "docs/guide/outputs.md",
           r"That is ([\d.]+) bytes per element and step in the MCAP", "fine_patch",
           lambda r: f"{mcap_bytes_per_element_step(r):.1f}"),
    Figure("fine-patch recording bytes per element and step", "docs/guide/outputs.md",
           r"in the MCAP and ([\d.]+) in the `\.rrd`", "fine_patch",
           lambda r: f"{r.size('plate_fine.rrd') / FINE_ELEMENT_STEPS:.1f}"),
    Figure("element-steps of MCAP within 100 MB", "docs/guide/outputs.md",
           r"the 100 MB target holds about ([\d.]+) million element-steps", "fine_patch",
           lambda r: f"{100e6 / mcap_bytes_per_element_step(r) / 1e6:.1f}"),
    Figure("steps of two fine patches within 100 MB", "docs/guide/outputs.md",
           r"two 128 x 128 patches for (\d+) steps", "fine_patch",
           lambda r: f"{round(100e6 / mcap_bytes_per_element_step(r) / FINE_ELEMENTS, -1):.0f}"),
    Figure("MCAP of four fine patches for 200 steps", "docs/guide/outputs.md",
           r"four such patches for 200 steps would be about (\d+) MB", "fine_patch",
           lambda r: f"{round(2 * r.size('plate_fine.mcap') / 1e6, -1):.0f}"),
    Figure("fine-patch run time", "docs/guide/outputs.md", r"in ([\d.]+) s for the whole run with the three files",
           "fine_patch", lambda r: f"{r.wall_s:.1f}", deterministic=False),
    Figure("fine-patch peak memory", "docs/guide/outputs.md", r"(\d+) MB peak memory \(before", "fine_patch",
           lambda r: f"{r.peak_bytes / 1e6:.0f}", deterministic=False),
    Figure("fine-patch measured when", "docs/guide/outputs.md",
           r"Measured on this 2-core machine \(([^)]*)\): `grasp transfer examples/plate_transfer_fine", "fine_patch",
           Run.conditions, deterministic=False),
    # docs/guide/outputs.md, the solution of a 1024 x 1024 patch as JSON and .npz
    Figure("1024 x 1024 solution JSON size", "docs/guide/outputs.md", r"the JSON is (\d+) MB, written in",
           "hertz_1024_outputs", mb("o.json", 0)),
    Figure("1024 x 1024 solution .npz size", "docs/guide/outputs.md", r"the `\.npz` (\d+) MB in",
           "hertz_1024_outputs", mb("o.npz", 0)),
    Figure("1024 x 1024 solution JSON write time", "docs/guide/outputs.md", r"MB, written in ([\d.-]+) s \(before",
           "hertz_1024_outputs", output(r"wrote \S*o\.json \([\d.]+ MB in ([\d.]+) s\)"), deterministic=False),
    Figure("1024 x 1024 solution .npz write time", "docs/guide/outputs.md", r"the `\.npz` \d+ MB in ([\d.-]+) s;",
           "hertz_1024_outputs", output(r"wrote \S*o\.npz \([\d.]+ MB in ([\d.]+) s\)"), deterministic=False),
    Figure("1024 x 1024 solve with its outputs: peak memory", "docs/guide/outputs.md",
           r"process peaks at ([\d.]+) GB with both", "hertz_1024_outputs",
           lambda r: f"{r.peak_bytes / 1e9:.2f}", deterministic=False),
    Figure("1024 x 1024 solve time", "docs/guide/outputs.md", r"against a solve of ([\d.-]+) s\.",
           "hertz_1024_outputs", model_and_solve_s, deterministic=False),
    Figure("1024 x 1024 solution measured when", "docs/guide/outputs.md",
           r"/tmp/o.json --npz /tmp/o.npz`, ([^)]*)\): the JSON is", "hertz_1024_outputs",
           Run.conditions, deterministic=False),
    # docs/guide/scenes.md, the memory of a 512 x 512 solve streamed into its JSON
    Figure("512 x 512 solve with --json: peak memory", "docs/guide/scenes.md",
           r"a 512 x 512 patch: (\d+) MB peak with `--json`", "hertz_512_json",
           lambda r: f"{r.peak_bytes / 1e6:.0f}", deterministic=False),
    # docs/guide/mujoco.md, the hand-off's recordings
    Figure("MuJoCo hand-off MCAP size", "docs/guide/mujoco.md", r"the MCAP ([\d.]+) MB and the Rerun recording",
           "mujoco_handoff", mb("handoff.mcap", 1)),
    Figure("MuJoCo hand-off run time", "docs/guide/mujoco.md", r"every 10th of 1600 steps; ([\d.]+) s on",
           "mujoco_handoff", lambda r: f"{r.wall_s:.1f}", deterministic=False),
    Figure("MuJoCo hand-off measured when", "docs/guide/mujoco.md", r"s on the 2-core machine on ([^)]*)\):",
           "mujoco_handoff", Run.conditions, deterministic=False),
    # Not deterministic: the recording's MuJoCo layer is written by the Python Rerun SDK, whose
    # batcher cuts chunks on a timer, so the size moves with the machine's load (0.70 to
    # 0.73 MB in four runs of the same build, 29 November 2026).
    Figure("MuJoCo hand-off recording size", "docs/guide/mujoco.md", r"the Rerun recording ([\d.]+) MB pass",
           "mujoco_handoff", mb("handoff.rrd", 2), deterministic=False),
    # docs/guide/solving.md, the error estimate
    Figure("error estimate coarse-grid ratio", "docs/guide/solving.md", r"coarse grids \[\[11, 11\]\], ratio ([\d.]+)",
           "error_estimate", output(r"ratio ([\d.]+)")),
    Figure("error estimate of P", "docs/guide/solving.md", r"order 1\): P within (\S+) N", "error_estimate",
           output(r"P within (\S+) N")),
    Figure("error estimate of Q", "docs/guide/solving.md", r"Q within (\S+) N \(", "error_estimate",
           output(r"Q within (\S+) N")),
    Figure("error estimate of Q against the load", "docs/guide/solving.md", r"N \((\S+) of the load\)",
           "error_estimate", output(r"\((\S+) of the load\)")),
    Figure("error estimate of the peak pressure", "docs/guide/solving.md", r"peak pressure (\S+) relative",
           "error_estimate", output(r"peak pressure (\S+) relative")),
    Figure("error estimate's extra time", "docs/guide/solving.md", r"relative; extra time ([\d.]+ m?s)",
           "error_estimate", output(r"extra time ([\d.]+ m?s)"), deterministic=False),
    # docs/guide/planning.md, the plans
    Figure("plan on 12 steps: its smallest disturbance margin", "docs/guide/planning.md",
           r"leaves a smallest disturbance margin of ([\d.]+) N, at t", "plan_12_steps",
           least_safe(2, 2)),
    Figure("plan on 12 steps: when", "docs/guide/planning.md",
           r"disturbance margin of [\d.]+ N, at t = ([\d.]+) s\.", "plan_12_steps",
           least_safe(1, 1)),
    Figure("plan with a disturbance margin: runs", "docs/guide/planning.md",
           r"\): (\d+) runs in [\d.]+ s \(", "plan_min_margin",
           lambda r: str(json.loads((r.folder / "plan.json").read_text())["runs"])),
    Figure("plan with a disturbance margin: run time", "docs/guide/planning.md",
           r"\): \d+ runs in ([\d.]+) s \(", "plan_min_margin",
           lambda r: f"{r.wall_s:.1f}", deterministic=False),
    Figure("plan with a disturbance margin: measured when", "docs/guide/planning.md",
           r"Measured on the 2-core machine \(([^)]*)\): \d+ runs", "plan_min_margin",
           Run.conditions, deterministic=False),
    Figure("plan with a disturbance margin: duration", "docs/guide/planning.md",
           r"searches\), ([\d.]+) s against", "plan_min_margin",
           number(r"duration: ([\d.]+) s", 2)),
    Figure("plan without the threshold: duration", "docs/guide/planning.md",
           r"s against ([\d.]+) s without the threshold", "plan_12_steps",
           number(r"duration: ([\d.]+) s", 2)),
    Figure("plan with a disturbance margin: its schedule's margin", "docs/guide/planning.md",
           r"of the written schedule finds ([\d.]+) N", "plan_min_margin",
           least_safe(2, 3)),
    Figure("plan with a disturbance margin: its schedule's margin, when", "docs/guide/planning.md",
           r"of the written schedule finds [\d.]+ N at t = ([\d.]+) s\.", "plan_min_margin",
           least_safe(1, 1)),
    Figure("plan against the linear template: duration", "docs/guide/planning.md",
           r"Measured: ([\d.]+) s against 20 s", "plan_linear",
           number(r"duration: ([\d.]+) s", 2)),
    Figure("plan against the linear template: shorter by", "docs/guide/planning.md",
           r"against 20 s \((\d+) % shorter\)", "plan_linear",
           number(r"template 20.00 s: ([\d.]+) % shorter", 0)),
    Figure("plan against the linear template: runs", "docs/guide/planning.md",
           r"% shorter\), (\d+) runs in", "plan_linear",
           lambda r: str(json.loads((r.folder / "plan.json").read_text())["runs"])),
]


@dataclasses.dataclass
class LongMarker:
    """A command block whose `<!-- doc-test: long -->` marker follows its run's measured time."""

    doc: str
    block: str  # a line of the block's command, found exactly once
    run: str


LONG_MARKERS = [
    LongMarker("docs/guide/planning.md", "--max-rate 1.5 --steps 12 --min-margin 1 --max-runs 12", "plan_min_margin"),
]

# The README's count of the whole test command's passed tests, with when and how it was run.
TEST_COUNT = re.compile(r"now `(\d+) passed, 0 failed` \(([^)]*)\)")


@dataclasses.dataclass
class Stale:
    """A quoted figure that differs from its fresh value."""

    figure: Figure
    quote: Quote
    fresh: str

    def __str__(self):
        return (f"{self.figure.doc}:{self.quote.line}: {self.figure.name}: quoted {self.quote.text}, "
                f"fresh {self.fresh}")


def stale_figures(texts, runs, figures):
    """Every figure of `figures` whose quote in `texts` (document -> text) is not its fresh value."""
    stale = []
    for figure in figures:
        quote = find(figure, texts[figure.doc])
        fresh = figure.value(runs.get(figure.run))
        if quote.text != fresh:
            stale.append(Stale(figure, quote, fresh))
    return stale


def rewrite(text, replacements):
    """`text` with each (start, end, new) span replaced."""
    for start, end, new in sorted(replacements, reverse=True):
        text = text[:start] + new + text[end:]
    return text


def long_marker_edit(text, marker, wall_s):
    """`text` with the marker before `marker.block`'s block set when `wall_s` is over LONG_S and
    removed otherwise."""
    lines = text.split("\n")
    at = [i for i, line in enumerate(lines) if marker.block in line]
    if len(at) != 1:
        raise LookupError(f"{marker.doc}: {marker.block!r} found {len(at)} times, not once")
    fence = max(i for i in range(at[0]) if lines[i].startswith("```"))
    marked = fence > 0 and lines[fence - 1].strip() == LONG_MARKER
    if wall_s > LONG_S and not marked:
        lines.insert(fence, LONG_MARKER)
    elif wall_s <= LONG_S and marked:
        del lines[fence - 1]
    return "\n".join(lines)


def test_count_edit(text, log):
    """The README with its test count and date from the closing line of a test-command log."""
    m = re.findall(r"^(\d+) passed, (\d+) failed$", log, re.M)
    if not m:
        raise LookupError("no closing `N passed, M failed` line in the test log")
    passed, failed = m[-1]
    if failed != "0":
        raise RuntimeError(f"the test log has {failed} failures: fix them before quoting the count")
    # The README's bullet is indented by two spaces: the wording wraps there.
    when = datetime.date.today().strftime("%-d %B") + ", counted by\n  `scripts/make-figures.py --test-log` from the test command's log"
    q = TEST_COUNT.search(text)
    return text[:q.start(1)] + passed + text[q.end(1):q.start(2)] + when + text[q.end(2):]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--write", action="store_true", help="rewrite the stale figures in place")
    parser.add_argument("--test-log", type=pathlib.Path, help="a log of `bash scripts/test.sh`: refresh the README's count")
    parser.add_argument("--only", help="only the figures of this document (e.g. docs/guide/outputs.md)")
    args = parser.parse_args()
    if args.test_log:
        readme = ROOT / "README.md"
        readme.write_text(test_count_edit(readme.read_text(), args.test_log.read_text()))
        print("rewrote README.md's test count")
        if not args.write:
            return 0
    figures = [f for f in FIGURES if not args.only or f.doc == args.only]
    texts = {doc: (ROOT / doc).read_text() for doc in {f.doc for f in FIGURES} | {m.doc for m in LONG_MARKERS}}
    with tempfile.TemporaryDirectory() as scratch:
        runs = Runs(scratch)
        stale = stale_figures(texts, runs, figures)
        for f in figures:
            if all(s.figure is not f for s in stale):
                quote = find(f, texts[f.doc])
                print(f"{f.doc}:{quote.line}: {f.name}: {quote.text} (fresh)")
        for s in stale:
            print(f"{s} (stale{'' if s.figure.deterministic else ', measured'})")
        if not args.write:
            return 1 if any(s.figure.deterministic for s in stale) else 0
        for doc in texts:
            new = rewrite(texts[doc], [(s.quote.start, s.quote.end, s.fresh) for s in stale if s.figure.doc == doc])
            for marker in LONG_MARKERS:
                if marker.doc == doc and marker.run in runs.done:
                    new = long_marker_edit(new, marker, runs.done[marker.run].wall_s)
            if new != texts[doc]:
                (ROOT / doc).write_text(new)
                print(f"rewrote {doc}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
