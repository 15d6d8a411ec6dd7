"""grasp.Scene: the three sources give the same scene; every kind of bad input is a clear error."""

import math
import json
import pathlib

import pytest

import grasp
from conftest import EXAMPLES


def test_path_str_pathlike_dict_and_json_text_give_the_same_scene(cube_a_dict):
    path = EXAMPLES / "cube_a.json"
    scenes = [
        grasp.Scene(str(path)),
        grasp.Scene(path),
        grasp.Scene(cube_a_dict),
        grasp.Scene(path.read_text()),
        grasp.Scene.from_file(path),
        grasp.Scene.from_dict(cube_a_dict),
        grasp.Scene.from_json(json.dumps(cube_a_dict)),
    ]
    first = scenes[0].to_dict()
    for s in scenes[1:]:
        assert s.to_dict() == first
    assert scenes[0].finger_names == [f["name"] for f in cube_a_dict["fingers"]]
    assert scenes[0].model == "energy"
    assert scenes[0].origin == str(path)
    assert scenes[2].origin == "<dict>"
    assert "fingers" in repr(scenes[0])


def test_a_zero_normal_is_a_scene_error_naming_the_field_and_the_fix(cube_a_dict):
    cube_a_dict["fingers"][1]["normal"] = [0.0, 0.0, 0.0]
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(cube_a_dict)
    paths = [p["path"] for p in e.value.problems]
    assert "fingers[1].normal" in paths
    problem = e.value.problems[paths.index("fingers[1].normal")]
    assert problem["message"] and problem["fix"]
    assert "fingers[1].normal" in str(e.value)
    assert isinstance(e.value, ValueError)


def test_every_problem_is_listed(cube_a_dict):
    cube_a_dict["fingers"][0]["normal"] = [0.0, 0.0, 0.0]
    cube_a_dict["object"]["weight"] = -1.0
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(cube_a_dict)
    paths = {p["path"] for p in e.value.problems}
    assert {"fingers[0].normal", "object.weight"} <= paths


def test_non_finite_numbers_in_a_dict_are_named_by_their_path(cube_a_dict):
    # NaN, infinities and 1e400 (read by Python as infinity) from Python objects
    # once gave "line 1, column 308: expected value" in a text the user never wrote.
    cube_a_dict["object"]["weight"] = float("nan")
    cube_a_dict["fingers"][1]["material"]["youngs_modulus"] = float("inf")
    cube_a_dict["fingers"][2]["contact_point"][0] = 1e400
    cube_a_dict["fingers"][0]["normal"] = (0.0, -math.inf, 0.0)
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(cube_a_dict)
    found = {p["path"]: p for p in e.value.problems}
    assert set(found) == {
        "object.weight",
        "fingers[1].material.youngs_modulus",
        "fingers[2].contact_point[0]",
        "fingers[0].normal[1]",
    }
    assert found["object.weight"]["message"] == "is NaN"
    assert all("finite" in p["fix"] for p in found.values())
    assert "line 1" not in str(e.value)


def test_malformed_json_and_unknown_fields_are_scene_errors(cube_a_dict):
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene('{"object": ')
    assert len(e.value.problems) == 1
    cube_a_dict["fingers"][0]["colour"] = "red"
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(cube_a_dict)
    assert "colour" in str(e.value)


def test_missing_file_and_wrong_type(tmp_path):
    with pytest.raises(OSError, match="cannot read scene file"):
        grasp.Scene(tmp_path / "nope.json")
    with pytest.raises(TypeError, match="expected a path, a dict or JSON text"):
        grasp.Scene(42)


def test_version_is_the_workspace_version():
    cargo = (pathlib.Path(__file__).resolve().parents[2] / "Cargo.toml").read_text()
    assert f'version = "{grasp.__version__}"' in cargo
