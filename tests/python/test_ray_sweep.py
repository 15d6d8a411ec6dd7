"""examples/python/ray_sweep.py on a local Ray runtime gives exactly the results of
`grasp batch` on the same sweep (ids, order, statuses, every finger force), bit for bit."""

import json
import os
import subprocess
import sys

import pytest

from conftest import EXAMPLES, ROOT, checker

ray = checker("ray", reason="Ray is installed by scripts/install-checkers.sh")


def read_lines(path):
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def test_ray_sweep_equals_grasp_batch(run_cli, tmp_path):
    sweep = tmp_path / "sweep.jsonl"
    proc = run_cli("sweep", EXAMPLES / "cube_a.json", "--vary", "fingers[*].friction.mu=0.05:0.8:6",
                   "--vary", "object.weight=1:8:2", "--out", sweep)
    assert proc.returncode == 0, proc.stderr
    # An invalid line among them: both must report it, neither may stop.
    with open(sweep, "a") as f:
        f.write('{"id": "broken", "scene": {"object": {}}}\n')
    batch = tmp_path / "batch.jsonl"
    proc = run_cli("batch", sweep, "--out", batch)
    assert proc.returncode in (0, 2), proc.stderr
    out = tmp_path / "ray.jsonl"
    env = dict(os.environ, RAY_ENABLE_UV_RUN_RUNTIME_ENV="0", RAY_USAGE_STATS_ENABLED="0")
    proc = subprocess.run(
        [sys.executable, str(ROOT / "examples/python/ray_sweep.py"), str(sweep), "--out", str(out),
         "--chunk", "4", "--cpus", "2"],
        capture_output=True, text=True, env=env, timeout=600,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    ours, theirs = read_lines(out), read_lines(batch)
    assert len(ours) == len(theirs) == 13
    statuses = set()
    for a, b in zip(ours, theirs):
        for key in ("id", "index", "of", "status", "reason", "problems", "vary", "fingers",
                    "equilibrium_residual", "worst_residual", "solver"):
            assert a.get(key) == b.get(key), (key, a["id"])
        statuses.add(a["status"])
    assert {"solved", "no_equilibrium", "invalid"} <= statuses
