"""Shapes from Python: the derived frames, warnings and errors, and the object drawn as its
mesh in the Rerun recording (checked with the independent `rerun` CLI)."""

import json
import subprocess

import numpy as np
import pytest

import grasp
from conftest import EXAMPLES, rerun_cli


def test_the_shape_report_gives_the_derived_frames_and_mass():
    scene = grasp.Scene(EXAMPLES / "box_pinch.json")
    report = scene.shape_report
    assert report["volume_m3"] == pytest.approx(0.06 * 0.04 * 0.1, rel=1e-12)
    assert report["mass_kg"] == pytest.approx(700 * 0.06 * 0.04 * 0.1, rel=1e-12)
    left = report["fingers"][0]
    assert left["source"] == "ray" and left["normal"] == [0.0, -1.0, 0.0]
    assert left["contact_point_m"] == pytest.approx([0.0, 0.02, 0.055], abs=1e-15)
    assert scene.warnings == []
    assert grasp.Scene(EXAMPLES / "cube_a.json").shape_report is None
    # The derived frame is the scene's: the solve sees the written-out contact points.
    sol = grasp.solve(scene)
    assert sol.status == "solved"
    assert np.allclose(sol.positions_m[:, 1][sol.finger == 0], 0.02, atol=1e-15)


def test_a_ray_that_misses_is_a_scene_error_naming_the_finger():
    d = json.loads((EXAMPLES / "box_pinch.json").read_text())
    d["fingers"][0]["place"]["ray"]["direction"] = [1, 0, 0]
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(d)
    assert [p["path"] for p in e.value.problems] == ["fingers[0].place.ray"]
    assert "misses" in e.value.problems[0]["message"]


@pytest.mark.skipif(rerun_cli() is None, reason="the rerun CLI (scripts/install-checkers.sh) is not installed")
def test_the_recording_draws_the_object_as_its_mesh(tmp_path):
    schedule = {"time": {"start": 0, "end": 1, "step": 0.25},
                "fingers": {"right": [{"ramp": {"keyframes": [[0, 10], [1, 20]]}}]}}
    rrd = tmp_path / "pinch.rrd"
    grasp.transfer(grasp.Scene(EXAMPLES / "box_pinch.json"), schedule, rrd=rrd)
    env = {"CI": "1", "PATH": "/usr/bin:/bin"}
    out = subprocess.run([rerun_cli(), "rrd", "print", str(rrd)], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    lines = [l for l in out.stdout.splitlines() if " - /world/object - " in l]
    assert lines and "Mesh3D:triangle_indices" in lines[0] and "Mesh3D:vertex_positions" in lines[0], out.stdout[:2000]


def _pinch_over_the_edge():
    """The box pinch with both 10 mm pads 3 mm below the box's top edge: each hangs 2 mm over
    (with the thesis's quadratic gap, which the warning is about: exact gaps know the edge)."""
    d = json.loads((EXAMPLES / "box_pinch.json").read_text())
    for f in d["fingers"]:
        f["place"]["ray"]["origin"][2] = 0.097
    d["gap"] = "quadratic"
    return d


def test_the_shape_warnings_reach_the_solution_and_the_cli_json(tmp_path, run_cli):
    d = _pinch_over_the_edge()
    scene = grasp.Scene(d)
    assert len(scene.warnings) == 2, scene.warnings
    for w, name in zip(scene.warnings, ["left", "right"]):
        assert w.startswith(f"finger {name}: the patch hangs 2.000 mm over the edge"), w
    sol = grasp.solve(scene)
    assert sol.status == "solved"
    assert sol.warnings[:2] == scene.warnings
    # The CLI writes the same warnings into its JSON.
    path, out = tmp_path / "pinch.json", tmp_path / "pinch.solution.json"
    path.write_text(json.dumps(d))
    p = run_cli("solve", path, "--json", out)
    assert p.returncode == 0, p.stdout + p.stderr
    assert json.loads(out.read_text())["warnings"] == sol.warnings


def test_an_open_mesh_refuses_a_density_and_every_solution_warns_of_it(tmp_path):
    # The box pinch's 60 x 40 x 100 mm box as an OBJ without its bottom face (z = 0).
    corners = [((i & 1) * 60 - 30, ((i >> 1) & 1) * 40 - 20, ((i >> 2) & 1) * 100) for i in range(8)]
    faces = [(4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4), (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
    obj = "".join(f"v {x} {y} {z}\n" for x, y, z in corners) + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
    (tmp_path / "open_box.obj").write_text(obj)
    d = json.loads((EXAMPLES / "box_pinch.json").read_text())
    d["object"]["shape"] = {"mesh": {"file": "open_box.obj", "unit": "mm"}}
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(d))
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(path)
    assert [p["path"] for p in e.value.problems] == ["object.density"]
    assert "needs a closed mesh" in e.value.problems[0]["message"]
    assert "4 edges with one triangle only" in e.value.problems[0]["message"]
    del d["object"]["density"]
    d["object"]["weight"], d["object"]["center_of_mass"] = 1.6, [0, 0, 0.05]
    path.write_text(json.dumps(d))
    scene = grasp.Scene(path)
    assert len(scene.warnings) == 1 and "the mesh is not closed" in scene.warnings[0], scene.warnings
    sol = grasp.solve(scene)
    assert sol.status == "solved"
    assert sol.warnings[0] == scene.warnings[0]
