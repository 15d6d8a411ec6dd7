"""Shared fixtures of the Python tests: the repository, its example scenes, the CLI binary."""

import json
import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def scene_examples():
    """Every example scene file (schedules excluded)."""
    return sorted(p for p in EXAMPLES.glob("*.json") if not p.name.endswith(".schedule.json"))


@pytest.fixture(scope="session")
def grasp_bin():
    """The `grasp` CLI: $GRASP_BIN (set by scripts/test.sh), else the release build."""
    path = os.environ.get("GRASP_BIN")
    if not path:
        target = os.environ.get("CARGO_TARGET_DIR", str(ROOT / "target"))
        path = os.path.join(target, "release", "grasp")
    if not os.path.exists(path):
        pytest.fail(f"the grasp CLI is not at {path}: run `cargo build --release` or set GRASP_BIN")
    return path


@pytest.fixture(scope="session")
def run_cli(grasp_bin):
    """Runs the CLI with arguments; returns the completed process (exit code not checked)."""

    def run(*args, env=None):
        full_env = dict(os.environ, **(env or {}))
        return subprocess.run([grasp_bin, *map(str, args)], capture_output=True, text=True, env=full_env, cwd=ROOT)

    return run


def element_records(finger):
    """A finger's elements from `grasp solve --json` as one dict per element, whichever form
    the file holds: `elements` (one record per element, patches up to 64 x 64) or
    `element_fields` (one array per field, finer patches), row `k` of every array."""
    if "elements" in finger:
        return finger["elements"]
    columns = finger["element_fields"]
    n = len(columns["index"])
    return [{field: values[k] for field, values in columns.items()} for k in range(n)]


def numbers_close(a, b, path=""):
    """JSON values equal, numbers to 1e-9 relative or 1e-12 absolute (in m and N: for numbers
    near zero): MuJoCo's last bits may differ by machine, and two descriptions of one model
    compile to the same model up to round-off. Each caller says why the tolerance fits it."""
    if isinstance(a, dict):
        assert set(a) == set(b), path
        for k in a:
            numbers_close(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            numbers_close(x, y, f"{path}[{i}]")
    elif isinstance(a, float) or isinstance(b, float):
        assert a == pytest.approx(b, rel=1e-9, abs=1e-12), path
    else:
        assert a == b, path


@pytest.fixture
def cube_a_dict():
    return json.loads((EXAMPLES / "cube_a.json").read_text())


def require_checkers():
    """True where the independent checkers must be present (scripts/test.sh installs them and
    sets GRASP_REQUIRE_CHECKERS=1): a missing one is then a failure, not a skip."""
    return os.environ.get("GRASP_REQUIRE_CHECKERS") == "1"


def checker(module, reason):
    """`pytest.importorskip(module)`, except that under scripts/test.sh a missing checker fails
    the run instead of skipping its tests quietly."""
    if require_checkers():
        import importlib

        return importlib.import_module(module)
    return pytest.importorskip(module, reason=reason)


def rerun_cli():
    """The `rerun` CLI of rerun-sdk (installed by scripts/install-checkers.sh), or None."""
    path = os.environ.get("GRASP_RERUN_CLI") or shutil.which("rerun")
    if require_checkers():
        # Never None under scripts/test.sh: a missing CLI fails each test that runs it.
        return path or "rerun"
    return path if path and os.path.exists(path) else None
