"""examples/slurm: the job-array script run as Slurm would run it (one process per task with
SLURM_ARRAY_TASK_ID / _COUNT set), then the merge script, gives the unsharded batch's lines."""

import json
import os
import subprocess

from conftest import EXAMPLES, ROOT

SLURM = ROOT / "examples" / "slurm"


def forces(path):
    lines = [json.loads(x) for x in path.read_text().splitlines() if x.strip()]
    return [(x["id"], x["status"], x["fingers"]) for x in lines]


def test_job_array_and_merge_equal_one_unsharded_batch(run_cli, grasp_bin, tmp_path):
    scenes = tmp_path / "sweep.jsonl"
    proc = run_cli("sweep", EXAMPLES / "cube_a.json", "--vary", "object.weight=1:10:7", "--out", scenes)
    assert proc.returncode == 0, proc.stderr
    env = dict(os.environ, GRASP=grasp_bin, SCENES=str(scenes), OUTDIR=str(tmp_path / "results"),
               OUT=str(tmp_path / "merged.jsonl"), SLURM_ARRAY_TASK_COUNT="3", SLURM_ARRAY_TASK_MIN="1")
    for task in (1, 2, 3):
        env["SLURM_ARRAY_TASK_ID"] = str(task)
        proc = subprocess.run(["bash", str(SLURM / "sweep.sbatch")], env=env, capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
    assert sorted(p.name for p in (tmp_path / "results").iterdir()) == [
        "shard-1.jsonl", "shard-2.jsonl", "shard-3.jsonl"]
    proc = subprocess.run(["bash", str(SLURM / "merge.sbatch")], env=env, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    whole = tmp_path / "whole.jsonl"
    assert run_cli("batch", scenes, "--out", whole).returncode == 0
    assert forces(tmp_path / "merged.jsonl") == forces(whole)


def test_merge_refuses_a_missing_shard(run_cli, grasp_bin, tmp_path):
    scenes = tmp_path / "sweep.jsonl"
    assert run_cli("sweep", EXAMPLES / "cube_a.json", "--vary", "object.weight=1:10:4", "--out", scenes).returncode == 0
    env = dict(os.environ, GRASP=grasp_bin, SCENES=str(scenes), OUTDIR=str(tmp_path / "r"),
               OUT=str(tmp_path / "m.jsonl"), SLURM_ARRAY_TASK_COUNT="2", SLURM_ARRAY_TASK_ID="0")
    assert subprocess.run(["bash", str(SLURM / "sweep.sbatch")], env=env, capture_output=True).returncode == 0
    proc = subprocess.run(["bash", str(SLURM / "merge.sbatch")], env=env, capture_output=True, text=True)
    assert proc.returncode != 0
    assert "missing" in (proc.stdout + proc.stderr).lower()
    assert not (tmp_path / "m.jsonl").exists()
