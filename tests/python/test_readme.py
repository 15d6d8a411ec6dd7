"""The README's Python section, run as a newcomer would paste it (from the repository root)."""

import re
import subprocess
import sys

from conftest import ROOT


def test_the_readme_python_example_runs():
    text = (ROOT / "README.md").read_text()
    section = text[text.index("## From Python"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    check = "\nassert sol.status == 'solved' and run.normal_forces_n.shape == (200, 4)\n"
    proc = subprocess.run([sys.executable, "-c", code + check], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    for ext in ("mcap", "rrd", "csv"):
        assert (ROOT / "out" / f"py.{ext}").stat().st_size > 0
