"""The Python chapter's main example (docs/guide/python.md), run as a newcomer would paste it from
the repository root (here a scratch copy of `examples/`), with what it should have computed."""

import re
import shutil
import subprocess
import sys

from conftest import ROOT


def test_the_python_chapter_example_solves_and_transfers(tmp_path):
    text = (ROOT / "docs" / "guide" / "python.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    assert "grasp.transfer(" in code, "the chapter's first Python block is its main example"
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    check = "\nassert sol.status == 'solved' and run.normal_forces_n.shape == (200, 4)\n"
    proc = subprocess.run([sys.executable, "-c", code + check], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    for ext in ("mcap", "rrd", "csv"):
        assert (tmp_path / "out" / f"py.{ext}").stat().st_size > 0
