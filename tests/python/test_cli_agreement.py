"""Python and the CLI give identical answers: for every example scene, `grasp solve --json`
and `grasp.solve` (same library path, same deterministic solver) agree bit for bit in every
element force, finger resultant and status."""

import json

import pytest

import grasp
from conftest import element_records, scene_examples


@pytest.mark.parametrize("path", scene_examples(), ids=lambda p: p.stem)
def test_python_and_cli_forces_are_identical(path, run_cli, tmp_path):
    out = tmp_path / "solution.json"
    proc = run_cli("solve", path, "--json", out)
    assert proc.returncode in (0, 2), proc.stderr
    cli = json.loads(out.read_text())
    py = grasp.solve(grasp.Scene(path)).to_dict()
    assert py["status"] == cli["status"]
    assert len(py["fingers"]) == len(cli["fingers"])
    for a, b in zip(py["fingers"], cli["fingers"]):
        assert a["name"] == b["name"]
        assert a["normal_force_n"] == b["normal_force_n"]
        assert a["tangential_force_n"] == b["tangential_force_n"]
        ea, eb = element_records(a), element_records(b)
        assert [e["normal_force_n"] for e in ea] == [e["normal_force_n"] for e in eb]
        assert [e["tangential_force_n"] for e in ea] == [e["tangential_force_n"] for e in eb]
        assert [e["state"] for e in ea] == [e["state"] for e in eb]
    assert py["residuals"] == cli["residuals"]
